/* renderer_composite.c: the composite pass (composite.vert, composite.frag): every ring's colour
 * and coverage to the display. The CPU classifies the display each frame: a cell whose every pixel
 * takes one ring without blending is drawn by the COMPOSITE_TILE program, which fetches that ring
 * directly; the others by the program that searches per pixel. Both fetch exactly the same texels,
 * so the image does not depend on the classification (docs/foveation.md "Composite").
 *
 * The cells are squares aligned to the target's rows from the bottom, as llvmpipe bins it in
 * 64-pixel tiles, split as a quadtree down to FOV_TILE_PX and drawn as points: a 64-pixel square
 * of one ring is one point that covers a whole bin (llvmpipe shades it without any coverage test),
 * and fewer, larger points cost less setup. Points have no diagonal edge: two triangles per
 * rectangle shade every 4x4 block their diagonal crosses twice (the rectangles this replaced ran
 * 1.20 fragment invocations per display pixel). Squares cut by the display's edge (sizes not a
 * multiple of 16) are drawn as rectangles of two triangles. */
#include "passes/renderer_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* >>cells */
/* Square sides, largest first: one llvmpipe bin, then halves down to the classification tile. */
static const int k_sides[] = {64, 32, FOV_TILE_PX};
enum { SIDES = sizeof k_sides / sizeof k_sides[0], SEG_EDGES = SIDES, SEGS };
_Static_assert(FOV_TILE_PX == 16, "sides halve from 64 down to the tile");

/* Which program draws a square: the tile program where it has a ring, else the search. */
enum { PROG_TILE, PROG_SEARCH, PROGS };

static int side_segment(int side)
{
    int s = 0;
    while (s < SIDES - 1 && k_sides[s] != side)
        s++;
    return s;
}

/* The ring every pixel of window rectangle [x0, x1) x [y0, y1) (row 0 at the bottom) takes
 * without blending, or -1: searched per pixel. */
static int window_rect_ring(const renderer *r, const frame_record *fr, int x0, int y0, int x1, int y1)
{
    display_desc d = frame_display(fr, r->width, r->height);
    return fov_tile_ring(&d, &r->pl.layout, fr->gaze_px[0], fr->gaze_px[1], x0, r->height - y1, x1, r->height - y0);
}

/* Quadtree over window square (x0, y0, side): a square wholly on the display and of one ring is
 * one entry, and so is every 16-pixel square (searched, or cut by the display's edge); the others
 * split into their quarters on the display. */
static void split(renderer *r, const frame_record *fr, int x0, int y0, int side)
{
    int x1 = x0 + side < r->width ? x0 + side : r->width, y1 = y0 + side < r->height ? y0 + side : r->height;
    bool whole = x1 == x0 + side && y1 == y0 + side && r->point_max >= (float)side;
    int ring = window_rect_ring(r, fr, x0, y0, x1, y1);
    if ((whole && ring >= 0) || side == FOV_TILE_PX) {
        r->squares[r->square_count++] = (comp_square){x0, y0, x1, y1, side, ring, whole};
        return;
    }
    int h = side / 2;
    for (int q = 0; q < 4; q++) {
        int qx = x0 + (q & 1) * h, qy = y0 + (q >> 1) * h;
        if (qx < r->width && qy < r->height)
            split(r, fr, qx, qy, h);
    }
}

static void classify(renderer *r, const frame_record *fr)
{
    r->square_count = 0;
    for (int y = 0; y < r->height; y += k_sides[0])
        for (int x = 0; x < r->width; x += k_sides[0])
            split(r, fr, x, y, k_sides[0]);
}

/* Appends one vertex (x, y in display pixels, top-left origin; ring) at v[*n]. */
static void put_vertex(float *v, int *n, float x, float y, int ring)
{
    float *q = v + 3 * (*n)++;
    q[0] = x;
    q[1] = y;
    q[2] = (float)ring;
}

/* Window rectangle [x0, x1) x [y0, y1) as two triangles. */
static void put_rect(const renderer *r, float *v, int *n, int x0, int y0, int x1, int y1, int ring)
{
    float X0 = (float)x0, X1 = (float)x1, Y0 = (float)(r->height - y1), Y1 = (float)(r->height - y0);
    const float c[6][2] = {{X0, Y0}, {X1, Y0}, {X1, Y1}, {X0, Y0}, {X1, Y1}, {X0, Y1}};
    for (int k = 0; k < 6; k++)
        put_vertex(v, n, c[k][0], c[k][1], ring);
}

/* Appends the vertices of one program's segment: points of one side (their centres), or the
 * squares cut by the display's edge as rectangles. */
static void put_segment(const renderer *r, int prog, int seg, float *v, int *n)
{
    for (int i = 0; i < r->square_count; i++) {
        const comp_square *q = &r->squares[i];
        if ((q->ring >= 0) != (prog == PROG_TILE) || (q->whole ? side_segment(q->side) : SEG_EDGES) != seg)
            continue;
        if (q->whole)
            put_vertex(v, n, (float)q->x0 + 0.5f * (float)q->side, (float)(r->height - q->y0) - 0.5f * (float)q->side,
                       q->ring);
        else
            put_rect(r, v, n, q->x0, q->y0, q->x1, q->y1, q->ring);
    }
}

fs_status renderer_composite_create(renderer *r)
{
    size_t tiles_x = (size_t)((r->width + FOV_TILE_PX - 1) / FOV_TILE_PX);
    size_t tiles = tiles_x * (size_t)((r->height + FOV_TILE_PX - 1) / FOV_TILE_PX);
    /* at most one square per tile, 6 vertices of (x, y, ring) each (a square cut by the display's
     * edge is two triangles) */
    r->tile_verts = malloc(sizeof(float) * 18 * tiles);
    r->squares = malloc(sizeof *r->squares * tiles);
    if (!r->tile_verts || !r->squares)
        return FS_ERR_NOMEM;
    GLfloat range[2] = {1.0f, 1.0f};
    glGetFloatv(GL_POINT_SIZE_RANGE, range);
    r->point_max = range[1];
    glCreateBuffers(1, &r->tile_vbo);
    glNamedBufferStorage(r->tile_vbo, (GLsizeiptr)(sizeof(float) * 18 * tiles), NULL, GL_DYNAMIC_STORAGE_BIT);
    glCreateVertexArrays(1, &r->tile_vao);
    glVertexArrayVertexBuffer(r->tile_vao, 0, r->tile_vbo, 0, 3 * sizeof(float));
    glVertexArrayAttribFormat(r->tile_vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(r->tile_vao, 0, 0);
    glEnableVertexArrayAttrib(r->tile_vao, 0);
    return FS_OK;
}

/* >>draw */
/* The composite's uniforms, the same in both of its programs. */
static void composite_uniforms(const renderer *r, const composite_program *c, const frame_record *fr)
{
    const fov_layout *l = &r->pl.layout;
    display_desc d = frame_display(fr, r->width, r->height);
    float outer[MAX_FOV_RINGS], principal[2], band[MAX_FOV_RINGS], rect[4 * MAX_FOV_RINGS], block[MAX_FOV_RINGS];
    for (int i = 0; i < l->count; i++) {
        float prev = i > 0 ? l->rings[i - 1].outer_deg : 0.0f;
        outer[i] = isinf(l->rings[i].outer_deg) ? 1e9f : l->rings[i].outer_deg;
        band[i] = isinf(l->rings[i].outer_deg) ? 0.0f : fminf(l->blend_deg, 0.5f * (l->rings[i].outer_deg - prev));
        const fov_ring_rect *rr = &fr->ring_rect[i];
        rect[4 * i] = (float)rr->x0;
        rect[4 * i + 1] = (float)rr->y0;
        rect[4 * i + 2] = (float)rr->x1;
        rect[4 * i + 3] = (float)rr->y1;
        block[i] = (float)rr->block;
    }
    glProgramUniform2f(c->id, c->u_display_px, (float)r->width, (float)r->height);
    glProgramUniform2f(c->id, c->u_array_px, (float)r->width, (float)r->height);
    glProgramUniform1f(c->id, c->u_focal_px, fov_focal_px(&d));
    fov_principal_px(&d, principal);
    glProgramUniform2f(c->id, c->u_principal_px, principal[0], principal[1]);
    glProgramUniform2f(c->id, c->u_gaze_px, fr->gaze_px[0], fr->gaze_px[1]);
    glProgramUniform1fv(c->id, c->u_ring_outer, l->count, outer);
    glProgramUniform1fv(c->id, c->u_ring_band, l->count, band);
    glProgramUniform4fv(c->id, c->u_ring_rect, l->count, rect);
    glProgramUniform1fv(c->id, c->u_ring_block, l->count, block);
}

/* One program's segments: squares as points of their side, those cut by the display's edge as
 * triangles. */
static void draw_segments(const int first[SEGS], const int count[SEGS])
{
    for (int s = 0; s < SEGS; s++) {
        if (count[s] == 0)
            continue;
        if (s == SEG_EDGES) {
            glDrawArrays(GL_TRIANGLES, first[s], count[s]);
            continue;
        }
        glPointSize((float)k_sides[s]);
        glDrawArrays(GL_POINTS, first[s], count[s]);
    }
    glPointSize(1.0f);
}

/* Writes the frame's vertices into r->tile_verts, each program's segments in order; returns how
 * many. Without tiles (--composite per-pixel, --overlay) the display is one rectangle searched per
 * pixel, as before the cells: the tests compare the cells' image with it bit for bit. */
static int put_vertices(renderer *r, const frame_record *fr, int first[PROGS][SEGS], int count[PROGS][SEGS])
{
    int n = 0;
    memset(count, 0, sizeof(int) * PROGS * SEGS);
    memset(first, 0, sizeof(int) * PROGS * SEGS);
    if (!r->pl.composite_tiles) {
        put_rect(r, r->tile_verts, &n, 0, 0, r->width, r->height, -1);
        count[PROG_SEARCH][SEG_EDGES] = n;
        return n;
    }
    classify(r, fr);
    for (int p = 0; p < PROGS; p++)
        for (int s = 0; s < SEGS; s++) {
            first[p][s] = n;
            put_segment(r, p, s, r->tile_verts, &n);
            count[p][s] = n - first[p][s];
        }
    return n;
}

void renderer_draw_composite(renderer *r, const frame_record *fr)
{
    int first[PROGS][SEGS], count[PROGS][SEGS];
    int n = put_vertices(r, fr, first, count);
    glNamedBufferSubData(r->tile_vbo, 0, (GLsizeiptr)(sizeof(float) * 3 * (size_t)n), r->tile_verts);
    /* With TAA the composite reads the resolved rings this frame wrote. */
    glBindTextureUnit(0, r->pl.taa ? r->taa_color[r->parity] : r->rt.color);
    glBindTextureUnit(1, r->pl.taa ? r->taa_coverage[r->parity] : r->rt.coverage);
    glBindSampler(0, r->ring_sampler);
    glBindSampler(1, r->ring_sampler);
    glBindFramebuffer(GL_FRAMEBUFFER, r->out_fbo);
    glViewport(0, 0, r->width, r->height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glBindVertexArray(r->tile_vao);
    const composite_program *progs[PROGS] = {&r->comp_tile, &r->comp};
    for (int p = 0; p < PROGS; p++) {
        int total = 0;
        for (int k = 0; k < SEGS; k++)
            total += count[p][k];
        if (total == 0)
            continue;
        composite_uniforms(r, progs[p], fr);
        glUseProgram(progs[p]->id);
        draw_segments(first[p], count[p]);
    }
    glBindSampler(0, 0);
    glBindSampler(1, 0);
}
