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

/* The warp of one frame, computed once for every image warped with it: coords (2 floats per pixel)
 * gets each pixel's position in the previous frame, valid[] 1 where it is warped and 0 where not.
 * Returns the number of valid pixels, or -1 when the current view-projection cannot be inverted
 * (nothing is written). */
long warp_build(const warp_desc *w, float *coords, unsigned char *valid);
/* Samples `prev` (R, G, B, coverage) at warp_build's positions into out[4] (0 where not valid). */
void warp_apply(const float *coords, const unsigned char *valid, const metrics_view *prev, float *const out[4]);
/* warp_build and warp_apply in one call, for a single image: -1 also when out of memory. */
long warp_previous(const warp_desc *w, const metrics_view *prev, float *const out[4], unsigned char *valid);

#endif
