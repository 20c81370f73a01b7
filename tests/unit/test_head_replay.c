/* test_head_replay.c: a recording's head motion drives the camera (session_frame with a pose trace,
 * docs/hmd.md "Head replay"): a synthetic EyeNavGS recording with known head rotations and known
 * eye-in-head angles; each frame's view matrix equals the recorded pose (placed by --head-place),
 * built here from the angles, within 1e-5; the true gaze lands at the pixel computed here from the
 * eye-in-head angles on the planar display; without the head the camera is the scene's. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/log.h"
#include "gaze/pose_trace.h"
#include "session/session.h"
#include "test.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)
enum { NF = 5 };

static double head_yaw(int i) { return (25 + 6 * i) * DEG; }
static double head_pitch(int i) { return (-12 + 2 * i) * DEG; }
static double head_roll(int i) { return (4 - i) * DEG; }
static double eye_yaw(int i) { return (10 - 3 * i) * DEG; } /* + right */
static double eye_pitch(int i) { return (-6 + 2 * i) * DEG; } /* + up */

/* 3x3 rotations, row-major: Ry(a) Rx(b) Rz(c), the head's orientation in the world. */
static void mul3(const double a[9], const double b[9], double out[9])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            out[r * 3 + c] = a[r * 3] * b[c] + a[r * 3 + 1] * b[3 + c] + a[r * 3 + 2] * b[6 + c];
}
static void head_matrix(int i, double m[9])
{
    double a = head_yaw(i), b = head_pitch(i), c = head_roll(i), t[9];
    double ry[9] = {cos(a), 0, sin(a), 0, 1, 0, -sin(a), 0, cos(a)};
    double rx[9] = {1, 0, 0, 0, cos(b), -sin(b), 0, sin(b), cos(b)};
    double rz[9] = {cos(c), -sin(c), 0, sin(c), cos(c), 0, 0, 0, 1};
    mul3(rx, rz, t);
    mul3(ry, t, m);
}

/* A rotation matrix's quaternion (x, y, z, w) (Shepperd; the angles here keep w large). */
static pose_quat quat_of(const double m[9])
{
    double w = sqrt(1.0 + m[0] + m[4] + m[8]) * 0.5;
    return (pose_quat){(m[7] - m[5]) / (4 * w), (m[2] - m[6]) / (4 * w), (m[3] - m[1]) / (4 * w), w};
}

static pose_v3 eye_pos(int i, int e) { return (pose_v3){1.0 + 0.05 * i + (e ? 0.064 : 0.0), 1.6, -2.0 - 0.03 * i}; }

/* The recording: per frame a left and a right row, the gaze = head * the eye-in-head rotation
 * (yaw about -y, then pitch about x: -z turns right by yaw and up by pitch). */
static size_t recording(char *buf, size_t cap)
{
    size_t n = (size_t)snprintf(buf, cap, "ViewIndex,FOV1,FOV2,FOV3,FOV4,PositionX,PositionY,PositionZ,QuaternionX,"
                                          "QuaternionY,QuaternionZ,QuaternionW,GazePosX,GazePosY,GazePosZ,GazeQX,"
                                          "GazeQY,GazeQZ,GazeQW,Timestamp\n");
    for (int i = 0; i < NF; i++) {
        double m[9];
        head_matrix(i, m);
        pose_quat h = quat_of(m);
        pose_quat eye = pose_qmul(pose_qaxis((pose_v3){0, 1, 0}, -eye_yaw(i)), pose_qaxis((pose_v3){1, 0, 0}, eye_pitch(i)));
        pose_quat g = pose_qmul(h, eye);
        for (int e = 0; e < 2; e++) {
            pose_v3 p = eye_pos(i, e);
            n += (size_t)snprintf(buf + n, cap - n,
                                  "%d,-0.942,0.698,-0.942,0.733,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,"
                                  "%.9f,%.9f,%.9f,%.9f,%d\n", e, p.x, p.y, p.z, h.x, h.y, h.z, h.w, p.x, p.y, p.z + 0.01,
                                  g.x, g.y, g.z, g.w, 40 * i + 4 * e);
        }
    }
    return n;
}

static session s;
static char g_text[16384];
static size_t g_n;
static const pose_place k_place = {{2.0, 0.5, -3.0}, 0.0, 1.0};

static int setup(void)
{
    g_n = recording(g_text, sizeof g_text);
    const char *text = g_text;
    size_t n = g_n;
    run_desc d = {.cmd = CMD_RENDER, .builtin = "forest", .width = 320, .height = 180};
    memset(&s, 0, sizeof s);
    if (session_load_scene(&d, &s.sc) != FS_OK || session_build_plan(&d, &s.sc, &s.pl) != FS_OK)
        return 1;
    if (gaze_parse(text, (long)n, "rec.csv", &(gaze_load_desc){0}, &s.gaze) != FS_OK ||
        pose_parse(text, (long)n, "rec.csv", NULL, &s.head) != FS_OK)
        return 1;
    gaze_place(&s.gaze, &(gaze_place_desc){0}, &(display_desc){320, 180, s.sc.display.hfov_deg, 0.0f, 0.0f});
    s.head_place = k_place;
    return 0;
}

static void teardown(void)
{
    gaze_free(&s.gaze);
    pose_free(&s.head);
    scene_free(&s.sc);
}

/* The largest difference between view and [R^T | -R^T c] (column-major; r row-major). */
static double view_error(const mat4 *view, const double r[9], const double c[3])
{
    double worst = 0;
    for (int row = 0; row < 3; row++) {
        double t = 0;
        for (int col = 0; col < 3; col++) {
            double want = r[col * 3 + row]; /* R^T */
            worst = fmax(worst, fabs(view->m[col * 4 + row] - want));
            t -= want * c[col];
        }
        worst = fmax(worst, fabs(view->m[12 + row] - t));
    }
    return worst;
}

TEST(camera_is_the_recorded_head)
{
    CHECK(setup() == 0);
    double worst = 0;
    for (int i = 0; i < NF; i++) {
        frame_record fr = session_frame(&s, i, 0.040f * (float)i, -1.0f);
        double r[9], c[3];
        head_matrix(i, r);
        pose_v3 l = eye_pos(i, 0), rr = eye_pos(i, 1);
        c[0] = k_place.pos.x + (l.x + rr.x) / 2; /* the camera between the eyes, placed */
        c[1] = k_place.pos.y + (l.y + rr.y) / 2;
        c[2] = k_place.pos.z + (l.z + rr.z) / 2;
        worst = fmax(worst, view_error(&fr.view, r, c));
        CHECK(fabs(fr.camera.position.x - c[0]) < 1e-5 && fabs(fr.camera.position.z - c[2]) < 1e-5);
    }
    printf("  view matrices: worst difference %.2e\n", worst);
    CHECK(worst < 1e-5);
    teardown();
}

TEST(gaze_lands_at_the_eye_in_head_angle)
{
    CHECK(setup() == 0);
    double f = 160.0 / tan(s.sc.display.hfov_deg * DEG / 2), worst = 0;
    for (int i = 0; i < NF; i++) {
        frame_record fr = session_frame(&s, i, 0.040f * (float)i, -1.0f);
        /* the direction (sin y cos p, sin p, -cos y cos p) through a pinhole at the display centre */
        double x = 160.0 + f * tan(eye_yaw(i)), y = 90.0 - f * tan(eye_pitch(i)) / cos(eye_yaw(i));
        worst = fmax(worst, fmax(fabs(fr.true_gaze_px[0] - x), fabs(fr.true_gaze_px[1] - y)));
    }
    printf("  gaze pixels: worst difference %.2e px\n", worst);
    CHECK(worst < 1e-3);
    teardown();
}

TEST(without_a_head_the_scene_camera)
{
    CHECK(setup() == 0);
    frame_record with = session_frame(&s, 2, 0.080f, 0.040f);
    pose_free(&s.head);
    frame_record without = session_frame(&s, 2, 0.080f, 0.040f);
    frame_record scene = frame_record_at(&s.sc, 2, 0.080f, 0.040f, 320, 180);
    CHECK(memcmp(&without.view, &scene.view, sizeof scene.view) == 0);
    CHECK(memcmp(&with.view, &scene.view, sizeof scene.view) != 0);
    gaze_free(&s.gaze);
    scene_free(&s.sc);
}

/* An hmd display's eye (session.eye 1, 2): the camera at the recorded eye's own position with the
 * head's orientation, and the gaze of that eye at its pixel on the eye's off-centre display. */
TEST(hmd_eyes_at_their_recorded_positions)
{
    CHECK(setup() == 0);
    static const double fov[2][4] = {{-0.942, 0.698, -0.942, 0.733}, {-0.698, 0.942, -0.942, 0.733}}; /* L R D U */
    double worst_view = 0, worst_px = 0;
    for (int e = 0; e < 2; e++) {
        display_desc dd;
        CHECK(display_from_fov_angles(&(display_fov_angles){fov[e][0], fov[e][1], fov[e][2], fov[e][3]}, 200, &dd));
        s.sc.display = dd;
        s.pl.width = dd.width;
        s.pl.height = dd.height;
        s.pl.ppx = dd.ppx;
        s.pl.ppy = dd.ppy;
        s.eye = e + 1;
        gaze_free(&s.gaze); /* that eye's samples, placed on that eye's display (as session_begin) */
        CHECK(gaze_parse(g_text, (long)g_n, "rec.csv", &(gaze_load_desc){.eye = e ? GAZE_EYE_RIGHT : GAZE_EYE_LEFT},
                         &s.gaze) == FS_OK);
        gaze_place(&s.gaze, &(gaze_place_desc){0}, &dd);
        for (int i = 0; i < NF; i++) {
            frame_record fr = session_frame(&s, i, 0.040f * (float)i, -1.0f);
            double r[9];
            head_matrix(i, r);
            pose_v3 p = eye_pos(i, e);
            double c[3] = {k_place.pos.x + p.x, k_place.pos.y + p.y, k_place.pos.z + p.z};
            worst_view = fmax(worst_view, view_error(&fr.view, r, c));
            /* the eye's pinhole from its angles: f = W / (tan R - tan L), the principal point at
             * f (-tan L) from the left edge and f tan U ... from the top, rounding shared */
            double f = 200.0 / (tan(fov[e][1]) - tan(fov[e][0]));
            double cx = -f * tan(fov[e][0]), cy = 0.5 * dd.height + 0.5 * f * (tan(fov[e][3]) + tan(fov[e][2]));
            double x = cx + f * tan(eye_yaw(i)), y = cy - f * tan(eye_pitch(i)) / cos(eye_yaw(i));
            worst_px = fmax(worst_px, fmax(fabs(fr.true_gaze_px[0] - x), fabs(fr.true_gaze_px[1] - y)));
        }
    }
    printf("  hmd eyes: view matrices worst %.2e, gaze pixels worst %.2e px\n", worst_view, worst_px);
    CHECK(worst_view < 1e-5);
    CHECK(worst_px < 1e-2);
    teardown();
}

int main(void)
{
    log_set_quiet_errors(false);
    RUN(camera_is_the_recorded_head);
    RUN(gaze_lands_at_the_eye_in_head_angle);
    RUN(without_a_head_the_scene_camera);
    RUN(hmd_eyes_at_their_recorded_positions);
    return test_summary();
}
