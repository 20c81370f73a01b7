/* warp.h: the previous frame warped into the current one by camera reprojection, for the
 * motion-compensated temporal error of issue 15 (docs/metrics.md; not yet in the metrics).
 *
 * Each current pixel's centre and window depth give a world point (the inverse of the current
 * view-projection); the previous view-projection projects it into the previous frame
 * (taa_reproject, the C twin of TAA's reprojection), where the previous image is sampled
 * bilinearly (taps clamped to the image). A pixel is not warped (valid = 0) where the point falls
 * outside the previous frame, lies behind its camera, or is disoccluded: the previous frame's own
 * depth there is nearer than the point by more than `depth_tolerance` (relative, in linear depth).
 * Pure C.
 */
#ifndef FOVSIM_WARP_H
#define FOVSIM_WARP_H

#include "core/fmath.h"
#include "core/status.h"
#include "metrics/metrics.h"

typedef struct warp_desc {
    int width, height;
    const float *depth;      /* the current frame's window depth in [0, 1], rows top first */
    mat4 view_proj;          /* the current frame's (unjittered) view-projection */
    mat4 prev_view_proj;     /* the previous frame's */
    const float *prev_depth; /* the previous frame's window depth, rows top first; NULL: no
                                disocclusion test */
    float prev_znear, prev_zfar; /* the previous projection's clip planes (to linearise depth) */
    float depth_tolerance;   /* relative; <= 0 means WARP_DEPTH_TOLERANCE_DEFAULT */
} warp_desc;

#define WARP_DEPTH_TOLERANCE_DEFAULT 0.02f

/* Warps `prev` (R, G, B, coverage) into out[4] (width * height each) and writes valid[] (1 where
 * warped, 0 where not: those pixels hold 0). Returns the number of valid pixels, or -1 when the
 * current view-projection cannot be inverted (FS_ERR_USAGE: nothing is written). */
long warp_previous(const warp_desc *w, const metrics_view *prev, float *const out[4], unsigned char *valid);

#endif
