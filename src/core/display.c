/* display.c: the display's pinhole model (see display.h). */
#include "core/display.h"

#include <math.h>

#include "core/fmath.h"

#define DEG2RAD (FS_PI / 180.0)
#define RAD2DEG (180.0 / FS_PI)

display_geom display_geom_of(const display_desc *d)
{
    display_geom g = {1280.0, 720.0, 640.0, 640.0, 360.0};
    if (!d)
        return g;
    double hfov = d->hfov_deg;
    if (isnan(hfov))
        hfov = 90.0;
    hfov = hfov < 0.001 ? 0.001 : hfov > 179.999 ? 179.999 : hfov;
    g.w = d->width < 1 ? 1.0 : (double)d->width;
    g.h = d->height < 1 ? 1.0 : (double)d->height;
    g.f = 0.5 * g.w / tan(0.5 * hfov * DEG2RAD);
    /* 0.5 w + 0 is exactly 0.5 w: centred displays keep their old arithmetic bit for bit. */
    g.cx = 0.5 * g.w + (isfinite(d->ppx) ? (double)d->ppx : 0.0);
    g.cy = 0.5 * g.h + (isfinite(d->ppy) ? (double)d->ppy : 0.0);
    return g;
}

void display_ray(const display_geom *g, double px, double py, double v[3])
{
    v[0] = px - g->cx;
    v[1] = -(py - g->cy);
    v[2] = -g->f;
}

bool display_pixel(const display_geom *g, const double v[3], double *px, double *py)
{
    if (!(v[2] < 0.0))
        return false;
    double s = g->f / -v[2];
    *px = g->cx + v[0] * s;
    *py = g->cy - v[1] * s;
    return true;
}

/* One coordinate of the principal point's offset at another size. */
static float pp_scaled(float pp, int size, int at)
{
    if (pp == 0.0f || at == size || size <= 0)
        return pp;
    return (float)((double)pp * at / size);
}

display_desc display_resized(const display_desc *d, int width, int height)
{
    return (display_desc){width, height, d->hfov_deg, pp_scaled(d->ppx, d->width, width),
                          pp_scaled(d->ppy, d->height, height)};
}

static bool angle_pair_ok(double lo, double hi)
{
    const double lim = 0.5 * FS_PI;
    return lo > -lim && hi < lim && lo < hi;
}

bool display_from_fov_angles(const display_fov_angles *fov, int width, display_desc *out)
{
    if (!fov || !out || width < 1 || !angle_pair_ok(fov->left, fov->right) || !angle_pair_ok(fov->down, fov->up))
        return false;
    double tl = tan(fov->left), tr = tan(fov->right), td = tan(fov->down), tu = tan(fov->up);
    double f = (double)width / (tr - tl);
    double span = f * (tu - td);
    long h = lround(span);
    if (h < 1)
        h = 1;
    if (!(span < 1e9))
        return false;
    *out = (display_desc){width, (int)h, (float)(2.0 * atan(0.5 * width / f) * RAD2DEG),
                          (float)(-0.5 * f * (tr + tl)), (float)(0.5 * f * (tu + td))};
    return true;
}

display_fov_angles display_fov_angles_of(const display_desc *d)
{
    display_geom g = display_geom_of(d);
    return (display_fov_angles){atan(-g.cx / g.f), atan((g.w - g.cx) / g.f), atan(-(g.h - g.cy) / g.f),
                                atan(g.cy / g.f)};
}
