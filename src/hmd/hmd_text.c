/* hmd_text.c: the text form of an hmd display, "hmd:PRESET[,KEY=VALUE...]" (hmd.h, docs/hmd.md
 * "The text form"): parsed key by key into hmd_keys, applied to the preset by hmd_make; formatted
 * as the preset and the keys whose values differ from it, so that it parses back to the same desc. */
#include "hmd/hmd.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/config.h"

#define FOV_EXPECTED "four angles in degrees LEFT/RIGHT/UP/DOWN as OpenXR signs them (left and down negative), " \
                     "each in -85..85, left < right, down < up"

/* A whole number or a finite number, nothing after it. */
static bool parse_double(const char *v, double *out)
{
    char *end;
    errno = 0;
    *out = strtod(v, &end);
    return *v && !errno && end != v && !*end && isfinite(*out);
}

static bool parse_int(const char *v, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long x = strtol(v, &end, 10);
    if (!*v || errno || *end || x < lo || x > hi)
        return false;
    *out = (int)x;
    return true;
}

static bool parse_fov(const char *v, hmd_fov *out)
{
    double deg[4];
    char buf[128];
    if (strlen(v) >= sizeof buf)
        return false;
    snprintf(buf, sizeof buf, "%s", v);
    char *p = buf;
    for (int i = 0; i < 4; i++) {
        char *slash = strchr(p, '/');
        if ((i < 3) != (slash != NULL))
            return false;
        if (slash)
            *slash = '\0';
        if (!parse_double(p, &deg[i]))
            return false;
        p = slash ? slash + 1 : p;
    }
    return hmd_fov_from_deg(deg, out);
}

/* One KEY=VALUE into k; `seen` (one bit per key) catches a key given twice. */
static bool parse_key(const char *key, const char *v, hmd_keys *k, unsigned *seen, char *err, size_t n)
{
    static const char *const names[] = {"width", "height", "ipd", "hz", "fov-left", "fov-right"};
    int id = -1;
    for (int i = 0; i < 6; i++)
        if (!strcmp(key, names[i]))
            id = i;
    if (id < 0) {
        snprintf(err, n, "unknown key '%s' (keys: width, height, ipd, hz, fov-left, fov-right)", key);
        return false;
    }
    if (*seen & (1u << id)) {
        snprintf(err, n, "key '%s' given twice", key);
        return false;
    }
    *seen |= 1u << id;
    double x = 0;
    bool ok = true;
    const char *expected = NULL;
    char range[96];
    switch (id) {
    case 0:
    case 1:
        ok = parse_int(v, 16, MAX_DISPLAY_SIZE, id == 0 ? &k->width : &k->height);
        snprintf(range, sizeof range, "panel pixels per eye in 16..%d", MAX_DISPLAY_SIZE);
        expected = range;
        break;
    case 2:
        ok = parse_double(v, &x) && x >= HMD_IPD_MIN_MM && x <= HMD_IPD_MAX_MM;
        k->ipd_mm = (float)x;
        expected = "millimetres in 40..90";
        break;
    case 3:
        ok = parse_double(v, &x) && x >= HMD_HZ_MIN && x <= HMD_HZ_MAX;
        k->refresh_hz = (float)x;
        expected = "a refresh rate in Hz in 1..1000";
        break;
    default:
        ok = parse_fov(v, &k->fov[id - 4]);
        k->fov_given[id - 4] = true;
        expected = FOV_EXPECTED;
    }
    if (!ok)
        snprintf(err, n, "key '%s': expected %s, got '%s'", key, expected, v);
    return ok;
}

bool hmd_parse(const char *text, hmd_desc *out, char *err, size_t n)
{
    char buf[512];
    if (strncmp(text, "hmd:", 4) != 0 || strlen(text) >= sizeof buf) {
        snprintf(err, n, "expected planar or hmd:PRESET[,KEY=VALUE...] (presets: %s), got '%.200s'",
                 hmd_preset_list(), text);
        return false;
    }
    snprintf(buf, sizeof buf, "%s", text + 4);
    char *save = NULL, *preset = strtok_r(buf, ",", &save);
    if (!preset || text[4] == ',' || strstr(text, ",,") || text[strlen(text) - 1] == ',') {
        snprintf(err, n, "expected hmd:PRESET[,KEY=VALUE...] without empty items (presets: %s), got '%.200s'",
                 hmd_preset_list(), text);
        return false;
    }
    hmd_keys k = {0};
    unsigned seen = 0;
    for (char *item; (item = strtok_r(NULL, ",", &save));) {
        char *eq = strchr(item, '=');
        if (!eq) {
            snprintf(err, n, "expected KEY=VALUE after the preset, got '%.100s'", item);
            return false;
        }
        *eq = '\0';
        if (!parse_key(item, eq + 1, &k, &seen, err, n))
            return false;
    }
    return hmd_make(preset, &k, out, err, n);
}

/* >>format */

/* The shortest %g of degrees that parses back to the same float radians. */
static void format_angle(float rad, char *out, size_t n)
{
    double deg = (double)rad * 180.0 / FS_PI;
    for (int p = 6; p <= 17; p++) {
        snprintf(out, n, "%.*g", p, deg);
        if ((float)(strtod(out, NULL) * FS_PI / 180.0) == rad)
            return;
    }
}

/* The shortest %g that parses back to the same float. */
static void format_float(float x, char *out, size_t n)
{
    for (int p = 6; p <= 9; p++) {
        snprintf(out, n, "%.*g", p, (double)x);
        if ((float)strtod(out, NULL) == x)
            return;
    }
}

static bool fov_equal(hmd_fov a, hmd_fov b)
{
    return a.left == b.left && a.right == b.right && a.up == b.up && a.down == b.down;
}

static void append_fov(char *out, size_t n, const char *key, hmd_fov f)
{
    char a[4][32];
    format_angle(f.left, a[0], sizeof a[0]);
    format_angle(f.right, a[1], sizeof a[1]);
    format_angle(f.up, a[2], sizeof a[2]);
    format_angle(f.down, a[3], sizeof a[3]);
    size_t l = strlen(out);
    snprintf(out + l, n - l, ",%s=%s/%s/%s/%s", key, a[0], a[1], a[2], a[3]);
}

void hmd_format(const hmd_desc *d, char *out, size_t n)
{
    hmd_desc p;
    char err[256], num[32];
    if (!hmd_make(d->preset, NULL, &p, err, sizeof err)) /* custom: every key differs from nothing */
        memset(&p, 0, sizeof p);
    snprintf(out, n, "hmd:%s", d->preset);
    size_t l;
    /* Both sides whenever either differs: one alone would be read as "the other for square pixels". */
    if (d->eye[0].width != p.eye[0].width || d->eye[0].height != p.eye[0].height) {
        l = strlen(out);
        snprintf(out + l, n - l, ",width=%d,height=%d", d->eye[0].width, d->eye[0].height);
    }
    if (d->ipd_mm != p.ipd_mm) {
        format_float(d->ipd_mm, num, sizeof num);
        l = strlen(out);
        snprintf(out + l, n - l, ",ipd=%s", num);
    }
    if (d->refresh_hz != p.refresh_hz) {
        format_float(d->refresh_hz, num, sizeof num);
        l = strlen(out);
        snprintf(out + l, n - l, ",hz=%s", num);
    }
    bool left = !fov_equal(d->eye[HMD_LEFT].fov, p.eye[HMD_LEFT].fov);
    if (left)
        append_fov(out, n, "fov-left", d->eye[HMD_LEFT].fov);
    /* The right eye as parsing would make it: the mirror of a given left eye, else the preset's. */
    hmd_fov implied = left ? hmd_fov_mirror(d->eye[HMD_LEFT].fov) : p.eye[HMD_RIGHT].fov;
    if (!fov_equal(d->eye[HMD_RIGHT].fov, implied))
        append_fov(out, n, "fov-right", d->eye[HMD_RIGHT].fov);
}
