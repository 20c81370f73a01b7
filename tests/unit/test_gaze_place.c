/* test_gaze_place.c: gaze in degrees (src/gaze/gaze_place.c and the readers' geometry): EyeLink
 * traces written here with known screen geometry keep their saccade amplitudes in degrees on any
 * display, --gaze-map normalized keeps today's positions, clamping warns once, the --gaze-screen
 * parser, and the Pupil Labs / Tobii directions. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/log.h"
#include "gaze/gaze.h"
#include "test.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)

static const display_desc k_d90 = {1280, 720, 90.0f, 0.0f, 0.0f}, k_d110 = {1920, 1080, 110.0f, 0.0f, 0.0f};

/* The angles of a placed sample on display d: frame_record's gaze_deg convention. */
static double deg_x(const display_desc *d, double x)
{
    double f = 0.5 * d->width / tan(0.5 * d->hfov_deg * DEG);
    return atan((x - 0.5) * d->width / f) / DEG;
}

static double deg_y(const display_desc *d, double y)
{
    double f = 0.5 * d->width / tan(0.5 * d->hfov_deg * DEG);
    return atan((0.5 - y) * d->height / f) / DEG;
}

/* >>EyeLink text: a 1024x768 screen seen from D px; 100 samples at theta0, then 100 at theta1
 * (horizontal, y at the centre). res: "block" (END ... RES), "sample" (per-sample fields) or
 * "none". */
static char *eyelink_text(double D, double theta0, double theta1, const char *res)
{
    size_t cap = 1 << 16, n = 0;
    char *s = malloc(cap);
    bool per_sample = !strcmp(res, "sample");
    n += (size_t)snprintf(s + n, cap - n, "** CONVERTED FROM test.edf\nMSG\t900 DISPLAY_COORDS 0 0 1023 767\n"
                          "START\t1000 \tLEFT\tSAMPLES\tEVENTS\nSAMPLES\tGAZE\tLEFT\t%sRATE\t500.00\n",
                          per_sample ? "VEL\tRES\t" : "");
    double u2 = 0;
    for (int i = 0; i < 200; i++) {
        double u = D * tan((i < 100 ? theta0 : theta1) * DEG);
        u2 += u * u / 200;
        if (per_sample) /* res = (pi/180) (D^2 + u^2) / D along x; at the centre along y */
            n += (size_t)snprintf(s + n, cap - n, "%d\t%.4f\t384.0\t1000.0\t0.0\t0.0\t%.6f\t%.6f\t...\n", 1000 + 2 * i,
                                  512 + u, DEG * (D * D + u * u) / D, DEG * D);
        else
            n += (size_t)snprintf(s + n, cap - n, "%d\t%.4f\t384.0\t1000.0\t...\n", 1000 + 2 * i, 512 + u);
    }
    if (!strcmp(res, "block")) /* the block's mean of res(u) */
        n += (size_t)snprintf(s + n, cap - n, "END\t1400 \tSAMPLES\tEVENTS\tRES\t%.6f\t%.6f\n", DEG * (D + u2 / D), DEG * D);
    else
        n += (size_t)snprintf(s + n, cap - n, "END\t1400 \tSAMPLES\tEVENTS\n");
    return s;
}

static bool load_text(char *text, const char *name, gaze_trace *t)
{
    fs_status s = gaze_parse(text, (long)strlen(text), name, NULL, t);
    free(text);
    return s == FS_OK;
}

/* The amplitude in degrees on display d of the saccade between samples 99 and 100. */
static double amplitude(const gaze_trace *t, const display_desc *d)
{
    return deg_x(d, t->samples[100].x) - deg_x(d, t->samples[99].x);
}

/* Same samples, field by field (the struct has padding). */
static bool same_samples(const gaze_trace *a, const gaze_trace *b)
{
    if (a->count != b->count)
        return false;
    for (int i = 0; i < a->count; i++) {
        const gaze_sample *p = &a->samples[i], *q = &b->samples[i];
        if (memcmp(&p->t, &q->t, sizeof p->t) || memcmp(&p->x, &q->x, sizeof p->x) || memcmp(&p->y, &q->y, sizeof p->y) ||
            memcmp(&p->confidence, &q->confidence, sizeof p->confidence) || p->valid != q->valid)
            return false;
    }
    return true;
}

/* stderr into a file while `fn` runs; returns how many lines contain `needle`. */
static int count_stderr(void (*fn)(void *), void *arg, const char *needle)
{
    fflush(stderr);
    FILE *tmp = tmpfile();
    int saved = dup(fileno(stderr));
    dup2(fileno(tmp), fileno(stderr));
    fn(arg);
    fflush(stderr);
    dup2(saved, fileno(stderr));
    close(saved);
    rewind(tmp);
    char line[1024];
    int k = 0;
    while (fgets(line, sizeof line, tmp))
        k += strstr(line, needle) != NULL;
    fclose(tmp);
    return k;
}

/* >>tests */

TEST(eyelink_saccade_keeps_degrees)
{
    static const char *const res[] = {"block", "sample"};
    static const display_desc *const disp[] = {&k_d90, &k_d110};
    for (int r = 0; r < 2; r++) {
        for (int k = 0; k < 2; k++) {
            gaze_trace t;
            CHECK(load_text(eyelink_text(2000, 2, 12, res[r]), "ten.asc", &t));
            CHECK(t.tan_per_x > 0 && strstr(t.geometry, r ? "per-sample" : "block") != NULL);
            gaze_place(&t, &(gaze_place_desc){GAZE_MAP_ANGLE, {0}}, disp[k]);
            CHECK_NEAR(amplitude(&t, disp[k]), 10.0, 0.1);
            CHECK_NEAR(deg_x(disp[k], t.samples[0].x), 2.0, 0.05); /* straight ahead at the centre */
            CHECK_NEAR(deg_y(disp[k], t.samples[0].y), 0.0, 1e-4);
            gaze_free(&t);
        }
    }
    /* the same trace stretched by normalised position is not 10 deg: the test can tell */
    gaze_trace t;
    CHECK(load_text(eyelink_text(2000, 2, 12, "block"), "ten.asc", &t));
    CHECK(fabs(amplitude(&t, &k_d90) - 10.0) > 1.0);
    gaze_free(&t);
}

TEST(gaze_screen_supplies_geometry)
{
    /* no RES: a 400 x 300 mm screen at 600 mm; the file's pixels are at 1024 / 400 px per mm */
    const double px_per_mm = 1024.0 / 400.0, dist_px = 600 * px_per_mm;
    gaze_trace t;
    CHECK(load_text(eyelink_text(dist_px, -4, 6, "none"), "nores.asc", &t));
    CHECK(t.tan_per_x == 0 && t.dir == NULL);
    gaze_screen sc;
    char err[256];
    CHECK(gaze_screen_parse("400x300@600", &sc, err, sizeof err));
    gaze_place(&t, &(gaze_place_desc){GAZE_MAP_ANGLE, sc}, &k_d110);
    CHECK_NEAR(amplitude(&t, &k_d110), 10.0, 0.1);
    CHECK_NEAR(deg_x(&k_d110, t.samples[0].x), -4.0, 0.05);
    gaze_free(&t);
}

/* Placed without geometry: nothing moves, and it is said once. */
static void place_no_geometry(void *arg)
{
    gaze_trace *t = arg;
    log_set_verbose(true);
    gaze_place(t, &(gaze_place_desc){GAZE_MAP_ANGLE, {0}}, &k_d90);
    log_set_verbose(false);
}

TEST(no_geometry_keeps_positions_and_says_so)
{
    gaze_trace t, u;
    CHECK(load_text(eyelink_text(2000, -4, 6, "none"), "nores.asc", &t));
    CHECK(load_text(eyelink_text(2000, -4, 6, "none"), "nores.asc", &u));
    CHECK(count_stderr(place_no_geometry, &t, "no screen geometry: placed by normalised position") == 1);
    CHECK(same_samples(&t, &u));
    gaze_free(&t);
    gaze_free(&u);
}

TEST(normalized_is_todays_positions)
{
    gaze_trace t, u;
    CHECK(load_text(eyelink_text(2000, 2, 12, "block"), "ten.asc", &t));
    CHECK(load_text(eyelink_text(2000, 2, 12, "block"), "ten.asc", &u));
    gaze_place(&t, &(gaze_place_desc){GAZE_MAP_NORMALIZED, {0}}, &k_d90);
    CHECK(same_samples(&t, &u));
    /* today's positions: pixels / screen size */
    CHECK_NEAR(t.samples[0].x, (512 + 2000 * tan(2 * DEG)) / 1024.0, 1e-6);
    gaze_place(&u, &(gaze_place_desc){GAZE_MAP_ANGLE, {0}}, &k_d90);
    CHECK(t.samples[150].x != u.samples[150].x); /* by angle it moves */
    gaze_free(&t);
    gaze_free(&u);
}

static void place_wide(void *arg)
{
    gaze_place(arg, &(gaze_place_desc){GAZE_MAP_ANGLE, {0}}, &k_d90);
}

TEST(clamped_once_with_the_excess)
{
    gaze_trace t;
    /* a screen seen from 300 px spans +-59.6 deg; a gaze at 50 deg on a 90 deg display: 5 deg over */
    CHECK(load_text(eyelink_text(300, 0, 50, "block"), "wide.asc", &t));
    CHECK(count_stderr(place_wide, &t, "clamped by up to 5.0°") == 1);
    CHECK(t.samples[150].x == 1.0f);
    CHECK_NEAR(t.samples[0].x, 0.5, 1e-6);
    gaze_free(&t);
    CHECK(load_text(eyelink_text(300, 0, 40, "sample"), "inside.asc", &t));
    CHECK(count_stderr(place_wide, &t, "clamped") == 0);
    CHECK_NEAR(deg_x(&k_d90, t.samples[150].x), 40.0, 0.05);
    gaze_free(&t);
}

TEST(screen_strings)
{
    gaze_screen s;
    char err[256], buf[64];
    CHECK(gaze_screen_parse("520x290@600", &s, err, sizeof err) && s.kind == GAZE_SCREEN_MM && s.w == 520 &&
          s.h == 290 && s.dist == 600);
    gaze_screen_format(&s, buf, sizeof buf);
    CHECK(!strcmp(buf, "520x290@600"));
    CHECK(gaze_screen_parse("82.5x52deg", &s, err, sizeof err) && s.kind == GAZE_SCREEN_FOV && s.w == 82.5 &&
          s.h == 52);
    gaze_screen_format(&s, buf, sizeof buf);
    CHECK(!strcmp(buf, "82.5x52deg"));
    static const char *const bad[] = {"", "520x290", "520x290@", "520x290@600mm", "-5x3@2", "0x3@2", "nanx3@2",
                                      "infx3@2", "82x52", "180x52deg", "82x52 deg", "82x0deg", "x@", "520x290@600@1",
                                      "2000000x1@1", "0x1p3@1"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        s.kind = GAZE_SCREEN_FOV;
        bool ok = gaze_screen_parse(bad[i], &s, err, sizeof err);
        CHECK(!ok && s.kind == GAZE_SCREEN_FOV); /* untouched */
        CHECK(!strncmp(err, "expected W_MMxH_MM@DIST_MM", 26) && !strchr(err, '\n'));
        char want[64];
        snprintf(want, sizeof want, "got '%s'", bad[i]);
        CHECK(strstr(err, want) != NULL);
        if (ok)
            fprintf(stderr, "  accepted '%s'\n", bad[i]);
    }
    CHECK(!gaze_screen_parse(NULL, &s, err, sizeof err));
}

TEST(merge_and_names)
{
    gaze_place_opts cli = {.desc = {.map = GAZE_MAP_NORMALIZED}, .map_set = true};
    gaze_place_opts sc = {.desc = {.map = GAZE_MAP_ANGLE, .screen = {GAZE_SCREEN_FOV, 82, 52, 0}}, .map_set = true,
                          .screen_set = true};
    gaze_place_desc m = gaze_place_merge(&cli, &sc);
    CHECK(m.map == GAZE_MAP_NORMALIZED && m.screen.kind == GAZE_SCREEN_FOV && m.screen.w == 82);
    m = gaze_place_merge(&(gaze_place_opts){0}, &(gaze_place_opts){0});
    CHECK(m.map == GAZE_MAP_ANGLE && m.screen.kind == GAZE_SCREEN_NONE);
    CHECK(!strcmp(gaze_map_name(GAZE_MAP_ANGLE), "angle") && !strcmp(gaze_map_name(GAZE_MAP_NORMALIZED), "normalized"));
}

TEST(pupil_gaze_point_3d)
{
    char text[1024];
    const double z = 500, x1 = z * tan(10 * DEG), y1 = z * tan(4 * DEG);
    snprintf(text, sizeof text,
             "gaze_timestamp,world_index,confidence,norm_pos_x,norm_pos_y,gaze_point_3d_x,gaze_point_3d_y,gaze_point_3d_z\n"
             "10.0,0,0.9,0.5,0.5,0,0,%g\n"
             "10.1,1,0.9,0.7,0.4,%.6f,%.6f,%g\n"
             "10.2,2,0.9,0.6,0.5,,,\n",
             z, x1, y1, z);
    gaze_trace t;
    CHECK(gaze_parse(text, (long)strlen(text), "gaze_positions.csv", NULL, &t) == FS_OK);
    CHECK(t.format == GAZE_FORMAT_PUPIL && t.dir != NULL && t.count == 3 && t.valid_count == 3);
    CHECK(t.samples[1].x == 0.7f); /* loading still keeps norm_pos */
    gaze_place(&t, &(gaze_place_desc){GAZE_MAP_ANGLE, {0}}, &k_d110);
    CHECK_NEAR(deg_x(&k_d110, t.samples[1].x), 10.0, 0.01);
    CHECK_NEAR(deg_y(&k_d110, t.samples[1].y), -4.0, 0.01); /* OpenCV y down: below the centre */
    CHECK_NEAR(t.samples[0].x, 0.5, 1e-6);
    /* the 2D-only row has no direction: invalid, holding the gaze before it */
    CHECK(!t.samples[2].valid && t.valid_count == 2 && t.samples[2].x == t.samples[1].x);
    gaze_free(&t);
}

TEST(tobii_gp3_directions)
{
    const double tx = tan(10 * DEG), ty = tan(5 * DEG);
    char text[1024];
    snprintf(text, sizeof text,
             "{\"ts\":1000,\"s\":0,\"gidx\":1,\"gp\":[0.5,0.5]}\n"
             "{\"ts\":1000,\"s\":0,\"gidx\":1,\"gp3\":[0,0,800]}\n"
             "{\"ts\":21000,\"s\":0,\"gidx\":2,\"gp3\":[%.5f,%.5f,1000]}\n" /* before its gp: joined by gidx */
             "{\"ts\":21000,\"s\":0,\"gidx\":2,\"gp\":[0.6,0.4]}\n"
             "{\"ts\":41000,\"s\":0,\"gidx\":3,\"gp\":[0.6,0.4]}\n",
             -1000 * tx, 1000 * ty);
    gaze_trace t;
    CHECK(gaze_parse(text, (long)strlen(text), "livedata.json", NULL, &t) == FS_OK);
    CHECK(t.format == GAZE_FORMAT_TOBII && t.dir != NULL && t.count == 3);
    gaze_place(&t, &(gaze_place_desc){GAZE_MAP_ANGLE, {0}}, &k_d90);
    /* gp3 x points to the wearer's left: -x is a gaze to the right */
    CHECK_NEAR(deg_x(&k_d90, t.samples[1].x), 10.0, 0.01);
    CHECK_NEAR(deg_y(&k_d90, t.samples[1].y), 5.0, 0.01);
    CHECK_NEAR(t.samples[0].x, 0.5, 1e-6);
    CHECK(!t.samples[2].valid && t.valid_count == 2); /* gidx 3 has no gp3 */
    gaze_free(&t);
    /* --gaze-screen wins: gp with the scene camera's field of view */
    CHECK(gaze_parse(text, (long)strlen(text), "livedata.json", NULL, &t) == FS_OK);
    gaze_place(&t, &(gaze_place_desc){GAZE_MAP_ANGLE, {GAZE_SCREEN_FOV, 82, 52, 0}}, &k_d90);
    CHECK_NEAR(deg_x(&k_d90, t.samples[1].x), atan(0.1 * 2 * tan(41 * DEG)) / DEG, 0.01);
    CHECK(t.samples[2].valid);
    gaze_free(&t);
}

int main(void)
{
    RUN(eyelink_saccade_keeps_degrees);
    RUN(gaze_screen_supplies_geometry);
    RUN(no_geometry_keeps_positions_and_says_so);
    RUN(normalized_is_todays_positions);
    RUN(clamped_once_with_the_excess);
    RUN(screen_strings);
    RUN(merge_and_names);
    RUN(pupil_gaze_point_3d);
    RUN(tobii_gp3_directions);
    return test_summary();
}
