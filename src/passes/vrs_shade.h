/* vrs_shade.h: the math of VRS foveation's emulated coarse shading, the C twin of
 * shaders/common/vrs_shade.glsl and shaders/forward_vrs.geom (docs/foveation.md "Variable-rate
 * shading: coarse shading"): which coarse pixel a pixel belongs to, the triangle's perspective-correct
 * barycentric weights at the coarse pixel's centre and their change per coarse pixel step, and the
 * mip level a lookup with that footprint reads. Pure C, no GL; unit-tested (tests/unit/test_vrs_shade.c)
 * and end to end by tests/cli/test_vrs_shade.sh.
 *
 * Conventions: window pixels as gl_FragCoord has them (origin bottom-left), display pixels as
 * vrs_map.h has them (origin top-left); a target `height` rows high.
 */
#ifndef FOVSIM_VRS_SHADE_H
#define FOVSIM_VRS_SHADE_H

#include "fov/vrs_map.h"

/* The coarse pixel of window pixel (px, py) under rate r: its top-left pixel in display
 * coordinates (aligned to the rate from the display's top-left corner, so inside one tile) and its
 * centre in window coordinates. GLSL twin: vrs_coarse_pixel. */
void vrs_coarse_pixel(int px, int py, vrs_rate r, int height, int origin[2], float centre[2]);

/* A triangle's 2D homogeneous edge functions from its clip positions (x, y, z, w per vertex):
 * edge[i] = c_{i+1} x c_{i+2} over (x, y, w). GLSL twin: forward_vrs.geom's main. */
void vrs_triangle_edges(const float clip[3][4], float edge[3][3]);

/* The triangle's perspective-correct barycentric weights b at window point (cx, cy) of a
 * viewport of vw x vh pixels, and their change bx, by over a step of (step_x, step_y) window pixels
 * (the coarse pixel's width and height). GLSL twin: vrs_bary. */
void vrs_bary(const float edge[3][3], float cx, float cy, float step_x, float step_y, float vw, float vh, float b[3],
              float bx[3], float by[3]);

/* The mip level a lookup reads whose uv changes by duv_dx, duv_dy per PIXEL, shaded at rate r:
 * the coarse footprint (the gradients scaled by the rate's width and height) by the isotropic rule
 * of alpha_texture_fade_level (bias mip_scale = 2^b). At 2x2 it is the full rate's level + 1
 * wherever that is >= 0 (and the texture is minified). */
float vrs_coarse_lod(const float duv_dx[2], const float duv_dy[2], vrs_rate r, const float tex_size[2],
                     float mip_scale);

#endif
