/* hmd.c: the presets, their keys applied, and an eye's geometry (hmd.h). The text form is
 * hmd_text.c. */
#include "hmd/hmd.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/config.h"

/* >>presets (docs/hmd.md "Presets": where each figure comes from) */

typedef struct hmd_preset {
    const char *name;
    hmd_fov left_eye; /* the right eye is its mirror */
    int width, height;
    float refresh_hz;
} hmd_preset;

/* The Meta Quest Pro's left eye as its OpenXR runtime reports it (xrLocateViews' XrFovf), the
 * values every EyeNavGS recording carries (Ding et al. 2025, arXiv:2506.02380; dataset
 * github.com/symmru/EyeNavGS_Rutgers_Dataset): 53.97 deg temporal, 39.99 nasal, 42.00 up, 53.97
 * down. Both eyes together span 107.9 x 96.0 deg, Meta's published 106 x 96. */
#define QUEST_PRO_FOV {-0.942f, 0.698f, 0.733f, -0.942f}

/* Widths are the published panel's; heights follow the square-pixel rule (hmd_square_height), so
 * the Quest Pro's 1800 x 1920 panel becomes 1800 x 1850 (docs/hmd.md "Square pixels"). */
static const hmd_preset k_presets[] = {
    /* Meta Quest Pro: 1800 x 1920 per eye, 72 or 90 Hz, 106 x 96 deg (Meta's tech specs,
     * www.meta.com/quest/quest-pro/tech-specs); the FOV as above. */
    {"quest-pro", QUEST_PRO_FOV, 1800, 1850, 90.0f},
    /* What an EyeNavGS recording carries: the Quest Pro as recorded, at 72 Hz. */
    {"eyenavgs", QUEST_PRO_FOV, 1800, 1850, 72.0f},
    /* Every figure from the keys (hmd_make checks that they are there). */
    {"custom", {0, 0, 0, 0}, 0, 0, 0.0f},
};
#define PRESET_COUNT (sizeof k_presets / sizeof k_presets[0])

const char *hmd_preset_list(void)
{
    return "quest-pro, eyenavgs, custom";
}

static const hmd_preset *preset_find(const char *name)
{
    for (size_t i = 0; i < PRESET_COUNT; i++)
        if (!strcmp(k_presets[i].name, name))
            return &k_presets[i];
    return NULL;
}

/* >>field of view */

/* 0 - x, not -x: a zero angle stays +0, so that a mirrored eye equals the same eye written out. */
hmd_fov hmd_fov_mirror(hmd_fov f)
{
    return (hmd_fov){0.0f - f.right, 0.0f - f.left, f.up, f.down};
}

bool hmd_fov_from_deg(const double deg[4], hmd_fov *out)
{
    for (int i = 0; i < 4; i++)
        if (!(fabs(deg[i]) <= HMD_ANGLE_MAX_DEG))
            return false;
    if (!(deg[0] < deg[1] && deg[3] < deg[2]))
        return false;
    float r[4];
    for (int i = 0; i < 4; i++)
        r[i] = (float)(deg[i] * FS_PI / 180.0) + 0.0f; /* -0 becomes +0: one zero, one desc */
    *out = (hmd_fov){r[0], r[1], r[2], r[3]};
    return out->left < out->right && out->down < out->up;
}

/* The fields of view in tangent space: x from tan(left) to tan(right), y from tan(down) to tan(up). */
static double span_x(const hmd_fov *f)
{
    return tan((double)f->right) - tan((double)f->left);
}

static double span_y(const hmd_fov *f)
{
    return tan((double)f->up) - tan((double)f->down);
}

/* >>a preset with its keys */

/* The other side of the panel for square pixels in tangent space:
 * width / (tanR - tanL) == height / (tanU - tanD), rounded to whole pixels. */
static int square_other(const hmd_fov *f, int given, bool given_is_width)
{
    double r = given_is_width ? span_y(f) / span_x(f) : span_x(f) / span_y(f);
    return (int)lround((double)given * r);
}

/* Panel size from the keys: both as given, one alone with the other for square pixels, none but a
 * changed field of view: the width kept, the height for square pixels. */
static bool apply_size(hmd_desc *d, const hmd_keys *k, bool fov_changed, char *err, size_t n)
{
    const hmd_fov *f = &d->eye[HMD_LEFT].fov;
    int w = k->width ? k->width : d->eye[0].width, h = k->height ? k->height : d->eye[0].height;
    if (k->width && !k->height)
        h = square_other(f, w, true);
    else if (k->height && !k->width)
        w = square_other(f, h, false);
    else if (!k->width && !k->height && fov_changed)
        h = square_other(f, w, true);
    if (w < 16 || w > MAX_DISPLAY_SIZE || h < 16 || h > MAX_DISPLAY_SIZE) {
        snprintf(err, n, "the panel would be %d x %d pixels for square pixels, outside 16..%d: give both "
                 "'width' and 'height'", w, h, MAX_DISPLAY_SIZE);
        return false;
    }
    d->eye[0].width = d->eye[1].width = w;
    d->eye[0].height = d->eye[1].height = h;
    return true;
}

static bool apply_keys(hmd_desc *d, const hmd_keys *k, char *err, size_t n)
{
    if (k->fov_given[HMD_LEFT]) {
        d->eye[HMD_LEFT].fov = k->fov[HMD_LEFT];
        d->eye[HMD_RIGHT].fov = hmd_fov_mirror(k->fov[HMD_LEFT]);
    }
    if (k->fov_given[HMD_RIGHT])
        d->eye[HMD_RIGHT].fov = k->fov[HMD_RIGHT];
    if (k->ipd_mm > 0)
        d->ipd_mm = k->ipd_mm;
    if (k->refresh_hz > 0)
        d->refresh_hz = k->refresh_hz;
    return apply_size(d, k, k->fov_given[0] || k->fov_given[1], err, n);
}

/* custom has no figures of its own: the keys must give them (named neutrally: the CLI's keys are
 * fov-left, the scene file's fov_left). */
static bool custom_complete(const hmd_keys *k, char *err, size_t n)
{
    const char *missing = !k->fov_given[HMD_LEFT] ? "the left eye's field of view"
                        : !k->refresh_hz         ? "the refresh rate"
                        : !k->width && !k->height ? "the width or height"
                                                  : NULL;
    if (missing)
        snprintf(err, n, "preset 'custom' gives no figures: %s is missing (docs/hmd.md)", missing);
    return !missing;
}

bool hmd_make(const char *preset, const hmd_keys *k, hmd_desc *out, char *err, size_t n)
{
    const hmd_preset *p = preset_find(preset);
    const hmd_keys none = {0};
    if (!k)
        k = &none;
    if (!p) {
        snprintf(err, n, "unknown preset '%s' (presets: %s)", preset, hmd_preset_list());
        return false;
    }
    if (!strcmp(p->name, "custom") && !custom_complete(k, err, n))
        return false;
    memset(out, 0, sizeof *out);
    snprintf(out->preset, sizeof out->preset, "%s", p->name);
    for (int e = 0; e < 2; e++) {
        out->eye[e].fov = e == HMD_LEFT ? p->left_eye : hmd_fov_mirror(p->left_eye);
        out->eye[e].width = p->width;
        out->eye[e].height = p->height;
    }
    out->ipd_mm = HMD_IPD_DEFAULT_MM;
    out->refresh_hz = p->refresh_hz;
    if (!apply_keys(out, k, err, n))
        return false;
    for (int e = 0; e < 2; e++) /* OpenXR's head frame: the eyes on x, left negative */
        out->eye[e].position = v3((e == HMD_LEFT ? -0.0005f : 0.0005f) * out->ipd_mm, 0.0f, 0.0f);
    return true;
}

/* >>an eye's geometry */

mat4 hmd_projection(const hmd_fov *f, float n, float far)
{
    double l = tan((double)f->left), r = tan((double)f->right), u = tan((double)f->up), d = tan((double)f->down);
    mat4 m = {{0}};
    m.m[0] = (float)(2.0 / (r - l));
    m.m[5] = (float)(2.0 / (u - d));
    m.m[8] = (float)((r + l) / (r - l)); /* the off-centre shift: column 2, the z of the eye-space point */
    m.m[9] = (float)((u + d) / (u - d));
    m.m[10] = (far + n) / (n - far);
    m.m[11] = -1.0f;
    m.m[14] = 2.0f * far * n / (n - far);
    return m;
}

hmd_pinhole hmd_eye_pinhole(const hmd_eye *e)
{
    const hmd_fov *f = &e->fov;
    double fx = e->width / span_x(f), fy = e->height / span_y(f);
    return (hmd_pinhole){(float)fx, (float)fy, (float)(-tan((double)f->left) * fx),
                         (float)(tan((double)f->up) * fy)};
}

bool hmd_dir_to_pixel(const hmd_eye *e, vec3 d, float *px, float *py)
{
    if (!(d.z < 0.0f))
        return false;
    const hmd_fov *f = &e->fov;
    double u = d.x / -(double)d.z, v = d.y / -(double)d.z;
    *px = (float)((u - tan((double)f->left)) / span_x(f) * e->width);
    *py = (float)((tan((double)f->up) - v) / span_y(f) * e->height);
    return true;
}

vec3 hmd_pixel_to_dir(const hmd_eye *e, float px, float py)
{
    const hmd_fov *f = &e->fov;
    double u = tan((double)f->left) + (double)px / e->width * span_x(f);
    double v = tan((double)f->up) - (double)py / e->height * span_y(f);
    double len = sqrt(u * u + v * v + 1.0);
    return v3((float)(u / len), (float)(v / len), (float)(-1.0 / len));
}

float hmd_pixel_angle_deg(const hmd_eye *e, float px, float py, vec3 gaze)
{
    vec3 a = hmd_pixel_to_dir(e, px, py);
    vec3 c = v3_cross(a, gaze);
    /* atan2 of |a x g| and a . g: accurate at small angles, where acos of the dot is not. */
    return (float)(atan2((double)v3_len(c), (double)v3_dot(a, gaze)) * 180.0 / FS_PI);
}

void hmd_ppd(const hmd_eye *e, float *ppd_x, float *ppd_y)
{
    /* At the principal point a pixel offset is f tan(angle): f * pi / 180 pixels per degree. */
    hmd_pinhole p = hmd_eye_pinhole(e);
    *ppd_x = (float)(p.fx * FS_PI / 180.0);
    *ppd_y = (float)(p.fy * FS_PI / 180.0);
}

bool hmd_eye_display(const hmd_eye *e, display_desc *out)
{
    display_fov_angles a = {e->fov.left, e->fov.right, e->fov.down, e->fov.up};
    return display_from_fov_angles(&a, e->width, out);
}
