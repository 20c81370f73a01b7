/* pass_bytes.c: bytes each stage writes and reads from its targets' footprints (pass_bytes.h). */
#include "passes/pass_bytes.h"

pass_bytes pass_bytes_forward(const target_bytes *t, long long px)
{
    long long out = t->color + t->coverage + t->motion; /* the colour attachments */
    if (t->msaa_samples <= 1)
        return (pass_bytes){px * t->depth, px * (out + t->depth)};
    long long s = t->msaa_samples, depth_resolve = t->taa ? t->depth : 0;
    /* samples drawn (depth tested), then resolved: samples read, pixels written */
    return (pass_bytes){s * px * t->depth + s * px * (out + depth_resolve),
                        s * px * (out + t->depth) + px * (out + depth_resolve)};
}

pass_bytes pass_bytes_taa(const target_bytes *t, long long px, long long prev_px)
{
    long long current = t->color + t->coverage + t->depth + t->motion;
    long long history = t->history_color + t->history_coverage + t->history_depth;
    return (pass_bytes){px * current + prev_px * history, px * history};
}

pass_bytes pass_bytes_composite(const target_bytes *t, const long long *ring_px, int rings, long long display_px)
{
    long long per_ring = t->taa ? t->history_color + t->history_coverage : t->color + t->coverage;
    long long read = 0;
    for (int i = 0; i < rings; i++)
        read += ring_px[i] * per_ring;
    return (pass_bytes){read, display_px * (t->out_color + t->out_coverage + t->out_debug)};
}
