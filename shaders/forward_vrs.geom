// forward_vrs.geom: VRS foveation's coarse shading (docs/foveation.md "Variable-rate shading:
// coarse shading"), the VRS twin of a forward pass, which draws the tiles coarser than 1x1 (the
// pass's own program, without this stage, draws the 1x1 tiles: with a geometry shader llvmpipe
// places vertices with other rounding). Each triangle passes through unchanged, and every
// fragment also gets, flat, the triangle's three vertices' shading attributes and
// its 2D homogeneous edge functions: forward.frag evaluates the attributes at its coarse pixel's
// centre from those, so all fragments of the triangle in one coarse pixel compute the same inputs
// bit for bit (their own interpolants would differ in rounding, and extrapolate).
#include "common/shared_defs.h"
#include "common/draw_order.glsl"

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

in vec3 v_world_pos[];
in vec3 v_world_normal[];
in vec3 v_object_pos[];
in vec2 v_uv[];
in vec4 v_color[];
out vec3 g_world_pos;
out vec3 g_world_normal;
out vec3 g_object_pos;
out vec2 g_uv;
out vec4 g_color;
#ifdef OBJECT_MOTION
in vec3 v_motion[];
out vec3 g_motion;
#endif
#ifdef FORWARD_DRAW_ORDER
flat in uint v_instance[];
flat in uint v_primitive[];
flat out uint g_instance;
flat out uint g_primitive;
#endif
#ifdef FORWARD_HASH_LAYER
flat in uint v_hash_instance[];
flat in uint v_hash_triangle[];
flat out uint g_hash_instance;
flat out uint g_hash_triangle;
#endif

// The triangle, the same for all its fragments. Edge function i of vertex i (clip x, y, w as the
// 3-vector c_i): E_0 = c_1 x c_2, E_1 = c_2 x c_0, E_2 = c_0 x c_1; at the NDC point q = (x, y, 1),
// e_i = q . E_i is proportional to vertex i's perspective-correct barycentric weight (Olano and
// Greer's 2D homogeneous rasterisation), whatever the triangle's winding or w's sign.
flat out vec3 g_tri_edge[3];
flat out vec2 g_tri_uv[3];
flat out vec4 g_tri_color[3];
flat out vec3 g_tri_normal[3];
flat out vec3 g_tri_obj[3];
flat out vec2 g_tri_zw[3];   // clip z and w (the stochastic test hashes the coarse centre's depth)
#ifdef COUNT_FRAGMENTS
// The counting variant: each primitive's key, unique in the frame (count_fragment in forward.frag).
// Clipping comes after this stage, so the pieces of a clipped triangle share their key and count
// once per coarse pixel, as the one primitive a GPU shades.
layout(std430, binding = COUNT_FRAGMENTS_BINDING) buffer fragment_counts { uint u_covered[]; };
flat out uint g_count_key;
#endif

void main()
{
    vec3 c0 = gl_in[0].gl_Position.xyw, c1 = gl_in[1].gl_Position.xyw, c2 = gl_in[2].gl_Position.xyw;
    vec3 e0 = cross(c1, c2), e1 = cross(c2, c0), e2 = cross(c0, c1);
#ifdef COUNT_FRAGMENTS
    uint key = atomicAdd(u_covered[COUNT_KEY_SEQUENCE], 1u) + 1u; // 0: a cell no primitive shaded yet
#endif
    for (int i = 0; i < 3; i++) {
#ifdef COUNT_FRAGMENTS
        g_count_key = key;
#endif
        g_tri_edge[0] = e0;
        g_tri_edge[1] = e1;
        g_tri_edge[2] = e2;
        for (int k = 0; k < 3; k++) {
            g_tri_uv[k] = v_uv[k];
            g_tri_color[k] = v_color[k];
            g_tri_normal[k] = v_world_normal[k];
            g_tri_obj[k] = v_object_pos[k];
            g_tri_zw[k] = gl_in[k].gl_Position.zw;
        }
        g_world_pos = v_world_pos[i];
        g_world_normal = v_world_normal[i];
        g_object_pos = v_object_pos[i];
        g_uv = v_uv[i];
        g_color = v_color[i];
#ifdef OBJECT_MOTION
        g_motion = v_motion[i];
#endif
#ifdef FORWARD_DRAW_ORDER
        g_instance = v_instance[i];
        g_primitive = v_primitive[i];
#endif
#ifdef FORWARD_HASH_LAYER
        g_hash_instance = v_hash_instance[i];
        g_hash_triangle = v_hash_triangle[i];
#endif
        gl_Position = gl_in[i].gl_Position;
        EmitVertex();
    }
    EndPrimitive();
}
