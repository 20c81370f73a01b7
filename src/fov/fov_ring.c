/* fov_ring.c: foveation ring math (see fov_ring.h for the contract and conventions).
 *
 * All angle and footprint math runs in double internally and is rounded to float/int at the
 * boundary. The GLSL twin of fov_eccentricity_deg and fov_composite_weight is
 * shaders/common/foveation.glsl; keep both in step.
 *
 * Decisions where the header is silent (documented here, tested in tests/unit/test_fov_ring.c):
 *   - Degenerate displays: width and height below 1 are taken as 1; a horizontal fov that is not a
 *     number is taken as 90 degrees, and one outside (0, 180) is clamped to [0.001, 179.999]; a
 *     non-finite principal point offset is taken as 0 (core/display.c, which every layer shares).
 *   - The principal point (core/display.h) is where view rays start from: eccentricities, cone
 *     sections and block angles measure from it; the fallback gaze stays the display centre.
 *   - A gaze with a NaN or infinite coordinate is taken as the display centre (both coordinates),
 *     in fov_eccentricity_deg as well as in the footprints. A non-finite display point p gives NaN.
 *   - fov_composite_weight: a negative eccentricity counts as 0 and NaN as +infinity (the last,
 *     coarsest ring); a blend band of 0 (or NaN) gives hard ring edges (next = 0).
 *   - fov_layout_parse writes nothing to *out on error. Every ring needs all three fields R:S:B.
 *     "auto", "aggressive" and "off" are matched exactly (lower case), surrounding whitespace allowed.
 *   - fov_layout_check also rejects a blend_deg that is negative or not finite.
 *   - Footprints are exact (analytic cone section, clipped to the display), grown by one pixel
 *     against rounding in callers' eccentricity tests; nesting holds for valid layouts (scales
 *     non-decreasing outwards, so each block size divides the next).
 */
#include "fov/fov_ring.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

#define DEG2RAD (FS_PI / 180.0)
#define RAD2DEG (180.0 / FS_PI)

/* The display as the math sees it (core/display.h: sanitised size, focal length, principal point). */
typedef display_geom disp;

static disp disp_of(const display_desc *d)
{
    FS_ASSERT(d != NULL);
    return display_geom_of(d);
}

/* View ray (camera space, y up, looking down -z) through display point (px, py). */
static void view_ray(const disp *D, double px, double py, double v[3])
{
    display_ray(D, px, py, v);
}

/* Angle in radians between two vectors, accurate for tiny and near-180-degree angles. */
static double angle_between(const double a[3], const double b[3])
{
    double cx = a[1] * b[2] - a[2] * b[1];
    double cy = a[2] * b[0] - a[0] * b[2];
    double cz = a[0] * b[1] - a[1] * b[0];
    double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), dot);
}

/* Largest eccentricity on the display seen from its principal point: to the farthest corner
 * (centre to corner for a centred display). */
static double corner_ecc_deg(const disp *D)
{
    double dx = fmax(D->cx, D->w - D->cx), dy = fmax(D->cy, D->h - D->cy);
    return atan(sqrt(dx * dx + dy * dy) / D->f) * RAD2DEG;
}

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

static int block_of(const fov_ring *r)
{
    return 1 << clampi(r->scale_log2, 0, MAX_FOV_SCALE_LOG2);
}

void fov_set_err(char *err, int size, const char *fmt, ...)
{
    if (!err || size <= 0)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, (size_t)size, fmt, ap);
    va_end(ap);
}

void fov_format_float(char *buf, size_t size, float v)
{
    if (v == 0.0f)
        v = 0.0f;
    for (int prec = 6; prec <= 9; prec++) {
        snprintf(buf, size, "%.*g", prec, (double)v);
        if (strtof(buf, NULL) == v)
            return;
    }
}

// >>layouts

fov_layout fov_layout_off(void)
{
    fov_layout l;
    memset(&l, 0, sizeof l);
    l.kind = FOV_LAYOUT_OFF;
    l.count = 1;
    l.rings[0] = (fov_ring){INFINITY, 0, 0.0f};
    l.blend_deg = FOV_BLEND_DEG_DEFAULT;
    return l;
}

/* The largest angle, in degrees, that a block of `block` x `block` display pixels spans along
 * any of its sides, anywhere on the display. At a display point t degrees from the view axis a
 * pixel spans cos^2(t)/f radians radially and cos(t)/f tangentially (f: focal length in pixels);
 * both are largest, 1/f, at the principal point. Exactly: the angle between the view rays through
 * two image-plane points is at most their distance over f (the eye is at least f from the line
 * through them), so no side of a block spans more than block/f radians, and blocks at the
 * principal point come within (block/f)^2/3 of that. */
static double block_angle_max_deg(const disp *D, int block)
{
    return (double)block / D->f * RAD2DEG;
}

/* Largest eccentricity between two display points: two corners. (The set of points within a given
 * angle of a ray meets the image plane in a convex region, so the farthest point of a rectangle
 * from any ray is a corner, and the farthest gaze on the display as well.) The main diagonal
 * first: a centred display's other pairs are never larger. */
static double diagonal_ecc_deg(const disp *D)
{
    double c[4][3];
    for (int k = 0; k < 4; k++)
        view_ray(D, k & 1 ? D->w : 0.0, k & 2 ? D->h : 0.0, c[k]);
    static const int pairs[6][2] = {{0, 3}, {1, 2}, {0, 1}, {2, 3}, {0, 2}, {1, 3}};
    double best = 0.0;
    for (int i = 0; i < 6; i++) {
        double a = angle_between(c[pairs[i][0]], c[pairs[i][1]]);
        best = a > best ? a : best;
    }
    return best * RAD2DEG;
}

static void acuity_model(float slope, float omega0, double *m, double *w0)
{
    *m = slope > 0.0f && isfinite(slope) ? slope : FOV_ACUITY_SLOPE_DEFAULT;
    *w0 = omega0 > 0.0f && isfinite(omega0) ? omega0 : FOV_ACUITY_OMEGA0_DEFAULT;
}

/* Resulting layouts with the default model (slope 0.0275, omega0 1/48 degree), rings as
 * [inner, outer) degrees and scale; e_k = (2^k (180/pi) / f - omega0) / slope
 * (tests/unit/test_fov_ring.c checks these):
 *   1280x720 @ 90 deg (f = 640 px, corner 48.9 deg), "5.7533083:1:0,12.264193:1/2:0,...":
 *     [0, 5.75) 1, [5.75, 12.26) 1/2, [12.26, 25.29) 1/4, [25.29, *) 1/8
 *     (1/16 would start at 51.33 deg, beyond the corner as seen from the centre: dropped)
 *   1920x1080 @ 90 deg (f = 960 px, corner 48.9 deg):
 *     [0, 3.58) 1, [3.58, 7.92) 1/2, [7.92, 16.60) 1/4, [16.60, 33.97) 1/8, [33.97, *) 1/16
 * (The displays are coarser than acuity at the centre: a 1280x720 @ 90 pixel is 5.4 arcmin against
 * MAR(0) = 1.25 arcmin, so full resolution is only kept until 2 pixels match MAR.)
 * A display so fine that 2^k-pixel blocks resolve the acuity even at the centre (2^k / f <=
 * omega0, e.g. hfov 1 degree) gets e_k = 0: ring k-1 would be empty [0, 0), so it is skipped and
 * the innermost ring is then coarser than full resolution (one 1/16 ring for 1280x720 at 1 deg). */
fov_layout fov_layout_auto(const display_desc *d, float slope, float omega0)
{
    disp D = disp_of(d);
    double m, w0;
    acuity_model(slope, omega0, &m, &w0);
    double emax = corner_ecc_deg(&D);

    fov_layout l;
    memset(&l, 0, sizeof l);
    l.kind = FOV_LAYOUT_AUTO;
    l.blend_deg = FOV_BLEND_DEG_DEFAULT;

    int scale = 0;       /* scale of the ring being built; its inner edge is prev */
    float prev = 0.0f;
    for (int k = 1; k <= MAX_FOV_SCALE_LOG2 && l.count < MAX_FOV_RINGS - 1; k++) {
        /* The gaze may be anywhere, so any ring's inner edge may pass through the principal point,
         * where a block is largest: ring k starts where MAR reaches that largest block. */
        double block_deg = block_angle_max_deg(&D, 1 << k);
        double ek = (block_deg - w0) / m;
        if (ek < 0.0)
            ek = 0.0; /* 2^k-pixel blocks resolve the acuity even at the fovea */
        if (!(ek < emax))
            break; /* scale k would start beyond the display's corner: ring k-1 is the last */
        /* Round outwards, so that MAR at the stored (float) border is not below the block by a
         * rounding error (the same expression as fov_ring_block_mar_ratio's). */
        float e = (float)ek;
        while (m * (double)e + w0 < block_deg)
            e = nextafterf(e, INFINITY);
        if (e > prev) {
            l.rings[l.count++] = (fov_ring){e, scale, 0.0f};
            prev = e;
        } /* else ring k-1 is empty ([0, 0)): skip it */
        scale = k;
    }
    l.rings[l.count++] = (fov_ring){INFINITY, scale, 0.0f};
    return l;
}

fov_layout fov_layout_aggressive(const display_desc *d)
{
    fov_layout l = fov_layout_auto(d, FOV_AGGRESSIVE_SLOPE_FACTOR * FOV_ACUITY_SLOPE_DEFAULT, FOV_ACUITY_OMEGA0_DEFAULT);
    l.kind = FOV_LAYOUT_AGGRESSIVE;
    for (int i = 0; i < l.count; i++)
        if (l.rings[i].scale_log2 > 0)
            l.rings[i].mip_bias += FOV_AGGRESSIVE_MIP_BIAS;
    return l;
}

const char *fov_layout_kind_name(fov_layout_kind k)
{
    switch (k) {
    case FOV_LAYOUT_OFF: return "off";
    case FOV_LAYOUT_AUTO: return "auto";
    case FOV_LAYOUT_AGGRESSIVE: return "aggressive";
    default: return "explicit";
    }
}

double fov_ring_block_mar_ratio(const display_desc *d, const fov_layout *l, int i, float slope, float omega0)
{
    if (!l || i < 0 || i >= l->count || i >= MAX_FOV_RINGS)
        return 0.0;
    int block = block_of(&l->rings[i]);
    if (block == 1)
        return 0.0; /* full resolution: the display's own pitch, not the layout's choice */
    disp D = disp_of(d);
    double inner = i > 0 ? l->rings[i - 1].outer_deg : 0.0;
    if (!(inner < diagonal_ecc_deg(&D)))
        return 0.0; /* no gaze on the display shows this ring */
    double m, w0;
    acuity_model(slope, omega0, &m, &w0);
    return block_angle_max_deg(&D, block) / (m * inner + w0);
}

double fov_layout_acuity_margin(const display_desc *d, const fov_layout *l, float slope, float omega0,
                                int *worst_ring)
{
    double worst = 0.0;
    int at = -1;
    for (int i = 0; l && i < l->count && i < MAX_FOV_RINGS; i++) {
        double r = fov_ring_block_mar_ratio(d, l, i, slope, omega0);
        if (r > worst)
            worst = r, at = i;
    }
    if (worst_ring)
        *worst_ring = at;
    return worst > 0.0 ? 1.0 / worst : INFINITY;
}

void fov_trim(const char **b, const char **e)
{
    while (*b < *e && (**b == ' ' || **b == '\t' || **b == '\n' || **b == '\r'))
        (*b)++;
    while (*e > *b && ((*e)[-1] == ' ' || (*e)[-1] == '\t' || (*e)[-1] == '\n' || (*e)[-1] == '\r'))
        (*e)--;
}

bool fov_take_token(const char *b, const char *e, char tok[FOV_TOKEN_MAX])
{
    fov_trim(&b, &e);
    if (e - b >= FOV_TOKEN_MAX)
        return false;
    memcpy(tok, b, (size_t)(e - b));
    tok[e - b] = '\0';
    return true;
}

/* A whole token as a finite double (no trailing characters). */
static bool parse_number(const char *tok, double *out)
{
    if (!tok[0] || tok[0] == ' ' || tok[0] == '\t')
        return false;
    char *end = NULL;
    double v = strtod(tok, &end);
    if (end == tok || *end != '\0' || !isfinite(v))
        return false;
    *out = v;
    return true;
}

bool fov_parse_ratio(const char *tok, double *out)
{
    const char *slash = strchr(tok, '/');
    if (!slash)
        return parse_number(tok, out);
    char num[FOV_TOKEN_MAX], den[FOV_TOKEN_MAX];
    double a, b;
    if (!fov_take_token(tok, slash, num) || !fov_take_token(slash + 1, tok + strlen(tok), den) ||
        !parse_number(num, &a) || !parse_number(den, &b) || b == 0.0)
        return false;
    *out = a / b;
    return true;
}

/* Scale "1", "0.25", "1/4" (spaces around '/' allowed) -> log2 of the block size. */
static bool parse_scale(const char *tok, int *scale_log2)
{
    double v;
    if (!fov_parse_ratio(tok, &v))
        return false;
    for (int k = 0; k <= MAX_FOV_SCALE_LOG2; k++)
        if (v == ldexp(1.0, -k)) {
            *scale_log2 = k;
            return true;
        }
    return false;
}

/* One "R:S:B" ring spec in [b, e). */
static fs_status parse_ring(const char *b, const char *e, int n, fov_ring *out, char *err, int err_size)
{
    const char *names[3] = {"radius", "scale", "mip bias"};
    char tok[3][FOV_TOKEN_MAX];
    int fields = 0;
    const char *q = b;
    char probe[FOV_TOKEN_MAX];
    if (fov_take_token(b, e, probe) && probe[0] == '\0') {
        fov_set_err(err, err_size, "ring %d: empty (expected R:S:B)", n);
        return FS_ERR_USAGE;
    }
    for (;;) {
        const char *c = q;
        while (c < e && *c != ':')
            c++;
        if (fields < 3 && !fov_take_token(q, c, tok[fields])) {
            fov_set_err(err, err_size, "ring %d: %s field is too long", n, names[fields]);
            return FS_ERR_USAGE;
        }
        fields++;
        if (c == e)
            break;
        q = c + 1;
    }
    if (fields != 3) {
        fov_set_err(err, err_size, "ring %d: expected 3 fields R:S:B (radius:scale:mip bias), got %d", n, fields);
        return FS_ERR_USAGE;
    }
    for (int k = 0; k < 3; k++)
        if (!tok[k][0]) {
            fov_set_err(err, err_size, "ring %d: %s is empty", n, names[k]);
            return FS_ERR_USAGE;
        }

    double v;
    if (strcmp(tok[0], "*") == 0) {
        out->outer_deg = INFINITY;
    } else if (parse_number(tok[0], &v) && (float)v > 0.0f && isfinite((float)v)) { /* as the float kept */
        out->outer_deg = (float)v;
    } else {
        fov_set_err(err, err_size, "ring %d: radius '%s' is not a positive finite number of degrees (or '*')", n, tok[0]);
        return FS_ERR_USAGE;
    }
    if (!parse_scale(tok[1], &out->scale_log2)) {
        fov_set_err(err, err_size, "ring %d: scale %s is not a power of two (1, 1/2, ... 1/%d)", n, tok[1],
                1 << MAX_FOV_SCALE_LOG2);
        return FS_ERR_USAGE;
    }
    if (!parse_number(tok[2], &v) || !isfinite((float)v)) {
        fov_set_err(err, err_size, "ring %d: mip bias '%s' is not a finite number", n, tok[2]);
        return FS_ERR_USAGE;
    }
    out->mip_bias = (float)v;
    return FS_OK;
}

fs_status fov_layout_parse(const char *text, const display_desc *d, fov_layout *out, char *err, int err_size)
{
    if (err && err_size > 0)
        err[0] = '\0';
    if (!text) {
        fov_set_err(err, err_size, "empty ring layout");
        return FS_ERR_USAGE;
    }
    const char *b = text, *e = text + strlen(text);
    fov_trim(&b, &e);
    if (b == e) {
        fov_set_err(err, err_size, "empty ring layout (expected auto, aggressive, off or R:S:B,...,*:S:B)");
        return FS_ERR_USAGE;
    }
    size_t len = (size_t)(e - b);
    if (len == 4 && memcmp(b, "auto", 4) == 0) {
        if (!d) {
            fov_set_err(err, err_size, "ring layout auto needs the display");
            return FS_ERR_USAGE;
        }
        if (out)
            *out = fov_layout_auto(d, 0.0f, 0.0f);
        return FS_OK;
    }
    if (len == 10 && memcmp(b, "aggressive", 10) == 0) {
        if (!d) {
            fov_set_err(err, err_size, "ring layout aggressive needs the display");
            return FS_ERR_USAGE;
        }
        if (out)
            *out = fov_layout_aggressive(d);
        return FS_OK;
    }
    if (len == 3 && memcmp(b, "off", 3) == 0) {
        if (out)
            *out = fov_layout_off();
        return FS_OK;
    }

    if (!memchr(b, ':', len)) { /* a misspelt name rather than a list */
        fov_set_err(err, err_size, "'%.*s' is not a ring layout (expected auto, aggressive, off or R:S:B,...,*:S:B)",
                    (int)(len > 40 ? 40 : len), b);
        return FS_ERR_USAGE;
    }
    fov_layout l;
    memset(&l, 0, sizeof l);
    l.kind = FOV_LAYOUT_EXPLICIT;
    l.blend_deg = FOV_BLEND_DEG_DEFAULT;
    const char *q = b;
    for (;;) {
        const char *c = q;
        while (c < e && *c != ',')
            c++;
        if (l.count == MAX_FOV_RINGS) {
            fov_set_err(err, err_size, "ring %d: more than %d rings", l.count + 1, MAX_FOV_RINGS);
            return FS_ERR_USAGE;
        }
        fs_status s = parse_ring(q, c, l.count + 1, &l.rings[l.count], err, err_size);
        if (s != FS_OK)
            return s;
        l.count++;
        if (c == e)
            break;
        q = c + 1;
    }
    fs_status s = fov_layout_check(&l, err, err_size);
    if (s == FS_OK && out)
        *out = l;
    return s;
}

fs_status fov_layout_check(const fov_layout *l, char *err, int err_size)
{
    if (!l) {
        fov_set_err(err, err_size, "no ring layout");
        return FS_ERR_USAGE;
    }
    if (l->count < 1 || l->count > MAX_FOV_RINGS) {
        fov_set_err(err, err_size, "layout has %d rings (expected 1..%d)", l->count, MAX_FOV_RINGS);
        return FS_ERR_USAGE;
    }
    for (int i = 0; i < l->count; i++) {
        const fov_ring *r = &l->rings[i];
        bool last = i == l->count - 1;
        if (last && !(isinf(r->outer_deg) && r->outer_deg > 0)) {
            fov_set_err(err, err_size, "ring %d: the last ring's radius must be '*' (got %g)", i + 1, (double)r->outer_deg);
            return FS_ERR_USAGE;
        }
        if (!last && isinf(r->outer_deg) && r->outer_deg > 0) {
            fov_set_err(err, err_size, "ring %d: radius '*' is allowed only for the last ring", i + 1);
            return FS_ERR_USAGE;
        }
        if (!last && !(r->outer_deg > 0 && isfinite(r->outer_deg))) {
            fov_set_err(err, err_size, "ring %d: radius %g is not a positive finite number of degrees", i + 1,
                    (double)r->outer_deg);
            return FS_ERR_USAGE;
        }
        if (!last && i > 0 && !(r->outer_deg > l->rings[i - 1].outer_deg)) {
            fov_set_err(err, err_size, "ring %d: radius %g is not larger than ring %d's %g", i + 1, (double)r->outer_deg,
                    i, (double)l->rings[i - 1].outer_deg);
            return FS_ERR_USAGE;
        }
        if (r->scale_log2 < 0 || r->scale_log2 > MAX_FOV_SCALE_LOG2) {
            fov_set_err(err, err_size, "ring %d: scale 2^-%d is not one of 1, 1/2, ... 1/%d", i + 1, r->scale_log2,
                    1 << MAX_FOV_SCALE_LOG2);
            return FS_ERR_USAGE;
        }
        if (i > 0 && r->scale_log2 < l->rings[i - 1].scale_log2) {
            fov_set_err(err, err_size, "ring %d: scale 1/%d is finer than ring %d's 1/%d", i + 1, 1 << r->scale_log2, i,
                    1 << l->rings[i - 1].scale_log2);
            return FS_ERR_USAGE;
        }
        if (!isfinite(r->mip_bias)) {
            fov_set_err(err, err_size, "ring %d: mip bias %g is not finite", i + 1, (double)r->mip_bias);
            return FS_ERR_USAGE;
        }
    }
    if (!(l->blend_deg >= 0.0f && isfinite(l->blend_deg))) {
        fov_set_err(err, err_size, "blend band %g is not a finite angle >= 0", (double)l->blend_deg);
        return FS_ERR_USAGE;
    }
    return FS_OK;
}

void fov_layout_format(const fov_layout *l, char *buf, int size)
{
    if (!buf || size <= 0)
        return;
    buf[0] = '\0';
    if (!l)
        return;
    size_t n = 0, cap = (size_t)size;
    int count = clampi(l->count, 0, MAX_FOV_RINGS);
    for (int i = 0; i < count && n < cap; i++) {
        const fov_ring *r = &l->rings[i];
        char rad[32], bias[32], scale[16];
        if (isinf(r->outer_deg) && r->outer_deg > 0)
            snprintf(rad, sizeof rad, "*");
        else
            fov_format_float(rad, sizeof rad, r->outer_deg);
        int k = r->scale_log2;
        if (k == 0)
            snprintf(scale, sizeof scale, "1");
        else if (k > 0 && k < 31)
            snprintf(scale, sizeof scale, "1/%d", 1 << k);
        else
            snprintf(scale, sizeof scale, "2^%d", -k); /* invalid; printed so it is visible */
        fov_format_float(bias, sizeof bias, r->mip_bias);
        int w = snprintf(buf + n, cap - n, "%s%s:%s:%s", i ? "," : "", rad, scale, bias);
        if (w < 0)
            break;
        n += (size_t)w;
    }
}

// >>angles

float fov_focal_px(const display_desc *d)
{
    return (float)disp_of(d).f;
}

void fov_principal_px(const display_desc *d, float out[2])
{
    disp D = disp_of(d);
    out[0] = (float)D.cx;
    out[1] = (float)D.cy;
}

float fov_pixels_per_degree(const display_desc *d)
{
    /* 1 / pitch(0), pitch(e) = (180/pi) cos^2(e) / f. */
    return (float)(disp_of(d).f * DEG2RAD);
}

float fov_eccentricity_deg(const display_desc *d, float gx, float gy, float px, float py)
{
    disp D = disp_of(d);
    double g[3], p[3];
    if (isfinite(gx) && isfinite(gy))
        view_ray(&D, gx, gy, g);
    else
        view_ray(&D, 0.5 * D.w, 0.5 * D.h, g);
    view_ray(&D, px, py, p);
    return (float)(angle_between(g, p) * RAD2DEG);
}

// >>footprints

/* Gaze in display pixels, clamped into [0, w] x [0, h]; not finite -> the display centre. */
static void clamp_gaze(const disp *D, float gx, float gy, double *x, double *y)
{
    if (!isfinite(gx) || !isfinite(gy)) {
        *x = 0.5 * D->w;
        *y = 0.5 * D->h;
        return;
    }
    *x = gx < 0.0f ? 0.0 : gx > D->w ? D->w : (double)gx;
    *y = gy < 0.0f ? 0.0 : gy > D->h ? D->h : (double)gy;
}

void fov_gaze_clamp(const display_desc *d, float *gx, float *gy)
{
    FS_ASSERT(gx != NULL && gy != NULL);
    if (!gx || !gy)
        return;
    disp D = disp_of(d);
    double x, y;
    clamp_gaze(&D, *gx, *gy, &x, &y);
    *gx = (float)x; /* exact: the input, 0, the size or half of it */
    *gy = (float)y;
}

/* Roots t of the cone boundary along the image-plane line where the other camera coordinate is
 * fixed at `fixed` (ua: the gaze ray's component along the free axis, ub: along the fixed axis).
 * On the plane z = -f the cone is F = (P . u)^2 - c2 |P|^2 = 0, P = (x, y, -f); along the line
 * that is A t^2 + 2 ua k t + k^2 - c2 (fixed^2 + f^2) = 0 with k = fixed ub - f uz, A = ua^2 - c2
 * (< 0 whenever the section is an ellipse). */
static int cone_line_roots(double ua, double ub, double uz, double f, double c2, double fixed, double t[2])
{
    double k = fixed * ub - f * uz, A = ua * ua - c2;
    double disc = c2 * (k * k + A * (fixed * fixed + f * f));
    if (!(disc >= 0.0) || A == 0.0)
        return 0;
    double r = sqrt(disc);
    t[0] = (-ua * k - r) / A;
    t[1] = (-ua * k + r) / A;
    return 2;
}

typedef struct bbox2 {
    double x0, y0, x1, y1;
    double xl, xr, yb, yt; /* the display rectangle in camera-plane coordinates (y up) */
    bool any;
} bbox2;

/* Adds a camera-plane point that lies on the display rectangle (within a hair), clamped onto it. */
static void bbox_add(bbox2 *b, double x, double y)
{
    const double tol = 1e-3; /* pixels; the caller grows the box by a whole pixel anyway */
    if (!(x >= b->xl - tol && x <= b->xr + tol && y >= b->yb - tol && y <= b->yt + tol))
        return;
    x = x < b->xl ? b->xl : x > b->xr ? b->xr : x;
    y = y < b->yb ? b->yb : y > b->yt ? b->yt : y;
    if (!b->any) {
        b->x0 = b->x1 = x, b->y0 = b->y1 = y, b->any = true;
        return;
    }
    b->x0 = x < b->x0 ? x : b->x0, b->x1 = x > b->x1 ? x : b->x1;
    b->y0 = y < b->y0 ? y : b->y0, b->y1 = y > b->y1 ? y : b->y1;
}

/* Bounding box (continuous display pixels) of the display points within `outer_deg` of the gaze
 * ray, i.e. of the cone's section with the image plane clipped to the display. Exact, no
 * sampling.
 *
 * The section's extremes: a vertical line x = x0 on the plane z = -f touches it where the plane
 * through the eye containing that line, normal n ~ (f, 0, x0), is tangent to the cone around the
 * unit gaze ray u, i.e. |n . u| = sin(theta) |n|:
 *   (uz^2 - s^2) x0^2 + 2 f ux uz x0 + f^2 (ux^2 - s^2) = 0,  s = sin(theta),
 * with roots -f ux uz / den +- f s sqrt(1 - uy^2 - s^2) / den, den = uz^2 - s^2 (the same for y
 * with ux and uy swapped). den > 0 exactly when gaze angle + theta < 90 degrees (the section is an
 * ellipse); otherwise it is unbounded and false is returned (the caller covers the display).
 *
 * Clipping: the section is convex, so the extremes of section ∩ display are among the section's
 * own extreme points that lie on the display, its crossings with the display's edge lines, and
 * the display corners inside it. Without the clip a gaze near a corner would pay for the part of
 * the ellipse that bulges off the display. */
static bool cone_bbox(const disp *D, double gx, double gy, double outer_deg, double box[4])
{
    if (!(outer_deg < 90.0))
        return false;
    double u[3];
    view_ray(D, gx, gy, u);
    double len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    u[0] /= len, u[1] /= len, u[2] /= len;
    double th = outer_deg > 0.0 ? outer_deg * DEG2RAD : 0.0;
    double s = sin(th), s2 = s * s, c2 = 1.0 - s2, f = D->f;
    double den = u[2] * u[2] - s2;
    if (!(den > 1e-12))
        return false;
    double qx = 1.0 - u[1] * u[1] - s2, qy = 1.0 - u[0] * u[0] - s2; /* both >= den > 0 */
    double cx = -f * u[0] * u[2] / den, rx = f * s * sqrt(qx > 0 ? qx : 0) / den;
    double cy = -f * u[1] * u[2] / den, ry = f * s * sqrt(qy > 0 ? qy : 0) / den;

    /* Exactly +-w/2, +-h/2 for a centred display. */
    bbox2 b = {0, 0, 0, 0, -D->cx, D->w - D->cx, D->cy - D->h, D->cy, false};
    double t[2];
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        /* Extreme points: the tangent line's double root gives the other coordinate. */
        double x = cx + sgn * rx, y = cy + sgn * ry;
        bbox_add(&b, x, -u[1] * (x * u[0] - f * u[2]) / (u[1] * u[1] - c2));
        bbox_add(&b, -u[0] * (y * u[1] - f * u[2]) / (u[0] * u[0] - c2), y);
        /* Crossings with the display's edge lines x = xl, xr and y = yb, yt. */
        double ex = sgn < 0 ? b.xl : b.xr, ey = sgn < 0 ? b.yb : b.yt;
        int n = cone_line_roots(u[1], u[0], u[2], f, c2, ex, t);
        for (int k = 0; k < n; k++)
            bbox_add(&b, ex, t[k]);
        n = cone_line_roots(u[0], u[1], u[2], f, c2, ey, t);
        for (int k = 0; k < n; k++)
            bbox_add(&b, t[k], ey);
        /* Display corners inside the cone. */
        for (int sy = -1; sy <= 1; sy += 2) {
            double p[3] = {ex, sy < 0 ? b.yb : b.yt, -f};
            double pu = p[0] * u[0] + p[1] * u[1] + p[2] * u[2];
            if (pu > 0.0 && pu * pu >= c2 * (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]))
                bbox_add(&b, p[0], p[1]);
        }
    }
    if (!b.any) /* cannot happen for a gaze on the display; keep the unclipped box */
        b.x0 = cx - rx, b.y0 = cy - ry, b.x1 = cx + rx, b.y1 = cy + ry, b.any = true;
    box[0] = D->cx + b.x0;
    box[1] = D->cy - b.y1; /* camera y up, display y down */
    box[2] = D->cx + b.x1;
    box[3] = D->cy - b.y0;
    return true;
}

static long long floor_to(long long v, long long b)
{
    long long q = v / b;
    if (v % b != 0 && v < 0)
        q--;
    return q * b;
}

static long long ceil_to(long long v, long long b)
{
    return -floor_to(-v, b);
}

static double clampd(double v, double lo, double hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

/* Footprints of rings 0..last for one gaze, each the union of its own cone's box and the previous
 * ring's footprint, so they nest by construction (with non-decreasing scales every block divides
 * the next, and snapping outwards keeps the union). */
static void footprint_chain(const disp *D, const fov_layout *l, int last, float gx_in, float gy_in,
                            int margin_blocks, fov_ring_rect *out)
{
    double gx, gy;
    clamp_gaze(D, gx_in, gy_in, &gx, &gy);
    long long margin = margin_blocks < 0 ? 0 : margin_blocks > (1 << 20) ? (1 << 20) : margin_blocks;
    long long W = (long long)D->w, H = (long long)D->h;
    for (int j = 0; j <= last; j++) {
        long long b = block_of(&l->rings[j]);
        long long gw = ceil_to(W, b), gh = ceil_to(H, b);
        long long x0 = 0, y0 = 0, x1 = gw, y1 = gh;
        double box[4];
        if (j < l->count - 1 && cone_bbox(D, gx, gy, l->rings[j].outer_deg, box)) {
            /* Pixel centres in [xmin, xmax] lie in [floor(xmin), ceil(xmax)); one more pixel each
             * side absorbs float rounding in callers' eccentricity tests. Clamp before the
             * integer conversion (boxes near 90 degrees are huge). */
            double lim = (double)(gw > gh ? gw : gh) + 4.0;
            x0 = (long long)clampd(floor(box[0]) - 1.0, -lim, lim);
            y0 = (long long)clampd(floor(box[1]) - 1.0, -lim, lim);
            x1 = (long long)clampd(ceil(box[2]) + 1.0, -lim, lim);
            y1 = (long long)clampd(ceil(box[3]) + 1.0, -lim, lim);
            x0 -= margin * b, y0 -= margin * b, x1 += margin * b, y1 += margin * b;
            if (j > 0) {
                const fov_ring_rect *p = &out[j - 1];
                x0 = p->x0 < x0 ? p->x0 : x0, y0 = p->y0 < y0 ? p->y0 : y0;
                x1 = p->x1 > x1 ? p->x1 : x1, y1 = p->y1 > y1 ? p->y1 : y1;
            }
            x0 = floor_to(x0, b), y0 = floor_to(y0, b);
            x1 = ceil_to(x1, b), y1 = ceil_to(y1, b);
            x0 = x0 < 0 ? 0 : x0 > gw ? gw : x0, x1 = x1 < 0 ? 0 : x1 > gw ? gw : x1;
            y0 = y0 < 0 ? 0 : y0 > gh ? gh : y0, y1 = y1 < 0 ? 0 : y1 > gh ? gh : y1;
            /* At least one ring pixel; only ever grows the rectangle. */
            if (x1 - x0 < b) {
                if (x0 + b <= gw)
                    x1 = x0 + b;
                else
                    x0 = gw - b, x1 = gw;
            }
            if (y1 - y0 < b) {
                if (y0 + b <= gh)
                    y1 = y0 + b;
                else
                    y0 = gh - b, y1 = gh;
            }
        }
        out[j] = (fov_ring_rect){(int)x0, (int)y0, (int)x1, (int)y1, (int)((x1 - x0) / b), (int)((y1 - y0) / b),
                                 (int)b};
    }
}

fov_ring_rect fov_ring_footprint(const display_desc *d, const fov_layout *l, int i, float gx, float gy,
                                 int margin_blocks)
{
    disp D = disp_of(d);
    FS_ASSERT(l != NULL && l->count >= 1 && l->count <= MAX_FOV_RINGS && i >= 0 && i < l->count);
    if (!l || l->count < 1 || l->count > MAX_FOV_RINGS || i < 0 || i >= l->count) {
        int w = (int)D.w, h = (int)D.h;
        return (fov_ring_rect){0, 0, w, h, w, h, 1};
    }
    fov_ring_rect chain[MAX_FOV_RINGS];
    footprint_chain(&D, l, i, gx, gy, margin_blocks, chain);
    return chain[i];
}

mat4 fov_ring_crop(const display_desc *d, const fov_ring_rect *r)
{
    disp D = disp_of(d);
    FS_ASSERT(r != NULL);
    if (!r)
        return m4_identity();
    double X0 = 2.0 * r->x0 / D.w - 1.0, X1 = 2.0 * r->x1 / D.w - 1.0;
    double Y0 = 1.0 - 2.0 * r->y1 / D.h, Y1 = 1.0 - 2.0 * r->y0 / D.h;
    double wx = X1 - X0 > 0 ? X1 - X0 : 2.0 / D.w, wy = Y1 - Y0 > 0 ? Y1 - Y0 : 2.0 / D.h;
    /* Acts on clip coordinates: x' = sx x + tx w, so after the divide ndc' = sx ndc + tx. */
    mat4 c = m4_identity();
    c.m[0] = (float)(2.0 / wx);
    c.m[12] = (float)(-(X0 + X1) / wx);
    c.m[5] = (float)(2.0 / wy);
    c.m[13] = (float)(-(Y0 + Y1) / wy);
    return c;
}

// >>composite

static float smoothstepf(float e0, float e1, float x)
{
    float t = (x - e0) / (e1 - e0);
    t = t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
    return t * t * (3.0f - 2.0f * t);
}

/* Continuity: just below outer_i the next weight reaches 1 (pure ring i+1); at outer_i ring i+1
 * takes over with its own next = 0, because its band lies inside it, at least half its width
 * away from its inner edge. So ring + next is continuous and non-decreasing in e. */
fov_blend fov_composite_weight(const fov_layout *l, float ecc_deg)
{
    fov_blend r = {0, 0.0f};
    if (!l || l->count < 1)
        return r;
    int last = (l->count > MAX_FOV_RINGS ? MAX_FOV_RINGS : l->count) - 1;
    float e = ecc_deg;
    if (isnan(e))
        e = INFINITY;
    else if (e < 0.0f)
        e = 0.0f;
    int i = 0;
    while (i < last && !(e < l->rings[i].outer_deg))
        i++;
    r.ring = i;
    if (i == last)
        return r;
    float outer = l->rings[i].outer_deg, inner = i > 0 ? l->rings[i - 1].outer_deg : 0.0f;
    float band = fminf(l->blend_deg, 0.5f * (outer - inner));
    if (!(band > 0.0f))
        return r;
    r.next = smoothstepf(outer - band, outer, e);
    return r;
}

long long fov_shaded_pixels(const display_desc *d, const fov_layout *l, float gx, float gy, int margin_blocks,
                            long long per_ring[MAX_FOV_RINGS])
{
    if (per_ring)
        for (int i = 0; i < MAX_FOV_RINGS; i++)
            per_ring[i] = 0;
    FS_ASSERT(l != NULL);
    if (!l || l->count < 1 || l->count > MAX_FOV_RINGS)
        return 0;
    disp D = disp_of(d);
    fov_ring_rect chain[MAX_FOV_RINGS];
    footprint_chain(&D, l, l->count - 1, gx, gy, margin_blocks, chain);
    long long total = 0;
    for (int i = 0; i < l->count; i++) {
        long long n = (long long)chain[i].width * chain[i].height;
        if (per_ring)
            per_ring[i] = n;
        total += n;
    }
    return total;
}

// >>tiles

int fov_tile_ring(const display_desc *d, const fov_layout *l, float gx, float gy, int x0, int y0, int x1, int y1)
{
    if (!l || l->count < 1 || x1 <= x0 || y1 <= y0)
        return -1;
    disp D = disp_of(d);
    fov_gaze_clamp(d, &gx, &gy);
    /* Pixel centres lie in [x0 + 0.5, x1 - 0.5]: bound from the centre of that box. */
    double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    double hx = 0.5 * (x1 - x0 - 1), hy = 0.5 * (y1 - y0 - 1);
    double e = fov_eccentricity_deg(d, gx, gy, (float)cx, (float)cy);
    double slack = sqrt(hx * hx + hy * hy) / D.f * RAD2DEG + FOV_TILE_SLACK_DEG;
    if (!isfinite(e) || !isfinite(slack))
        return -1;
    fov_blend lo = fov_composite_weight(l, (float)(e - slack)), hi = fov_composite_weight(l, (float)(e + slack));
    /* Within one ring the next ring's weight only rises with e: 0 at the top bound means 0 inside. */
    return lo.ring == hi.ring && hi.next == 0.0f ? hi.ring : -1;
}

int fov_tile_max(const display_desc *d)
{
    disp D = disp_of(d);
    int tx = ((int)D.w + FOV_TILE_PX - 1) / FOV_TILE_PX, ty = ((int)D.h + FOV_TILE_PX - 1) / FOV_TILE_PX;
    return tx * ty;
}

int fov_composite_tiles(const display_desc *d, const fov_layout *l, float gx, float gy, fov_tile *out, int max)
{
    disp D = disp_of(d);
    int w = (int)D.w, h = (int)D.h, n = 0;
    for (int y0 = 0; y0 < h; y0 += FOV_TILE_PX) {
        int y1 = y0 + FOV_TILE_PX < h ? y0 + FOV_TILE_PX : h;
        for (int x0 = 0; x0 < w; x0 += FOV_TILE_PX) {
            int x1 = x0 + FOV_TILE_PX < w ? x0 + FOV_TILE_PX : w;
            int ring = fov_tile_ring(d, l, gx, gy, x0, y0, x1, y1);
            if (n > 0 && out[n - 1].y0 == y0 && out[n - 1].x1 == x0 && out[n - 1].ring == ring) {
                out[n - 1].x1 = x1; /* extends the run */
                continue;
            }
            if (n == max)
                return n;
            out[n++] = (fov_tile){x0, y0, x1, y1, ring};
        }
    }
    return n;
}

// >>culling

float fov_ring_hole_deg(const fov_layout *l, int i)
{
    if (!l || i < 1 || i >= l->count || i >= MAX_FOV_RINGS)
        return 0.0f;
    float outer = l->rings[i - 1].outer_deg, inner = i > 1 ? l->rings[i - 2].outer_deg : 0.0f;
    float band = fminf(l->blend_deg, 0.5f * (outer - inner));
    float h = outer - (band > 0.0f ? band : 0.0f);
    return isfinite(h) && h > 0.0f ? h : 0.0f;
}

float fov_ring_cull_deg(const display_desc *d, const fov_layout *l, int i)
{
    float h = fov_ring_hole_deg(l, i);
    if (!(h > 0.0f) || h >= 90.0f)
        return 0.0f;
    disp D = disp_of(d);
    double c = h - FOV_CULL_MARGIN_BLOCKS * (double)(1 << l->rings[i].scale_log2) / D.f * RAD2DEG;
    return c > 0.0 ? (float)c : 0.0f;
}

bool fov_rect_within_deg(const display_desc *d, float gx, float gy, const float rect[4], float deg)
{
    if (!(deg > 0.0f) || !(deg < 90.0f))
        return false;
    for (int c = 0; c < 4; c++) {
        float e = fov_eccentricity_deg(d, gx, gy, rect[c & 1 ? 2 : 0], rect[c & 2 ? 3 : 1]);
        if (!(e < deg))
            return false;
    }
    return true;
}
