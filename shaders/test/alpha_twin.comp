// alpha_twin.comp: evaluates every function of common/alpha_hash.glsl on a buffer of inputs, for
// tests/gpu/test_alpha_twin.c, which compares each result with the C twin (src/passes/alpha_hash.c).
// Used only by that test. The structs match twin_in / twin_out of the test (std430, vec4 fields).
#include "common/alpha_hash.glsl"

layout(local_size_x = 64) in;

struct twin_in {
    vec4 obj;  // xyz object position, w hash_scale
    vec4 dx;   // xyz dFdx(obj)
    vec4 dy;   // xyz dFdy(obj)
    vec4 p0;   // fade: cutoff, lod, alpha LOD clamp, fade_n
    vec4 p1;   // lod: duv_dx.xy, duv_dy.xy
    vec4 p2;   // lod: tex_size.xy; a2c: xi1, xi2
    vec4 p3;   // a2c: alpha, chi; cdf: x, lerp_factor
    vec4 p4;   // fade: threshold; texture fade level: mip scale
    uvec4 u0;  // hash_kind, anisotropic, pixel_x, pixel_y
    uvec4 u1;  // frame, salt (also the hashed threshold's layer), a2c n, a2c sample index
};

struct twin_out {
    vec4 r0;   // alpha_hashed_threshold_layer(layer u1.y), alpha_hash_pcg(obj), alpha_hash_sine(obj),
               // alpha_stochastic_threshold
    vec4 r1;   // alpha_hashed_fade, alpha_texture_lod, alpha_texture_fade_level(p1.xy, p1.zw, p2.xy, p4.y),
               // alpha_hash_cdf
    vec4 r2;   // alpha_hash_log2_scale, alpha_hashed_a2c_threshold, alpha_hash_sine2(obj.xy), sin(obj.x)
    uvec4 r3;  // alpha_hashed_a2c_mask, alpha_hash_pcg3d(u0.zw, u1.x)
    vec4 r4;   // alpha_hashed_frame_offset(p4.x, u1.x), the high and low 16 bits of
               // alpha_hash_level_key(u1.x % 125 - 62) (exact as floats),
               // alpha_lod_clamp(texture fade level, p0.z)
    uvec4 r5;  // alpha_hash_layer(u0.z, u0.w), alpha_hash_pcg1(u1.x), the bits of
               // alpha_hash_pcg_cell(floor(obj), u1.y) and of alpha_hashed_threshold (no layer)
};

layout(std430, binding = 0) readonly buffer twin_inputs { twin_in tin[]; };
layout(std430, binding = 1) writeonly buffer twin_outputs { twin_out tout[]; };
uniform uint u_count;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count)
        return;
    twin_in a = tin[i];
    twin_out r;
    int kind = int(a.u0.x);
    bool aniso = a.u0.y != 0u;
    r.r0.x = alpha_hashed_threshold_layer(a.obj.xyz, a.dx.xyz, a.dy.xyz, a.obj.w, kind, aniso, a.u1.y);
    r.r0.y = alpha_hash_pcg(a.obj.xyz);
    r.r0.z = alpha_hash_sine(a.obj.xyz);
    r.r0.w = alpha_stochastic_threshold(a.u0.z, a.u0.w, a.u1.x, a.u1.y);
    r.r1.x = alpha_hashed_fade(a.p0.x, a.p4.x, a.p0.y, a.p0.w);
    r.r1.y = alpha_texture_lod(a.p1.xy, a.p1.zw, a.p2.xy);
    r.r1.z = alpha_texture_fade_level(a.p1.xy, a.p1.zw, a.p2.xy, a.p4.y);
    r.r1.w = alpha_hash_cdf(a.p3.z, a.p3.w);
    r.r2 = vec4(alpha_hash_log2_scale(a.dx.xyz, a.dy.xyz, a.obj.w),
                alpha_hashed_a2c_threshold(int(a.u1.w), int(a.u1.z), a.p2.z, a.p2.w, a.p3.y),
                alpha_hash_sine2(a.obj.xy), sin(a.obj.x));
    r.r3 = uvec4(alpha_hashed_a2c_mask(a.p3.x, int(a.u1.z), a.p2.z, a.p2.w, a.p3.y),
                 alpha_hash_pcg3d(uvec3(a.u0.z, a.u0.w, a.u1.x)));
    uint level_key = alpha_hash_level_key(int(a.u1.x % 125u) - 62);
    r.r4 = vec4(alpha_hashed_frame_offset(a.p4.x, a.u1.x), float(level_key >> 16u), float(level_key & 0xffffu),
                alpha_lod_clamp(r.r1.z, a.p0.z));
    vec3 cell = floor(vec3(alpha_hash_coord(a.obj.x), alpha_hash_coord(a.obj.y), alpha_hash_coord(a.obj.z)));
    r.r5 = uvec4(alpha_hash_layer(a.u0.z, a.u0.w), alpha_hash_pcg1(a.u1.x),
                 floatBitsToUint(alpha_hash_pcg_cell(cell, a.u1.y)),
                 floatBitsToUint(alpha_hashed_threshold(a.obj.xyz, a.dx.xyz, a.dy.xyz, a.obj.w, kind, aniso)));
    tout[i] = r;
}
