// taa_twin.comp: evaluates every function of common/taa.glsl (and of common/sway.glsl, the
// per-object motion TAA follows) on a buffer of inputs, for
// tests/gpu/test_taa_twin.c, which compares each result with the C twin (src/passes/taa_math.c).
// Used only by that test. The structs match twin_in / twin_out of the test (std430, vec4 / mat4
// fields, mat4 column-major as the C float[16]).
#include "common/sway.glsl"
#include "common/taa.glsl"

layout(local_size_x = 64) in;

struct twin_in {
    vec4 a;    // xyz: colour / history (clip) / current (resolve) / ycocg; w: sanitize input
    vec4 b;    // xyz: clip mean / resolve history; w: blend
    vec4 c;    // xyz: clip sigma; w: gamma
    vec4 d;    // xyz: reproject ndc; w: catmull-rom frac
    uvec4 u;   // halton index, halton base, jitter frame, jitter length
    uvec4 v;   // x: resolve history_valid
    mat4 inv;  // reproject: inverse jittered view-projection
    mat4 prev; // reproject: previous view-projection
    vec4 e;    // xyz: per-object motion (reproject_moving); w: sway t_prev
    vec4 f;    // sway: frequency, phase, y, t
    vec4 g;    // sway: offset xyz, height
    vec4 nb[TAA_MAX_TAPS]; // neighbourhood taps (RGBA); nb[0..4]: history taps
    vec4 nbcov[3];         // neighbourhood coverages, 9 of 12
    vec4 hw[2];            // history tap weights, 5 of 8
    vec4 h;                // catmull-rom taps: position xy, footprint size zw
    uvec4 w;               // x: neighbourhood n, y: per_tap (neighbourhood and history), z: history n
};

struct twin_out {
    vec4 o0;   // taa_halton, taa_jitter.xy, taa_sanitize(a.w)
    vec4 o1;   // taa_rgb_to_ycocg(a.xyz), taa_sanitize_color(a.xyz).x
    vec4 o2;   // taa_ycocg_to_rgb(a.xyz), 0
    vec4 o3;   // taa_clip_to_box(a, b, c, c.w, d.w), 0
    vec4 o4;   // taa_catmull_rom_weights(d.w)
    vec4 o5;   // taa_resolve(a, b, v.x != 0, b.w), 0
    vec4 o6;   // taa_reproject(d.xyz, inv, prev), valid ? 1 : 0
    vec4 o7;   // taa_resolve4(a, vec4(b.xyz, c.w), v.x != 0, b.w)
    vec4 o8;   // taa_sanitize4(a)
    vec4 o9;   // taa_resolve(a.w, c.w, v.x != 0, b.w) (one channel), taa_sparse_coverage(d.w, a.w, c.x, c.y, c.z)
               // and its margin, taa_sparse_coverage(d.w, c.x, c.x, c.x, TAA_SPARSE_SLACK)
    vec4 o10;  // taa_reproject_moving(d.xyz, e.xyz, inv, prev), valid ? 1 : 0
    vec4 o11;  // sway_motion(g, f.xy, f.z, f.w, e.w), sway_wave(f.x, f.y, f.w)
    vec4 o12;  // sway_displacement(g, f.xy, f.z, f.w), sway_weight(f.z, g.w)
    vec4 o13;  // taa_neighbourhood(nb, nbcov, w.x, w.y != 0): mean, alpha.x
    vec4 o14;  //   sigma, alpha.y
    vec4 o15;  //   coverage.xy, 0, 0
    vec4 o16;  // taa_catmull_rom_taps(h.xy, h.zw): taps 0, 1 (x, y)
    vec4 o17;  //   taps 2, 3 (x, y)
    vec4 o18;  //   tap 4 (x, y), weights 0, 1
    vec4 o19;  //   weights 2, 3, 4, 0
    vec4 o20;  // taa_history_sum(nb[0..4], hw, w.z, w.y != 0)
    vec4 o21;  // taa_history_surface_here(d.xyz, e.xyz, inv, prev, a.xy, h.zw, b.w, c.w): keep, 0, offset
    vec4 o22;  //   its result ? 1 : 0, 0, 0, 0
};

layout(std430, binding = 0) readonly buffer twin_inputs { twin_in tin[]; };
layout(std430, binding = 1) writeonly buffer twin_outputs { twin_out tout[]; };
uniform uint u_count;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count)
        return;
    twin_in p = tin[i];
    twin_out r;
    r.o0 = vec4(taa_halton(p.u.x, p.u.y), taa_jitter(p.u.z, p.u.w), taa_sanitize(p.a.w));
    r.o1 = vec4(taa_rgb_to_ycocg(p.a.xyz), taa_sanitize_color(p.a.xyz).x);
    r.o2 = vec4(taa_ycocg_to_rgb(p.a.xyz), 0.0);
    r.o3 = vec4(taa_clip_to_box(p.a.xyz, p.b.xyz, p.c.xyz, p.c.w, p.d.w), 0.0);
    r.o4 = taa_catmull_rom_weights(p.d.w);
    r.o5 = vec4(taa_resolve(p.a.xyz, p.b.xyz, p.v.x != 0u, p.b.w), 0.0);
    vec3 prev_ndc;
    bool valid = taa_reproject(p.d.xyz, p.inv, p.prev, prev_ndc);
    r.o6 = vec4(prev_ndc, valid ? 1.0 : 0.0);
    r.o7 = taa_resolve4(p.a, vec4(p.b.xyz, p.c.w), p.v.x != 0u, p.b.w);
    r.o8 = taa_sanitize4(p.a);
    float margin, unused;
    float sc = taa_sparse_coverage(p.d.w, p.a.w, p.c.x, p.c.y, p.c.z, margin);
    r.o9 = vec4(taa_resolve(p.a.w, p.c.w, p.v.x != 0u, p.b.w), sc, margin,
                taa_sparse_coverage(p.d.w, p.c.x, p.c.x, p.c.x, float(TAA_SPARSE_SLACK), unused));
    valid = taa_reproject_moving(p.d.xyz, p.e.xyz, p.inv, p.prev, prev_ndc);
    r.o10 = vec4(prev_ndc, valid ? 1.0 : 0.0);
    r.o11 = vec4(sway_motion(p.g, p.f.xy, p.f.z, p.f.w, p.e.w), sway_wave(p.f.x, p.f.y, p.f.w));
    r.o12 = vec4(sway_displacement(p.g, p.f.xy, p.f.z, p.f.w), sway_weight(p.f.z, p.g.w));
    vec4 taps[TAA_MAX_TAPS];
    float cov[TAA_MAX_TAPS];
    for (int k = 0; k < TAA_MAX_TAPS; k++) {
        taps[k] = p.nb[k];
        cov[k] = p.nbcov[k / 4][k % 4];
    }
    taa_box b = taa_neighbourhood(taps, cov, int(p.w.x), p.w.y != 0u);
    r.o13 = vec4(b.mean, b.alpha.x);
    r.o14 = vec4(b.sigma, b.alpha.y);
    r.o15 = vec4(b.coverage, 0.0, 0.0);
    vec3 ct[5];
    taa_catmull_rom_taps(p.h.xy, p.h.zw, ct);
    r.o16 = vec4(ct[0].xy, ct[1].xy);
    r.o17 = vec4(ct[2].xy, ct[3].xy);
    r.o18 = vec4(ct[4].xy, ct[0].z, ct[1].z);
    r.o19 = vec4(ct[2].z, ct[3].z, ct[4].z, 0.0);
    vec4 ht[5];
    float hw[5];
    for (int k = 0; k < 5; k++) {
        ht[k] = p.nb[k];
        hw[k] = p.hw[k / 4][k % 4];
    }
    r.o20 = taa_history_sum(ht, hw, int(p.w.z), p.w.y != 0u);
    float keep;
    vec2 offset;
    bool here = taa_history_surface_here(p.d.xyz, p.e.xyz, p.inv, p.prev, p.a.xy, p.h.zw, p.b.w, p.c.w, keep, offset);
    r.o21 = vec4(keep, 0.0, offset);
    r.o22 = vec4(here ? 1.0 : 0.0, 0.0, 0.0, 0.0);
    tout[i] = r;
}
