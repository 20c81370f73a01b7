/* vrs_map.c: the VRS shading-rate map (see vrs_map.h for the contract and conventions).
 *
 * Decisions where the header is silent (tested in tests/unit/test_vrs_map.c):
 *   - The auto rule takes the lowest eccentricity over the tile's part on the display, and the
 *     pixel-angle bound over the whole tile (its overhang too): a coarse pixel of the last column
 *     may reach past the display edge, and its span there is bounded as well.
 *   - The math runs in double; degenerate displays are sanitised as fov_ring.c does (size at least
 *     1, a NaN field of view taken as 90 degrees, others clamped to [0.001, 179.999]).
 *   - An explicit map's tile takes the band of its lowest eccentricity: no pixel of it is shaded
 *     coarser than its own band asks.
 */
#include "fov/vrs_map.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fov/fov_ring.h"

#define DEG2RAD (FS_PI / 180.0)
#define RAD2DEG (180.0 / FS_PI)

const vrs_rate k_vrs_rates[VRS_RATE_COUNT] = {VRS_1X1, VRS_1X2, VRS_2X1, VRS_2X2, VRS_2X4, VRS_4X2, VRS_4X4};
static const char *const k_rate_names[VRS_RATE_COUNT] = {"1x1", "1x2", "2x1", "2x2", "2x4", "4x2", "4x4"};

const char *foveation_kind_name(foveation_kind k)
{
    switch (k) {
    case FOVEATION_RINGS: return "rings";
    case FOVEATION_VRS: return "vrs";
    case FOVEATION_OFF: return "off";
    default: return "unset";
    }
}

bool foveation_kind_parse(const char *text, foveation_kind *out)
{
    static const foveation_kind kinds[] = {FOVEATION_RINGS, FOVEATION_VRS, FOVEATION_OFF};
    for (int i = 0; text && i < 3; i++)
        if (!strcmp(text, foveation_kind_name(kinds[i]))) {
            *out = kinds[i];
            return true;
        }
    return false;
}

int vrs_rate_index(vrs_rate r)
{
    for (int i = 0; i < VRS_RATE_COUNT; i++)
        if (k_vrs_rates[i] == r)
            return i;
    return -1;
}

const char *vrs_rate_name(vrs_rate r)
{
    int i = vrs_rate_index(r);
    return i < 0 ? "?" : k_rate_names[i];
}

bool vrs_rate_parse(const char *text, vrs_rate *out)
{
    for (int i = 0; text && i < VRS_RATE_COUNT; i++)
        if (!strcmp(text, k_rate_names[i])) {
            *out = k_vrs_rates[i];
            return true;
        }
    return false;
}

bool vrs_tile_valid(int tile)
{
    return tile == 8 || tile == 16 || tile == 32;
}

// >>text form

/* One "OUTER:RATE" band in [b, e) into s->outer_deg[n - 1], s->rate[n - 1]. */
static fs_status parse_band(const char *b, const char *e, int n, vrs_spec *s, char *err, int err_size)
{
    char item[FOV_TOKEN_MAX], outer[FOV_TOKEN_MAX], rate[FOV_TOKEN_MAX];
    if (!fov_take_token(b, e, item)) {
        fov_set_err(err, err_size, "band %d: too long (expected OUTER:RATE, e.g. 10:1x1)", n);
        return FS_ERR_USAGE;
    }
    const char *colon = strchr(item, ':');
    if (!item[0] || !colon || strchr(colon + 1, ':')) {
        fov_set_err(err, err_size, "band %d: expected OUTER:RATE (e.g. 10:1x1), got '%s'", n, item);
        return FS_ERR_USAGE;
    }
    fov_take_token(item, colon, outer);
    fov_take_token(colon + 1, item + strlen(item), rate);
    double v;
    if (!strcmp(outer, "*"))
        s->outer_deg[n - 1] = INFINITY;
    else if (fov_parse_ratio(outer, &v) && (float)v > 0.0f && isfinite((float)v)) /* as the float it is kept in */
        s->outer_deg[n - 1] = (float)v;
    else {
        fov_set_err(err, err_size, "band %d: border '%s' is not a positive finite number of degrees (or '*')", n, outer);
        return FS_ERR_USAGE;
    }
    if (!vrs_rate_parse(rate, &s->rate[n - 1])) {
        fov_set_err(err, err_size, "band %d: rate '%s' is not one of 1x1, 1x2, 2x1, 2x2, 2x4, 4x2, 4x4", n, rate);
        return FS_ERR_USAGE;
    }
    return FS_OK;
}

/* Band n (1-based) against the band inside it: border beyond, rate no finer along either axis. */
static fs_status check_band(const vrs_spec *s, int n, char *err, int err_size)
{
    int i = n - 1;
    if (i == 0)
        return FS_OK;
    if (isinf(s->outer_deg[i - 1])) {
        fov_set_err(err, err_size, "band %d: '*' must be the last band (it covers the rest of the display)", i);
        return FS_ERR_USAGE;
    }
    if (!(s->outer_deg[i] > s->outer_deg[i - 1])) {
        fov_set_err(err, err_size, "band %d: border %g deg is not beyond band %d's %g deg (borders increase outwards)",
                    n, (double)s->outer_deg[i], i, (double)s->outer_deg[i - 1]);
        return FS_ERR_USAGE;
    }
    vrs_rate a = s->rate[i - 1], r = s->rate[i];
    if (vrs_rate_width(r) < vrs_rate_width(a) || vrs_rate_height(r) < vrs_rate_height(a)) {
        fov_set_err(err, err_size, "band %d: rate %s is finer than band %d's %s along %s (rates coarsen outwards)", n,
                    vrs_rate_name(r), i, vrs_rate_name(a), vrs_rate_width(r) < vrs_rate_width(a) ? "x" : "y");
        return FS_ERR_USAGE;
    }
    return FS_OK;
}

fs_status vrs_spec_parse(const char *text, vrs_spec *out, char *err, int err_size)
{
    if (err && err_size > 0)
        err[0] = '\0';
    const char *b = text ? text : "", *e = b + strlen(b);
    fov_trim(&b, &e);
    if ((size_t)(e - b) == 4 && !memcmp(b, "auto", 4)) {
        if (out)
            *out = (vrs_spec){.is_auto = true};
        return FS_OK;
    }
    if (b == e || !memchr(b, ':', (size_t)(e - b))) {
        fov_set_err(err, err_size, "expected auto or OUTER:RATE,...,*:RATE (e.g. 10:1x1,25:2x2,*:4x4), got '%.*s'",
                    (int)(e - b), b);
        return FS_ERR_USAGE;
    }
    vrs_spec s = {.is_auto = false};
    for (const char *q = b;;) {
        const char *c = memchr(q, ',', (size_t)(e - q));
        if (!c)
            c = e;
        if (s.count == VRS_MAX_BANDS) {
            fov_set_err(err, err_size, "more than %d bands", VRS_MAX_BANDS);
            return FS_ERR_USAGE;
        }
        s.count++;
        fs_status st = parse_band(q, c, s.count, &s, err, err_size);
        if (st == FS_OK)
            st = check_band(&s, s.count, err, err_size);
        if (st != FS_OK)
            return st;
        if (c == e)
            break;
        q = c + 1;
    }
    if (!isinf(s.outer_deg[s.count - 1])) {
        fov_set_err(err, err_size, "band %d: the last band's border must be '*' (it covers the rest of the display)",
                    s.count);
        return FS_ERR_USAGE;
    }
    if (out)
        *out = s;
    return FS_OK;
}

void vrs_spec_format(const vrs_spec *s, char *buf, int size)
{
    if (!buf || size <= 0)
        return;
    buf[0] = '\0';
    if (!s || s->is_auto) {
        snprintf(buf, (size_t)size, "auto");
        return;
    }
    int n = 0;
    for (int i = 0; i < s->count && n < size; i++) {
        char outer[32] = "*";
        if (!isinf(s->outer_deg[i]))
            fov_format_float(outer, sizeof outer, s->outer_deg[i]);
        n += snprintf(buf + n, (size_t)(size - n), "%s%s:%s", i ? "," : "", outer, vrs_rate_name(s->rate[i]));
    }
}

// >>the map

/* The display as the map's math sees it (core/display.h, the sanitising fov_ring.c uses). */
typedef display_geom vdisp;

static vdisp vdisp_of(const display_desc *d)
{
    return display_geom_of(d);
}

void vrs_tile_grid(const display_desc *d, int tile, int *tiles_x, int *tiles_y)
{
    vdisp D = vdisp_of(d);
    int t = tile > 0 ? tile : VRS_TILE_DEFAULT;
    *tiles_x = ((int)D.w + t - 1) / t;
    *tiles_y = ((int)D.h + t - 1) / t;
}

/* Camera-plane point (y up, looking down -z) of display point (x, y). */
static void plane_point(const vdisp *D, double x, double y, double p[3])
{
    display_ray(D, x, y, p);
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Cosine-like score of the ray through p0 + t dir against u: (u . p) / |p| (|u| fixed). */
static double score_at(const double u[3], const double p0[3], const double dir[3], double t, double p[3])
{
    for (int k = 0; k < 3; k++)
        p[k] = p0[k] + t * dir[k];
    return dot3(u, p) / sqrt(dot3(p, p));
}

/* The point of the segment p0 + t dir, t in [0, len] (dir a unit vector), whose ray is closest in
 * angle to u. Along the line the score has one stationary point, where
 * (B C - A D) + (B D - A) t = 0 (A = u.p0, B = u.dir, C = p0.p0, D = p0.dir); the segment's best is
 * there (clamped) or at an end. */
static double segment_best(const double u[3], const double p0[3], const double dir[3], double len, double best[3])
{
    double A = dot3(u, p0), B = dot3(u, dir), C = dot3(p0, p0), D = dot3(p0, dir);
    double ts[3] = {0.0, len, 0.0};
    int n = 2;
    if (A - B * D != 0.0) {
        double t = (B * C - A * D) / (A - B * D);
        ts[n++] = t < 0.0 ? 0.0 : t > len ? len : t;
    }
    double s_best = score_at(u, p0, dir, ts[0], best), p[3];
    for (int i = 1; i < n; i++) {
        double s = score_at(u, p0, dir, ts[i], p);
        if (s > s_best)
            s_best = s, memcpy(best, p, sizeof p);
    }
    return s_best;
}

static double angle_deg(const double a[3], const double b[3])
{
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return atan2(sqrt(dot3(c, c)), dot3(a, b)) * RAD2DEG;
}

double vrs_rect_min_ecc_deg(const display_desc *d, float gx, float gy, double x0, double y0, double x1, double y1)
{
    if (gx >= x0 && gx <= x1 && gy >= y0 && gy <= y1)
        return 0.0;
    vdisp D = vdisp_of(d);
    double u[3], corner[4][3];
    plane_point(&D, gx, gy, u);
    plane_point(&D, x0, y0, corner[0]); /* top-left, then clockwise */
    plane_point(&D, x1, y0, corner[1]);
    plane_point(&D, x1, y1, corner[2]);
    plane_point(&D, x0, y1, corner[3]);
    const double right[3] = {1, 0, 0}, down[3] = {0, -1, 0}, left[3] = {-1, 0, 0}, up[3] = {0, 1, 0};
    const double *dirs[4] = {right, down, left, up};
    double lens[4] = {x1 - x0, y1 - y0, x1 - x0, y1 - y0};
    double best[3], p[3];
    double s_best = segment_best(u, corner[0], dirs[0], lens[0], best);
    for (int k = 1; k < 4; k++) {
        double s = segment_best(u, corner[k], dirs[k], lens[k], p);
        if (s > s_best)
            s_best = s, memcpy(best, p, sizeof p);
    }
    return angle_deg(u, best);
}

/* log2 of the most display pixels whose span, at `pixel_rad` radians each at most, fits in `mar_rad`
 * (0..2: rates go up to 4 pixels). */
static int fit_log2(double pixel_rad, double mar_rad)
{
    int k = 0;
    while (k < 2 && (double)(2 << k) * pixel_rad <= mar_rad)
        k++;
    return k;
}

/* The smallest |v| and the largest |v| over [a, b]. */
static void abs_range(double a, double b, double *lo, double *hi)
{
    *lo = a <= 0.0 && b >= 0.0 ? 0.0 : fmin(fabs(a), fabs(b));
    *hi = fmax(fabs(a), fabs(b));
}

vrs_rate vrs_tile_rate_auto(const display_desc *d, int tile, float gx, float gy, int x0, int y0, float slope,
                            float omega0)
{
    vdisp D = vdisp_of(d);
    double m = slope > 0.0f && isfinite(slope) ? slope : FOV_ACUITY_SLOPE_DEFAULT;
    double w0 = omega0 > 0.0f && isfinite(omega0) ? omega0 : FOV_ACUITY_OMEGA0_DEFAULT;
    double x1 = fmin(x0 + tile, D.w), y1 = fmin(y0 + tile, D.h);
    double e = vrs_rect_min_ecc_deg(d, gx, gy, x0, y0, x1, y1);
    double mar = (m * e + w0) * DEG2RAD;
    /* The pixel-angle bounds over the whole tile, overhang included. */
    double xlo, xhi, ylo, yhi, f2 = D.f * D.f;
    abs_range(x0 - D.cx, x0 + tile - D.cx, &xlo, &xhi);
    abs_range(D.cy - y0 - tile, D.cy - y0, &ylo, &yhi);
    double den = f2 + xlo * xlo + ylo * ylo;
    int wl = fit_log2(sqrt(f2 + yhi * yhi) / den, mar), hl = fit_log2(sqrt(f2 + xhi * xhi) / den, mar);
    /* No 1x4 or 4x1: the longer side is at most twice the shorter. */
    if (wl > hl + 1)
        wl = hl + 1;
    if (hl > wl + 1)
        hl = wl + 1;
    return VRS_RATE(wl, hl);
}

static vrs_rate band_rate(const vrs_spec *s, double e)
{
    int i = 0;
    while (i < s->count - 1 && !(e < s->outer_deg[i]))
        i++;
    return s->rate[i];
}

void vrs_map_fill(const display_desc *d, const vrs_spec *s, int tile, float gx, float gy, vrs_rate *rates)
{
    vdisp D = vdisp_of(d);
    int t = vrs_tile_valid(tile) ? tile : VRS_TILE_DEFAULT, nx, ny;
    vrs_tile_grid(d, t, &nx, &ny);
    fov_gaze_clamp(d, &gx, &gy);
    for (int ty = 0; ty < ny; ty++)
        for (int tx = 0; tx < nx; tx++) {
            int x0 = tx * t, y0 = ty * t;
            vrs_rate r;
            if (!s || s->is_auto || s->count < 1)
                r = vrs_tile_rate_auto(d, t, gx, gy, x0, y0, 0.0f, 0.0f);
            else
                r = band_rate(s, vrs_rect_min_ecc_deg(d, gx, gy, x0, y0, fmin(x0 + t, D.w), fmin(y0 + t, D.h)));
            rates[ty * nx + tx] = r;
        }
}

vrs_stats vrs_map_stats(const display_desc *d, int tile, const vrs_rate *rates)
{
    vrs_stats st;
    memset(&st, 0, sizeof st);
    vdisp D = vdisp_of(d);
    int t = vrs_tile_valid(tile) ? tile : VRS_TILE_DEFAULT, nx, ny;
    vrs_tile_grid(d, t, &nx, &ny);
    long long W = (long long)D.w, H = (long long)D.h, total = W * H;
    for (int ty = 0; ty < ny; ty++)
        for (int tx = 0; tx < nx; tx++) {
            long long w = W - (long long)tx * t < t ? W - (long long)tx * t : t;
            long long h = H - (long long)ty * t < t ? H - (long long)ty * t : t;
            vrs_rate r = rates[ty * nx + tx];
            int i = vrs_rate_index(r);
            FS_ASSERT(i >= 0);
            if (i < 0)
                r = VRS_1X1, i = 0; /* not a rate: counted as full rate */
            st.pixels[i] += w * h;
            st.shaded += (double)(w * h) / (vrs_rate_width(r) * vrs_rate_height(r));
        }
    for (int i = 0; i < VRS_RATE_COUNT; i++)
        st.share[i] = (double)st.pixels[i] / (double)total;
    st.saving = 1.0 - st.shaded / (double)total;
    return st;
}
