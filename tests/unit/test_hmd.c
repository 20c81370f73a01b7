/* Unit tests of the hmd display model (src/hmd/, docs/hmd.md "The display"): the asymmetric
 * projection maps the frustum's four edges to the viewport's (NDC +-1) for the presets and random
 * fields of view; pixel <-> direction round trips; the principal point and focal length agree with
 * the projection and with the test's own tangent-space formula; the presets' figures and square
 * pixels; the visual angle between pixels; the text form's round trip and its refusals; the scene
 * file's "display" object. */
#include <string.h>

#include "core/log.h"
#include "hmd/hmd.h"
#include "scene/scene_json.h"
#include "test.h"

/* Deterministic uniform numbers in [lo, hi). */
static unsigned g_rng = 12345u;
static double urand(double lo, double hi)
{
    g_rng = g_rng * 1664525u + 1013904223u;
    return lo + (hi - lo) * (double)(g_rng >> 8) / 16777216.0;
}

static hmd_fov random_fov(void)
{
    double deg[4];
    deg[0] = urand(-80, 30);             /* left: may lie right of straight ahead (canted) */
    deg[1] = urand(deg[0] + 5, 80);      /* right */
    deg[3] = urand(-80, 30);             /* down */
    deg[2] = urand(deg[3] + 5, 80);      /* up */
    hmd_fov f;
    CHECK(hmd_fov_from_deg(deg, &f));
    return f;
}

/* Clip coordinates of eye-space point p through projection m, divided by w, in double. */
static void ndc(const mat4 *m, double x, double y, double z, double out[3])
{
    double c[4];
    for (int r = 0; r < 4; r++)
        c[r] = m->m[r] * x + m->m[4 + r] * y + m->m[8 + r] * z + m->m[12 + r];
    for (int i = 0; i < 3; i++)
        out[i] = c[i] / c[3];
}

/* The frustum's edges and corners, at several depths, land on NDC +-1; near and far on z = -1, +1. */
static void check_projection(const hmd_fov *f)
{
    const float n = 0.05f, far = 500.0f;
    mat4 m = hmd_projection(f, n, far);
    double l = tan((double)f->left), r = tan((double)f->right), u = tan((double)f->up), d = tan((double)f->down);
    const double depths[] = {0.05, 1.0, 37.0, 500.0};
    for (int k = 0; k < 4; k++) {
        double z = depths[k], o[3];
        ndc(&m, l * z, 0.5 * (u + d) * z, -z, o);
        CHECK_NEAR(o[0], -1.0, 1e-6);
        ndc(&m, r * z, 0.5 * (u + d) * z, -z, o);
        CHECK_NEAR(o[0], 1.0, 1e-6);
        ndc(&m, 0.5 * (l + r) * z, u * z, -z, o);
        CHECK_NEAR(o[1], 1.0, 1e-6);
        ndc(&m, 0.5 * (l + r) * z, d * z, -z, o);
        CHECK_NEAR(o[1], -1.0, 1e-6);
        ndc(&m, l * z, d * z, -z, o); /* a corner */
        CHECK_NEAR(o[0], -1.0, 1e-6);
        CHECK_NEAR(o[1], -1.0, 1e-6);
    }
    double o[3];
    ndc(&m, 0, 0, -n, o);
    CHECK_NEAR(o[2], -1.0, 1e-5);
    ndc(&m, 0, 0, -far, o);
    CHECK_NEAR(o[2], 1.0, 1e-5);
}

static hmd_desc preset(const char *name)
{
    hmd_desc d;
    char err[256] = "";
    bool ok = hmd_make(name, NULL, &d, err, sizeof err);
    if (!ok)
        fprintf(stderr, "%s: %s\n", name, err);
    CHECK(ok);
    return d;
}

TEST(projection_maps_frustum_edges_to_viewport_edges)
{
    const char *names[] = {"quest-pro", "eyenavgs"};
    for (int p = 0; p < 2; p++) {
        hmd_desc d = preset(names[p]);
        check_projection(&d.eye[HMD_LEFT].fov);
        check_projection(&d.eye[HMD_RIGHT].fov);
    }
    for (int i = 0; i < 200; i++) {
        hmd_fov f = random_fov();
        check_projection(&f);
    }
    /* A symmetric field of view gives m4_perspective_hfov's matrix. */
    hmd_fov s = {-0.6f, 0.6f, 0.4f, -0.4f};
    mat4 a = hmd_projection(&s, 0.1f, 100.0f);
    mat4 b = m4_perspective_hfov(1.2f, (float)(tan(0.6) / tan(0.4)), 0.1f, 100.0f);
    for (int i = 0; i < 16; i++)
        CHECK_NEAR(a.m[i], b.m[i], 1e-6);
}

static hmd_eye random_eye(void)
{
    hmd_eye e = {.fov = random_fov(), .width = (int)urand(16, 4000), .height = (int)urand(16, 4000)};
    return e;
}

TEST(pixel_direction_round_trip)
{
    for (int i = 0; i < 200; i++) {
        hmd_eye e = i == 0 ? preset("eyenavgs").eye[HMD_LEFT] : random_eye();
        for (int k = 0; k < 20; k++) {
            float px = (float)urand(0, e.width), py = (float)urand(0, e.height), qx, qy;
            vec3 d = hmd_pixel_to_dir(&e, px, py);
            CHECK_NEAR(v3_len(d), 1.0, 1e-6);
            CHECK(hmd_dir_to_pixel(&e, d, &qx, &qy));
            CHECK_NEAR(qx, px, 1e-6 * e.width);
            CHECK_NEAR(qy, py, 1e-6 * e.height);
            vec3 d2 = hmd_pixel_to_dir(&e, qx, qy);
            CHECK_NEAR(v3_len(v3_sub(d2, d)), 0.0, 1e-6);
        }
        float qx, qy;
        CHECK(!hmd_dir_to_pixel(&e, v3(0.1f, 0.2f, 0.0f), &qx, &qy)); /* not forward */
        CHECK(!hmd_dir_to_pixel(&e, v3(0.0f, 0.0f, 1.0f), &qx, &qy));
    }
}

/* The test's own mapping: pixel x = (tan(yaw-like) - tan(left)) / (tan(right) - tan(left)) * width,
 * y from the top; edges at 0 and width/height, straight ahead at the principal point. */
TEST(pixels_of_known_directions)
{
    hmd_eye e = preset("eyenavgs").eye[HMD_LEFT];
    float px, py;
    CHECK(hmd_dir_to_pixel(&e, v3(tanf(e.fov.left), 0.0f, -1.0f), &px, &py));
    CHECK_NEAR(px, 0.0, 1e-3);
    CHECK(hmd_dir_to_pixel(&e, v3(tanf(e.fov.right), tanf(e.fov.up), -1.0f), &px, &py));
    CHECK_NEAR(px, e.width, 1e-3);
    CHECK_NEAR(py, 0.0, 1e-3);
    CHECK(hmd_dir_to_pixel(&e, v3(0.0f, tanf(e.fov.down), -1.0f), &px, &py));
    CHECK_NEAR(py, e.height, 1e-3);
    /* Straight ahead: 0.942 of 0.942 + 0.698 rad's tangents from the left, 0.733 of the vertical's from the top. */
    CHECK(hmd_dir_to_pixel(&e, v3(0.0f, 0.0f, -1.0f), &px, &py));
    double tl = tan(0.942), tr = tan(0.698), tu = tan(0.733), td = tan(0.942);
    CHECK_NEAR(px, 1800.0 * tl / (tl + tr), 1e-3);
    CHECK_NEAR(py, 1850.0 * tu / (tu + td), 1e-3);
    CHECK(px > 0.5f * e.width); /* the left eye's wider temporal side puts straight ahead right of centre */
}

TEST(pinhole_agrees_with_projection)
{
    for (int i = 0; i < 200; i++) {
        hmd_eye e = random_eye();
        hmd_pinhole p = hmd_eye_pinhole(&e);
        mat4 m = hmd_projection(&e.fov, 0.1f, 100.0f);
        for (int k = 0; k < 10; k++) {
            double x = urand(-1, 1), y = urand(-1, 1), o[3];
            ndc(&m, x, y, -1.0, o);
            /* NDC to display pixels: x from the left, y from the top. */
            double vx = (o[0] + 1.0) * 0.5 * e.width, vy = (1.0 - o[1]) * 0.5 * e.height;
            CHECK_NEAR(p.cx + p.fx * x, vx, 1e-5 * e.width);
            CHECK_NEAR(p.cy - p.fy * y, vy, 1e-5 * e.height);
            float px, py;
            CHECK(hmd_dir_to_pixel(&e, v3((float)x, (float)y, -1.0f), &px, &py));
            CHECK_NEAR(px, vx, 1e-5 * e.width);
            CHECK_NEAR(py, vy, 1e-5 * e.height);
        }
        /* Straight ahead is NDC (0 + shift): the principal point. */
        double o[3];
        ndc(&m, 0, 0, -1.0, o);
        CHECK_NEAR(p.cx, (o[0] + 1.0) * 0.5 * e.width, 1e-5 * e.width);
        CHECK_NEAR(p.cy, (1.0 - o[1]) * 0.5 * e.height, 1e-5 * e.height);
        float ppx, ppy;
        hmd_ppd(&e, &ppx, &ppy);
        CHECK_NEAR(ppx, p.fx * FS_PI / 180.0, 1e-3);
        CHECK_NEAR(ppy, p.fy * FS_PI / 180.0, 1e-3);
    }
}

TEST(visual_angle_between_pixels)
{
    hmd_eye e = preset("eyenavgs").eye[HMD_RIGHT];
    hmd_pinhole p = hmd_eye_pinhole(&e);
    vec3 ahead = v3(0, 0, -1);
    CHECK_NEAR(hmd_pixel_angle_deg(&e, p.cx, p.cy, ahead), 0.0, 1e-4);
    /* The left edge on the principal row is the field of view's left angle away from straight ahead. */
    CHECK_NEAR(hmd_pixel_angle_deg(&e, 0.0f, p.cy, ahead), -e.fov.left * 180.0 / FS_PI, 1e-3);
    CHECK_NEAR(hmd_pixel_angle_deg(&e, p.cx, 0.0f, ahead), e.fov.up * 180.0 / FS_PI, 1e-3);
    /* Against a gaze 10 deg right of ahead: the pixel straight ahead is 10 deg away. */
    vec3 g = v3((float)sin(10.0 * FS_PI / 180.0), 0.0f, -(float)cos(10.0 * FS_PI / 180.0));
    CHECK_NEAR(hmd_pixel_angle_deg(&e, p.cx, p.cy, g), 10.0, 1e-3);
    /* One pixel right of the principal point: about 1 / ppd degrees. */
    float ppx, ppy;
    hmd_ppd(&e, &ppx, &ppy);
    CHECK_NEAR(hmd_pixel_angle_deg(&e, p.cx + 1.0f, p.cy, ahead), 1.0 / ppx, 1e-3 / ppx);
}

TEST(presets_figures_and_square_pixels)
{
    hmd_desc d = preset("eyenavgs");
    CHECK(d.eye[HMD_LEFT].fov.left == -0.942f && d.eye[HMD_LEFT].fov.right == 0.698f);
    CHECK(d.eye[HMD_LEFT].fov.down == -0.942f && d.eye[HMD_LEFT].fov.up == 0.733f);
    CHECK(d.eye[HMD_RIGHT].fov.left == -0.698f && d.eye[HMD_RIGHT].fov.right == 0.942f);
    CHECK(d.eye[HMD_RIGHT].fov.down == -0.942f && d.eye[HMD_RIGHT].fov.up == 0.733f);
    CHECK(d.refresh_hz == 72.0f && d.ipd_mm == 63.0f);
    CHECK_NEAR(d.eye[HMD_LEFT].position.x, -0.0315, 1e-7);
    CHECK_NEAR(d.eye[HMD_RIGHT].position.x, 0.0315, 1e-7);
    CHECK(d.eye[0].position.y == 0.0f && d.eye[0].position.z == 0.0f);
    hmd_desc q = preset("quest-pro");
    CHECK(q.eye[0].width == 1800 && q.refresh_hz == 90.0f); /* Meta's published width and refresh */
    const hmd_desc *all[] = {&d, &q};
    for (int i = 0; i < 2; i++)
        for (int e = 0; e < 2; e++) {
            const hmd_eye *y = &all[i]->eye[e];
            double sx = tan((double)y->fov.right) - tan((double)y->fov.left);
            double sy = tan((double)y->fov.up) - tan((double)y->fov.down);
            CHECK(fabs(y->height - y->width * sy / sx) <= 0.5); /* square within rounding */
        }
    /* A width alone brings the height along; a changed field of view keeps the width. */
    char err[256];
    CHECK(hmd_parse("hmd:quest-pro,width=1440,ipd=64", &q, err, sizeof err));
    CHECK(q.eye[1].width == 1440 && q.eye[1].height == 1480 && q.ipd_mm == 64.0f);
    CHECK_NEAR(q.eye[HMD_RIGHT].position.x, 0.032, 1e-7);
    CHECK(hmd_parse("hmd:eyenavgs,fov-left=-45/45/30/-30", &q, err, sizeof err));
    CHECK(q.eye[0].width == 1800 && q.eye[0].height == (int)lround(1800 * tan(FS_PI / 6) / tan(FS_PI / 4)));
    CHECK_NEAR(q.eye[HMD_RIGHT].fov.left, -FS_PI / 4, 1e-6); /* the right eye mirrored */
    CHECK_NEAR(q.eye[HMD_RIGHT].fov.up, FS_PI / 6, 1e-6);
}

static bool desc_equal(const hmd_desc *a, const hmd_desc *b)
{
    bool eq = !strcmp(a->preset, b->preset) && a->ipd_mm == b->ipd_mm && a->refresh_hz == b->refresh_hz;
    for (int e = 0; e < 2; e++)
        eq = eq && !memcmp(&a->eye[e].fov, &b->eye[e].fov, sizeof(hmd_fov)) && a->eye[e].width == b->eye[e].width &&
             a->eye[e].height == b->eye[e].height && a->eye[e].position.x == b->eye[e].position.x;
    return eq;
}

static void check_round_trip(const char *text)
{
    hmd_desc a, b;
    char err[256] = "", back[512];
    bool ok = hmd_parse(text, &a, err, sizeof err);
    if (!ok)
        fprintf(stderr, "%s: %s\n", text, err);
    CHECK(ok);
    hmd_format(&a, back, sizeof back);
    ok = hmd_parse(back, &b, err, sizeof err);
    if (!ok || !desc_equal(&a, &b))
        fprintf(stderr, "%s -> %s: %s\n", text, back, ok ? "another desc" : err);
    CHECK(ok && desc_equal(&a, &b));
}

TEST(text_form_round_trip)
{
    const char *texts[] = {"hmd:eyenavgs", "hmd:quest-pro", "hmd:quest-pro,width=1440,ipd=64",
                           "hmd:eyenavgs,height=1000", "hmd:eyenavgs,width=1000,height=2000,hz=120.5",
                           "hmd:eyenavgs,fov-left=-50/40/40/-50", "hmd:eyenavgs,fov-right=-30/50/45/-55",
                           "hmd:quest-pro,fov-left=-50/40/40/-50,fov-right=-41/52/41/-52,ipd=58.3",
                           "hmd:custom,fov-left=-45/45/45/-45,width=2000,hz=90",
                           "hmd:custom,fov-left=10/60/20/-5.5,fov-right=-60/-10/20/-5.5,height=1024,hz=60,ipd=70",
                           /* zero angles: a mirrored +0 equals a written 0 (fuzz_hmd) */
                           "hmd:custom,fov-left=0/60/0/-5,fov-right=-60/0/0/-5,height=24,hz=7",
                           "hmd:custom,fov-left=-0/60/-0/-5,height=24,hz=7"};
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++)
        check_round_trip(texts[i]);
    /* A preset formats as its name alone; a change as the preset and that change. */
    char out[512];
    hmd_desc d = preset("eyenavgs");
    hmd_format(&d, out, sizeof out);
    CHECK(!strcmp(out, "hmd:eyenavgs"));
    char err[256];
    CHECK(hmd_parse("hmd:quest-pro,ipd=64", &d, err, sizeof err));
    hmd_format(&d, out, sizeof out);
    CHECK(!strcmp(out, "hmd:quest-pro,ipd=64"));
    /* Random explicit displays, angles written with 9 digits. */
    for (int i = 0; i < 200; i++) {
        hmd_fov f = random_fov(), g = random_fov();
        char text[512];
        snprintf(text, sizeof text, "hmd:custom,fov-left=%.9g/%.9g/%.9g/%.9g,fov-right=%.9g/%.9g/%.9g/%.9g,"
                 "width=%d,hz=%.9g,ipd=%.9g", f.left * 180 / FS_PI, f.right * 180 / FS_PI, f.up * 180 / FS_PI,
                 f.down * 180 / FS_PI, g.left * 180 / FS_PI, g.right * 180 / FS_PI, g.up * 180 / FS_PI,
                 g.down * 180 / FS_PI, (int)urand(100, 3000), urand(30, 240), urand(40, 90));
        /* Rounding may put a tiny span's derived height below 16: skip those, they are refused. */
        hmd_desc a;
        if (hmd_parse(text, &a, err, sizeof err))
            check_round_trip(text);
    }
}

TEST(bad_text_refused_with_the_key)
{
    const struct {
        const char *text, *message;
    } bad[] = {
        {"eyenavgs", "expected planar or hmd:PRESET"},
        {"hmd:", "without empty items"},
        {"hmd:vive", "unknown preset 'vive' (presets: quest-pro, eyenavgs, custom)"},
        {"hmd:eyenavgs,", "without empty items"},
        {"hmd:eyenavgs,,ipd=60", "without empty items"},
        {"hmd:eyenavgs,ipd", "expected KEY=VALUE after the preset, got 'ipd'"},
        {"hmd:eyenavgs,ipd=abc", "key 'ipd': expected millimetres in 40..90, got 'abc'"},
        {"hmd:eyenavgs,ipd=95", "key 'ipd': expected millimetres in 40..90, got '95'"},
        {"hmd:eyenavgs,ipd=60,ipd=61", "key 'ipd' given twice"},
        {"hmd:eyenavgs,zoom=2", "unknown key 'zoom' (keys: width, height, ipd, hz, fov-left, fov-right)"},
        {"hmd:eyenavgs,width=0", "key 'width': expected panel pixels per eye in 16..8192, got '0'"},
        {"hmd:eyenavgs,height=1.5", "key 'height': expected panel pixels per eye"},
        {"hmd:eyenavgs,hz=0", "key 'hz': expected a refresh rate in Hz in 1..1000, got '0'"},
        {"hmd:eyenavgs,hz=nan", "key 'hz': expected a refresh rate"},
        {"hmd:eyenavgs,fov-left=-50/40/40", "key 'fov-left': expected four angles in degrees LEFT/RIGHT/UP/DOWN"},
        {"hmd:eyenavgs,fov-left=40/-50/40/-50", "key 'fov-left': expected four angles"},
        {"hmd:eyenavgs,fov-right=-50/40/40/-90", "key 'fov-right': expected four angles"},
        {"hmd:eyenavgs,fov-left=-50/40/40/-50/1", "key 'fov-left': expected four angles"},
        {"hmd:custom,width=100,hz=90", "preset 'custom' gives no figures: the left eye's field of view is missing"},
        {"hmd:custom,fov-left=-45/45/45/-45,hz=90", "the width or height is missing"},
        {"hmd:eyenavgs,width=8000,fov-left=-5/5/80/-80", "outside 16..8192: give both 'width' and 'height'"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        hmd_desc d;
        char err[320] = "";
        bool ok = hmd_parse(bad[i].text, &d, err, sizeof err);
        if (ok || !strstr(err, bad[i].message))
            fprintf(stderr, "'%s': %s, wanted '%s'\n", bad[i].text, ok ? "accepted" : err, bad[i].message);
        CHECK(!ok && strstr(err, bad[i].message));
        CHECK(!strchr(err, '\n'));
    }
}

/* >>the scene file's "display" */

static fs_status load_display(const char *display, scene *sc)
{
    char json[1024];
    snprintf(json, sizeof json, "{\"display\": %s, \"assets\": [{\"generator\": \"tree\"}], \"instances\": "
             "[{\"asset\": \"tree\"}], \"camera\": [{\"position\": [0, 2, 8], \"target\": [0, 2, 0]}]}", display);
    return scene_json_parse(json, strlen(json), "hmd.json", NULL, sc);
}

TEST(scene_display_kind)
{
    scene sc;
    CHECK(load_display("{\"width\": 640, \"height\": 360}", &sc) == FS_OK);
    CHECK(sc.display_kind == DISPLAY_PLANAR && sc.display.width == 640);
    scene_free(&sc);
    CHECK(load_display("{\"kind\": \"planar\", \"hfov\": 70}", &sc) == FS_OK);
    CHECK(sc.display_kind == DISPLAY_PLANAR && sc.display.hfov_deg == 70.0f);
    scene_free(&sc);
    /* The JSON keys give what the text form's give. */
    CHECK(load_display("{\"kind\": \"hmd\", \"preset\": \"quest-pro\", \"width\": 1440, \"ipd\": 64, "
                       "\"fov_right\": [-41, 52, 41, -52]}", &sc) == FS_OK);
    hmd_desc t;
    char err[256];
    CHECK(hmd_parse("hmd:quest-pro,width=1440,ipd=64,fov-right=-41/52/41/-52", &t, err, sizeof err));
    CHECK(sc.display_kind == DISPLAY_HMD && desc_equal(&sc.hmd, &t));
    scene_free(&sc);
    const char *bad[] = {"{\"kind\": \"vr\"}", "{\"kind\": 3}", "{\"kind\": \"hmd\"}",
                         "{\"kind\": \"hmd\", \"preset\": \"eyenavgs\", \"hfov\": 90}",
                         "{\"kind\": \"hmd\", \"preset\": \"eyenavgs\", \"ipd\": 30}",
                         "{\"kind\": \"hmd\", \"preset\": \"eyenavgs\", \"fov_left\": [-50, 40, 40]}",
                         "{\"kind\": \"hmd\", \"preset\": \"eyenavgs\", \"fov_left\": [50, -40, 40, -40]}",
                         "{\"kind\": \"hmd\", \"preset\": \"nope\"}", "{\"kind\": \"planar\", \"ipd\": 63}"};
    log_set_quiet_errors(true);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        fs_status s = load_display(bad[i], &sc);
        if (s != FS_ERR_SCENE)
            fprintf(stderr, "display %s: accepted\n", bad[i]);
        CHECK(s == FS_ERR_SCENE);
    }
    log_set_quiet_errors(false);
}

int main(void)
{
    RUN(projection_maps_frustum_edges_to_viewport_edges);
    RUN(pixel_direction_round_trip);
    RUN(pixels_of_known_directions);
    RUN(pinhole_agrees_with_projection);
    RUN(visual_angle_between_pixels);
    RUN(presets_figures_and_square_pixels);
    RUN(text_form_round_trip);
    RUN(bad_text_refused_with_the_key);
    RUN(scene_display_kind);
    return test_summary();
}
