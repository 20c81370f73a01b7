/* shared_defs.h: constants shared by the GLSL shaders and their C twins.
 *
 * This file is valid C and valid GLSL: only #define lines and comments. C includes it as
 * "common/shared_defs.h" (shaders/ is on the include path); GLSL includes it with
 * #include "common/shared_defs.h". Change a value here and both sides change together.
 */
#ifndef FOVSIM_SHARED_DEFS_H
#define FOVSIM_SHARED_DEFS_H

/* Alpha-test strategies (numbering matches enum alpha_mode in src/scene/scene.h). */
#define ALPHA_MODE_ID_TRADITIONAL 1
#define ALPHA_MODE_ID_STOCHASTIC 2
#define ALPHA_MODE_ID_HASHED 3
#define ALPHA_MODE_ID_A2C 4
#define ALPHA_MODE_ID_HASHED_A2C 5
#define ALPHA_MODE_ID_CASTANO 6
#define ALPHA_MODE_ID_MIPSCALE 7

/* Smallest alpha we divide premultiplied colour by (texels with less are treated as empty). */
#define PREMUL_ALPHA_EPS 1.0e-6

/* Vertex attribute locations of the forward pass (positions, normals, uv, colour, instance matrix
 * in 4 consecutive slots). */
#define ATTR_POSITION 0
#define ATTR_NORMAL 1
#define ATTR_UV 2
#define ATTR_COLOR 3
#define ATTR_INSTANCE 4

/* Texture units. */
#define TEX_UNIT_BASE_COLOR 0

#endif
