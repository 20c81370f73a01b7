// sway.glsl: wind sway of instances. C twin: src/scene/sway.c (declared in src/scene/sway.h, which
// documents each function); both take their constants from common/shared_defs.h and evaluate the
// same float operations in the same order. tests/gpu/test_sway_twin.c compares them.
#ifndef FOVSIM_SWAY_GLSL
#define FOVSIM_SWAY_GLSL

#include "common/shared_defs.h"

bool sway_is_finite(float x)
{
    return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u;
}

// C twin: sway_weight. clamp(y / height, 0, 1)^2; NaN y or a bad height -> 0.
float sway_weight(float y, float height)
{
    if (!sway_is_finite(height) || !(height > 0.0) || (floatBitsToUint(y) & 0x7fffffffu) > 0x7f800000u)
        return 0.0;
    precise float q = y / height;
    q = q < 0.0 ? 0.0 : (q > 1.0 ? 1.0 : q);
    precise float w = q * q;
    return w;
}

// C twin: sway_wave. sin(2 pi fract(frequency t + phase)); a non-finite argument -> 0.
float sway_wave(float frequency, float phase, float t)
{
    precise float c = frequency * t;
    c = c + phase;
    if (!sway_is_finite(c))
        return 0.0;
    c = c - floor(c);
    return sin(float(SWAY_TWO_PI) * c);
}

// C twin: sway_displacement. `sway` = (offset, height), `wave` = (frequency, phase).
vec3 sway_displacement(vec4 sway, vec2 wave, float y, float t)
{
    float k = sway_weight(y, sway.w) * sway_wave(wave.x, wave.y, t);
    // Beyond SWAY_OFFSET_MAX or not finite: no sway (bit tests: comparisons may not see NaN).
    const float lim = float(SWAY_OFFSET_MAX);
    if (!sway_is_finite(sway.x) || !sway_is_finite(sway.y) || !sway_is_finite(sway.z) || abs(sway.x) > lim ||
        abs(sway.y) > lim || abs(sway.z) > lim)
        return vec3(0.0);
    precise vec3 d = sway.xyz * k;
    return d;
}

// C twin: sway_motion. Displacement at t_prev minus displacement at t.
vec3 sway_motion(vec4 sway, vec2 wave, float y, float t, float t_prev)
{
    precise vec3 m = sway_displacement(sway, wave, y, t_prev) - sway_displacement(sway, wave, y, t);
    return m;
}

#endif
