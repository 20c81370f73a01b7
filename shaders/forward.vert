// forward.vert: one vertex of an instanced primitive. Object space = asset space (the whole tree),
// which hashed alpha anchors to (seed 000 §5).
#include "common/shared_defs.h"
#ifdef SWAY
#include "common/sway.glsl"
#endif
#ifdef RING_LOD
#include "common/ring_lod.glsl"
#endif

layout(location = ATTR_POSITION) in vec3 a_position;
layout(location = ATTR_NORMAL) in vec3 a_normal;
layout(location = ATTR_UV) in vec2 a_uv;
layout(location = ATTR_COLOR) in vec4 a_color;
layout(location = ATTR_INSTANCE) in mat4 a_model; // slots ATTR_INSTANCE .. +3, one per instance

uniform mat4 u_view_proj;

#ifdef SWAY
// Wind sway (common/sway.glsl): per instance, (offset, height) and (frequency, phase).
layout(location = ATTR_SWAY) in vec4 a_sway;
layout(location = ATTR_SWAY_WAVE) in vec2 a_sway_wave;
uniform float u_time;       // this frame, seconds
#ifdef OBJECT_MOTION
uniform float u_prev_time;  // the frame TAA's history is from (u_time when there is none)
out vec3 v_motion;          // world position last frame - world position now
#endif
#endif

#ifdef RING_LOD
// Ring LOD (common/ring_lod.glsl, docs/ring-lod.md): per vertex its card's centre and rank; per ring
// the law (a, k, gain); per draw the scene slot of its first instance (the rank rotation's key).
layout(location = ATTR_CARD) in vec4 a_card;
layout(location = ATTR_CARD_SIDE) in float a_card_side; // sqrt(card area), asset units
uniform vec3 u_ring_lod;
uniform uint u_ring_lod_instance;
uniform float u_ring_lod_px; // per-card schedule: the ring's pixels per unit at distance 1; 0: u_ring_lod
uniform vec3 u_eye;
#endif

out vec3 v_world_pos;
out vec3 v_world_normal;
out vec3 v_object_pos;
out vec2 v_uv;
out vec4 v_color;
#include "common/draw_order.glsl"
#ifdef FORWARD_TRIANGLE
// The triangle this vertex provokes: (in the asset, in the primitive = gl_PrimitiveID)
layout(location = ATTR_TRIANGLE) in uvec2 a_triangle;
#endif
#ifdef FORWARD_DRAW_ORDER
flat out uint v_instance;   // the instance within its draw (common/draw_order.glsl)
flat out uint v_primitive;  // the triangle within its primitive (common/draw_order.glsl)
#endif
#ifdef FORWARD_HASH_LAYER
uniform uint u_hash_instance; // the scene slot of the draw's first instance (common/draw_order.glsl)
flat out uint v_hash_instance;
flat out uint v_hash_triangle;
#endif

void main()
{
    vec3 pos = a_position;
#ifdef RING_LOD
    // Kept cards grow about their centres, leaving ones shrink to their centre (no area): exactly
    // a_position where the ring's law is the identity (u = 1) or the card is never simplified.
    vec3 law = u_ring_lod;
    if (u_ring_lod_px > 0.0) {
        // The card's side in this ring's pixels: instances scale it by their transform (the cube
        // root of its volume change), distance shrinks it.
        mat3 m3 = mat3(a_model);
        float side = a_card_side * pow(abs(determinant(m3)), 1.0 / 3.0);
        float d = max(distance((a_model * vec4(a_card.xyz, 1.0)).xyz, u_eye), 1e-6);
        law = ring_lod_law_for(ring_lod_card_u(side * u_ring_lod_px / d));
    }
    pos = ring_lod_apply(pos, vec4(a_card.xyz, ring_lod_rank(a_card.w, u_ring_lod_instance + uint(gl_InstanceID))),
                         law);
#endif
    vec4 world = a_model * vec4(pos, 1.0);
#ifdef SWAY
    // The displacement is added in world space (the wind has one direction for every instance)
    // and depends on the asset-space height, so trunk and leaves bend together.
    world.xyz += sway_displacement(a_sway, a_sway_wave, pos.y, u_time) * world.w;
#ifdef OBJECT_MOTION
    v_motion = sway_motion(a_sway, a_sway_wave, pos.y, u_time, u_prev_time);
#endif
#endif
    v_world_pos = world.xyz;
    // Normals transform by the inverse transpose of the model matrix, which is the cofactor matrix
    // divided by the determinant: three cross products instead of a 3x3 inverse per vertex, and the
    // determinant's sign keeps mirrored instances' normals pointing out (the length is normalised
    // in the fragment shader).
    mat3 m = mat3(a_model);
    mat3 cof = mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
    v_world_normal = cof * a_normal * sign(determinant(m));
    v_object_pos = pos;
    v_uv = a_uv;
    v_color = a_color;
#ifdef FORWARD_DRAW_ORDER
    v_instance = uint(gl_InstanceID);
    v_primitive = a_triangle.y;
#endif
#ifdef FORWARD_HASH_LAYER
    v_hash_instance = u_hash_instance + uint(gl_InstanceID);
    v_hash_triangle = a_triangle.x;
#endif
    gl_Position = u_view_proj * world;
}
