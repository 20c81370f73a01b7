// forward.vert: one vertex of an instanced primitive. Object space = asset space (the whole tree),
// which hashed alpha anchors to (seed 000 §5).
#include "common/shared_defs.h"

layout(location = ATTR_POSITION) in vec3 a_position;
layout(location = ATTR_NORMAL) in vec3 a_normal;
layout(location = ATTR_UV) in vec2 a_uv;
layout(location = ATTR_COLOR) in vec4 a_color;
layout(location = ATTR_INSTANCE) in mat4 a_model; // slots ATTR_INSTANCE .. +3, one per instance

uniform mat4 u_view_proj;

out vec3 v_world_pos;
out vec3 v_world_normal;
out vec3 v_object_pos;
out vec2 v_uv;
out vec4 v_color;

void main()
{
    vec4 world = a_model * vec4(a_position, 1.0);
    v_world_pos = world.xyz;
    v_world_normal = transpose(inverse(mat3(a_model))) * a_normal;
    v_object_pos = a_position;
    v_uv = a_uv;
    v_color = a_color;
    gl_Position = u_view_proj * world;
}
