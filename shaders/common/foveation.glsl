// foveation.glsl: GLSL twin of fov_eccentricity_deg and fov_composite_weight in src/fov/fov_ring.c
// (conventions in src/fov/fov_ring.h: display pixels with origin top-left, pinhole camera with focal
// length u_focal_px, gaze in display pixels).
#ifndef FOV_RING_COUNT
#error "foveation.glsl needs FOV_RING_COUNT (set by the plan)"
#endif
#include "common/eccentricity.glsl"

uniform vec2 u_display_px;              // width, height
uniform float u_focal_px;               // (width / 2) / tan(hfov / 2)
uniform vec2 u_principal_px;            // principal point, display pixels (width / 2, height / 2 if centred)
uniform vec2 u_gaze_px;                 // gaze, display pixels, top-left origin
uniform float u_ring_outer[FOV_RING_COUNT]; // degrees; the last is large (covers everything)
uniform float u_ring_band[FOV_RING_COUNT];  // blend band inside each border, degrees

// Angle in degrees between the view rays through display point p and the gaze.
float fov_eccentricity_deg(vec2 p)
{
    return fov_angle_deg(p, u_gaze_px, u_principal_px, u_focal_px);
}

// Innermost ring whose outer radius exceeds e, and the weight of the next ring inside the blend band.
void fov_composite_weight(float e, out int ring, out float next)
{
    ring = FOV_RING_COUNT - 1;
    for (int i = FOV_RING_COUNT - 2; i >= 0; i--)
        if (e < u_ring_outer[i])
            ring = i;
    // smoothstep is undefined for an empty band; the C twin gives 0 there (a hard edge).
    float band = u_ring_band[ring];
    next = ring < FOV_RING_COUNT - 1 && band > 0.0 ? smoothstep(u_ring_outer[ring] - band, u_ring_outer[ring], e) : 0.0;
}
