// eccentricity.glsl: the angle between two display points' view rays, in degrees (GLSL twin of
// fov_eccentricity_deg in src/fov/fov_ring.c; conventions in src/fov/fov_ring.h: display pixels
// with origin top-left, pinhole camera of focal length `focal_px` whose principal point, where the
// view axis meets the display, is `principal_px`: the display centre unless the display is
// off-centre, core/display.h). Shared by the composite
// (common/foveation.glsl) and the TAA resolve (taa.frag, TAA_RING_CULL).
#ifndef FOVSIM_ECCENTRICITY_GLSL
#define FOVSIM_ECCENTRICITY_GLSL

vec3 fov_ray(vec2 p, vec2 principal_px, float focal_px)
{
    return vec3(p.x - principal_px.x, -(p.y - principal_px.y), -focal_px);
}

// atan2 form: exact 0 at the gaze, accurate for small angles.
float fov_angle_deg(vec2 p, vec2 g, vec2 principal_px, float focal_px)
{
    vec3 a = fov_ray(p, principal_px, focal_px), b = fov_ray(g, principal_px, focal_px);
    return degrees(atan(length(cross(a, b)), dot(a, b)));
}

#endif
