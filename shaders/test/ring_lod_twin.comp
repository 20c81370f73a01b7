// ring_lod_twin.comp: evaluates every function of common/ring_lod.glsl on a buffer of inputs, for
// tests/gpu/test_ring_lod_twin.c, which compares each result with the C twin
// (src/fov/ring_lod.c). Used only by that test. The structs match twin_in / twin_out of the test
// (std430, vec4 / uvec4 fields).
#include "common/ring_lod.glsl"

layout(local_size_x = 64) in;

struct twin_in {
    vec4 card; // centre xyz, rank w (a card rank, RING_LOD_RANK_KEEP or a value at a ramp edge)
    vec4 p;    // vertex position xyz; w: a card side in ring pixels for ring_lod_card_u
    vec4 law;  // a, k, gain (ring_lod_law_for); w: a u for ring_lod_law_for
    uvec4 key; // x: instance key
};

struct twin_out {
    vec4 o0;  // ring_lod_weight(card.w, law), ring_lod_scale(card.w, law), ring_lod_rank(card.w, key.x),
              // ring_lod_weight(ring_lod_rank(card.w, key.x), law)
    vec4 o1;  // ring_lod_apply(p, card, law), 0
    vec4 o2;  // ring_lod_apply(p, vec4(card.xyz, ring_lod_rank(card.w, key.x)), law), 0
    uvec4 o3; // ring_lod_instance_offset(key.x), floatBitsToUint(ring_lod_rank(card.w, key.x)), 0, 0
    vec4 o4;  // ring_lod_law_for(law.w), ring_lod_card_u(p.w)
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
    vec3 law = p.law.xyz;
    float rr = ring_lod_rank(p.card.w, p.key.x);
    r.o0 = vec4(ring_lod_weight(p.card.w, law), ring_lod_scale(p.card.w, law), rr, ring_lod_weight(rr, law));
    r.o1 = vec4(ring_lod_apply(p.p.xyz, p.card, law), 0.0);
    r.o2 = vec4(ring_lod_apply(p.p.xyz, vec4(p.card.xyz, rr), law), 0.0);
    r.o3 = uvec4(ring_lod_instance_offset(p.key.x), floatBitsToUint(rr), 0u, 0u);
    r.o4 = vec4(ring_lod_law_for(p.law.w), ring_lod_card_u(p.p.w));
    tout[i] = r;
}
