// list_resolve.frag: the exact reference's resolve (docs/reference.md, "Exact"): each pixel's
// fragment list (written by the list pass, common/abuffer.glsl) sorted front to back and composited
// over the opaque pass's colour. The C twin is abuffer_composite (src/passes/abuffer.c): same
// order (depth, then draw order, then primitive), same compositing. A list longer than
// ABUFFER_RESOLVE_MAX is left to the C twin, and a list that lost fragments (the store was full) to
// the stochastic fallback: the flag output says which.
#include "common/shared_defs.h"

layout(binding = 0) uniform usampler2D u_head;        // first node of each pixel's list
layout(binding = 1) uniform usamplerBuffer u_nodes;   // ABUFFER_NODE_TEXELS texels per node
layout(binding = 2) uniform sampler2DArray u_base_color;    // the opaque pass (layer 0)
layout(binding = 3) uniform sampler2DArray u_base_coverage;
layout(std430, binding = ABUFFER_COUNTER_BINDING) readonly buffer abuffer_counter {
    uint u_list_count; // nodes the list pass asked for
};
uniform uint u_capacity;                              // nodes the store holds

// Equal depths: whether node a comes before node b (draw order, then primitive).
bool abuffer_tie_before(uint a, uint b)
{
    uvec2 ka = texelFetch(u_nodes, int(a) * ABUFFER_NODE_TEXELS).zw, kb = texelFetch(u_nodes, int(b) * ABUFFER_NODE_TEXELS).zw;
    return ka.x != kb.x ? ka.x < kb.x : ka.y < kb.y;
}

layout(location = 0) out vec4 o_color;    // premultiplied colour, A
layout(location = 1) out vec4 o_coverage; // .r coverage, .g ABUFFER_FLAG_*

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    uint stored = min(u_list_count, u_capacity);
    vec4 base = texelFetch(u_base_color, ivec3(p, 0), 0);
    float base_cov = texelFetch(u_base_coverage, ivec3(p, 0), 0).r;
    float depth[ABUFFER_RESOLVE_MAX];
    uint node[ABUFFER_RESOLVE_MAX];
    int n = 0;
    float flag = ABUFFER_FLAG_DONE;
    uint ptr = texelFetch(u_head, p, 0).r;
    for (uint steps = 0u; steps <= stored; steps++) {
        if ((ptr & ABUFFER_OVERFLOW_BIT) != 0u)
            flag = ABUFFER_FLAG_OVERFLOW;
        ptr &= ~ABUFFER_OVERFLOW_BIT;
        if (ptr == ABUFFER_END)
            break;
        if (ptr >= stored) { // a node that was never written
            flag = ABUFFER_FLAG_OVERFLOW;
            break;
        }
        if (n == ABUFFER_RESOLVE_MAX) { // too long for this pass: the C twin resolves it
            flag = max(flag, ABUFFER_FLAG_LONG);
            break;
        }
        uvec4 a = texelFetch(u_nodes, int(ptr) * ABUFFER_NODE_TEXELS);
        depth[n] = uintBitsToFloat(a.y);
        node[n] = ptr;
        n++;
        ptr = a.x;
    }
    // Insertion sort, front to back: depth, then draw order, then primitive (fetched from the
    // nodes only on equal depths, which are rare: two arrays instead of four).
    for (int i = 1; i < n; i++) {
        float d = depth[i];
        uint k = node[i];
        int j = i;
        while (j > 0 && (d < depth[j - 1] || (d == depth[j - 1] && abuffer_tie_before(k, node[j - 1])))) {
            depth[j] = depth[j - 1];
            node[j] = node[j - 1];
            j--;
        }
        depth[j] = d;
        node[j] = k;
    }
    // Front-to-back "over" (abuffer_composite): alpha 0, NaN or a non-finite colour hides nothing.
    vec3 c = vec3(0.0);
    float alpha = 0.0, t = 1.0;
    for (int i = 0; i < n && t > 0.0; i++) {
        uvec4 b = texelFetch(u_nodes, int(node[i]) * ABUFFER_NODE_TEXELS + 1);
        vec3 rgb = uintBitsToFloat(b.xyz);
        float al = uintBitsToFloat(b.w);
        if (!(al > 0.0) || any(isnan(rgb)) || any(isinf(rgb)))
            continue;
        al = min(al, 1.0);
        c += t * rgb;
        alpha += t * al;
        t *= 1.0 - al;
    }
    o_color = vec4(c + t * base.rgb, alpha + t * base.a);
    o_coverage = vec4(alpha + t * base_cov, flag, 0.0, 0.0);
}
