/* renderer_read.c: read-back of the last frame, rows top first: its images (renderer_read,
 * renderer_read_opaque), depth and fragment lists; and the framebuffer the viewer blits. */
#include "passes/renderer_internal.h"

#include <stdlib.h>
#include <string.h>

#include "core/log.h"

/* >>readback */
/* Reverses the row order of p (h rows of w * comps 4-byte values) through `row` (one row). */
static void flip_rows(void *p, void *row, int w, int h, int comps)
{
    size_t n = (size_t)w * (size_t)comps * 4;
    for (int y = 0; y < h / 2; y++) {
        char *a = (char *)p + (size_t)y * n, *b = (char *)p + (size_t)(h - 1 - y) * n;
        memcpy(row, a, n);
        memcpy(a, b, n);
        memcpy(b, row, n);
    }
}

/* Reads `color` (RGBA) and `coverage` (its first channel) at level 0, layer 0, into *img as R, G, B,
 * A and coverage, then any of the debug channels and the list resolve's flags the plan writes. */
static fs_status read_images(renderer *r, exr_image *img, GLuint color, GLuint coverage, bool extras)
{
    size_t n = (size_t)r->width * (size_t)r->height;
    /* The interleaved read-back lives as long as the renderer: nothing in the frame loop is
     * allocated per frame but the image handed to the caller (docs/benchmarks.md, "Allocator"). */
    if (!r->read_buf) {
        r->read_buf = malloc(sizeof(float) * 4 * n);
        r->read_row = malloc(sizeof(float) * 4 * (size_t)r->width);
        if (!r->read_buf || !r->read_row)
            return FS_ERR_NOMEM;
    }
    float *rgba = r->read_buf;
    if (!exr_image_init(img, r->width, r->height))
        return FS_ERR_NOMEM;
    static const char *const names[] = {"R", "G", "B", "A", "coverage", "ring.id", "eccentricity"};
    int channels = extras && r->pl.debug_channels ? 7 : 5;
    float *planes[7], *flags = NULL;
    for (int c = 0; c < channels; c++)
        if (!(planes[c] = exr_image_add_channel(img, names[c]))) {
            exr_image_free(img);
            return FS_ERR_NOMEM;
        }
    if (extras && r->pl.list_resolve && !(flags = exr_image_add_channel(img, RENDERER_LIST_FLAG_CHANNEL))) {
        exr_image_free(img);
        return FS_ERR_NOMEM;
    }
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureSubImage(color, 0, 0, 0, 0, r->width, r->height, 1, GL_RGBA, GL_FLOAT,
                         (GLsizei)(sizeof(float) * 4 * n), rgba);
    glGetTextureSubImage(coverage, 0, 0, 0, 0, r->width, r->height, 1, GL_RED, GL_FLOAT,
                         (GLsizei)(sizeof(float) * n), planes[4]);
    flip_rows(rgba, r->read_row, r->width, r->height, 4); /* GL rows are bottom first, EXR top first */
    flip_rows(planes[4], r->read_row, r->width, r->height, 1);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 4; c++)
            planes[c][i] = rgba[4 * i + (size_t)c];
    if (channels == 7) {
        glGetTextureImage(r->out_tex[OUT_DEBUG], 0, GL_RG, GL_FLOAT, (GLsizei)(sizeof(float) * 2 * n), rgba);
        flip_rows(rgba, r->read_row, r->width, r->height, 2);
        for (size_t i = 0; i < n; i++) {
            planes[5][i] = rgba[2 * i];
            planes[6][i] = rgba[2 * i + 1];
        }
    }
    if (flags) {
        glGetTextureImage(coverage, 0, GL_GREEN, GL_FLOAT, (GLsizei)(sizeof(float) * n), flags);
        flip_rows(flags, r->read_row, r->width, r->height, 1);
    }
    return FS_OK;
}

fs_status renderer_read(renderer *r, exr_image *img)
{
    /* Composite: the display targets; rings off: layer 0 of the ring arrays (display-sized); the
     * exact reference: its resolve. */
    GLuint color = r->pl.composite      ? r->out_tex[OUT_COLOR]
                   : r->pl.list_resolve ? r->list_color
                   : r->pl.taa          ? r->taa_color[r->out_parity]
                                        : r->rt.color;
    GLuint coverage = r->pl.composite      ? r->out_tex[OUT_COVERAGE]
                      : r->pl.list_resolve ? r->list_coverage
                      : r->pl.taa          ? r->taa_coverage[r->out_parity]
                                           : r->rt.coverage;
    return read_images(r, img, color, coverage, true);
}

fs_status renderer_read_opaque(renderer *r, exr_image *img)
{
    FS_ASSERT(r->pl.list_resolve);
    return read_images(r, img, r->rt.color, r->rt.coverage, false);
}

fs_status renderer_read_depth(renderer *r, float *depth)
{
    FS_ASSERT(!r->pl.composite && !r->pl.msaa);
    size_t n = (size_t)r->width * (size_t)r->height;
    if (!r->read_row && !(r->read_row = malloc(sizeof(float) * 4 * (size_t)r->width)))
        return FS_ERR_NOMEM;
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(r->rt.depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT, (GLsizei)(sizeof(float) * n), depth);
    flip_rows(depth, r->read_row, r->width, r->height, 1);
    return FS_OK;
}

fs_status renderer_read_lists(renderer *r, abuffer_lists *out, bool with_nodes)
{
    FS_ASSERT(r->list_head);
    size_t npix = (size_t)r->width * (size_t)r->height;
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint count = 0;
    glGetNamedBufferSubData(r->list_counter, 0, sizeof count, &count);
    uint64_t stored = count < r->list_capacity ? count : r->list_capacity;
    *out = (abuffer_lists){r->width, r->height, NULL, NULL, count, r->list_capacity};
    if (!with_nodes)
        return FS_OK;
    if (!r->list_head_buf && !(r->list_head_buf = malloc(sizeof(uint32_t) * npix)))
        return FS_ERR_NOMEM;
    if (!r->read_row && !(r->read_row = malloc(sizeof(float) * 4 * (size_t)r->width)))
        return FS_ERR_NOMEM;
    if (stored > r->list_node_buf_cap) {
        free(r->list_node_buf);
        r->list_node_buf_cap = 0;
        if (!(r->list_node_buf = malloc((size_t)stored * sizeof(abuffer_node))))
            return FS_ERR_NOMEM;
        r->list_node_buf_cap = stored;
    }
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(r->list_head, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, (GLsizei)(sizeof(uint32_t) * npix),
                      r->list_head_buf);
    flip_rows(r->list_head_buf, r->read_row, r->width, r->height, 1); /* rows top first, as the images */
    if (stored > 0)
        glGetNamedBufferSubData(r->list_nodes, 0, (GLsizeiptr)(stored * sizeof(abuffer_node)), r->list_node_buf);
    *out = (abuffer_lists){r->width, r->height, r->list_head_buf, r->list_node_buf, count, r->list_capacity};
    return FS_OK;
}

/* >>present: what the viewer blits (the colour renderer_read reads) */
unsigned renderer_output_framebuffer(const renderer *r)
{
    return r->pl.composite ? r->out_fbo : r->pl.taa ? r->taa_fbo[r->out_parity][0] : r->rt.fbo[0];
}
