/* gaze_place.c: a loaded trace placed on the simulated display by visual angle (gaze.h,
 * gaze_place), and the --gaze-screen / --gaze-map values.
 *
 * Every trace is loaded in its recording's normalised frame. The recording's geometry (per-sample
 * directions, or a pinhole frame tan_per_x/y, or --gaze-screen) turns a sample into tangents of
 * its angles from straight ahead; the display is a pinhole too (the renderer's projection, the
 * convention of frame_record's gaze_deg: theta_x = atan((x_px - w/2) / f)), so a sample lands at
 * x_px = w/2 + f tan(theta_x), y_px = h/2 - f tan(theta_y). Exact tan mapping both ways: a 10 deg
 * saccade in the recording is 10 deg on any display. How each format gets its geometry:
 * docs/gaze-formats.md ("Degrees").
 */
#include "gaze/gaze_read.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define DEG (3.14159265358979323846 / 180.0)

/* >>values */

const char *gaze_map_name(gaze_map m) { return m == GAZE_MAP_NORMALIZED ? "normalized" : "angle"; }

/* A positive decimal number at *p (strtod, refusing nan, inf and hex); advances *p. */
static bool positive(const char **p, double hi, double *v)
{
    const char *b = *p;
    if (!((**p >= '0' && **p <= '9') || **p == '.'))
        return false;
    while ((**p >= '0' && **p <= '9') || **p == '.')
        ++*p;
    char buf[32];
    if (*p - b >= (long)sizeof buf)
        return false;
    snprintf(buf, sizeof buf, "%.*s", (int)(*p - b), b);
    char *end;
    *v = strtod(buf, &end);
    return *end == '\0' && *v > 0 && *v <= hi;
}

bool gaze_screen_parse(const char *text, gaze_screen *out, char *err, size_t cap)
{
    const char *p = text ? text : "";
    gaze_screen s = {0};
    bool ok = positive(&p, GAZE_SCREEN_MAX_MM, &s.w) && (*p == 'x' || *p == 'X') && (++p, true) &&
              positive(&p, GAZE_SCREEN_MAX_MM, &s.h);
    if (ok && *p == '@') {
        ++p;
        s.kind = GAZE_SCREEN_MM;
        ok = positive(&p, GAZE_SCREEN_MAX_MM, &s.dist) && *p == '\0';
    } else if (ok && strcmp(p, "deg") == 0) {
        s.kind = GAZE_SCREEN_FOV;
        ok = s.w < GAZE_SCREEN_MAX_FOV_DEG + 1e-9 && s.h < GAZE_SCREEN_MAX_FOV_DEG + 1e-9;
    } else {
        ok = false;
    }
    if (!ok) {
        snprintf(err, cap, "expected W_MMxH_MM@DIST_MM (e.g. 520x290@600, each in (0, %.0f] mm) or a field of view "
                 "HxVdeg (e.g. 82x52deg, each in (0, %.0f]), got '%s'", GAZE_SCREEN_MAX_MM, GAZE_SCREEN_MAX_FOV_DEG, text ? text : "");
        return false;
    }
    *out = s;
    return true;
}

void gaze_screen_format(const gaze_screen *s, char *buf, size_t cap)
{
    if (s->kind == GAZE_SCREEN_MM)
        snprintf(buf, cap, "%gx%g@%g", s->w, s->h, s->dist);
    else if (s->kind == GAZE_SCREEN_FOV)
        snprintf(buf, cap, "%gx%gdeg", s->w, s->h);
    else if (cap)
        buf[0] = '\0';
}

gaze_place_desc gaze_place_merge(const gaze_place_opts *first, const gaze_place_opts *second)
{
    gaze_place_desc d = {0};
    d.map = first->map_set ? first->desc.map : second->map_set ? second->desc.map : GAZE_MAP_ANGLE;
    d.screen = first->screen_set ? first->desc.screen : second->screen_set ? second->desc.screen : d.screen;
    return d;
}

/* >>place */

/* The pinhole frame --gaze-screen describes, as tan per unit of normalised coordinate. */
static void screen_tan_per(const gaze_screen *s, double *kx, double *ky)
{
    if (s->kind == GAZE_SCREEN_MM) {
        *kx = s->w / s->dist;
        *ky = s->h / s->dist;
    } else {
        *kx = 2 * tan(0.5 * s->w * DEG);
        *ky = 2 * tan(0.5 * s->h * DEG);
    }
}

typedef struct frame_geom {
    const float *dir;  /* per-sample tangents, or NULL: the pinhole frame below */
    double kx, ky;
} frame_geom;

/* Sample i's tangents; false when it has no direction. */
static bool sample_tan(const gaze_trace *t, const frame_geom *g, int i, double *tx, double *ty)
{
    if (g->dir) {
        *tx = g->dir[2 * i];
        *ty = g->dir[2 * i + 1];
        return !isnan(*tx) && !isnan(*ty);
    }
    *tx = (t->samples[i].x - 0.5) * g->kx;
    *ty = (0.5 - t->samples[i].y) * g->ky;
    return true;
}

typedef struct clamp_stats {
    double span_x, span_y; /* largest |theta| of the trace, degrees */
    double over;           /* largest angle past the display's edge, degrees */
} clamp_stats;

/* One tangent clamped to [lo, hi] (the display's edges as tangents from the view axis; lo = -hi on
 * a centred display), noting the trace's extent and the excess. */
static double clamp_tan(double v, double lo, double hi, double *span, clamp_stats *cs)
{
    double a = atan(fabs(v)) / DEG;
    if (a > *span)
        *span = a;
    if (v >= lo && v <= hi)
        return v;
    double lim = v < lo ? lo : hi;
    double over = a - atan(fabs(lim)) / DEG;
    if (over > cs->over)
        cs->over = over;
    return lim;
}

/* Invalid samples hold the placed gaze again (gaze_finish's rule: the last valid before, the first
 * valid when the trace starts invalid). */
static void refill_held(gaze_trace *t)
{
    int first = 0;
    while (first < t->count && !t->samples[first].valid)
        first++;
    if (first == t->count)
        return;
    float hx = t->samples[first].x, hy = t->samples[first].y;
    for (int i = 0; i < t->count; i++) {
        gaze_sample *s = &t->samples[i];
        if (s->valid)
            hx = s->x, hy = s->y;
        else
            s->x = hx, s->y = hy;
    }
}

/* The geometry to use, said in the log; false (and said once) when there is none. */
static bool choose_geom(const gaze_trace *t, const gaze_place_desc *d, frame_geom *g)
{
    *g = (frame_geom){0};
    char sc[64];
    if (d->screen.kind != GAZE_SCREEN_NONE) {
        screen_tan_per(&d->screen, &g->kx, &g->ky);
        gaze_screen_format(&d->screen, sc, sizeof sc);
        log_info("GAZE: [%s] placed by angle from --gaze-screen %s%s", t->path, sc,
                 t->dir || t->tan_per_x > 0 ? " (instead of the file's geometry)" : "");
        return true;
    }
    if (t->dir) {
        g->dir = t->dir;
    } else if (t->tan_per_x > 0 && t->tan_per_y > 0) {
        g->kx = t->tan_per_x;
        g->ky = t->tan_per_y;
    } else if (t->format == GAZE_FORMAT_CSV) { /* display coordinates by definition: nothing to warn about */
        log_info("GAZE: [%s] no screen geometry: placed by normalised position (fovsim CSV)", t->path);
        return false;
    } else {
        log_warn("GAZE: [%s] no screen geometry: placed by normalised position (--gaze-screen W_MMxH_MM@DIST_MM or "
                 "HxVdeg gives one)", t->path);
        return false;
    }
    log_info("GAZE: [%s] placed by angle: %s", t->path, t->geometry);
    return true;
}

void gaze_place(gaze_trace *t, const gaze_place_desc *desc, const display_desc *disp)
{
    if (!t || t->count <= 0 || !desc || desc->map == GAZE_MAP_NORMALIZED)
        return;
    frame_geom g;
    if (!choose_geom(t, desc, &g))
        return;
    /* The pinhole (core/display.h): tangents from the view axis, principal point (cx, cy). Its
     * sanitising is fov_ring's (a field of view outside (0, 180) clamped, NaN 90), so a trace is
     * placed on the display the rings measure. */
    const display_geom dg = display_geom_of(disp);
    const double w = dg.w, h = dg.h, f = dg.f;
    const double ppx = dg.cx - 0.5 * w, ppy = dg.cy - 0.5 * h; /* 0 on a centred display */
    const double x_lo = -dg.cx / f, x_hi = (w - dg.cx) / f, y_lo = (dg.cy - h) / f, y_hi = dg.cy / f;
    clamp_stats cs = {0};
    int lost = 0;
    for (int i = 0; i < t->count; i++) {
        gaze_sample *s = &t->samples[i];
        double tx, ty;
        if (!s->valid)
            continue;
        if (!sample_tan(t, &g, i, &tx, &ty)) {
            s->valid = false; /* a direction format's sample without a direction */
            lost++;
            continue;
        }
        tx = clamp_tan(tx, x_lo, x_hi, &cs.span_x, &cs);
        ty = clamp_tan(ty, y_lo, y_hi, &cs.span_y, &cs);
        /* (cx + f tx) / w, written so that ppx = 0 keeps 0.5 + f tx / w bit for bit. */
        s->x = (float)(0.5 + (ppx + f * tx) / w);
        s->y = (float)(0.5 + (ppy - f * ty) / h);
    }
    t->valid_count -= lost;
    if (lost)
        log_info("GAZE: [%s] %d samples without a gaze direction are invalid", t->path, lost);
    if (cs.over > 0)
        log_warn("GAZE: [%s] trace spans ±%.1f° x ±%.1f°, the display ±%.1f° x ±%.1f°: clamped by up to %.1f°",
                 t->path, cs.span_x, cs.span_y, atan(fmax(-x_lo, x_hi)) / DEG, atan(fmax(-y_lo, y_hi)) / DEG, cs.over);
    refill_held(t);
}
