/* vrs_map.h: foveation by variable-rate shading (VRS, issue 33): the shading-rate map, one rate per
 * square tile of display pixels, from the acuity model of fov_ring.h or from an explicit list of
 * eccentricity bands; the map's statistics; the text forms of the options. Plain C, no GL: the
 * renderer uploads the array vrs_map_fill writes (one byte per tile) as its rate image.
 * docs/foveation.md "Variable-rate shading (VRS): the rate map".
 *
 * Conventions (those of fov_ring.h): display pixels with the origin at the top-left corner, gaze in
 * display pixels. Tiles start at the display's top-left corner; the last column and row of tiles
 * may hang over the display's right and bottom edges (only their pixels on the display count). A
 * coarse pixel of rate W x H covers W x H display pixels aligned to the tile (tile sizes are
 * multiples of 4), so no coarse pixel straddles two tiles.
 *
 * What it does NOT do: the shading itself (issue 33 part 2), cost counts (part 3).
 */
#ifndef FOVSIM_VRS_MAP_H
#define FOVSIM_VRS_MAP_H

#include <stdbool.h>
#include <stdint.h>

#include "core/display.h"
#include "core/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How a run foveates: --foveation and the scene key "foveation". UNSET: not given (the scene's, else
 * rings). OFF is the same as --rings off. */
typedef enum foveation_kind { FOVEATION_UNSET = 0, FOVEATION_RINGS, FOVEATION_VRS, FOVEATION_OFF } foveation_kind;
/* "rings", "vrs", "off" ("unset" for UNSET). */
const char *foveation_kind_name(foveation_kind k);
/* "rings", "vrs" or "off" (exactly); false otherwise. */
bool foveation_kind_parse(const char *text, foveation_kind *out);

/* What the drawing commands that do not draw VRS say when asked for it (render, compare, bench and
 * bench --accuracy draw it, sweeps through their tasks' compare, plan shows the map; bench
 * --calibrate, demo, reference and view do not). */
#define VRS_NOT_BUILT                                                                                                  \
    "VRS is drawn by render, compare, bench (and --accuracy) and a sweep manifest's \"rings\": \"vrs\"; this "      \
    "command does not draw it"

/* A shading rate: the coarse pixel's width and height in display pixels as log2 each, packed as
 * (log2 width) << 2 | (log2 height), the encoding of D3D12's shading-rate images, so a shader reads
 * width = 1 << (r >> 2), height = 1 << (r & 3). Only the seven rates below exist (no 1x4, 4x1). */
typedef uint8_t vrs_rate;
#define VRS_RATE(wlog2, hlog2) ((vrs_rate)(((wlog2) << 2) | (hlog2)))
#define VRS_1X1 VRS_RATE(0, 0)
#define VRS_1X2 VRS_RATE(0, 1)
#define VRS_2X1 VRS_RATE(1, 0)
#define VRS_2X2 VRS_RATE(1, 1)
#define VRS_2X4 VRS_RATE(1, 2)
#define VRS_4X2 VRS_RATE(2, 1)
#define VRS_4X4 VRS_RATE(2, 2)
#define VRS_RATE_COUNT 7
/* The rates from finest to coarsest (by area, 1x2 before 2x1): index i of the statistics. */
extern const vrs_rate k_vrs_rates[VRS_RATE_COUNT];
static inline int vrs_rate_width(vrs_rate r) { return 1 << (r >> 2); }
static inline int vrs_rate_height(vrs_rate r) { return 1 << (r & 3); }
/* Index of r in k_vrs_rates, -1 for a code that is not one of the seven. */
int vrs_rate_index(vrs_rate r);
/* "2x4" (width x height); "?" for a code that is not a rate. */
const char *vrs_rate_name(vrs_rate r);
/* "1x1" ... "4x4", one of the seven exactly; false otherwise. */
bool vrs_rate_parse(const char *text, vrs_rate *out);

/* Tile sizes: 8, 16 (default) or 32 display pixels. */
#define VRS_TILE_DEFAULT 16
bool vrs_tile_valid(int tile);

/* The rate map's rule: the acuity model (auto), or explicit eccentricity bands "10:1x1,25:2x2,*:4x4"
 * (outer border in degrees, innermost first, strictly increasing, the last '*'; each band's rate at
 * least as coarse in width and in height as the band inside it). */
#define VRS_MAX_BANDS 8
typedef struct vrs_spec {
    bool is_auto;
    int count;                       /* explicit: 1..VRS_MAX_BANDS */
    float outer_deg[VRS_MAX_BANDS];  /* INFINITY for the last */
    vrs_rate rate[VRS_MAX_BANDS];
} vrs_spec;

/* "auto" or the explicit list (blanks around items allowed). On error one line into err naming the
 * item ("band 2: rate '3x3' is not one of 1x1, 1x2, 2x1, 2x2, 2x4, 4x2, 4x4") and FS_ERR_USAGE;
 * *out untouched. */
fs_status vrs_spec_parse(const char *text, vrs_spec *out, char *err, int err_size);
/* "auto" or "10:1x1,25:2x2,*:4x4". */
void vrs_spec_format(const vrs_spec *s, char *buf, int size);

/* Tiles across and down for a display: ceil(width / tile), ceil(height / tile). */
void vrs_tile_grid(const display_desc *d, int tile, int *tiles_x, int *tiles_y);

/* The lowest eccentricity (degrees) of any point of the display rectangle [x0, x1] x [y0, y1]
 * (continuous pixels) from gaze g: 0 when g lies in it, else the minimum over its four edges,
 * exact (along a line of the image plane the angle to the gaze ray has one minimum, found in
 * closed form). */
double vrs_rect_min_ecc_deg(const display_desc *d, float gx, float gy, double x0, double y0, double x1, double y1);

/* The auto rule for the tile whose top-left pixel is (x0, y0), `tile` pixels square: the
 * coarsest rate whose coarse pixel spans, along each axis, no more than MAR(e) = slope e + omega0
 * (fov_ring.h's model; slope, omega0 <= 0: the defaults) at the lowest eccentricity e of the
 * tile's part on the display. The
 * span of W pixels along x is bounded by W times the largest angle one pixel spans along x anywhere
 * in the tile, sqrt(f^2 + Ymax^2) / (f^2 + Xmin^2 + Ymin^2) radians (X, Y: offsets from the principal
 * point; f the focal length in pixels), likewise along y; so the rule is exact per tile and
 * conservative for every point of it. Pixels span less away from the principal point, and less
 * along the direction away from it than across it, so anisotropic rates (2x1, 4x2 left and right,
 * 1x2, 2x4 above and below) appear where one axis allows twice the other. */
vrs_rate vrs_tile_rate_auto(const display_desc *d, int tile, float gx, float gy, int x0, int y0, float slope,
                            float omega0);

/* Fills rates[ty * tiles_x + tx] (vrs_tile_grid's size; row 0 is the top row of tiles, so a GL
 * texture of it, whose rows run bottom-up, is flipped or read at tiles_y - 1 - ty) for gaze g
 * (display pixels; clamped onto the display as fov_gaze_clamp does): auto by vrs_tile_rate_auto
 * with the default model; explicit: the band holding the tile's lowest eccentricity (the finest
 * rate any of its pixels' bands asks for). Cost: about 150 ns of CPU per tile (1280x720 at 16 px,
 * 80 x 45 tiles: 0.54 ms; docs/foveation.md), cheap enough to redo every frame. */
void vrs_map_fill(const display_desc *d, const vrs_spec *s, int tile, float gx, float gy, vrs_rate *rates);

/* What a map shades: display pixels per rate (indices of k_vrs_rates; tiles clipped to the
 * display), their shares (sum 1), the coarse pixels shaded (sum of pixels / rate area; fractional
 * at partial coarse pixels, as the ideal count) and the ideal shading saving
 * 1 - shaded / display pixels. */
typedef struct vrs_stats {
    long long pixels[VRS_RATE_COUNT];
    double share[VRS_RATE_COUNT];
    double shaded;
    double saving;
} vrs_stats;
vrs_stats vrs_map_stats(const display_desc *d, int tile, const vrs_rate *rates);

#ifdef __cplusplus
}
#endif

#endif
