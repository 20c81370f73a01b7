/* alpha_test.h: C twin of the traditional test in shaders/common/alpha_test.glsl, and the mapping
 * from alpha modes to the shader's ALPHA_MODE_ID_* (the FS_ALPHA_MODES table in
 * common/shared_defs.h). The thresholds of the stochastic, hashed and A2C tests have their twins in
 * alpha_hash.h. tests/gpu/test_gl.c checks the GLSL traditional test against alpha_test_traditional
 * on every 8-bit alpha.
 */
#ifndef FOVSIM_ALPHA_TEST_H
#define FOVSIM_ALPHA_TEST_H

#include <stdbool.h>

#include "scene/scene.h"

/* GLSL twin: alpha_test_passes(alpha, cutoff) with ALPHA_MODE_ID_TRADITIONAL. */
bool alpha_test_traditional(float alpha, float cutoff);
/* The ALPHA_MODE_ID_* value the shader is compiled with for `m`. */
int alpha_mode_shader_id(alpha_mode m);

#endif
