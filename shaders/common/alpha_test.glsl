// alpha_test.glsl: the one alpha test of fovsim (one function, so no pass can test differently: docs/design.md "Conventions").
// The strategy comes from the plan as ALPHA_MODE (an ALPHA_MODE_ID_* value from shared_defs.h).
// The threshold math lives in alpha_hash.glsl, whose C twin is src/passes/alpha_hash.c.
#ifndef ALPHA_MODE
#error "alpha_test.glsl needs ALPHA_MODE (set by the plan)"
#endif
#include "common/alpha_hash.glsl"

uniform float u_hash_scale;  // noise scale in pixels (seed 000 §5.4.1)
uniform int u_hash_kind;     // ALPHA_HASH_*
uniform bool u_hash_aniso;   // anisotropic hash
uniform float u_fade_n;      // fade-in length in mip levels; <= 0: no fade
uniform uint u_frame;        // frame index: stochastic thresholds change every frame

// True when a fragment of opacity `alpha` survives the test. `obj` is the object-space position
// (anchored to the whole instance) and dx, dy its change per pixel step along x and y, `lod` the
// mip level the trilinear lookup reads (bias included, >= 0), `pixel` and `depth` the pixel and
// window depth the stochastic test hashes. alpha_test below passes the fragment's own; VRS's coarse
// shading (forward.frag) passes its coarse pixel's, so the whole coarse pixel decides once.
// HASHED_A2C also writes gl_SampleMask; A2C leaves coverage to GL_SAMPLE_ALPHA_TO_COVERAGE.
bool alpha_test_at(float alpha, float cutoff, vec3 obj, vec3 dx, vec3 dy, float lod, uvec2 pixel, float depth)
{
#if ALPHA_MODE == ALPHA_MODE_ID_TRADITIONAL || ALPHA_MODE == ALPHA_MODE_ID_CASTANO
    // glTF MASK: "rendered fully opaque if alpha >= alphaCutoff". Castano differs only in its
    // texture (coverage-preserving mips).
    return alpha >= cutoff;
#elif ALPHA_MODE == ALPHA_MODE_ID_STOCHASTIC
    if (alpha <= 0.0 || alpha >= 1.0)
        return alpha >= 1.0; /* as any threshold in (0, 1] would decide */
    // Independent per fragment, not just per pixel: overlapping layers at one pixel must not share
    // a threshold (that would correlate them like a fixed dither). The salt mixes the primitive, the
    // fragment's depth bits and its draw order (common/draw_order.glsl): coplanar cards of other
    // draws or instances share the first two, and would otherwise pass and fail together.
    uint salt = v_primitive * 0x9E3779B9u ^ floatBitsToUint(depth) ^ (u_draw_order + v_instance) * 0x85EBCA6Bu;
    return alpha >= alpha_stochastic_threshold(pixel.x, pixel.y, u_frame, salt);
#elif ALPHA_MODE == ALPHA_MODE_ID_HASHED
    // The caller took the derivatives (in uniform control flow); skip the hash where no threshold can change
    // the answer: thresholds lie in (0, 1], so alpha 0 never passes and alpha 1 always does. Most
    // texels of foliage at fine mips are exactly 0 or 1, and whole SIMD groups skip the hashing.
    // Where the fade-in has not started (b = 0: magnified or mip-0 texels), alpha_hashed_fade
    // returns the cutoff whatever the hash: the traditional test, without hashing. One branch for
    // the three cases: llvmpipe
    // evaluates both sides anyway, and one branch costs it less mask bookkeeping than three returns.
    if (alpha <= 0.0 || alpha >= 1.0 || (u_fade_n > 0.0 && lod <= 0.0))
        return alpha >= 1.0 || (alpha > 0.0 && alpha >= max(cutoff, float(ALPHA_THRESHOLD_MIN)));
    // Each instance and triangle hashes its own lattice (docs/hashed-alpha.md, "Layers"): far away,
    // one noise cell holds many overlapping leaves, which would otherwise share one threshold.
    uint layer = alpha_hash_layer(v_hash_instance, v_hash_triangle);
    float t = alpha_hashed_threshold_layer(obj, dx, dy, u_hash_scale, u_hash_kind, u_hash_aniso, layer);
#ifdef TAA_HASH_OFFSET
    t = alpha_hashed_frame_offset(t, u_frame);
#endif
    return alpha >= alpha_hashed_fade(cutoff, t, lod, u_fade_n);
#elif ALPHA_MODE == ALPHA_MODE_ID_MIPSCALE
    // Seed 002: scale alpha up with the mip level so coarse mips keep their coverage.
    return alpha * (1.0 + max(lod, 0.0) * ALPHA_MIPSCALE_PER_LOD) >= cutoff;
#elif ALPHA_MODE == ALPHA_MODE_ID_A2C
    return alpha > 0.0;
#elif ALPHA_MODE == ALPHA_MODE_ID_HASHED_A2C
    // Seed 000 §6: per-sample thresholds with a hashed offset and odd increment. One hashed value
    // per fragment gives chi; xi1 and xi2 are derived from it (fract of multiples of a uniform
    // variable are uniform), so layers with different hashes get decorrelated masks.
    uint layer = alpha_hash_layer(v_hash_instance, v_hash_triangle);
    float t = alpha_hashed_threshold_layer(obj, dx, dy, u_hash_scale, u_hash_kind, u_hash_aniso, layer);
#ifdef TAA_HASH_OFFSET
    t = alpha_hashed_frame_offset(t, u_frame);
#endif
    uint m = alpha_hashed_a2c_mask(alpha, MSAA_SAMPLES, fract(t * 7.0), fract(t * 13.0), t);
    gl_SampleMask[0] = int(m);
    return m != 0u;
#else
#error "unknown ALPHA_MODE"
#endif
}

// The test of this fragment: its own object-space derivatives, pixel and depth. Must be called in
// uniform control flow (derivatives).
bool alpha_test(float alpha, float cutoff, vec3 obj, float lod)
{
    return alpha_test_at(alpha, cutoff, obj, dFdx(obj), dFdy(obj), lod, uvec2(gl_FragCoord.xy), gl_FragCoord.z);
}
