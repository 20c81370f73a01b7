/* pass_bytes.h: bytes each stage of a frame writes and reads, from its targets' footprints
 * (docs/benchmarks.md "Work counts"): what a GPU's memory traffic would be at the least, each
 * target touched once over the pixels the stage draws. Pure C (the renderer fills target_bytes
 * from its resource tables, renderer_upload.c); overdraw, texture fetches and caches are not
 * modelled.
 *
 *   forward (one ring, all its passes): writes its targets (colour, coverage, depth, motion) over
 *       the footprint once (the clear, then the fragments that land there), reads depth once (the
 *       depth test); MSAA: every sample of them, and the resolve into the ring's layer (reads the
 *       samples, writes the pixels; depth too where TAA reprojects through it);
 *   TAA resolve: reads the current ring (colour, coverage, depth, motion) and the history
 *       (colour, coverage, history depth) of the previous footprint, writes the history;
 *   composite: reads every ring's colour and coverage footprint (the resolved history with TAA),
 *       writes the display targets (colour, coverage, debug). */
#ifndef FOVSIM_PASS_BYTES_H
#define FOVSIM_PASS_BYTES_H

#include <stdbool.h>

typedef struct pass_bytes {
    long long read, written;
} pass_bytes;

/* Bytes per pixel of each target; 0 = the target does not exist in this plan. */
typedef struct target_bytes {
    int color, coverage, depth, motion;          /* a ring's forward targets */
    int history_color, history_coverage, history_depth; /* TAA history (history_depth: disocclusion) */
    int out_color, out_coverage, out_debug;      /* the composite's display targets */
    int msaa_samples;                            /* forward passes drawn through MSAA (0 or 1: not) */
    bool taa;                                    /* the composite reads the history; MSAA resolves depth */
} target_bytes;

/* A ring's forward passes over a footprint of px pixels. */
pass_bytes pass_bytes_forward(const target_bytes *t, long long px);
/* A ring's TAA resolve: px pixels now, prev_px in the history's footprint. */
pass_bytes pass_bytes_taa(const target_bytes *t, long long px, long long prev_px);
/* The composite of `rings` rings of ring_px pixels each onto display_px pixels. */
pass_bytes pass_bytes_composite(const target_bytes *t, const long long *ring_px, int rings, long long display_px);

#endif
