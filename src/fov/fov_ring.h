/* fov_ring.h: foveation ring math in plain C — layouts, eccentricity, per-ring footprints and
 * frusta, composite weights. Used by the renderer and by the unit tests; the GLSL twin of
 * fov_eccentricity_deg and fov_composite_weight is shaders/common/foveation.glsl (same constants,
 * common/shared_defs.h).
 *
 * Conventions
 *   - Display pixels: integer coordinates with origin at the TOP-LEFT corner, x right, y down; pixel
 *     (x, y) covers [x, x+1) x [y, y+1) and its centre is (x + 0.5, y + 0.5). This is the gaze and
 *     EXR convention; the GL side flips rows where it has to.
 *   - Gaze: normalised display coordinates (0..1, origin top-left) or display pixels (gaze_px =
 *     gaze * (width, height)).
 *   - Eccentricity: the angle in degrees between the view ray through a display point and the view
 *     ray through the gaze point, for a pinhole camera with the display's focal length and principal
 *     point (core/display.h; the display centre unless ppx, ppy say otherwise).
 *   - A ring i has block size b = 2^scale_log2: one ring pixel covers exactly b x b display pixels,
 *     and its footprint rectangle starts on a multiple of b, so ring pixels align with a sub-grid of
 *     display pixels (no half-pixel drift between rings).
 *
 * What it does NOT do: GL, gaze file parsing (src/gaze), choosing which frame uses which gaze.
 */
#ifndef FOVSIM_FOV_RING_H
#define FOVSIM_FOV_RING_H

#include <stdbool.h>

#include "core/config.h"
#include "core/display.h"
#include "core/fmath.h"
#include "core/log.h"
#include "core/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Guenter et al. 2012 linear acuity model MAR(e) = slope * e + omega0 (degrees). */
#define FOV_ACUITY_SLOPE_DEFAULT 0.0275f
#define FOV_ACUITY_OMEGA0_DEFAULT (1.0f / 48.0f)
#define FOV_BLEND_DEG_DEFAULT 2.0f
/* Ring pixels added around each footprint so bilinear upsampling never reads outside it. */
#define FOV_MARGIN_BLOCKS 2

typedef struct fov_ring {
    float outer_deg; /* outer eccentricity radius in degrees; INFINITY for the last ring ("*") */
    int scale_log2;  /* resolution scale 2^-scale_log2: 0 = full, 1 = 1/2, ... MAX_FOV_SCALE_LOG2 */
    float mip_bias;  /* extra texture LOD bias in log2 units, default 0 */
} fov_ring;

typedef enum fov_layout_kind {
    FOV_LAYOUT_OFF = 0,  /* foveation off: one full-resolution ring, no composite */
    FOV_LAYOUT_AUTO,       /* from the acuity model */
    FOV_LAYOUT_EXPLICIT,   /* from a scene file or --rings */
    FOV_LAYOUT_AGGRESSIVE, /* fov_layout_aggressive: the acuity model, twice the slope, +0.5 bias */
} fov_layout_kind;

typedef struct fov_layout {
    fov_layout_kind kind;
    int count;                       /* 1..MAX_FOV_RINGS */
    fov_ring rings[MAX_FOV_RINGS];   /* innermost first; outer_deg strictly increasing; last = INFINITY */
    float blend_deg;                 /* blend band inside each ring border, degrees, default
                                        FOV_BLEND_DEG_DEFAULT; ring i's band is
                                        min(blend_deg, (outer_i - outer_{i-1}) / 2), outer_{-1} = 0 */
} fov_layout;

/* >>layouts */

/* Foveation off: one ring, scale 1, bias 0, covering the display. */
fov_layout fov_layout_off(void);
/* The acuity layout for a display (docs/design.md "Foveation", docs/foveation.md "Layouts"): ring k
 * (block 2^k) starts at the eccentricity e_k where MAR(e_k) = slope * e_k + omega0 equals the
 * largest angle a 2^k-pixel block spans anywhere on the display, 2^k / f radians at the principal
 * point (f: focal length in pixels; both the radial pitch cos^2(t)/f and the tangential cos(t)/f
 * peak there). That holds for any gaze on the display, since a ring's inner edge can pass through
 * the principal point, so the layout does not depend on the gaze: no ring's block is coarser than
 * MAR at the ring's inner edge, for either pitch and any gaze (fov_layout_acuity_margin >= 1).
 * The innermost ring is full resolution unless 2^k-pixel blocks already resolve MAR at the
 * centre (e_k = 0: the empty rings [0, 0) are skipped, so a very fine display starts coarser);
 * rings whose inner edge lies beyond the display's largest eccentricity from its principal point
 * (to the farthest corner; centre to corner on a centred display) are dropped; scales stop at MAX_FOV_SCALE_LOG2. slope/omega0 <= 0 mean the
 * defaults. */
fov_layout fov_layout_auto(const display_desc *d, float slope, float omega0);
/* The "aggressive" layout (bench --accuracy's third layout, the viewer's L key, --rings aggressive):
 * the acuity model with FOV_AGGRESSIVE_SLOPE_FACTOR times the MAR slope (resolution falls off that
 * much faster with eccentricity) and FOV_AGGRESSIVE_MIP_BIAS more mip bias on every reduced ring.
 * Kind FOV_LAYOUT_AGGRESSIVE. */
#define FOV_AGGRESSIVE_SLOPE_FACTOR 2.0f
#define FOV_AGGRESSIVE_MIP_BIAS 0.5f
fov_layout fov_layout_aggressive(const display_desc *d);
/* "off", "auto", "aggressive" or "explicit": the layout's kind as the CLI and reports name it. */
const char *fov_layout_kind_name(fov_layout_kind k);
/* Acuity check of any layout (auto or explicit) on a display, for any gaze on the display: the
 * largest ratio of the angle a block of ring i spans (along any side, either pitch) to the MAR at
 * ring i's inner edge, over every gaze on the display and every display point in the ring. The
 * block bound is 2^k / f radians (the supremum over the display, approached at the principal
 * point to within (2^k / f)^2 / 3 relative), so the ratio is tight when some gaze puts the
 * principal point in the ring (inner edge up to the centre-to-corner eccentricity) and an upper
 * bound beyond. 0 for full-resolution rings (the
 * display's own pixels) and for rings no gaze on the display shows (inner edge at or beyond the
 * corner-to-corner eccentricity). slope/omega0 <= 0 mean the default model. */
double fov_ring_block_mar_ratio(const display_desc *d, const fov_layout *l, int i, float slope, float omega0);
/* The layout's guaranteed acuity margin: the smallest MAR / block over its rings (1 / the largest
 * fov_ring_block_mar_ratio); >= 1 means no block anywhere is coarser than the MAR at its ring's
 * inner edge, for any gaze; below 1 (possible for explicit layouts) some block is coarser by that
 * factor. INFINITY when no ring coarser than full resolution is ever shown. *worst_ring (may be
 * NULL) gets the ring that sets it, -1 for INFINITY. */
double fov_layout_acuity_margin(const display_desc *d, const fov_layout *l, float slope, float omega0,
                                int *worst_ring);
/* Parses "auto", "aggressive", "off", or an explicit list "10:1:0,25:0.5:0,*:0.25:0.5" (outer degrees or "*"
 * for the last, scale as 1, 0.5, 0.25, ... or 1/2, 1/4, ..., mip bias). On error writes one line
 * into err (e.g. "ring 2: scale 0.3 is not a power of two (1, 1/2, ... 1/16)") and returns
 * FS_ERR_USAGE. `d` is needed for "auto" and "aggressive". */
fs_status fov_layout_parse(const char *text, const display_desc *d, fov_layout *out, char *err, int err_size);

/* What the text forms of fov_ring.c and ring_lod.c share. FOV_TOKEN_MAX: the longest token + 1. */
#define FOV_TOKEN_MAX 64
/* Moves b forward and e back past blanks, tabs and line ends: [b, e) trimmed. */
void fov_trim(const char **b, const char **e);
/* Copies [b, e) without surrounding whitespace into tok; false when it does not fit. */
bool fov_take_token(const char *b, const char *e, char tok[FOV_TOKEN_MAX]);
/* A whole token as a finite number: "1", "0.25" or "1/4" (blanks around '/' allowed). */
bool fov_parse_ratio(const char *tok, double *out);
/* Writes one formatted line into err (size bytes; nothing when err is NULL). */
void fov_set_err(char *err, int size, const char *fmt, ...) FS_PRINTF(3, 4);
/* The shortest %g form of v that reads back as the same float ("-0" printed as "0"). */
void fov_format_float(char *buf, size_t size, float v);
/* Checks an explicit layout: 1..MAX_FOV_RINGS rings, radii positive, finite and increasing, last
 * INFINITY, scales in [0, MAX_FOV_SCALE_LOG2] and non-decreasing outwards, biases finite. */
fs_status fov_layout_check(const fov_layout *l, char *err, int err_size);
/* "10:1:0,25:0.5:0,*:0.25:0.5" form of a layout (for EXR headers and `fovsim plan`). */
void fov_layout_format(const fov_layout *l, char *buf, int size);

/* >>angles */

/* Focal length of the display's pinhole camera in pixels: (width / 2) / tan(hfov / 2) (the same for
 * an off-centre principal point: core/display.h). */
float fov_focal_px(const display_desc *d);
/* The principal point (where the view axis meets the display, core/display.h) in display pixels,
 * top-left origin, as the shaders take it: (width / 2 + ppx, height / 2 + ppy). */
void fov_principal_px(const display_desc *d, float out[2]);
/* Display pixels per degree at the principal point (the display centre unless it is off-centre). */
float fov_pixels_per_degree(const display_desc *d);
/* Eccentricity in degrees of display point p (pixels, top-left origin, continuous) for gaze point
 * g (pixels). Stable for p == g (0) and for any finite inputs, including points far outside the
 * display; uses atan2(|a x b|, a . b), not acos. */
float fov_eccentricity_deg(const display_desc *d, float gx, float gy, float px, float py);

/* >>footprints */

/* The gaze every footprint is built around: clamped into [0, width] x [0, height] (display
 * pixels); a NaN or infinite coordinate gives the display centre. The composite must measure
 * eccentricities from this same gaze (upload it, not the raw one), or a pixel could take a ring
 * whose footprint does not hold it. */
void fov_gaze_clamp(const display_desc *d, float *gx, float *gy);

/* One ring's footprint for one gaze position. */
typedef struct fov_ring_rect {
    int x0, y0, x1, y1; /* display pixels covered, half-open; x0, y0 multiples of the block size;
                           x1 - x0 and y1 - y0 multiples of the block size (x1 may exceed the
                           display width by less than one block, so may y1) */
    int width, height;  /* ring target pixels: (x1 - x0) / block, (y1 - y0) / block, >= 1 */
    int block;          /* 2^scale_log2 */
} fov_ring_rect;

/* Footprint of ring i of layout l for gaze g (pixels): the bounding rectangle of every display
 * pixel whose eccentricity is <= rings[i].outer_deg, grown by `margin_blocks` ring pixels on each
 * side (for the upsampling filter), snapped outwards to the block grid and clamped to the display
 * (rounded up to whole blocks). The last ring, and any ring whose cone reaches 90 degrees from the
 * gaze, cover the whole display. The footprint of ring i contains that of ring i-1 in display
 * pixels (frusta nest). Gaze outside the display is clamped to the display first. */
fov_ring_rect fov_ring_footprint(const display_desc *d, const fov_layout *l, int i, float gx, float gy,
                                 int margin_blocks);
/* Projection of a footprint: the sub-rectangle [x0, x1) x [y0, y1) of the display's projection
 * `display_proj` (an OpenGL perspective matrix for the whole display), as an asymmetric frustum:
 * NDC (-1,-1)..(1,1) of the result maps exactly onto the rectangle. Multiply on the left of the
 * display projection: ring_proj = fov_ring_crop(...) * display_proj. */
mat4 fov_ring_crop(const display_desc *d, const fov_ring_rect *r);

/* >>composite */

/* Which ring a display point takes and how much of the next ring blends in: the innermost ring
 * whose outer radius exceeds e is `ring`; inside the band [outer - blend, outer) the next ring's
 * weight rises smoothly (smoothstep) from 0 to 1, so the image is continuous across borders. */
typedef struct fov_blend {
    int ring;     /* innermost ring covering e */
    float next;   /* weight of ring + 1 in [0, 1]; 0 for the last ring */
} fov_blend;
fov_blend fov_composite_weight(const fov_layout *l, float ecc_deg);

/* >>tiles: which display pixels may skip the ring search */

/* Side of the composite's classification tiles, display pixels. */
#define FOV_TILE_PX 16
/* Slack, in degrees, added to every tile's eccentricity bounds: covers the difference between the
 * GLSL and the C eccentricity (float atan on the GPU; measured <= 1.5e-3 relative). */
#define FOV_TILE_SLACK_DEG 0.01f

/* A rectangle of display pixels [x0, x1) x [y0, y1) (top-left origin) the composite draws with one
 * program: ring >= 0 when every pixel centre in it takes that ring with no blend (fov_composite_weight
 * gives {ring, 0}), so the composite may fetch that ring without searching; -1 when its pixels differ
 * or blend (the per-pixel search runs). */
typedef struct fov_tile {
    int x0, y0, x1, y1;
    int ring;
} fov_tile;

/* The ring every pixel centre of [x0, x1) x [y0, y1) takes with no blend, or -1. Conservative: the
 * eccentricity of the rectangle's centre +- its half diagonal times the largest angular size of a
 * display pixel (1 / focal length, at the principal point; the angle between two view rays is at
 * most their points' distance / focal length), +- FOV_TILE_SLACK_DEG. */
int fov_tile_ring(const display_desc *d, const fov_layout *l, float gx, float gy, int x0, int y0, int x1, int y1);
/* Classifies the display in FOV_TILE_PX tiles for gaze g (clamped as fov_gaze_clamp does) and
 * merges horizontal runs of tiles of one class into one rectangle. The rectangles partition the
 * display exactly. Writes at most `max` (fov_tile_max) into out; returns how many. */
int fov_composite_tiles(const display_desc *d, const fov_layout *l, float gx, float gy, fov_tile *out, int max);
/* Rectangles fov_composite_tiles may write for a display: one per tile. */
int fov_tile_max(const display_desc *d);

/* >>culling: what a ring never shows */

/* Ring pixels kept around the region a ring never shows, for the filters that read next to where it
 * is shown: the composite's bilinear tap (1), TAA's 3x3 neighbourhood (1) and its sub-pixel jitter
 * (1/2), and the Catmull-Rom history taps of the next frame (2 + 1/2). */
#define FOV_CULL_MARGIN_BLOCKS 3

/* Ring i's hole: the eccentricity below which no display pixel takes ring i, the finer ring being
 * shown alone there (outer radius of ring i-1 minus its blend band); 0 for ring 0 (no hole). */
float fov_ring_hole_deg(const fov_layout *l, int i);
/* The radius inside which ring i may skip geometry: the hole less FOV_CULL_MARGIN_BLOCKS ring pixels
 * at the display's largest angular pixel size, so every filter that reads ring i where it is shown
 * reads drawn pixels; 0 (nothing culled) when that is not positive or the hole reaches 90 degrees
 * (where the cone's image is no longer a convex region of the display plane). */
float fov_ring_cull_deg(const display_desc *d, const fov_layout *l, int i);
/* Whether every point of the display rectangle rect = {x0, y0, x1, y1} (pixels, top-left origin)
 * lies less than `deg` (< 90) from gaze g: the region is a cone's section, convex, so its four
 * corners decide. */
bool fov_rect_within_deg(const display_desc *d, float gx, float gy, const float rect[4], float deg);

/* Fraction of display pixels each ring shades (sum of ring target pixels / display pixels) for
 * gaze g; returns the total shaded pixels. per_ring may be NULL. */
long long fov_shaded_pixels(const display_desc *d, const fov_layout *l, float gx, float gy, int margin_blocks,
                            long long per_ring[MAX_FOV_RINGS]);

#ifdef __cplusplus
}
#endif

#endif
