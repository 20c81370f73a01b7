/* renderer_vrs.c: VRS foveation's rate image (plan.vrs; docs/foveation.md "Variable-rate shading:
 * coarse shading"): an R8UI texture with one texel per tile, refilled every frame from vrs_map_fill
 * for the frame's rendered gaze, which the forward passes' VRS variant reads (common/vrs_shade.glsl). */
#include "passes/renderer_internal.h"

#include <stdlib.h>
#include <string.h>

#include "common/shared_defs.h"

fs_status renderer_vrs_create(renderer *r)
{
    display_desc dd = plan_display(&r->pl);
    vrs_tile_grid(&dd, r->pl.vrs_tile, &r->vrs_tiles_x, &r->vrs_tiles_y);
    size_t tiles = (size_t)r->vrs_tiles_x * (size_t)r->vrs_tiles_y;
    r->vrs_rates = malloc(tiles);
    r->vrs_rects = malloc(sizeof(int) * 4 * tiles); /* at most one per tile */
    if (!r->vrs_rates || !r->vrs_rects)
        return FS_ERR_NOMEM;
    glCreateTextures(GL_TEXTURE_2D, 1, &r->vrs_tex);
    glTextureStorage2D(r->vrs_tex, 1, GL_R8UI, r->vrs_tiles_x, r->vrs_tiles_y);
    /* An integer texture is complete only with nearest filtering (texelFetch ignores it). */
    glTextureParameteri(r->vrs_tex, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(r->vrs_tex, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return FS_OK;
}

/* The map's 1x1 tiles as window rectangles (row 0 at the bottom): each row's runs of 1x1 tiles,
 * merged with the run above where it spans the same columns; cut at the display's edges. */
static void vrs_full_rate_rects(renderer *r)
{
    int t = r->pl.vrs_tile, nx = r->vrs_tiles_x, ny = r->vrs_tiles_y, n = 0;
    r->vrs_coarse = false;
    for (int ty = 0; ty < ny; ty++) {
        int row_first = n;
        for (int tx = 0; tx < nx;) {
            r->vrs_coarse |= r->vrs_rates[ty * nx + tx] != VRS_1X1;
            if (r->vrs_rates[ty * nx + tx] != VRS_1X1) {
                tx++;
                continue;
            }
            int x0 = tx;
            while (tx < nx && r->vrs_rates[ty * nx + tx] == VRS_1X1)
                tx++;
            int px0 = x0 * t, px1 = tx * t < r->width ? tx * t : r->width;
            int top = ty * t, bottom = (ty + 1) * t < r->height ? (ty + 1) * t : r->height;
            int merged = -1; /* a rectangle ending on the row above with the same columns: grow it down */
            for (int k = 0; k < row_first && merged < 0; k++)
                if (r->vrs_rects[4 * k] == px0 && r->vrs_rects[4 * k + 2] == px1 - px0 &&
                    r->vrs_rects[4 * k + 1] == r->height - top)
                    merged = k;
            if (merged >= 0) {
                r->vrs_rects[4 * merged + 1] = r->height - bottom;
                r->vrs_rects[4 * merged + 3] += bottom - top;
                continue;
            }
            int *q = &r->vrs_rects[4 * n++];
            q[0] = px0, q[1] = r->height - bottom, q[2] = px1 - px0, q[3] = bottom - top;
        }
    }
    r->vrs_rect_count = n;
}

void renderer_vrs_frame(renderer *r, const frame_record *fr)
{
    display_desc dd = frame_display(fr, r->width, r->height);
    size_t n = (size_t)r->vrs_tiles_x * (size_t)r->vrs_tiles_y;
    /* Tracking lost with policy full: the display at full rate, as the rings draw it then. */
    if (fr->full_res)
        memset(r->vrs_rates, VRS_1X1, n);
    else
        vrs_map_fill(&dd, &r->pl.vrs_spec, r->pl.vrs_tile, fr->gaze_px[0], fr->gaze_px[1], r->vrs_rates);
    /* Row 0 of the map is the top row of tiles: the texture keeps that order, the shader flips. */
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(r->vrs_tex, 0, 0, 0, r->vrs_tiles_x, r->vrs_tiles_y, GL_RED_INTEGER, GL_UNSIGNED_BYTE,
                        r->vrs_rates);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glBindTextureUnit(TEX_UNIT_VRS_RATE, r->vrs_tex);
    glBindSampler(TEX_UNIT_VRS_RATE, 0);
    vrs_full_rate_rects(r);
}

void renderer_vrs_uniforms(const renderer *r, const gpu_program *pg)
{
    glProgramUniform1i(pg->id, pg->u_vrs_tile, r->pl.vrs_tile);
    glProgramUniform2f(pg->id, pg->u_vrs_viewport, (float)r->width, (float)r->height);
}
