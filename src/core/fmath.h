/* fmath.h: the small vector and matrix kit fovsim needs (no GL).
 *
 * Matrices are 4x4, column-major (m[col*4 + row]) as OpenGL expects, and act on column vectors:
 * p' = M p. Angles are radians unless a name says _deg. Does not do quaternion slerp, SIMD or
 * anything not used by fovsim.
 */
#ifndef FOVSIM_FMATH_H
#define FOVSIM_FMATH_H

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FS_PI 3.14159265358979323846

typedef struct { float x, y, z; } vec3;
typedef struct { float m[16]; } mat4;

static inline vec3 v3(float x, float y, float z)
{
    vec3 r = {x, y, z};
    return r;
}
vec3 v3_add(vec3 a, vec3 b);
vec3 v3_sub(vec3 a, vec3 b);
vec3 v3_scale(vec3 a, float s);
vec3 v3_lerp(vec3 a, vec3 b, float t);
float v3_dot(vec3 a, vec3 b);
vec3 v3_cross(vec3 a, vec3 b);
float v3_len(vec3 a);
/* Unit vector along a; returns `fallback` when a is zero or not finite. */
vec3 v3_norm_or(vec3 a, vec3 fallback);
vec3 v3_min(vec3 a, vec3 b);
vec3 v3_max(vec3 a, vec3 b);

mat4 m4_identity(void);
mat4 m4_mul(mat4 a, mat4 b); /* a * b: b applies first */
mat4 m4_translate(vec3 t);
mat4 m4_scale(vec3 s);
/* Rotation from a unit quaternion (x, y, z, w), as glTF stores it. */
mat4 m4_quat(const float q[4]);
mat4 m4_rotate_y(float radians);
/* glTF node transform: T * R * S. */
mat4 m4_trs(const float t[3], const float q[4], const float s[3]);
/* Right-handed view matrix looking from eye at target; up is +Y unless the view is vertical. */
mat4 m4_look_at(vec3 eye, vec3 target, vec3 up);
/* OpenGL perspective projection, depth to [-1,1]; hfov in radians, aspect = width / height. */
mat4 m4_perspective_hfov(float hfov, float aspect, float znear, float zfar);
/* The same pinhole with its principal point off the viewport centre (glFrustum's asymmetric form):
 * the view axis lands at NDC (cx, cy) instead of (0, 0); hfov is the field of view of a viewport of
 * the same width centred on the principal point. cx = cy = 0 gives m4_perspective_hfov exactly. */
mat4 m4_perspective_offaxis(float hfov, float aspect, float cx, float cy, float znear, float zfar);
/* General inverse; returns false (and identity) for a singular matrix. */
bool m4_invert(mat4 a, mat4 *out);
vec3 m4_point(mat4 a, vec3 p);  /* transforms a point (w = 1) */
vec3 m4_dir(mat4 a, vec3 d);    /* transforms a direction (w = 0) */
/* Inverse transpose of the upper 3x3 (for normals), returned in a mat4. */
mat4 m4_normal_matrix(mat4 a);
/* True when the box [lo, hi] (object space) transformed by the model-view-projection `mvp` lies
 * entirely outside one clip plane (-w <= x, y, z <= w), so nothing of it can be visible.
 * Conservative: false means "maybe visible". */
bool m4_box_outside_clip(mat4 mvp, vec3 lo, vec3 hi);
/* Bounding rectangle, in pixels of a w x h viewport (top-left origin, y down), of the axis-aligned
 * box [lo, hi] seen through mvp: rect = {x0, y0, x1, y1}. False (rect untouched) when a corner lies
 * on or behind the eye plane (clip w <= 1e-6) or the projection is not finite: then the box has no
 * bounded image. */
bool m4_box_screen_rect(mat4 mvp, vec3 lo, vec3 hi, float w, float h, float rect[4]);

#ifdef __cplusplus
}
#endif

#endif
