/* renderer_stats.c: what the last frame counted (renderer_last_stats): each stage's GL timer and
 * pipeline statistics queries, the counting variant's covered fragments (docs/benchmarks.md "Work
 * counts") and the footprint bytes renderer_draw.c recorded. */
#include "passes/renderer_internal.h"

#include <stdio.h>
#include <string.h>

#include "common/shared_defs.h"

_Static_assert(MAX_FOV_RINGS * PLAN_MAX_PASSES <= COUNT_SHADED_OFFSET, "count slots overlap (shared_defs.h)");

/* Stage k's count out of slots c[] (covered or shaded, one per ring and pass, as read_covered). */
static long long stage_count(const renderer *r, const renderer_stats *s, const GLuint *c, int k, int *ring)
{
    int n = r->pl.pass_count;
    if (!s->pass_geometry[k])
        return r->fullscreen_px[k];
    if (!r->pl.composite)
        return c[k];
    long long sum = 0;
    for (int p = 0; p < n; p++)
        sum += c[*ring * n + p];
    (*ring)++;
    return sum;
}

/* The last frame's covered fragments (renderer_stats.pass_covered and ring_pass_covered) and
 * shaded ones (pass_shaded), when it was drawn with the counting variant. Stage order as
 * name_stages (renderer.c): rings off, one stage per pass (ring 0), then the full-screen stages;
 * rings on, each ring's passes as one stage, then its TAA resolve, then the composite. */
static void read_covered(renderer *r, renderer_stats *s)
{
    for (int i = 0; i < r->stage_count; i++) {
        s->pass_covered[i] = s->pass_shaded[i] = -1;
        s->pass_geometry[i] = r->fullscreen_px[i] < 0;
    }
    for (int i = 0; i < MAX_FOV_RINGS; i++)
        for (int p = 0; p < PLAN_MAX_PASSES; p++)
            s->ring_pass_covered[i][p] = -1;
    s->covered = s->shaded = -1;
    if (!r->counted)
        return;
    GLuint c[COUNT_WORDS];
    /* The shaders' atomics are incoherent writes: make them visible to the read-back (without
     * it llvmpipe may return the counters before the last pass has run). */
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(r->count_buf, 0, sizeof c, c);
    int rings = r->pl.composite ? r->pl.layout.count : 1, n = r->pl.pass_count;
    for (int i = 0; i < rings; i++)
        for (int p = 0; p < n; p++)
            s->ring_pass_covered[i][p] = c[i * n + p];
    s->covered = s->shaded = 0;
    for (int k = 0, ring = 0, ring_shaded = 0; k < r->stage_count; k++) {
        s->pass_covered[k] = stage_count(r, s, c, k, &ring);
        s->pass_shaded[k] = stage_count(r, s, c + COUNT_SHADED_OFFSET, k, &ring_shaded);
        s->covered += s->pass_covered[k];
        s->shaded += s->pass_shaded[k];
    }
}

void renderer_stats_take_shaded(renderer_stats *timed, const renderer_stats *counted)
{
    if (!counted->vrs || counted->shaded < 0 || counted->pass_count != timed->pass_count)
        return;
    for (int k = 0; k < timed->pass_count; k++) {
        long long fs = timed->pass_fs_invocations[k];
        if (!timed->pass_geometry[k] || fs < 0)
            continue;
        timed->fragments += counted->pass_shaded[k] - fs;
        timed->pass_fs_invocations[k] = counted->pass_shaded[k];
    }
}

renderer_stats renderer_last_stats(renderer *r)
{
    renderer_stats s = {0};
    s.pass_count = r->stage_count;
    s.shaded_pixels = r->shaded_pixels;
    s.ring_count = r->pl.layout.count;
    s.vrs = r->pl.vrs;
    memcpy(s.ring_instances, r->ring_instances, sizeof s.ring_instances);
    bool counts = r->stats_pending && r->stat_queries_on;
    s.vs_invocations = s.primitives = s.fragments = s.clipped = counts ? 0 : -1;
    read_covered(r, &s);
    s.bytes_read = s.bytes_written = 0;
    for (int i = 0; i < r->stage_count; i++) {
        s.pass_bytes_read[i] = r->stage_bytes[i].read;
        s.pass_bytes_written[i] = r->stage_bytes[i].written;
        s.bytes_read = s.bytes_read < 0 || s.pass_bytes_read[i] < 0 ? -1 : s.bytes_read + s.pass_bytes_read[i];
        s.bytes_written =
            s.bytes_written < 0 || s.pass_bytes_written[i] < 0 ? -1 : s.bytes_written + s.pass_bytes_written[i];
    }
    for (int i = 0; i < r->stage_count; i++) {
        snprintf(s.pass_names[i], sizeof s.pass_names[i], "%s", r->stage_names[i]);
        s.pass_ms[i] = -1.0;
        s.pass_wall_ms[i] = r->stage_wall_ms[i];
        if (r->stats_pending) {
            GLuint64 ns = 0;
            glGetQueryObjectui64v(r->time_queries[i], GL_QUERY_RESULT, &ns);
            s.pass_ms[i] = (double)ns * 1e-6;
        }
        long long *dst[RENDERER_STAT_TARGETS] = {&s.pass_vs_invocations[i], &s.pass_primitives[i],
                                                 &s.pass_fs_invocations[i], &s.pass_clipped[i]};
        long long *sum[RENDERER_STAT_TARGETS] = {&s.vs_invocations, &s.primitives, &s.fragments, &s.clipped};
        for (int q = 0; q < RENDERER_STAT_TARGETS; q++) {
            *dst[q] = -1;
            if (counts) {
                GLuint64 v = 0;
                glGetQueryObjectui64v(r->stat_queries[i][q], GL_QUERY_RESULT, &v);
                *dst[q] = (long long)v;
                *sum[q] += (long long)v;
            }
        }
    }
    return s;
}
