/* test_gaze.c: gaze traces (src/gaze/): the real recordings in ../shared/gaze, the scripted
 * traces in gaze_paths/, a Pupil Labs export (tests/data), malformed input, and gaze_at. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <malloc.h>
#include <sys/resource.h>

#include "core/config.h"
#include "core/log.h"
#include "gaze/gaze.h"
#include "test.h"

#define EYELINK_DIR "gaze/eyelink_asc_eyelinker/"
#define TOBII_LIVEDATA "gaze/tobii_glasses2_glassesviewer_demo/livedata.json"

static fs_status parse_str(const char *text, const gaze_load_desc *d, gaze_trace *t)
{
    return gaze_parse(text, (long)strlen(text), "test", d, t);
}

/* t[0] == 0 and strictly increasing; counts valid samples inside the display. */
static bool times_ok(const gaze_trace *t)
{
    if (t->count < 1 || t->samples[0].t != 0.0 || t->duration != t->samples[t->count - 1].t)
        return false;
    for (int i = 1; i < t->count; i++)
        if (!(t->samples[i].t > t->samples[i - 1].t))
            return false;
    return true;
}

static int count_valid(const gaze_trace *t)
{
    int v = 0;
    for (int i = 0; i < t->count; i++)
        v += t->samples[i].valid;
    return v;
}

static double inside_fraction(const gaze_trace *t)
{
    int in = 0, v = 0;
    for (int i = 0; i < t->count; i++) {
        const gaze_sample *s = &t->samples[i];
        if (!s->valid)
            continue;
        v++;
        in += s->x >= 0 && s->x <= 1 && s->y >= 0 && s->y <= 1;
    }
    return v ? (double)in / v : 0;
}

/* >>real recordings */

TEST(eyelink_recordings_load)
{
    /* SOURCES.md B1; span = last - first sample time (ms, gaps between the 4 blocks included). */
    static const struct {
        const char *file;
        int samples, invalid;
        double span_ms, first_ms;
    } k[] = {
        {"mono250.asc", 914, 0, 10168, 5885949},
        {"mono1000.asc", 3619, 0, 9604, 7709679},
        {"bino500.asc", 1745, 0, 10372, 6185399},
        {"monoRemote250.asc", 5129, 0, 25004, 12976172},
        /* 70 samples miss the left eye, 54 of them both eyes: AUTO keeps the 16 with a right eye. */
        {"binoRemote500.asc", 48224, 54, 102922, 11961952},
    };
    for (size_t i = 0; i < sizeof k / sizeof k[0]; i++) {
        char rel[256];
        snprintf(rel, sizeof rel, EYELINK_DIR "%s", k[i].file);
        gaze_trace t;
        fs_status s = gaze_load(test_shared_path(rel), NULL, &t);
        CHECK(s == FS_OK);
        if (s != FS_OK)
            continue;
        CHECK(t.format == GAZE_FORMAT_EYELINK);
        CHECK(t.count == k[i].samples);
        CHECK(t.count - t.valid_count == k[i].invalid);
        CHECK(count_valid(&t) == t.valid_count);
        CHECK(t.screen_w == 1024 && t.screen_h == 768);
        CHECK(times_ok(&t));
        CHECK_NEAR(t.duration, k[i].span_ms / 1000.0, 1e-9);
        CHECK_NEAR(t.time_offset, k[i].first_ms / 1000.0, 1e-9);
        CHECK(inside_fraction(&t) > 0.95);
        CHECK(strcmp(t.path, test_shared_path(rel)) == 0);
        gaze_free(&t);
        CHECK(t.samples == NULL && t.count == 0);
    }
}

TEST(eyelink_first_sample_normalised)
{
    /* mono250 first sample: 5885949  510.1  383.0  1037.0  ... */
    gaze_trace t;
    CHECK(gaze_load(test_shared_path(EYELINK_DIR "mono250.asc"), NULL, &t) == FS_OK);
    if (t.count > 0) {
        CHECK_NEAR(t.samples[0].x, 510.1 / 1024.0, 1e-6);
        CHECK_NEAR(t.samples[0].y, 383.0 / 768.0, 1e-6);
        CHECK_NEAR(t.samples[1].t, 0.004, 1e-12); /* 250 Hz */
        CHECK(t.samples[0].confidence == 1.0f);
    }
    gaze_free(&t);
}

TEST(eyelink_binocular_eye_choice)
{
    gaze_trace l, r, a, v;
    const char *p = test_shared_path(EYELINK_DIR "bino500.asc");
    CHECK(gaze_load(p, &(gaze_load_desc){.eye = GAZE_EYE_LEFT}, &l) == FS_OK);
    CHECK(gaze_load(p, &(gaze_load_desc){.eye = GAZE_EYE_RIGHT}, &r) == FS_OK);
    CHECK(gaze_load(p, &(gaze_load_desc){.eye = GAZE_EYE_AUTO}, &a) == FS_OK);
    CHECK(gaze_load(p, &(gaze_load_desc){.eye = GAZE_EYE_AVERAGE}, &v) == FS_OK);
    CHECK(l.count == 1745 && r.count == 1745 && a.count == 1745 && v.count == 1745);
    if (l.count == 1745 && r.count == 1745 && a.count == 1745 && v.count == 1745) {
        /* first sample: 6185399  504.5 367.1 922.0  508.0 399.5 913.0 */
        CHECK_NEAR(l.samples[0].x, 504.5 / 1024, 1e-6);
        CHECK_NEAR(r.samples[0].y, 399.5 / 768, 1e-6);
        double diff = 0;
        int between = 0;
        for (int i = 0; i < 1745; i++) {
            double lx = l.samples[i].x, rx = r.samples[i].x, ly = l.samples[i].y, ry = r.samples[i].y;
            diff += fabs(lx - rx) + fabs(ly - ry);
            between += a.samples[i].x >= fmin(lx, rx) - 1e-6 && a.samples[i].x <= fmax(lx, rx) + 1e-6 &&
                       a.samples[i].y >= fmin(ly, ry) - 1e-6 && a.samples[i].y <= fmax(ly, ry) + 1e-6;
            CHECK_NEAR(a.samples[i].x, v.samples[i].x, 1e-6); /* no missing eye in bino500 */
        }
        CHECK(diff / 1745 > 0.005); /* the eyes differ by several pixels */
        CHECK(between == 1745);
    }
    gaze_free(&l);
    gaze_free(&r);
    gaze_free(&a);
    gaze_free(&v);
}

TEST(eyelink_binocular_missing_eye)
{
    /* binoRemote500: 70 samples miss the left eye, 54 both (SOURCES.md B1 counts the 70). */
    static const struct {
        gaze_eye eye;
        int invalid;
    } k[] = {{GAZE_EYE_LEFT, 70}, {GAZE_EYE_RIGHT, 54}, {GAZE_EYE_AVERAGE, 70}, {GAZE_EYE_AUTO, 54}};
    for (size_t i = 0; i < sizeof k / sizeof k[0]; i++) {
        gaze_trace t;
        CHECK(gaze_load(test_shared_path(EYELINK_DIR "binoRemote500.asc"), &(gaze_load_desc){.eye = k[i].eye}, &t) ==
              FS_OK);
        CHECK(t.count == 48224);
        CHECK(t.count - t.valid_count == k[i].invalid);
        gaze_free(&t);
    }
}

TEST(eyelink_monocular_eye)
{
    gaze_trace t;
    log_set_quiet_errors(true);
    /* mono250 records the left eye, mono1000 the right one. */
    CHECK(gaze_load(test_shared_path(EYELINK_DIR "mono250.asc"), &(gaze_load_desc){.eye = GAZE_EYE_RIGHT}, &t) ==
          FS_ERR_GAZE);
    CHECK(t.samples == NULL && t.count == 0);
    CHECK(gaze_load(test_shared_path(EYELINK_DIR "mono1000.asc"), &(gaze_load_desc){.eye = GAZE_EYE_LEFT}, &t) ==
          FS_ERR_GAZE);
    log_set_quiet_errors(false);
    CHECK(gaze_load(test_shared_path(EYELINK_DIR "mono1000.asc"), &(gaze_load_desc){.eye = GAZE_EYE_RIGHT}, &t) ==
          FS_OK);
    CHECK(t.count == 3619);
    gaze_free(&t);
    CHECK(gaze_load(test_shared_path(EYELINK_DIR "mono250.asc"), &(gaze_load_desc){.eye = GAZE_EYE_AVERAGE}, &t) ==
          FS_OK);
    CHECK(t.count == 914);
    gaze_free(&t);
}

TEST(tobii_livedata_loads)
{
    gaze_trace t;
    CHECK(gaze_load(test_shared_path(TOBII_LIVEDATA), NULL, &t) == FS_OK);
    CHECK(t.format == GAZE_FORMAT_TOBII);
    CHECK(t.count == 1424);
    CHECK(t.valid_count == 1331);
    CHECK(t.count - count_valid(&t) == 93);
    CHECK(times_ok(&t));
    CHECK_NEAR(t.duration, 28.723466, 1e-6);
    CHECK_NEAR(t.time_offset, 484.678568, 1e-9);
    CHECK(t.screen_w == 0 && t.screen_h == 0);
    /* SOURCES.md B2: valid gp x spans 0.339-0.756, y 0.021-0.827 */
    float x0 = 1, x1 = 0, y0 = 1, y1 = 0;
    for (int i = 0; i < t.count; i++) {
        if (!t.samples[i].valid)
            continue;
        x0 = fminf(x0, t.samples[i].x), x1 = fmaxf(x1, t.samples[i].x);
        y0 = fminf(y0, t.samples[i].y), y1 = fmaxf(y1, t.samples[i].y);
    }
    CHECK_NEAR(x0, 0.339, 0.001);
    CHECK_NEAR(x1, 0.756, 0.001);
    CHECK_NEAR(y0, 0.021, 0.001);
    CHECK_NEAR(y1, 0.827, 0.001);
    /* first gaze record: {"ts":484678568,"s":0,...,"gp":[0.5234,0.4100]} */
    if (t.count > 0) {
        CHECK_NEAR(t.samples[0].x, 0.5234, 1e-6);
        CHECK_NEAR(t.samples[0].y, 0.4100, 1e-6);
    }
    gaze_free(&t);
}

TEST(pupil_export_loads)
{
    gaze_trace t;
    CHECK(gaze_load(test_source_path("tests/data/pupil_gaze_positions.csv"), NULL, &t) == FS_OK);
    CHECK(t.format == GAZE_FORMAT_PUPIL);
    /* 24 rows, 2 timestamps appear twice -> 22 samples; 7123.11 (confidence 0.3) is invalid. */
    CHECK(t.count == 22);
    CHECK(t.valid_count == 21);
    CHECK(times_ok(&t));
    CHECK_NEAR(t.time_offset, 7123.1, 1e-9);
    if (t.count == 22) {
        CHECK_NEAR(t.samples[0].x, 0.40, 1e-6);
        CHECK_NEAR(t.samples[0].y, 0.30, 1e-6); /* 1 - norm_pos_y */
        CHECK_NEAR(t.samples[0].confidence, 0.95, 1e-6);
        CHECK_NEAR(t.samples[1].t, 0.005, 1e-9);
        CHECK_NEAR(t.samples[1].x, 0.43, 1e-6); /* two rows averaged */
        CHECK_NEAR(t.samples[1].y, 0.33, 1e-6);
        CHECK_NEAR(t.samples[1].confidence, 0.85, 1e-6);
        CHECK(!t.samples[2].valid);
        CHECK_NEAR(t.samples[2].x, 0.43, 1e-6); /* an invalid sample holds the gaze before it */
        CHECK(t.samples[4].valid);               /* valid + invalid row: only the valid one counts */
        CHECK_NEAR(t.samples[4].x, 0.48, 1e-6);
        CHECK_NEAR(t.samples[4].y, 0.38, 1e-6);
        CHECK_NEAR(t.samples[5].x, 1.05, 1e-6); /* off the world image: kept in the samples... */
        gaze_point g = gaze_at(&t, t.samples[5].t, NULL);
        CHECK(g.x == 1.0f && g.y == 1.0f); /* ...clamped by gaze_at */
    }
    gaze_free(&t);
    /* Keeping every row: 22 valid samples, and 7123.12 averages both rows. */
    CHECK(gaze_load(test_source_path("tests/data/pupil_gaze_positions.csv"),
                    &(gaze_load_desc){.min_confidence = -1}, &t) == FS_OK);
    CHECK(t.valid_count == 22);
    if (t.count == 22)
        CHECK_NEAR(t.samples[4].x, (0.48 + 0.05) / 2, 1e-6);
    gaze_free(&t);
}

/* >>scripted traces */

TEST(gaze_paths_load)
{
    static const char *const files[] = {"center_fixation.csv", "fixation_saccade.csv", "pursuit_circle.csv",
                                        "pursuit_line.csv",    "reading.csv",          "saccade_worst_case.csv"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        char rel[256];
        snprintf(rel, sizeof rel, "gaze_paths/%s", files[i]);
        gaze_trace t;
        CHECK(gaze_load(test_source_path(rel), NULL, &t) == FS_OK);
        CHECK(t.format == GAZE_FORMAT_CSV);
        CHECK(t.count > 100 && t.valid_count == t.count);
        CHECK(times_ok(&t));
        CHECK(inside_fraction(&t) == 1.0);
        CHECK(t.duration >= 2.0 && t.duration <= 30.0);
        gaze_free(&t);
    }
}

TEST(gaze_paths_worst_case_jumps)
{
    gaze_trace t;
    CHECK(gaze_load(test_source_path("gaze_paths/saccade_worst_case.csv"), NULL, &t) == FS_OK);
    int jumps = 0;
    for (int i = 1; i < t.count; i++) {
        const gaze_sample *a = &t.samples[i - 1], *b = &t.samples[i];
        if (fabs(b->x - a->x) > 0.9 && fabs(b->y - a->y) > 0.9) {
            jumps++;
            CHECK_NEAR(b->t - a->t, 0.001, 1e-6);
            CHECK_NEAR(a->x, 0.02, 1e-6);
            CHECK_NEAR(b->x, 0.98, 1e-6);
            /* the gaze really crosses the display within 1 ms */
            gaze_point mid = gaze_at(&t, a->t + 0.0005, NULL);
            CHECK_NEAR(mid.x, 0.5, 1e-3);
            gaze_point after = gaze_at(&t, b->t, NULL);
            CHECK(after.x == 0.98f && after.y == 0.98f);
        }
    }
    CHECK(jumps == 1);
    gaze_free(&t);
}

TEST(gaze_paths_circle_radius)
{
    gaze_trace t;
    CHECK(gaze_load(test_source_path("gaze_paths/pursuit_circle.csv"), NULL, &t) == FS_OK);
    for (int i = 0; i < t.count; i++)
        CHECK_NEAR(hypot(t.samples[i].x - 0.5, t.samples[i].y - 0.5), 0.25, 1e-5);
    gaze_free(&t);
}

/* >>malformed input */

TEST(malformed_inputs)
{
    static const struct {
        gaze_format format;
        const char *text;
    } k[] = {
        /* detection */
        {GAZE_FORMAT_AUTO, ""},
        {GAZE_FORMAT_AUTO, "\n\n  \n"},
        {GAZE_FORMAT_AUTO, "hello world\n"},
        {GAZE_FORMAT_AUTO, "a,b,c\n1,2,3\n"},
        {GAZE_FORMAT_AUTO, "\x7f" "ELF\x02\x01\x01"},
        /* fovsim CSV */
        {GAZE_FORMAT_AUTO, "t,x,y\n"},                                 /* only a header */
        {GAZE_FORMAT_AUTO, "# comment\nt,x,y\n# nothing else\n\n"},    /* header and comments */
        {GAZE_FORMAT_AUTO, "t,x,y\n0,0.5,0.5\n0.1,abc,0.5\n"},         /* not a number */
        {GAZE_FORMAT_AUTO, "t,x,y\n0,0.5,0.5\n0.1,0.5\n"},             /* missing column */
        {GAZE_FORMAT_AUTO, "t,x,y\n0,0.5,0.5\n0.1,0.5,0.5,7\n"},       /* extra column */
        {GAZE_FORMAT_AUTO, "t,x,y\n0.2,0.5,0.5\n0.1,0.5,0.5\n"},       /* time backwards */
        {GAZE_FORMAT_AUTO, "t,x,y\n0,nan,0.5\n"},                      /* NaN */
        {GAZE_FORMAT_AUTO, "t,x,y\n0,0.5,inf\n"},                      /* Inf */
        {GAZE_FORMAT_AUTO, "t,x,y\n0,0.5,1e999\n"},                    /* overflow */
        {GAZE_FORMAT_AUTO, "t,x,y\n0,0x1p-1,0.5\n"},                   /* hex float */
        {GAZE_FORMAT_AUTO, "t,x,y\n,0.5,0.5\n"},                       /* empty field */
        {GAZE_FORMAT_AUTO, "t,x,y,confidence\n0,0.5,0.5,1.5\n"},       /* confidence > 1 */
        {GAZE_FORMAT_AUTO, "t,x,y,x\n0,0.5,0.5,0.5\n"},                /* column twice */
        {GAZE_FORMAT_AUTO, "t,x,y\n0,\"0.5,0.5\n"},                    /* unterminated quote */
        {GAZE_FORMAT_CSV, "time,x,y\n0,0.5,0.5\n"},                    /* forced: no t column */
        /* Pupil Labs */
        {GAZE_FORMAT_AUTO, "gaze_timestamp,world_index,confidence,norm_pos_x,norm_pos_y\n1.0,0,0.9,0.5\n"},
        {GAZE_FORMAT_AUTO, "gaze_timestamp,world_index,confidence,norm_pos_x,norm_pos_y\n1.0,0,0.9,0.5,x\n"},
        {GAZE_FORMAT_AUTO, "gaze_timestamp,world_index,confidence,norm_pos_x,norm_pos_y\n2.0,0,0.9,0.5,0.5\n"
                           "1.0,0,0.9,0.5,0.5\n"},
        {GAZE_FORMAT_AUTO, "pupil_timestamp,world_index,eye_id,confidence,norm_pos_x,norm_pos_y,diameter\n"
                           "1.0,0,0,0.9,0.5,0.5,30\n"},                /* pupil_positions.csv */
        {GAZE_FORMAT_PUPIL, "t,x,y\n0,0.5,0.5\n"},                     /* forced on a fovsim CSV */
        /* EyeLink */
        {GAZE_FORMAT_AUTO, "** EYELINK\nMSG\t1 DISPLAY_COORDS 0 0 1023 767\nSTART\t10 \tLEFT\tSAMPLES\n"
                           "10\t1.0\t2.0\t3.0\t...\n11x\t1.0\t2.0\t3.0\t...\nEND\t12\n"},   /* bad time */
        {GAZE_FORMAT_AUTO, "** EYELINK\nMSG\t1 DISPLAY_COORDS 0 0 1023 767\nSTART\t10 \tLEFT\tSAMPLES\n"
                           "10\t1.0\t2.0\t...\nEND\t12\n"},                                 /* 2 values */
        {GAZE_FORMAT_AUTO, "** EYELINK\nMSG\t1 DISPLAY_COORDS 0 0 1023 767\nSTART\t10 \tLEFT\tSAMPLES\n"
                           "10\t1.0\tabc\t3.0\t...\nEND\t12\n"},                            /* x word */
        {GAZE_FORMAT_AUTO, "** EYELINK\nMSG\t1 DISPLAY_COORDS 0 0 1023 767\nSTART\t10 \tLEFT\tSAMPLES\n"
                           "12\t1.0\t2.0\t3.0\t...\n11\t1.0\t2.0\t3.0\t...\nEND\t12\n"},    /* backwards */
        {GAZE_FORMAT_AUTO, "** EYELINK\nSTART\t10 \tLEFT\tSAMPLES\n10\t1.0\t2.0\t3.0\t...\nEND\t12\n"}, /* no size */
        {GAZE_FORMAT_AUTO, "** EYELINK\nMSG\t1 DISPLAY_COORDS 0 0 x 767\n"},                /* bad coords */
        {GAZE_FORMAT_AUTO, "** EYELINK\nMSG\t1 DISPLAY_COORDS 0 0 1023 767\nSTART\t10 \tLEFT\tSAMPLES\nEND\t12\n"},
        {GAZE_FORMAT_AUTO, "** EYELINK\nMSG\t1 DISPLAY_COORDS 0 0 1023 767\nSTART\t10 \tLEFT\tSAMPLES\n"
                           "SAMPLES\tHREF\tLEFT\tRATE\t500.00\n10\t1.0\t2.0\t3.0\t...\nEND\t12\n"}, /* HREF */
        {GAZE_FORMAT_EYELINK, "t,x,y\n0,0.5,0.5\n"},
        /* Tobii */
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.5]}\n{\"ts\":2,\"s\":0,\"gp\":[0.5,0.5]\n"}, /* no '}' */
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.5]}\n{\"ts\":2,\"s\":0,\"gp\":[0.5]}\n"},   /* 1 number */
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.5]}\n{\"ts\":\"2\",\"s\":0,\"gp\":[0.5,0.5]}\n"},
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.5]}\n{\"s\":0,\"gp\":[0.5,0.5]}\n"},       /* no ts */
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.5]}\n{\"ts\":2,\"gp\":[0.5,0.5]}\n"},      /* no s */
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.5]} x\n"},                               /* trailing */
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"gp\":[NaN,0.5]}\n"},
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"ac\":[1,2,3]}\n"},                                   /* no gaze */
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"x\":\"a\\qb\",\"gp\":[0.5,0.5]}\n"},                 /* bad escape */
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.5]}\n[1,2]\n"},                          /* not an object */
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.5]}\n{\"ts\":2 \"s\":0}\n"},             /* no comma */
        {GAZE_FORMAT_AUTO, "{\"ts\":1,\"s\":0,\"gp\":[01,0.5]}\n"},                                  /* leading 0 */
        {GAZE_FORMAT_TOBII, "t,x,y\n0,0.5,0.5\n"},
    };
    log_set_quiet_errors(true);
    for (size_t i = 0; i < sizeof k / sizeof k[0]; i++) {
        gaze_trace t;
        fs_status s = parse_str(k[i].text, &(gaze_load_desc){.format = k[i].format}, &t);
        if (s != FS_ERR_GAZE)
            fprintf(stderr, "  malformed input %zu was accepted (status %d)\n", i, (int)s);
        CHECK(s == FS_ERR_GAZE);
        CHECK(t.samples == NULL && t.count == 0);
        gaze_free(&t);
    }
    log_set_quiet_errors(false);
}

static const char *write_file(const char *name, const char *text, size_t n)
{
    static char buf[1200];
    snprintf(buf, sizeof buf, "%s/%s", test_out_dir(), name);
    FILE *f = fopen(buf, "wb");
    if (f) {
        fwrite(text, 1, n, f);
        fclose(f);
    }
    return buf;
}

TEST(load_errors)
{
    gaze_trace t;
    log_set_quiet_errors(true);
    CHECK(gaze_load(test_shared_path("gaze/no_such_file.csv"), NULL, &t) == FS_ERR_IO);
    CHECK(gaze_load(test_shared_path("gaze"), NULL, &t) == FS_ERR_IO); /* a directory */
    CHECK(gaze_load(write_file("gaze_empty.csv", "", 0), NULL, &t) == FS_ERR_GAZE);
    CHECK(gaze_load(write_file("gaze_header.csv", "t,x,y\r\n", 7), NULL, &t) == FS_ERR_GAZE);
    CHECK(gaze_load(test_shared_path("gaze/tobii_glasses2_glassesviewer_demo/calibration.json"), NULL, &t) ==
          FS_ERR_GAZE);
    CHECK(t.samples == NULL);
    log_set_quiet_errors(false);
    CHECK(gaze_load(write_file("gaze_ok.csv", "t,x,y\n0,0.5,0.5\n", 16), NULL, &t) == FS_OK);
    CHECK(t.count == 1);
    gaze_free(&t);
    gaze_free(NULL);
}

/* Random bytes and byte-flipped real files through every reader: an error or a trace, never a crash
 * (the real check is running this under ASan/UBSan). */
TEST(garbage_never_crashes)
{
    unsigned seed = 12345;
    char buf[4096];
    static const char *const bases[] = {
        "t,x,y,confidence\n0,0.5,0.5,1\n0.01,0.6,0.4,0.9\n0.02,0.7,0.3,0.2\n",
        "gaze_timestamp,world_index,confidence,norm_pos_x,norm_pos_y,base_data\n1.0,0,0.9,0.5,0.5,1.0-0\n"
        "1.01,0,0.9,0.5,0.5,1.01-1\n",
        "** EYELINK\nMSG\t1 DISPLAY_COORDS 0 0 1023 767\nSTART\t10 \tLEFT\tRIGHT\tSAMPLES\n10\t1.0\t2.0\t3.0\t4\t5\t6\t.....\n"
        "12\t.\t.\t0.0\t4\t5\t6\t.C...\nEND\t12\n",
        "{\"ts\":2,\"s\":0,\"gidx\":1,\"l\":3,\"gp\":[0.5,0.4]}\n{\"ts\":1,\"s\":0,\"eye\":\"left\",\"pd\":3.1}\n"
        "{\"ts\":3,\"s\":1,\"dir\":\"out\",\"gp\":[0,0]}\n",
    };
    log_set_quiet_errors(true);
    int ok = 0;
    for (int iter = 0; iter < 4000; iter++) {
        size_t n;
        const char *base = bases[iter % 4];
        if (iter % 5 == 4) { /* random bytes */
            n = (size_t)(iter * 7 % (int)sizeof buf);
            for (size_t i = 0; i < n; i++) {
                seed = seed * 1103515245u + 12345u;
                buf[i] = (char)(seed >> 16);
            }
        } else { /* a valid file with a few bytes changed, or cut short */
            n = strlen(base);
            memcpy(buf, base, n);
            for (int j = 0; j < 1 + iter % 3; j++) {
                seed = seed * 1103515245u + 12345u;
                size_t at = (seed >> 8) % n;
                seed = seed * 1103515245u + 12345u;
                /* mostly bytes that matter to the readers, sometimes any byte */
                static const char alphabet[] = "0123456789.,-+eE\t\n \"{}[]:#\\";
                buf[at] = seed % 5 ? alphabet[(seed >> 16) % (sizeof alphabet - 1)] : (char)(seed >> 16);
            }
            seed = seed * 1103515245u + 12345u;
            if (seed % 3 == 0)
                n = (seed >> 8) % n;
        }
        gaze_trace t;
        fs_status s = gaze_parse(n ? buf : NULL, (long)n, "garbage", &(gaze_load_desc){.format = (gaze_format)(iter % 5)},
                                 &t);
        CHECK(s == FS_OK || s == FS_ERR_GAZE);
        if (s == FS_OK) {
            ok++;
            CHECK(t.count >= 1 && times_ok(&t));
            gaze_point g = gaze_at(&t, t.duration * 0.5, NULL);
            CHECK(g.x >= 0 && g.x <= 1 && g.y >= 0 && g.y <= 1);
        }
        gaze_free(&t);
    }
    log_set_quiet_errors(false);
    printf("garbage_never_crashes: %d of 4000 inputs loaded\n", ok);
    CHECK(ok > 100); /* the flips do not break every file */
}

TEST(huge_lines)
{
    const size_t n = 8u << 20;
    char *text = malloc(n + 64);
    CHECK(text != NULL);
    if (!text)
        return;
    gaze_trace t;
    log_set_quiet_errors(true);
    /* one 8 MiB line with no newline, of each kind */
    static const char fill[] = {'x', ',', '1', '{', '"', '\t', '\0'};
    for (size_t k = 0; k < sizeof fill; k++) {
        memset(text, fill[k], n);
        CHECK(gaze_parse(text, (long)n, "huge", NULL, &t) == FS_ERR_GAZE);
        CHECK(gaze_parse(text, (long)n, "huge", &(gaze_load_desc){.format = GAZE_FORMAT_TOBII}, &t) == FS_ERR_GAZE);
        CHECK(gaze_parse(text, (long)n, "huge", &(gaze_load_desc){.format = GAZE_FORMAT_EYELINK}, &t) ==
              FS_ERR_GAZE);
        CHECK(gaze_parse(text, (long)n, "huge", &(gaze_load_desc){.format = GAZE_FORMAT_PUPIL}, &t) == FS_ERR_GAZE);
    }
    /* a huge header, then a huge row of commas */
    memcpy(text, "t,x,y", 5);
    memset(text + 5, ',', n / 2);
    text[5 + n / 2] = '\n';
    memset(text + 6 + n / 2, ',', n / 2);
    CHECK(gaze_parse(text, (long)(6 + n), "huge", NULL, &t) == FS_ERR_GAZE);
    /* deeply nested JSON */
    size_t d = 0;
    d += (size_t)sprintf(text, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.5],\"deep\":");
    for (int i = 0; i < 100000; i++)
        text[d++] = '[';
    CHECK(gaze_parse(text, (long)d, "deep", NULL, &t) == FS_ERR_GAZE);
    log_set_quiet_errors(false);
    free(text);
}

/* >>formats in detail */

TEST(csv_columns_comments_crlf)
{
    gaze_trace t;
    /* BOM, comment, columns in another order, an extra column, CRLF, blank and comment lines,
     * quoted fields, spaces */
    const char *text = "\xEF\xBB\xBF# a trace\r\n"
                       "note, y ,x,T\r\n"
                       "\"a, b\",0.25,0.75,10\r\n"
                       "\r\n"
                       "# pause\r\n"
                       "c, 0.5 ,\"0.5\",10.5\r\n";
    CHECK(parse_str(text, NULL, &t) == FS_OK);
    CHECK(t.format == GAZE_FORMAT_CSV);
    CHECK(t.count == 2);
    if (t.count == 2) {
        CHECK(t.samples[0].t == 0.0 && t.samples[1].t == 0.5);
        CHECK(t.samples[0].x == 0.75f && t.samples[0].y == 0.25f);
        CHECK(t.samples[0].confidence == 1.0f && t.samples[0].valid);
    }
    CHECK(t.time_offset == 10.0);
    CHECK(strcmp(t.path, "test") == 0);
    gaze_free(&t);
}

TEST(csv_confidence_threshold)
{
    gaze_trace t;
    const char *text = "t,x,y,confidence\n0,0.1,0.1,0.9\n1,0.2,0.2,0.59\n2,0.3,0.3,0.6\n3,0.4,0.4,0.1\n";
    CHECK(parse_str(text, NULL, &t) == FS_OK); /* default 0.6 */
    CHECK(t.valid_count == 2);
    CHECK(t.count == 4 && t.samples[2].valid && !t.samples[3].valid);
    gaze_free(&t);
    CHECK(parse_str(text, &(gaze_load_desc){.min_confidence = 0.05f}, &t) == FS_OK);
    CHECK(t.valid_count == 4);
    gaze_free(&t);
    log_set_quiet_errors(true); /* the "no valid sample" warning */
    CHECK(parse_str(text, &(gaze_load_desc){.min_confidence = 0.95f}, &t) == FS_OK);
    log_set_quiet_errors(false);
    CHECK(t.valid_count == 0);
    bool end;
    gaze_point g = gaze_at(&t, 1.0, &end);
    CHECK(g.x == 0.5f && g.y == 0.5f && !end); /* no valid sample: the centre */
    gaze_free(&t);
    CHECK(parse_str(text, &(gaze_load_desc){.min_confidence = -1}, &t) == FS_OK);
    CHECK(t.valid_count == 4);
    gaze_free(&t);
}

TEST(repeated_timestamps_averaged)
{
    gaze_trace t;
    const char *text = "t,x,y,confidence\n"
                       "0,0.1,0.2,1\n"
                       "0,0.3,0.4,0.8\n"
                       "1,0.5,0.5,1\n"
                       "1,0.5,0.5,1\n"
                       "1,0.8,0.2,1\n"
                       "2,0.9,0.9,0.1\n" /* invalid + valid at t = 2: only the valid one */
                       "2,0.6,0.7,0.7\n"
                       "3,0.1,0.1,0.1\n" /* all invalid at t = 3 */
                       "3,0.3,0.3,0.3\n";
    CHECK(parse_str(text, NULL, &t) == FS_OK);
    CHECK(t.count == 4);
    if (t.count == 4) {
        CHECK_NEAR(t.samples[0].x, 0.2, 1e-6);
        CHECK_NEAR(t.samples[0].y, 0.3, 1e-6);
        CHECK_NEAR(t.samples[0].confidence, 0.9, 1e-6);
        CHECK_NEAR(t.samples[1].x, 0.6, 1e-6);
        CHECK_NEAR(t.samples[1].y, 0.4, 1e-6);
        CHECK(t.samples[2].valid);
        CHECK_NEAR(t.samples[2].x, 0.6, 1e-6);
        CHECK_NEAR(t.samples[2].confidence, 0.7, 1e-6);
        CHECK(!t.samples[3].valid);
        CHECK_NEAR(t.samples[3].confidence, 0.2, 1e-6);
    }
    CHECK(t.valid_count == 3);
    gaze_free(&t);
}

TEST(eyelink_variants)
{
    gaze_trace t;
    /* Header-less sample lines are one block; a 2000 Hz-style repeated time is averaged; events,
     * messages and the indented calibration numbers are skipped. */
    const char *mono = "** DATE: test\n"
                       "MSG\t100 DISPLAY_COORDS 0 0 99 49\n"
                       "   5656.2  233.84 -41.107  1.4823 -0.60013\n"
                       "START\t1000 \tRIGHT\tSAMPLES\tEVENTS\n"
                       "SAMPLES\tGAZE\tRIGHT\tRATE\t2000.00\tTRACKING\tCR\tFILTER\t2\n"
                       "1000\t  10.0\t  20.0\t 1000.0\t...\n"
                       "1000\t  20.0\t  30.0\t 1000.0\t...\n"
                       "SFIX R   1001\n"
                       "1001\t   .\t   .\t    0.0\t...\n"
                       "SBLINK R 1001\n"
                       "1002\t  50.0\t  25.0\t 1000.0\tI..\n"
                       "END\t1002 \tSAMPLES\tEVENTS\tRES\t 35.18\t 35.14\n"
                       "5000\t  50.0\t  25.0\t 1000.0\t...\n" /* outside a block: not a sample */
                       "INPUT\t5001\t0\n"
                       "START\t6000 \tRIGHT\tSAMPLES\tEVENTS\n"
                       "6000\t  -10.0\t  60.0\t 1000.0\t...\n"
                       "END\t6001\n";
    CHECK(parse_str(mono, NULL, &t) == FS_OK);
    CHECK(t.format == GAZE_FORMAT_EYELINK);
    CHECK(t.screen_w == 100 && t.screen_h == 50);
    CHECK(t.count == 4 && t.valid_count == 3);
    if (t.count == 4) {
        CHECK_NEAR(t.samples[0].x, 0.15, 1e-6);
        CHECK_NEAR(t.samples[0].y, 0.5, 1e-6);
        CHECK(!t.samples[1].valid);
        CHECK_NEAR(t.samples[1].t, 0.001, 1e-12);
        CHECK_NEAR(t.samples[2].x, 0.5, 1e-6);
        CHECK_NEAR(t.samples[3].t, 5.0, 1e-12); /* the gap between blocks stays */
        CHECK_NEAR(t.samples[3].x, -0.1, 1e-6); /* off screen: kept */
    }
    gaze_free(&t);
    /* Remote mode: target columns and the 13-char flags after the 3-char flags; GAZE_COORDS only;
     * fractional times; a MSG with an offset. */
    const char *remote = "MSG\t99 -3 GAZE_COORDS 0.00 0.00 199.00 99.00\n"
                         "START\t100 \tLEFT\tSAMPLES\tEVENTS\n"
                         "SAMPLES\tGAZE\tLEFT\tHTARGET\tRATE\t 250.00\tTRACKING\tCR\tFILTER\t2\n"
                         "100.5\t  100.0\t  50.0\t  228.0\t... \t 4717.0\t 2908.0\t  611.2 .............\n"
                         "104.5\t  .\t  .\t  0.0\t... \t 4717.0\t 2908.0\t  611.2 MANTBL........\n"
                         "END\t105\n";
    CHECK(parse_str(remote, NULL, &t) == FS_OK);
    CHECK(t.screen_w == 200 && t.screen_h == 100);
    CHECK(t.count == 2 && t.valid_count == 1);
    CHECK_NEAR(t.time_offset, 0.1005, 1e-12);
    if (t.count == 2)
        CHECK_NEAR(t.samples[0].x, 0.5, 1e-6);
    gaze_free(&t);
    /* Binocular with velocity columns (10 values) and CRLF. */
    const char *vel = "MSG\t1 DISPLAY_COORDS 0 0 999 999\r\n"
                      "START\t10 \tLEFT\tRIGHT\tSAMPLES\r\n"
                      "10\t100\t200\t1\t300\t400\t1\t5\t5\t5\t5\t.....\r\n"
                      "12\t100\t200\t1\t.\t.\t0.0\t5\t5\t5\t5\t...C.\r\n"
                      "END\t12\r\n";
    CHECK(parse_str(vel, &(gaze_load_desc){.eye = GAZE_EYE_AUTO}, &t) == FS_OK);
    CHECK(t.count == 2 && t.valid_count == 2);
    if (t.count == 2) {
        CHECK_NEAR(t.samples[0].x, 0.2, 1e-6);
        CHECK_NEAR(t.samples[1].x, 0.1, 1e-6); /* right eye missing: the left one */
    }
    gaze_free(&t);
    CHECK(parse_str(vel, &(gaze_load_desc){.eye = GAZE_EYE_AVERAGE}, &t) == FS_OK);
    CHECK(t.valid_count == 1);
    gaze_free(&t);
}

TEST(tobii_sorted_and_filtered)
{
    gaze_trace t;
    /* Streams interleave and are out of order; per-eye records carry "eye"; s != 0 is invalid. */
    const char *text = "{\"ts\":3000,\"s\":0,\"pts\":622438,\"pv\":4}\n"
                       "{\"ts\":2000,\"s\":0,\"gidx\":2,\"l\":5,\"gp\":[0.3,0.4]}\n"
                       "{\"ts\":1500,\"s\":0,\"gidx\":1,\"eye\":\"left\",\"gp\":[9,9]}\n"
                       "\n"
                       "{\"ts\":1000,\"s\":0,\"gidx\":1,\"l\":5,\"gp\":[0.1,0.2]}\n"
                       "{\"ts\":1000,\"s\":0,\"gidx\":1,\"gp3\":[1.5,-2.0e1,3]}\n"
                       "{\"ts\":4000,\"s\":1,\"gidx\":4,\"l\":5,\"gp\":[0.0,0.0]}\n"
                       "{ \"ts\" : 3000 , \"s\" : 0 , \"ac\" : [ -0.039 , -10.146 , 0.840 ] , \"x\" : {\"a\":[true,false,null,\"\\u00e9\\n\"]} }\n"
                       "{\"ts\":5000,\"s\":0,\"gp\":[0.5,0.6]}";
    CHECK(parse_str(text, NULL, &t) == FS_OK);
    CHECK(t.format == GAZE_FORMAT_TOBII);
    CHECK(t.count == 4 && t.valid_count == 3);
    CHECK(times_ok(&t));
    CHECK_NEAR(t.time_offset, 0.001, 1e-12);
    if (t.count == 4) {
        CHECK_NEAR(t.samples[0].x, 0.1, 1e-6);
        CHECK_NEAR(t.samples[1].t, 0.001, 1e-12);
        CHECK_NEAR(t.samples[1].y, 0.4, 1e-6);
        CHECK(!t.samples[2].valid);
        CHECK_NEAR(t.samples[3].t, 0.004, 1e-12);
    }
    gaze_free(&t);
}

/* README "Limits": a Tobii line nests at most 1000 arrays and objects deep, its object included
 * (cJSON's CJSON_NESTING_LIMIT); the rest of such a line still counts. */
TEST(tobii_nesting_limit)
{
    char *text = malloc(4096);
    CHECK(text != NULL);
    if (!text)
        return;
    log_set_quiet_errors(true);
    for (int arrays = 998; arrays <= 1000; arrays++) {
        int n = sprintf(text, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.25],\"deep\":");
        for (int i = 0; i < arrays; i++)
            text[n++] = '[';
        for (int i = 0; i < arrays; i++)
            text[n++] = ']';
        text[n++] = '}';
        gaze_trace t;
        fs_status s = gaze_parse(text, n, "deep", NULL, &t);
        CHECK(s == (arrays < 1000 ? FS_OK : FS_ERR_GAZE));
        if (s == FS_OK)
            CHECK(t.count == 1 && t.samples[0].y == 0.25f);
        gaze_free(&t);
    }
    log_set_quiet_errors(false);
    free(text);
}

/* README "Limits": a Tobii line is at most MAX_TOBII_RECORD_BYTES long, refused by its
 * length before cJSON builds a tree of it (about 40 bytes a byte: a 100 MB record took 4 GB). A
 * valid gaze record padded to the bound loads; one byte more is refused, naming the bound. */
TEST(tobii_record_bound)
{
    const size_t max = MAX_TOBII_RECORD_BYTES;
    char *text = malloc(max + 2);
    CHECK(text != NULL);
    if (!text)
        return;
    log_set_quiet_errors(true);
    for (size_t len = max; len <= max + 1; len++) {
        int n = sprintf(text, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.25],\"pad\":\"");
        memset(text + n, 'x', len - (size_t)n - 2);
        memcpy(text + len - 2, "\"}", 2);
        text[len] = '\0';
        gaze_trace t;
        fs_status s = gaze_parse(text, (long)len, "long", NULL, &t);
        CHECK(s == (len <= max ? FS_OK : FS_ERR_GAZE));
        if (s == FS_OK)
            CHECK(t.count == 1 && t.samples[0].y == 0.25f);
        gaze_free(&t);
    }
    log_set_quiet_errors(false);
    free(text);
}

/* Out of memory while cJSON builds a line's tree is exit 9 (FS_ERR_NOMEM), not "expected valid
 * JSON" (it was exit 5). The address space is capped near what the process has mapped and the heap
 * filled with 64-byte blocks (cJSON's node size) until malloc fails; 64 KB of them are given back,
 * enough to start, not for the 20,000 nodes of the line. Restored after. Skipped under the
 * sanitizers, which map terabytes of shadow memory. */
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define NO_RLIMIT_TEST 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || __has_feature(thread_sanitizer)
#define NO_RLIMIT_TEST 1
#endif
#endif
TEST(tobii_out_of_memory)
{
#ifdef NO_RLIMIT_TEST
    fprintf(stderr, "  (skipped under a sanitizer)\n");
#else
    const int count = 20000;
    char *text = malloc((size_t)count * 2 + 64);
    CHECK(text != NULL);
    if (!text)
        return;
    int n = sprintf(text, "{\"ts\":1,\"s\":0,\"gp\":[0.5,0.25],\"a\":[");
    for (int i = 0; i < count; i++)
        n += sprintf(text + n, i ? ",0" : "0");
    n += sprintf(text + n, "]}");
    CHECK((size_t)n <= MAX_TOBII_RECORD_BYTES);
    gaze_trace t;
    CHECK(gaze_parse(text, n, "big", NULL, &t) == FS_OK); /* it loads with memory enough */
    gaze_free(&t);
    struct rlimit old;
    long pages = 0;
    FILE *f = fopen("/proc/self/statm", "r");
    bool have = f && fscanf(f, "%ld", &pages) == 1 && getrlimit(RLIMIT_AS, &old) == 0;
    if (f)
        fclose(f);
    CHECK(have);
    if (have) {
        malloc_trim(0);
        struct rlimit cap = old;
        cap.rlim_cur = (rlim_t)pages * 4096 + (256u << 10);
        log_set_quiet_errors(true);
        fs_status s = FS_ERR_INTERNAL;
        if (setrlimit(RLIMIT_AS, &cap) == 0) {
            void **ballast = NULL, **b;
            while ((b = malloc(64)) != NULL) {
                *b = ballast;
                ballast = b;
            }
            for (int i = 0; i < 1000 && ballast; i++) {
                b = *ballast;
                free(ballast);
                ballast = b;
            }
            s = gaze_parse(text, n, "big", NULL, &t);
            while (ballast) {
                b = *ballast;
                free(ballast);
                ballast = b;
            }
            setrlimit(RLIMIT_AS, &old);
        }
        log_set_quiet_errors(false);
        if (s != FS_ERR_NOMEM)
            fprintf(stderr, "  status %d\n", (int)s);
        CHECK(s == FS_ERR_NOMEM);
        gaze_free(&t);
    }
    free(text);
#endif
}

TEST(format_names)
{
    static const gaze_format all[] = {GAZE_FORMAT_AUTO, GAZE_FORMAT_CSV, GAZE_FORMAT_PUPIL, GAZE_FORMAT_EYELINK,
                                      GAZE_FORMAT_TOBII};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        CHECK(gaze_format_parse(gaze_format_name(all[i])) == all[i]);
    CHECK(strcmp(gaze_format_name(GAZE_FORMAT_EYELINK), "eyelink") == 0);
    CHECK(gaze_format_parse("Tobii") == GAZE_FORMAT_TOBII);
    CHECK(gaze_format_parse("edf") == GAZE_FORMAT_AUTO);
    CHECK(gaze_format_parse(NULL) == GAZE_FORMAT_AUTO);
}

/* >>gaze_at */

TEST(gaze_at_interpolates)
{
    gaze_trace t;
    CHECK(parse_str("t,x,y\n0,0.2,0.4\n1,0.6,0.8\n3,0.6,0.2\n", NULL, &t) == FS_OK);
    bool end = true;
    gaze_point g = gaze_at(&t, 0.0, &end);
    CHECK(g.x == 0.2f && g.y == 0.4f && !g.held && !end);
    g = gaze_at(&t, 1.0, &end);
    CHECK(g.x == 0.6f && g.y == 0.8f && !g.held && !end);
    g = gaze_at(&t, 0.5, NULL);
    CHECK_NEAR(g.x, 0.4, 1e-6);
    CHECK_NEAR(g.y, 0.6, 1e-6);
    CHECK(!g.held);
    g = gaze_at(&t, 2.5, &end);
    CHECK_NEAR(g.y, 0.35, 1e-6);
    g = gaze_at(&t, 3.0, &end);
    CHECK(g.x == 0.6f && g.y == 0.2f && !end && !g.held);
    g = gaze_at(&t, -1.0, &end);
    CHECK(g.x == 0.2f && g.y == 0.4f && !end);
    g = gaze_at(&t, NAN, &end);
    CHECK(g.x == 0.2f && g.y == 0.4f);
    gaze_free(&t);
}

TEST(gaze_at_holds_across_blink)
{
    gaze_trace t;
    /* valid at 0 and 1, blink (confidence 0) from 2 to 4 with junk positions, valid at 5 */
    CHECK(parse_str("t,x,y,confidence\n0,0.1,0.1,1\n1,0.3,0.3,1\n2,0.9,0.9,0\n3,0.0,1.0,0\n4,0.9,0.0,0\n"
                    "5,0.7,0.7,1\n",
                    NULL, &t) == FS_OK);
    gaze_point g;
    for (double tm = 1.0 + 1e-6; tm < 5.0; tm += 0.25) {
        g = gaze_at(&t, tm, NULL);
        CHECK(g.x == 0.3f && g.y == 0.3f && g.held);
    }
    g = gaze_at(&t, 5.0, NULL);
    CHECK(g.x == 0.7f && !g.held);
    g = gaze_at(&t, 0.5, NULL);
    CHECK_NEAR(g.x, 0.2, 1e-6);
    CHECK(!g.held);
    gaze_free(&t);
}

TEST(gaze_at_starts_invalid)
{
    gaze_trace t;
    CHECK(parse_str("t,x,y,confidence\n0,0.9,0.9,0\n1,0.8,0.8,0.1\n2,0.25,0.75,1\n3,0.5,0.5,1\n", NULL, &t) == FS_OK);
    gaze_point g = gaze_at(&t, 0.0, NULL);
    CHECK(g.x == 0.25f && g.y == 0.75f && g.held);
    g = gaze_at(&t, 1.5, NULL);
    CHECK(g.x == 0.25f && g.y == 0.75f && g.held);
    g = gaze_at(&t, 2.5, NULL);
    CHECK_NEAR(g.x, 0.375, 1e-6);
    gaze_free(&t);
}

TEST(gaze_at_beyond_end)
{
    gaze_trace t;
    CHECK(parse_str("t,x,y,confidence\n0,0.1,0.1,1\n1,0.4,0.6,1\n2,0.9,0.9,0\n", NULL, &t) == FS_OK);
    bool end = false;
    gaze_point g = gaze_at(&t, 2.0, &end);
    CHECK(!end && g.x == 0.4f && g.held); /* the last sample is invalid: hold */
    g = gaze_at(&t, 2.0001, &end);
    CHECK(end && g.x == 0.4f && g.y == 0.6f && g.held);
    g = gaze_at(&t, 1e9, &end);
    CHECK(end && g.x == 0.4f);
    g = gaze_at(&t, INFINITY, &end);
    CHECK(end && g.x == 0.4f);
    gaze_free(&t);
    /* one sample */
    CHECK(parse_str("t,x,y\n7,0.3,0.7\n", NULL, &t) == FS_OK);
    CHECK(t.duration == 0.0 && t.time_offset == 7.0);
    g = gaze_at(&t, 0.0, &end);
    CHECK(!end && g.x == 0.3f && !g.held);
    g = gaze_at(&t, 1.0, &end);
    CHECK(end && g.x == 0.3f && g.held);
    gaze_free(&t);
    /* an empty trace (not loaded) gives the centre */
    gaze_trace none = {0};
    g = gaze_at(&none, 1.0, &end);
    CHECK(g.x == 0.5f && g.y == 0.5f && !end);
}

TEST(gaze_at_clamps)
{
    gaze_trace t;
    CHECK(parse_str("t,x,y\n0,-0.5,1.5\n1,0.5,0.5\n2,1.5,-0.25\n", NULL, &t) == FS_OK);
    CHECK(t.samples[0].x == -0.5f); /* samples are not clamped */
    gaze_point g = gaze_at(&t, 0.0, NULL);
    CHECK(g.x == 0.0f && g.y == 1.0f);
    g = gaze_at(&t, 0.25, NULL);
    CHECK(g.x == 0.0f && g.y == 1.0f);
    g = gaze_at(&t, 0.75, NULL);
    CHECK_NEAR(g.x, 0.25, 1e-6);
    CHECK_NEAR(g.y, 0.75, 1e-6);
    g = gaze_at(&t, 5, NULL);
    CHECK(g.x == 1.0f && g.y == 0.0f);
    gaze_free(&t);
}

TEST(gaze_at_rebases_start)
{
    gaze_trace t;
    CHECK(parse_str("t,x,y\n1000.5,0.1,0.1\n1001.5,0.3,0.3\n", NULL, &t) == FS_OK);
    CHECK(t.time_offset == 1000.5 && t.samples[0].t == 0.0 && t.duration == 1.0);
    gaze_point g = gaze_at(&t, 0.5, NULL);
    CHECK_NEAR(g.x, 0.2, 1e-6);
    gaze_free(&t);
}

TEST(gaze_at_large_trace)
{
    /* 50k samples at 1 kHz with a blink every 997 samples; 1e6 queries. */
    const int n = 50000;
    size_t cap = (size_t)n * 48 + 64, len = 0;
    char *text = malloc(cap);
    CHECK(text != NULL);
    if (!text)
        return;
    len += (size_t)snprintf(text, cap, "t,x,y,confidence\n");
    for (int i = 0; i < n; i++) {
        double tm = i * 0.001;
        len += (size_t)snprintf(text + len, cap - len, "%.3f,%.6f,%.6f,%d\n", tm, 0.5 + 0.4 * sin(tm),
                                0.5 + 0.4 * cos(tm), i % 997 == 500 ? 0 : 1);
    }
    gaze_trace t;
    struct timespec a, b;
    clock_gettime(CLOCK_MONOTONIC, &a);
    CHECK(gaze_parse(text, (long)len, "large", NULL, &t) == FS_OK);
    clock_gettime(CLOCK_MONOTONIC, &b);
    double parse_ms = (b.tv_sec - a.tv_sec) * 1e3 + (b.tv_nsec - a.tv_nsec) / 1e6;
    free(text);
    CHECK(t.count == n);
    const int q = 1000000;
    double sum = 0, max_err = 0;
    clock_gettime(CLOCK_MONOTONIC, &a);
    for (int i = 0; i < q; i++) {
        /* scattered times so a cached or linear search would not help */
        double tm = fmod(i * 0.7548776662466927, 1.0) * t.duration;
        gaze_point g = gaze_at(&t, tm, NULL);
        sum += g.x;
        if (!g.held)
            max_err = fmax(max_err, fabs(g.x - (0.5 + 0.4 * sin(tm))));
    }
    clock_gettime(CLOCK_MONOTONIC, &b);
    double q_ms = (b.tv_sec - a.tv_sec) * 1e3 + (b.tv_nsec - a.tv_nsec) / 1e6;
    CHECK(max_err < 1e-5);
    CHECK(sum > 0);
    printf("gaze_at_large_trace: parse 50k samples %.1f ms, 1e6 gaze_at %.1f ms\n", parse_ms, q_ms);
    gaze_free(&t);
}

int main(void)
{
    RUN(eyelink_recordings_load);
    RUN(eyelink_first_sample_normalised);
    RUN(eyelink_binocular_eye_choice);
    RUN(eyelink_binocular_missing_eye);
    RUN(eyelink_monocular_eye);
    RUN(tobii_livedata_loads);
    RUN(pupil_export_loads);
    RUN(gaze_paths_load);
    RUN(gaze_paths_worst_case_jumps);
    RUN(gaze_paths_circle_radius);
    RUN(malformed_inputs);
    RUN(load_errors);
    RUN(garbage_never_crashes);
    RUN(huge_lines);
    RUN(csv_columns_comments_crlf);
    RUN(csv_confidence_threshold);
    RUN(repeated_timestamps_averaged);
    RUN(eyelink_variants);
    RUN(tobii_sorted_and_filtered);
    RUN(tobii_nesting_limit);
    RUN(tobii_record_bound);
    RUN(tobii_out_of_memory);
    RUN(format_names);
    RUN(gaze_at_interpolates);
    RUN(gaze_at_holds_across_blink);
    RUN(gaze_at_starts_invalid);
    RUN(gaze_at_beyond_end);
    RUN(gaze_at_clamps);
    RUN(gaze_at_rebases_start);
    RUN(gaze_at_large_trace);
    return test_summary();
}
