// abuffer.glsl: the exact reference's list pass (docs/reference.md, "Exact"): every MASK and BLEND
// fragment of opacity > 0 in front of the nearest opaque surface (or alpha-1 MASK fragment, drawn
// into the depth buffer by the solid pass, pushed back so that it is stored too) is appended to its
// pixel's list. The resolve (sort front to back, composite over the opaque colour) is
// shaders/list_resolve.frag, with the C twin abuffer_resolve (src/passes/abuffer.c); the layout and
// the constants are in shared_defs.h. Needs `layout(early_fragment_tests) in;` in the shader: the
// depth test must run before the stores, not after.

layout(binding = ABUFFER_IMAGE_HEAD, r32ui) uniform coherent uimage2D u_list_head;
layout(binding = ABUFFER_IMAGE_NODES, rgba32ui) uniform writeonly uimageBuffer u_list_nodes;
layout(std430, binding = ABUFFER_COUNTER_BINDING) coherent buffer abuffer_counter {
    uint u_list_count; // nodes asked for so far (may pass the capacity: then some were lost)
};
uniform uint u_list_capacity; // nodes the store holds

// A node index of the store, unique to this invocation. Where subgroup ballots are available, one
// invocation asks the counter for the whole subgroup's nodes and each takes its own from them:
// one atomic per subgroup instead of one per fragment (on llvmpipe the per-fragment counter was a
// third of the list pass). Helper invocations take no part (they have no side effects).
uint abuffer_alloc()
{
#if defined(GL_ARB_shader_ballot) && defined(GL_ARB_gpu_shader_int64)
    uint64_t mask = ballotARB(!gl_HelperInvocation);
    uvec2 m = unpackUint2x32(mask);
    uint lead = m.x != 0u ? uint(findLSB(m.x)) : 32u + uint(findLSB(m.y));
    uint base = 0u;
    if (gl_SubGroupInvocationARB == lead)
        base = atomicAdd(u_list_count, uint(bitCount(m.x) + bitCount(m.y)));
    base = readInvocationARB(base, lead);
    uvec2 lt = unpackUint2x32(mask & gl_SubGroupLtMaskARB);
    return base + uint(bitCount(lt.x) + bitCount(lt.y));
#else
    return atomicAdd(u_list_count, 1u);
#endif
}

// Appends one fragment: premultiplied colour, alpha in (0, 1], window depth, draw order (the
// instance's place in the API order of draws) and primitive.
void abuffer_append(vec3 premul, float alpha, float depth, uint order, uint prim)
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    uint idx = abuffer_alloc();
    if (idx >= u_list_capacity) {
        // Full: every later allocation fails too (the counter only grows). Mark the pixel; a
        // fragment stored concurrently carries the mark on in its `next`.
        imageAtomicOr(u_list_head, p, ABUFFER_OVERFLOW_BIT);
        return;
    }
    uint next = imageAtomicExchange(u_list_head, p, idx);
    int t = int(idx) * ABUFFER_NODE_TEXELS;
    imageStore(u_list_nodes, t, uvec4(next, floatBitsToUint(depth), order, prim));
    imageStore(u_list_nodes, t + 1, uvec4(floatBitsToUint(premul), floatBitsToUint(alpha)));
}
