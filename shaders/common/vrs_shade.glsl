// vrs_shade.glsl: VRS foveation's coarse shading, emulated (docs/foveation.md "Variable-rate
// shading: coarse shading"). C twin of the math: src/passes/vrs_shade.c. Included by forward.frag
// in its VRS twin (plan_pass_vrs), after shade_in.
//
// The rate image holds one rate per tile (vrs_map.h: D3D12's encoding, (log2 w) << 2 | log2 h; row 0
// is the TOP row of tiles, as vrs_map_fill writes it). A coarse pixel of rate w x h is the block of
// display pixels aligned to w x h from the display's top-left corner (so it never straddles a
// tile). Every fragment of a triangle inside one coarse pixel evaluates the triangle's attributes at
// the coarse pixel's centre from its three vertices (forward_vrs.geom) with the same operations on
// the same flat values, so they compute the same inputs bit for bit: one shade per triangle and
// coarse pixel, broadcast to the pixels it covers, as on hardware.

layout(binding = TEX_UNIT_VRS_RATE) uniform usampler2D u_vrs_rate;
uniform int u_vrs_tile;       // tile side in pixels (8, 16 or 32)
uniform vec2 u_vrs_viewport;  // the target's size in pixels (the display)

flat in vec3 g_tri_edge[3];
flat in vec2 g_tri_uv[3];
flat in vec4 g_tri_color[3];
flat in vec3 g_tri_normal[3];
flat in vec3 g_tri_obj[3];
flat in vec2 g_tri_zw[3];

// C twin: vrs_coarse_pixel. The coarse pixel of window pixel p (origin bottom-left, as
// gl_FragCoord) under rate r on a target `height` rows high: its top-left pixel in display
// coordinates (origin top-left) and its centre in window coordinates.
void vrs_coarse_pixel(ivec2 p, uint r, int height, out ivec2 origin, out vec2 centre)
{
    int w = 1 << int(r >> 2u), h = 1 << int(r & 3u);
    int top = height - 1 - p.y;
    origin = ivec2(p.x & ~(w - 1), top & ~(h - 1));
    centre = vec2(float(origin.x) + 0.5 * float(w), float(height - origin.y) - 0.5 * float(h));
}

// C twin: vrs_bary. The triangle's perspective-correct barycentric weights at window point c, and
// their change per coarse pixel step (w pixels along x, h along y) in bx, by.
vec3 vrs_bary(vec2 c, vec2 step, out vec3 bx, out vec3 by)
{
    precise vec2 ndc = c * (2.0 / u_vrs_viewport) - 1.0;
    precise vec3 e = vec3(ndc.x * g_tri_edge[0].x + ndc.y * g_tri_edge[0].y + g_tri_edge[0].z,
                          ndc.x * g_tri_edge[1].x + ndc.y * g_tri_edge[1].y + g_tri_edge[1].z,
                          ndc.x * g_tri_edge[2].x + ndc.y * g_tri_edge[2].y + g_tri_edge[2].z);
    precise float sum = e.x + e.y + e.z;
    precise vec3 b = e / sum;
    // d e_i / d ndc = E_i.xy; d b_i = (d e_i - b_i d sum) / sum; one window pixel is 2 / size in NDC.
    vec3 ex = vec3(g_tri_edge[0].x, g_tri_edge[1].x, g_tri_edge[2].x);
    vec3 ey = vec3(g_tri_edge[0].y, g_tri_edge[1].y, g_tri_edge[2].y);
    precise vec2 k = step * (2.0 / u_vrs_viewport);
    bx = (ex - b * (ex.x + ex.y + ex.z)) / sum * k.x;
    by = (ey - b * (ey.x + ey.y + ey.z)) / sum * k.y;
    return b;
}

// The rate of this fragment's tile (VRS_RATE encoding; 0 = 1x1).
uint vrs_rate_here()
{
    int height = int(u_vrs_viewport.y);
    return texelFetch(u_vrs_rate, ivec2(int(gl_FragCoord.x), height - 1 - int(gl_FragCoord.y)) / u_vrs_tile, 0).r;
}

// The shading inputs of this fragment's coarse pixel under rate r (coarser than 1x1): the
// triangle's attributes, and their change per coarse pixel step, at the coarse pixel's centre.
shade_in vrs_shade_in(uint r)
{
    ivec2 origin;
    vec2 centre;
    vrs_coarse_pixel(ivec2(gl_FragCoord.xy), r, int(u_vrs_viewport.y), origin, centre);
    vec3 bx, by;
    vec3 b = vrs_bary(centre, vec2(float(1 << int(r >> 2u)), float(1 << int(r & 3u))), bx, by);
    mat3x2 uv = mat3x2(g_tri_uv[0], g_tri_uv[1], g_tri_uv[2]);
    mat3 obj = mat3(g_tri_obj[0], g_tri_obj[1], g_tri_obj[2]);
    mat3x4 col = mat3x4(g_tri_color[0], g_tri_color[1], g_tri_color[2]);
    mat3 nrm = mat3(g_tri_normal[0], g_tri_normal[1], g_tri_normal[2]);
    mat3x2 zw = mat3x2(g_tri_zw[0], g_tri_zw[1], g_tri_zw[2]);
    vec2 czw = zw * b;
    return shade_in(uv * b, uv * bx, uv * by, col * b, nrm * b, obj * b, obj * bx, obj * by, uvec2(origin),
                    0.5 * czw.x / czw.y + 0.5, true);
}
