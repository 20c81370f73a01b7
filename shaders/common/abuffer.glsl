// abuffer.glsl: the exact reference's list pass (docs/reference.md, "Exact"): every MASK and BLEND
// fragment of opacity > 0 in front of the nearest opaque surface is appended to its pixel's list.
// The resolve (sort front to back, composite over the opaque colour) is the C function
// abuffer_resolve (src/passes/abuffer.c), which reads these lists back; the layout and the
// constants are in shared_defs.h. Needs `layout(early_fragment_tests) in;` in the shader: the depth
// test against the opaque surfaces must run before the stores, not after.

layout(binding = ABUFFER_IMAGE_HEAD, r32ui) uniform coherent uimage2D u_list_head;
layout(binding = ABUFFER_IMAGE_SOLID, r32ui) uniform coherent uimage2D u_list_solid;
layout(binding = ABUFFER_IMAGE_NODES, rgba32ui) uniform writeonly uimageBuffer u_list_nodes;
layout(binding = 0, offset = 0) uniform atomic_uint u_list_counter;
uniform uint u_list_capacity; // nodes the store holds

// Appends one fragment: premultiplied colour, alpha in (0, 1], window depth, draw order (the
// instance's place in the API order of draws) and primitive.
void abuffer_append(vec3 premul, float alpha, float depth, uint order, uint prim)
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    uint z = floatBitsToUint(depth); // depth >= 0: the bits order as the values do
    // Fragments behind an alpha-1 fragment this pixel has already seen contribute nothing: the
    // solid image keeps the nearest such depth (a filter that saves memory; which fragments it
    // catches depends on arrival order, the result does not).
    uint solid = alpha >= 1.0 ? imageAtomicMin(u_list_solid, p, z) : imageLoad(u_list_solid, p).r;
    if (z > solid)
        return;
    uint idx = atomicCounterIncrement(u_list_counter);
    if (idx >= u_list_capacity) {
        // Full: every later allocation fails too (the counter only grows). Mark the pixel; a
        // fragment stored concurrently carries the mark on in its `next`.
        imageAtomicOr(u_list_head, p, ABUFFER_OVERFLOW_BIT);
        return;
    }
    uint next = imageAtomicExchange(u_list_head, p, idx);
    int t = int(idx) * ABUFFER_NODE_TEXELS;
    imageStore(u_list_nodes, t, uvec4(next, z, order, prim));
    imageStore(u_list_nodes, t + 1, uvec4(floatBitsToUint(premul), floatBitsToUint(alpha)));
}
