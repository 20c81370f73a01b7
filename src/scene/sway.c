/* sway.c: wind sway of instances (sway.h); GLSL twin shaders/common/sway.glsl. */
#include "scene/sway.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "common/shared_defs.h"

static bool finite_bits(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return (u & 0x7f800000u) != 0x7f800000u;
}

float sway_weight(float y, float height)
{
    if (!finite_bits(height) || !(height > 0.0f) || y != y)
        return 0.0f;
    float q = y / height;
    q = q < 0.0f ? 0.0f : (q > 1.0f ? 1.0f : q);
    return q * q;
}

float sway_wave(float frequency, float phase, float t)
{
    float c = frequency * t;
    c = c + phase;
    if (!finite_bits(c))
        return 0.0f;
    c = c - floorf(c);
    return sinf((float)SWAY_TWO_PI * c);
}

vec3 sway_displacement(const instance_sway *s, float y, float t)
{
    float k = sway_weight(y, s->height) * sway_wave(s->frequency, s->phase, t);
    vec3 o = s->offset;
    if (!(fabsf(o.x) <= (float)SWAY_OFFSET_MAX) || !(fabsf(o.y) <= (float)SWAY_OFFSET_MAX) ||
        !(fabsf(o.z) <= (float)SWAY_OFFSET_MAX))
        return v3(0, 0, 0); /* also NaN and infinities */
    return v3(o.x * k, o.y * k, o.z * k);
}

vec3 sway_motion(const instance_sway *s, float y, float t, float t_prev)
{
    vec3 a = sway_displacement(s, y, t_prev), b = sway_displacement(s, y, t);
    return v3(a.x - b.x, a.y - b.y, a.z - b.z);
}
