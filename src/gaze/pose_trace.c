/* pose_trace.c: the pose_trace.h math: quaternions, resampling a pose trace to frame times, the
 * eye-in-head gaze, the recording's world placed in a scene, view matrices. The reader is
 * gaze_eyenav.c; conventions in docs/gaze-formats.md ("EyeNavGS").
 */
#include "gaze/pose_trace.h"

#include <math.h>

#define DEG (3.14159265358979323846 / 180.0)

/* >>quaternions */

pose_quat pose_qmul(pose_quat a, pose_quat b)
{
    return (pose_quat){a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                       a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                       a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
                       a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

pose_quat pose_qconj(pose_quat q) { return (pose_quat){-q.x, -q.y, -q.z, q.w}; }

static double qdot(pose_quat a, pose_quat b) { return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w; }

pose_quat pose_qnorm(pose_quat q)
{
    double n = sqrt(qdot(q, q));
    if (!(n > 0) || !isfinite(n))
        return (pose_quat){0, 0, 0, 1};
    return (pose_quat){q.x / n, q.y / n, q.z / n, q.w / n};
}

pose_v3 pose_qrot(pose_quat q, pose_v3 v)
{
    /* v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z) */
    double tx = 2 * (q.y * v.z - q.z * v.y), ty = 2 * (q.z * v.x - q.x * v.z), tz = 2 * (q.x * v.y - q.y * v.x);
    return (pose_v3){v.x + q.w * tx + (q.y * tz - q.z * ty), v.y + q.w * ty + (q.z * tx - q.x * tz),
                     v.z + q.w * tz + (q.x * ty - q.y * tx)};
}

pose_quat pose_slerp(pose_quat a, pose_quat b, double f)
{
    if (f <= 0)
        return a;
    if (f >= 1)
        return b;
    double d = qdot(a, b);
    if (d < 0) { /* q and -q are one rotation: take the shorter arc */
        b = (pose_quat){-b.x, -b.y, -b.z, -b.w};
        d = -d;
    }
    double ka = 1 - f, kb = f;
    if (d < 0.9999995) { /* else nearly equal: lerp is exact to rounding and avoids 0/0 */
        double th = acos(d), s = sin(th);
        ka = sin((1 - f) * th) / s;
        kb = sin(f * th) / s;
    }
    return pose_qnorm((pose_quat){ka * a.x + kb * b.x, ka * a.y + kb * b.y, ka * a.z + kb * b.z, ka * a.w + kb * b.w});
}

pose_quat pose_qaxis(pose_v3 axis, double radians)
{
    double s = sin(0.5 * radians);
    return (pose_quat){axis.x * s, axis.y * s, axis.z * s, cos(0.5 * radians)};
}

/* >>eye in head */

pose_quat pose_eye_in_head(pose_quat head, pose_quat gaze) { return pose_qmul(pose_qconj(head), gaze); }

pose_v3 pose_gaze_dir(pose_quat head, pose_quat gaze)
{
    return pose_qrot(pose_qnorm(pose_eye_in_head(head, gaze)), (pose_v3){0, 0, -1});
}

void pose_dir_angles(pose_v3 d, double *yaw, double *pitch, double *eccentricity)
{
    if (yaw)
        *yaw = atan2(d.x, -d.z);
    if (pitch)
        *pitch = atan2(d.y, hypot(d.x, d.z));
    if (eccentricity) /* atan2 rather than acos(-d.z): accurate near 0 */
        *eccentricity = atan2(hypot(d.x, d.y), -d.z);
}

/* >>resampling */

static pose_v3 lerp3(pose_v3 a, pose_v3 b, double f)
{
    return (pose_v3){a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), a.z + f * (b.z - a.z)};
}

static pose_state state_of(const pose_sample *s, bool held)
{
    pose_state r = {.pos = s->pos, .head = s->head, .gaze = s->gaze, .gaze_valid = s->gaze_valid};
    for (int k = 0; k < 4; k++)
        r.fov[k] = s->fov[k];
    r.held = held || !s->gaze_valid;
    return r;
}

/* Index lo with s[lo].t <= time < s[lo + 1].t; takes s[0].t <= time < s[n - 1].t. */
static int bracket(const pose_sample *s, int n, double time)
{
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        if (s[mid].t <= time)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

pose_state pose_at(const pose_trace *t, int eye, double time, bool *beyond_end)
{
    if (beyond_end)
        *beyond_end = false;
    if (!t || t->count <= 0 || (eye != POSE_LEFT && eye != POSE_RIGHT) || !t->eye[eye])
        return (pose_state){.head = {0, 0, 0, 1}, .gaze = {0, 0, 0, 1}, .held = true};
    const pose_sample *s = t->eye[eye];
    const int n = t->count;
    if (isnan(time))
        time = 0;
    if (time <= s[0].t)
        return state_of(&s[0], time < s[0].t);
    if (time >= s[n - 1].t) {
        if (beyond_end && time > s[n - 1].t)
            *beyond_end = true;
        return state_of(&s[n - 1], time > s[n - 1].t);
    }
    int lo = bracket(s, n, time);
    const pose_sample *a = &s[lo], *b = &s[lo + 1];
    if (time == a->t)
        return state_of(a, false);
    double f = (time - a->t) / (b->t - a->t);
    pose_state r = state_of(a, false);
    r.pos = lerp3(a->pos, b->pos, f);
    r.head = pose_slerp(a->head, b->head, f);
    if (a->gaze_valid && b->gaze_valid) {
        r.gaze = pose_slerp(a->gaze, b->gaze, f);
    } else { /* hold the eye in the head, as gaze_at holds the gaze on the display */
        r.gaze = pose_qnorm(pose_qmul(r.head, pose_eye_in_head(a->head, a->gaze)));
        r.gaze_valid = false;
        r.held = true;
    }
    return r;
}

/* >>placement */

void pose_to_scene(const pose_trace *t, const pose_place *pl, pose_v3 pos, pose_quat q, pose_v3 *pos_out,
                   pose_quat *q_out)
{
    pose_quat tilt = t && t->has_scene ? t->scene.tilt : (pose_quat){0, 0, 0, 1};
    double rec_scale = t && t->has_scene && t->scene.scale > 0 ? t->scene.scale : 1.0;
    pose_v3 o = t && t->has_scene ? t->scene.initial : (pose_v3){0, 0, 0};
    const pose_place zero = {{0, 0, 0}, 0, 0};
    if (!pl)
        pl = &zero;
    double scale = pl->scale > 0 ? pl->scale : 1.0;
    /* metres, gravity-aligned, about the initial position; then the placement */
    pose_quat yaw = pose_qaxis((pose_v3){0, 1, 0}, pl->yaw_deg * DEG);
    pose_quat r = pose_qnorm(pose_qmul(yaw, tilt));
    pose_v3 m = {(pos.x - o.x) / rec_scale, (pos.y - o.y) / rec_scale, (pos.z - o.z) / rec_scale};
    pose_v3 p = pose_qrot(r, m);
    if (pos_out)
        *pos_out = (pose_v3){pl->pos.x + scale * p.x, pl->pos.y + scale * p.y, pl->pos.z + scale * p.z};
    if (q_out)
        *q_out = pose_qnorm(pose_qmul(r, q));
}

mat4 pose_view_matrix(pose_v3 pos, pose_quat q)
{
    /* the inverse of the camera's rigid transform: R^T (x - pos) */
    pose_quat c = pose_qconj(pose_qnorm(q));
    float qc[4] = {(float)c.x, (float)c.y, (float)c.z, (float)c.w};
    mat4 r = m4_quat(qc);
    pose_v3 tr = pose_qrot(c, (pose_v3){-pos.x, -pos.y, -pos.z});
    r.m[12] = (float)tr.x;
    r.m[13] = (float)tr.y;
    r.m[14] = (float)tr.z;
    return r;
}

mat4 pose_eye_view(const pose_trace *t, const pose_place *pl, int eye, double time)
{
    pose_state s = pose_at(t, eye, time, NULL);
    pose_v3 p;
    pose_quat q;
    pose_to_scene(t, pl, s.pos, s.head, &p, &q);
    return pose_view_matrix(p, q);
}
