/* warp.h: the previous frame warped into the current one by camera reprojection, for the
 * motion-compensated temporal error (metrics_temporal; docs/metrics.md "Temporal error").
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

/* The camera did not move between two frames when no pixel of the frame moves by more than this
 * many display pixels (x or y) when reprojected into the previous frame: checked at the display's
 * corners at the depth of the frame's nearest surface and at the far plane (for the small motions in
 * question the reprojection's displacement is largest at those corners: rotation moves the corners
 * most, translation the nearest points). Computed in double. Why 1e-3: moving a bilinear sample of
 * an image in [0, 1] by 1e-3 pixel changes it by at most 1e-3, about one half-float ulp at 1.0
 * (2^-10), the resolution of the frames the metrics read. Measured (docs/metrics.md "Still camera"):
 * the 1-ulp camera jitter the wind scene had moved a surface 1 m away by under 1e-4 pixel, and the
 * slowest moving camera of the built-in scenes moves it by hundreds of pixels per frame. */
#define WARP_STILL_TOLERANCE_PX 1e-3

/* Whether the camera is still between view-projections prev and cur (WARP_STILL_TOLERANCE_PX) on
 * a width x height display whose nearest surface lies at window depth near_depth (the smallest value
 * of the frame's depth, warp_min_depth; 0, the near plane, is the strictest). Bit-identical matrices
 * are still; a matrix that cannot be inverted, or a point behind the previous camera, is not. The
 * one test of "the camera did not move" that the warp (identity) and the static-view flicker
 * (commands/measure.c) share. */
bool warp_camera_still(const mat4 *prev, const mat4 *cur, int width, int height, float near_depth);
/* The smallest finite window depth of a frame clamped to [0, 1] (1 when there is none: all sky). */
float warp_min_depth(const float *depth, int width, int height);

/* The warp of one frame, computed once for every image warped with it: coords (2 floats per pixel)
 * gets each pixel's position in the previous frame, valid[] 1 where it is warped and 0 where not.
 * When the camera is still (warp_camera_still) the warp is the identity exactly: each pixel's own
 * integer position, which warp_apply copies without resampling (the disocclusion test still runs,
 * on the two frames' depths at the pixel), so an unchanged frame's temporal error is exactly 0.
 * The warp knows the camera only: foliage that sways is not followed (docs/metrics.md).
 * Returns the number of valid pixels, or -1 when the current view-projection cannot be inverted
 * (nothing is written). */
long warp_build(const warp_desc *w, float *coords, unsigned char *valid);
/* Samples `prev` (R, G, B, coverage) at warp_build's positions into out[4] (0 where not valid). */
void warp_apply(const float *coords, const unsigned char *valid, const metrics_view *prev, float *const out[4]);
/* warp_build and warp_apply in one call, for a single image: -1 also when out of memory. */
long warp_previous(const warp_desc *w, const metrics_view *prev, float *const out[4], unsigned char *valid);

#endif
