/* sway.h: wind sway of instances, the C twin of shaders/common/sway.glsl.
 *
 * A swaying instance (scene file: an instance entry's "sway", docs/scene-format.md) bends in the
 * wind: a vertex at asset-space height y moves, in world space, by
 *
 *     offset * w(y) * sin(2 pi * fract(frequency * t + phase)),   w(y) = clamp(y / height, 0, 1)^2
 *
 * so the asset's base (y <= 0) stays put, the displacement grows with the square of the height
 * (a cantilever's bending shape) and never exceeds |offset|. The GLSL twin evaluates the same float
 * operations in the same order (tests/gpu/test_sway_twin.c compares them); constants come from
 * common/shared_defs.h.
 *
 *   sway_weight        w(y): 0 at and below the base, 1 from `height` up; NaN y or a height that is
 *                      not positive and finite -> 0 (no motion)
 *   sway_wave          sin(2 pi fract(frequency t + phase)), in [-1, 1]; fract first, so it stays
 *                      accurate for hours of scene time; a non-finite argument -> 0
 *   sway_displacement  offset * weight * wave (world units); an offset with a component beyond
 *                      SWAY_OFFSET_MAX or not finite -> 0
 *   sway_motion        displacement at t_prev minus at t: where the vertex was last frame, relative
 *                      to where it is now (TAA's per-object motion)
 *
 * Guarantees: every function returns finite values for every input, and |displacement| <= |offset|
 * for finite offsets.
 */
#ifndef FOVSIM_SWAY_H
#define FOVSIM_SWAY_H

#include "scene/scene.h"

float sway_weight(float y, float height);
float sway_wave(float frequency, float phase, float t);
vec3 sway_displacement(const instance_sway *s, float y, float t);
vec3 sway_motion(const instance_sway *s, float y, float t, float t_prev);

#endif
