// forward.frag: shading of one primitive in one of four passes, chosen by the plan:
//   PASS_OPAQUE  opaque materials: no alpha lookup matters, no test;
//   PASS_MASK    alpha-tested materials (ALPHA_MODE picks the test);
//   PASS_BLEND   alpha-blended materials, premultiplied output, no depth writes;
//   PASS_LIST    the exact reference: MASK and BLEND fragments appended to per-pixel lists
//                (common/abuffer.glsl), nothing written to the targets.
// Outputs: colour (linear, premultiplied, A = opacity) and coverage (docs/design.md "Coverage": opacity contributed
// by alpha-mapped surfaces; 0 for opaque geometry and background).
#ifdef PASS_LIST
// The list pass allocates its nodes once per subgroup where it can (common/abuffer.glsl).
#extension GL_ARB_shader_ballot : enable
#extension GL_ARB_gpu_shader_int64 : enable
#endif
#include "common/shared_defs.h"
#include "common/lighting.glsl"
#ifdef VRS
// VRS foveation: forward_vrs.geom hands on the vertex shader's outputs under these names (and the
// triangle's vertices, for the coarse shading: common/vrs_shade.glsl).
#define v_world_pos g_world_pos
#define v_world_normal g_world_normal
#define v_object_pos g_object_pos
#define v_uv g_uv
#define v_color g_color
#define v_motion g_motion
#define v_instance g_instance
#define v_primitive g_primitive
#define v_hash_instance g_hash_instance
#define v_hash_triangle g_hash_triangle
#endif

#if !defined(PASS_OPAQUE) && !defined(PASS_MASK) && !defined(PASS_BLEND) && !defined(PASS_SOLID) && !defined(PASS_LIST)
#error "forward.frag needs one of PASS_OPAQUE, PASS_MASK, PASS_BLEND, PASS_SOLID, PASS_LIST"
#endif
#include "common/draw_order.glsl"
#ifdef FORWARD_DRAW_ORDER
flat in uint v_instance;
flat in uint v_primitive;        // gl_PrimitiveID, without its cost on llvmpipe (common/draw_order.glsl)
uniform uint u_draw_order;       // the draw's first instance in the API order of this pass's draws
#endif
#ifdef FORWARD_HASH_LAYER
flat in uint v_hash_instance;    // the instance's scene slot (common/draw_order.glsl)
flat in uint v_hash_triangle;    // the asset's triangle (common/draw_order.glsl)
#endif
#ifdef PASS_MASK
#include "common/alpha_test.glsl"
#endif
#ifdef PASS_LIST
layout(early_fragment_tests) in; // only fragments in front of the opaque surfaces are stored
#include "common/abuffer.glsl"
#endif

in vec3 v_world_pos;
in vec3 v_world_normal;
in vec3 v_object_pos;
in vec2 v_uv;
in vec4 v_color;
#ifdef OBJECT_MOTION
in vec3 v_motion;
#endif

layout(binding = TEX_UNIT_BASE_COLOR) uniform sampler2D u_base_tex; // linear, premultiplied
uniform bool u_has_base_tex;
uniform vec4 u_base_color;   // linear factor
uniform float u_alpha_cutoff;
uniform bool u_double_sided;
uniform float u_mip_bias;    // log2 units, added to every lookup
uniform float u_mip_scale;   // exp2(u_mip_bias)
uniform vec3 u_eye;
#ifdef ALPHA_LOD_CLAMP
// The material's alpha LOD clamp (docs/hashed-alpha.md "Alpha LOD clamp"): the alpha test reads
// alpha at most at this mip level; ALPHA_LOD_OFF (< 0) for the pass's materials without one.
uniform float u_alpha_lod_max;
#endif

// What shading reads of the surface at a point: attributes and their change per pixel step, the
// pixel and depth the stochastic test hashes. `coarse`: VRS's coarse pixel's (common/vrs_shade.glsl;
// textureGrad with these derivatives); else the fragment's own (the implicit-derivative lookups).
struct shade_in {
    vec2 uv, duv_dx, duv_dy;
    vec4 color;
    vec3 normal, obj, dobj_dx, dobj_dy;
    uvec2 pixel;
    float depth;
    bool coarse;
};

// The fragment's own inputs (in uniform control flow: derivatives).
shade_in pixel_shade_in()
{
    return shade_in(v_uv, dFdx(v_uv), dFdy(v_uv), v_color, v_world_normal, v_object_pos, dFdx(v_object_pos),
                    dFdy(v_object_pos), uvec2(gl_FragCoord.xy), gl_FragCoord.z, false);
}
#ifdef VRS
#include "common/vrs_shade.glsl"
#endif

#ifdef COUNT_FRAGMENTS
// Covered fragments of each ring and pass (COUNT_FRAGMENTS_BINDING): helper invocations (the
// rest of a 2x2 quad or a 4x4 llvmpipe block) are not covered and do not count.
layout(std430, binding = COUNT_FRAGMENTS_BINDING) buffer fragment_counts { uint u_covered[]; };
uniform uint u_count_slot;
#ifdef VRS
layout(std430, binding = COUNT_COARSE_KEYS_BINDING) buffer coarse_keys { uint u_coarse_key[]; };
flat in uint g_count_key; // this primitive's, unique in the frame (forward_vrs.geom)
#endif

// Counts this fragment: covered, and shaded when it is the first of its primitive in its coarse
// pixel (VRS rate `rate`; without VRS every covered fragment is shaded). The first: the exchange
// finds another key in the coarse pixel's cell. Exact as long as the rasteriser hands over a
// primitive's fragments of one coarse pixel without another primitive's between them: llvmpipe
// draws each 64x64 tile's primitives in order, one at a time, and a coarse pixel (aligned from
// the top-left, like the tiles) never straddles two tiles; tests/cli/test_vrs_counts.sh checks
// the count against a brute-force CPU rasterisation.
void count_fragment(uint rate)
{
    if (gl_HelperInvocation)
        return;
    atomicAdd(u_covered[u_count_slot], 1u);
    bool shades = true;
#ifdef VRS
    ivec2 origin;
    vec2 centre;
    vrs_coarse_pixel(ivec2(gl_FragCoord.xy), rate, int(u_vrs_viewport.y), origin, centre);
    uint cell = uint(origin.y) * uint(u_vrs_viewport.x) + uint(origin.x);
    shades = atomicExchange(u_coarse_key[cell], g_count_key) != g_count_key;
#endif
    if (shades)
        atomicAdd(u_covered[COUNT_SHADED_OFFSET + u_count_slot], 1u);
}
#endif

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_coverage; // .r stored; .a drives blending of the coverage target
#ifdef OBJECT_MOTION
layout(location = 2) out vec4 o_motion;   // .xyz: world position last frame - now (0: still)
#endif

void main()
{
#ifdef VRS
    // This twin shades the tiles coarser than 1x1; the pass's own program draws the others, exactly
    // as without VRS (renderer_vrs.c scissors it to them).
    uint vrs_rate = vrs_rate_here();
    if (vrs_rate == 0u)
        discard;
#endif
#ifdef COUNT_FRAGMENTS
    // Before the alpha test: every fragment the primitive covers counts, kept or discarded.
#ifdef VRS
    count_fragment(vrs_rate);
#else
    count_fragment(0u);
#endif
#endif
#ifdef VRS
    shade_in s = vrs_shade_in(vrs_rate);
#else
    shade_in s = pixel_shade_in();
#endif
    vec4 tex = !u_has_base_tex ? vec4(1.0)
               : s.coarse      ? textureGrad(u_base_tex, s.uv, s.duv_dx * u_mip_scale, s.duv_dy * u_mip_scale)
                               : texture(u_base_tex, s.uv, u_mip_bias);
    float alpha = tex.a * u_base_color.a * s.color.a;
    vec3 albedo = tex.rgb / max(tex.a, PREMUL_ALPHA_EPS) * u_base_color.rgb * s.color.rgb;

#ifdef PASS_MASK
    // The mip level the trilinear lookup reads (mip bias included), for the hashed fade-in and mip
    // scaling (seed 000 §5.5.1, seed 002).
    float lod = 0.0;
#if ALPHA_MODE == ALPHA_MODE_ID_HASHED || ALPHA_MODE == ALPHA_MODE_ID_MIPSCALE || defined(A2C_SHARPEN)
    if (u_has_base_tex) {
#if ALPHA_MODE == ALPHA_MODE_ID_HASHED
        vec2 size = vec2(textureSize(u_base_tex, 0));
        // From the uv derivatives in one log2 (alpha_texture_fade_level, the GL spec's isotropic
        // lod; the sampler has no bias or anisotropic filtering of its own): cheaper than
        // textureQueryLod on llvmpipe.
        lod = alpha_texture_fade_level(s.duv_dx, s.duv_dy, size, u_mip_scale);
#else
        // The coarse pixel's level by the same isotropic rule (alpha_texture_fade_level).
        lod = s.coarse ? alpha_texture_fade_level(s.duv_dx, s.duv_dy, vec2(textureSize(u_base_tex, 0)), u_mip_scale)
                       : max(textureQueryLod(u_base_tex, s.uv).y + u_mip_bias, 0.0);
#endif
    }
#endif
#ifdef ALPHA_LOD_CLAMP
    // Where the lookup reads a level coarser than the clamp, alpha comes from the clamp's level
    // instead (colour keeps the whole chain): a card smaller than a coarse level's texel then keeps
    // its own alpha rather than the atlas's average around it. Mip scaling then scales by the
    // clamped level (the one alpha was read at); the hashed fade-in keeps the pixel footprint's
    // level: a pixel still spans 2^lod texels, of which the finer read is one point sample, and
    // only the full noise keeps its expectation the footprint's mean alpha. C twin: alpha_lod_clamp.
    if (u_has_base_tex) {
        float level = alpha_texture_fade_level(s.duv_dx, s.duv_dy, vec2(textureSize(u_base_tex, 0)), u_mip_scale);
        float read = alpha_lod_clamp(level, u_alpha_lod_max);
        if (read < level) {
            alpha = textureLod(u_base_tex, s.uv, read).a * u_base_color.a * s.color.a;
#if ALPHA_MODE != ALPHA_MODE_ID_HASHED
            lod = min(lod, read);
#endif
        }
    }
#endif
#ifdef A2C_SHARPEN
    // Seed 002 (Golus): keep the mips' density (alpha scaled up per level), then sharpen alpha to
    // one pixel around the cutoff so alpha-to-coverage draws crisp, antialiased edges instead of
    // a soft, banded blend.
    alpha *= 1.0 + lod * ALPHA_MIPSCALE_PER_LOD;
    float alpha_width = fwidth(alpha); // out of any branch: the quad's derivatives
#ifdef VRS
    // Across coarse pixels, as a GPU's derivatives under VRS: alpha one coarse pixel along x and
    // along y (the same lookups for every fragment of the coarse pixel, so still one shade), against
    // this one's; within a coarse pixel fwidth is 0, which would make every edge hard. The texture's
    // alpha only (the vertex colour's is taken as constant), unclamped by --alpha-lod-max on all
    // three lookups (docs/foveation.md).
    if (s.coarse && u_has_base_tex) {
        float k = u_base_color.a * s.color.a * (1.0 + lod * ALPHA_MIPSCALE_PER_LOD);
        vec2 gx = s.duv_dx * u_mip_scale, gy = s.duv_dy * u_mip_scale;
        float a0 = tex.a * k;
        alpha_width = abs(textureGrad(u_base_tex, s.uv + s.duv_dx, gx, gy).a * k - a0) +
                      abs(textureGrad(u_base_tex, s.uv + s.duv_dy, gx, gy).a * k - a0);
    }
#endif
    alpha = clamp((alpha - u_alpha_cutoff) / max(alpha_width, 1e-4) + 0.5, 0.0, 1.0);
#endif
    if (!alpha_test_at(alpha, u_alpha_cutoff, s.obj, s.dobj_dx, s.dobj_dy, lod, s.pixel, s.depth))
        discard;
#endif

    vec3 n = normalize(s.normal);
    if (u_double_sided && !gl_FrontFacing)
        n = -n;
    vec3 rgb = shade_lambert(albedo, n);
#ifdef OBJECT_MOTION
    o_motion = vec4(v_motion, 0.0); // the blend pass leaves it unwritten (colour mask)
#endif

#if defined(PASS_SOLID)
    // Depth only (colour is masked off): the fragments a stochastic test always keeps.
    if (!(alpha >= 1.0))
        discard;
    o_color = vec4(0.0);
    o_coverage = vec4(0.0);
#elif defined(PASS_LIST)
    // What a stochastic test keeps with probability alpha (MASK) or blends by alpha (BLEND): the
    // expectation of both is the front-to-back composite of these fragments.
    float a = min(alpha, 1.0);
    if (a > 0.0)
        abuffer_append(rgb * a, a, gl_FragCoord.z, u_draw_order + v_instance, v_primitive);
    o_color = vec4(0.0); // colour writes are masked off in this pass
    o_coverage = vec4(0.0);
#elif defined(PASS_BLEND)
    o_color = vec4(rgb * alpha, alpha);
    o_coverage = vec4(alpha, 0.0, 0.0, alpha);
#elif defined(PASS_MASK) && ALPHA_MODE == ALPHA_MODE_ID_A2C
    // Alpha-to-coverage turns alpha into a sample mask; GL_SAMPLE_ALPHA_TO_ONE then stores 1.
    o_color = vec4(rgb, alpha);
    o_coverage = vec4(1.0, 0.0, 0.0, alpha);
#elif defined(PASS_MASK)
    o_color = vec4(rgb, 1.0);
    o_coverage = vec4(1.0, 0.0, 0.0, 1.0);
#else
    o_color = vec4(rgb, 1.0);
    o_coverage = vec4(0.0, 0.0, 0.0, 1.0);
#endif
}
