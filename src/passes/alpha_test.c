#include "passes/alpha_test.h"

bool alpha_test_traditional(float alpha, float cutoff)
{
    return alpha >= cutoff; /* twin of alpha_test.glsl; NaN alpha fails, as in GLSL */
}

int alpha_mode_shader_id(alpha_mode m)
{
    /* The shader's ALPHA_MODE_ID_<NAME> is enum alpha_mode's value (shader_src_build defines them
     * from the same table); "not set" draws traditional. */
    return m > ALPHA_MODE_DEFAULT && m < ALPHA_MODE_COUNT ? (int)m : (int)ALPHA_MODE_TRADITIONAL;
}
