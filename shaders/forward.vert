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
    // Normals transform by the inverse transpose of the model matrix, which is the cofactor matrix
    // divided by the determinant: three cross products instead of a 3x3 inverse per vertex, and the
    // determinant's sign keeps mirrored instances' normals pointing out (the length is normalised
    // in the fragment shader).
    mat3 m = mat3(a_model);
    mat3 cof = mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
    v_world_normal = cof * a_normal * sign(determinant(m));
    v_object_pos = a_position;
    v_uv = a_uv;
    v_color = a_color;
    gl_Position = u_view_proj * world;
}
