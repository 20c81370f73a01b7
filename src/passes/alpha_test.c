#include "passes/alpha_test.h"

#include "common/shared_defs.h"

bool alpha_test_traditional(float alpha, float cutoff)
{
    return alpha >= cutoff; /* twin of alpha_test.glsl; NaN alpha fails, as in GLSL */
}

int alpha_mode_shader_id(alpha_mode m)
{
    switch (m) {
    case ALPHA_MODE_TRADITIONAL: return ALPHA_MODE_ID_TRADITIONAL;
    case ALPHA_MODE_STOCHASTIC: return ALPHA_MODE_ID_STOCHASTIC;
    case ALPHA_MODE_HASHED: return ALPHA_MODE_ID_HASHED;
    case ALPHA_MODE_A2C: return ALPHA_MODE_ID_A2C;
    case ALPHA_MODE_HASHED_A2C: return ALPHA_MODE_ID_HASHED_A2C;
    case ALPHA_MODE_CASTANO: return ALPHA_MODE_ID_CASTANO;
    case ALPHA_MODE_MIPSCALE: return ALPHA_MODE_ID_MIPSCALE;
    default: return ALPHA_MODE_ID_TRADITIONAL;
    }
}

