/* exr_eyes.h: the two eyes of the multi-view EXR tests (test_exr_views.c, test_exr_views_tools.c):
 * two single-view images of one size with distinct values per eye, channel and pixel, shared
 * and per-eye attributes. Include after test.h. */
#ifndef FOVSIM_TEST_EXR_EYES_H
#define FOVSIM_TEST_EXR_EYES_H

#include <stdbool.h>

#include "output/exr_write.h"

#define W 13
#define H 7

/* The channels of each eye: plain ones (stored unprefixed for the default view) and layered ones. */
static const char *const k_eye_channels[] = {"R", "G", "B", "A", "coverage", "hashed.R", "ring.id"};
enum { NEYE = sizeof k_eye_channels / sizeof k_eye_channels[0] };

static inline const char *path_of(const char *name)
{
    static char buf[4][1200];
    static int k;
    k = (k + 1) & 3;
    snprintf(buf[k], sizeof buf[k], "%s/%s", test_out_dir(), name);
    return buf[k];
}

/* A value per eye, channel and pixel: no two alike between the eyes, and most not halves, so
 * a read that rounds differently or takes the other eye's plane shows. */
static inline float eye_value(int eye, int c, int i)
{
    return 0.001f + 0.37f * (float)eye + 0.031f * (float)c + 0.0007f * (float)i;
}

static inline void make_eye(exr_image *img, int eye, float gaze_x)
{
    CHECK(exr_image_init(img, W, H));
    for (int c = 0; c < NEYE; c++) {
        float *p = exr_image_add_channel(img, k_eye_channels[c]);
        CHECK(p != NULL);
        for (int i = 0; p && i < W * H; i++)
            p[i] = eye_value(eye, c, i);
    }
    exr_image_set_int(img, "fovsim:frame", 12);                /* shared: stored once */
    exr_image_set_string(img, "fovsim:scene", "forest");       /* shared */
    exr_image_set_v2f(img, "fovsim:gaze", gaze_x, 0.25f);      /* the eyes' own: */
    exr_image_set_int(img, "fovsim:eye", eye);
    exr_image_set_string(img, "fovsim:eye_name", eye ? "right" : "left");
    exr_image_set_float(img, "fovsim:hfov_deg", eye ? 96.5f : 96.0f);
    if (eye == 1)
        exr_image_set_float(img, "fovsim:ipd_half_m", 0.032f); /* only the right eye has it */
}

/* Whether `img` has exactly the channels and values of eye `eye` at half precision. */
static inline bool is_eye(const exr_image *img, int eye)
{
    bool ok = img->width == W && img->height == H && img->channel_count == NEYE;
    for (int c = 0; ok && c < NEYE; c++) {
        const float *p = exr_image_channel(img, k_eye_channels[c]);
        ok = p != NULL;
        for (int i = 0; ok && i < W * H; i++)
            ok = p[i] == exr_half_round(eye_value(eye, c, i));
    }
    return ok;
}

#endif
