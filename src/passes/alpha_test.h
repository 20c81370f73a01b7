/* alpha_test.h: C twin of shaders/common/alpha_test.glsl (same constants: common/shared_defs.h).
 *
 * Unit tests call these directly; a GPU test checks the shader agrees. Only the traditional test
 * exists so far; stochastic, hashed and the A2C variants come with the alpha-strategies issue.
 */
#ifndef FOVSIM_ALPHA_TEST_H
#define FOVSIM_ALPHA_TEST_H

#include <stdbool.h>

#include "scene/scene.h"

/* GLSL twin: alpha_test_passes(alpha, cutoff) with ALPHA_MODE_ID_TRADITIONAL. */
bool alpha_test_traditional(float alpha, float cutoff);
/* The ALPHA_MODE_ID_* value the shader is compiled with for `m`. */
int alpha_mode_shader_id(alpha_mode m);
/* True for modes the forward pass can draw today. */
bool alpha_mode_is_implemented(alpha_mode m);

#endif
