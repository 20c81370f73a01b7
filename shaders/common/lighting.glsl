// lighting.glsl: one directional light + ambient, Lambert, two-sided foliage.
uniform vec3 u_light_dir;     // direction the light travels, normalised (world)
uniform vec3 u_light_color;   // linear
uniform vec3 u_ambient;       // linear

// n: unit world normal already facing the viewer for two-sided surfaces.
vec3 shade_lambert(vec3 albedo, vec3 n)
{
    float ndl = max(dot(n, -u_light_dir), 0.0);
    return albedo * (u_ambient + u_light_color * ndl);
}
