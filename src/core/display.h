/* display.h: the display a frame is drawn for: its size in pixels, its horizontal field of view and
 * its principal point. The scene file names it; foveation, metrics and the frame record read it. It
 * lives in core/ so that those layers need not include the scene.
 *
 * The display is a pinhole camera with square pixels (docs/design.md "The display model"):
 *   - focal length in pixels f = (width / 2) / tan(hfov / 2), so hfov is the field of view of a
 *     display of that width CENTRED on the principal point (for an off-centre display it is not
 *     the angle between its left and right edges);
 *   - principal point (where the view axis meets the display) at (width / 2 + ppx, height / 2 + ppy)
 *     display pixels, top-left origin, x right, y down. ppx = ppy = 0 (zero-initialised) is the
 *     centred display every computation had before; results for it are bit-identical.
 * display_ray and display_pixel are the one pixel <-> view direction pair every layer uses. */
#ifndef FOVSIM_DISPLAY_H
#define FOVSIM_DISPLAY_H

#include <stdbool.h>

typedef struct display_desc {
    int width, height; /* pixels, default 1280 x 720 */
    float hfov_deg;    /* horizontal field of view of a display of this width centred on the
                          principal point, default 90 */
    float ppx, ppy;    /* principal point minus the display centre, pixels (x right, y down);
                          0, 0 = centred (today's displays) */
} display_desc;

/* The display as the angle math sees it, sanitised: width and height at least 1, a NaN hfov taken
 * as 90 degrees and others clamped to [0.001, 179.999], a non-finite ppx or ppy taken as 0. */
typedef struct display_geom {
    double w, h; /* pixels */
    double f;    /* focal length, pixels */
    double cx, cy; /* principal point, display pixels, top-left origin */
} display_geom;

display_geom display_geom_of(const display_desc *d);
/* View ray (camera space, y up, looking down -z, not normalised: z = -f) through display point
 * (px, py) (continuous pixels, top-left origin). */
void display_ray(const display_geom *g, double px, double py, double v[3]);
/* The display point whose view ray is direction v (camera space); false (and nothing written) when
 * v does not point in front of the camera (v[2] >= 0). Inverse of display_ray. */
bool display_pixel(const display_geom *g, const double v[3], double *px, double *py);

/* The same display at another size (a --size override, the reference's supersampled grid): the
 * principal point's offset scaled with it (exactly kept at the display's own size), hfov kept. */
display_desc display_resized(const display_desc *d, int width, int height);

/* An eye's field of view as OpenXR gives it (XrFovf): angles in radians from the view axis, left and
 * down negative, right and up positive. */
typedef struct display_fov_angles {
    double left, right, down, up;
} display_fov_angles;

/* The square-pixel display `width` pixels wide that spans fov: f = width / (tan(right) - tan(left)),
 * hfov = 2 atan(width / 2f), ppx = -f (tan(right) + tan(left)) / 2, height = the vertical span
 * f (tan(up) - tan(down)) rounded to whole pixels (at least 1), ppy = f (tan(up) + tan(down)) / 2
 * (the rounding shared equally by the top and bottom edges). Angles must satisfy
 * -90 deg < left < right < 90 deg, the same for down < up; false otherwise (out untouched). */
bool display_from_fov_angles(const display_fov_angles *fov, int width, display_desc *out);
/* The four edge angles of a display (the inverse of display_from_fov_angles). */
display_fov_angles display_fov_angles_of(const display_desc *d);

#endif
