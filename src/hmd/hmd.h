/* hmd.h: a head-mounted display: two eyes, each with its own asymmetric field of view (the four
 * angles of OpenXR's XrFovf), its position in the head and its panel pixels, and one refresh rate.
 * The presets, the text form (`--display hmd:PRESET[,KEY=VALUE...]`) and the geometry an eye needs
 * (its projection, pixel <-> direction, principal point and focal length). Pure C, no GL.
 * docs/hmd.md "The display".
 *
 * Conventions (OpenXR's): angles in radians, left and down negative, right and up positive; the
 * head frame is +x right, +y up, -z forward, in metres; eye 0 is the left eye, 1 the right, at
 * x = -ipd/2 and +ipd/2. Display pixels: origin top-left, y down, pixel i's centre at i + 0.5. */
#ifndef FOVSIM_HMD_H
#define FOVSIM_HMD_H

#include <stdbool.h>
#include <stddef.h>

#include "core/display.h"
#include "core/fmath.h"
#include "core/status.h"

/* A scene's display: planar (core/display.h: size and horizontal field of view) or an hmd. */
typedef enum display_kind { DISPLAY_PLANAR = 0, DISPLAY_HMD } display_kind;

#define HMD_IPD_MIN_MM 40.0
#define HMD_IPD_MAX_MM 90.0
#define HMD_IPD_DEFAULT_MM 63.0f
#define HMD_HZ_MIN 1.0
#define HMD_HZ_MAX 1000.0
/* |angle| in degrees: the tangent grows without bound towards 90, and no headset comes near. */
#define HMD_ANGLE_MAX_DEG 85.0
#define HMD_PRESET_MAX 16

/* One eye's field of view, XrFovf's members in XrFovf's order (radians). */
typedef struct hmd_fov {
    float left, right, up, down;
} hmd_fov;

typedef struct hmd_eye {
    hmd_fov fov;
    vec3 position;     /* in the head frame, metres */
    int width, height; /* panel pixels */
} hmd_eye;

enum { HMD_LEFT = 0, HMD_RIGHT = 1 };

typedef struct hmd_desc {
    char preset[HMD_PRESET_MAX]; /* the preset it started from ("custom": none) */
    hmd_eye eye[2];
    float ipd_mm;     /* the eyes' distance; their positions are +-ipd/2 on x */
    float refresh_hz;
} hmd_desc;

/* What a description changes of its preset: the keys of the text form and of the scene file's
 * "display" object, already range-checked by their parsers. */
typedef struct hmd_keys {
    int width, height;        /* 0: the preset's; one given alone: the other follows for square pixels */
    float ipd_mm, refresh_hz; /* 0: the preset's (ipd: 63 mm for custom) */
    bool fov_given[2];        /* fov[HMD_LEFT] alone: the right eye is its mirror */
    hmd_fov fov[2];           /* radians */
} hmd_keys;

/* An eye as a pinhole camera with an off-centre principal point, in display pixels: a direction
 * (x, y, -1) lands at (cx + fx x, cy - fy y). fx == fy when the pixels are square. */
typedef struct hmd_pinhole {
    float fx, fy, cx, cy;
} hmd_pinhole;

/* >>presets and the text form */

/* "quest-pro, eyenavgs, custom". */
const char *hmd_preset_list(void);
/* The preset `name` with `k` applied (k NULL: none), checked as a whole. false and one line in err
 * (without the option's name) when the preset is unknown, custom misses a key, or a derived size
 * is out of range. */
bool hmd_make(const char *preset, const hmd_keys *k, hmd_desc *out, char *err, size_t n);
/* "hmd:PRESET[,KEY=VALUE...]" (docs/hmd.md); false and one line in err naming the key and what was
 * expected. */
bool hmd_parse(const char *text, hmd_desc *out, char *err, size_t n);
/* The text form hmd_parse reads back to the same desc: the preset and the keys that differ. */
void hmd_format(const hmd_desc *d, char *out, size_t n);

/* Degrees LEFT/RIGHT/UP/DOWN (signed as XrFovf) to radians; false unless each is in
 * [-HMD_ANGLE_MAX_DEG, HMD_ANGLE_MAX_DEG] and left < right, down < up. */
bool hmd_fov_from_deg(const double deg[4], hmd_fov *out);
/* The other eye's field of view: left and right swapped and negated. */
hmd_fov hmd_fov_mirror(hmd_fov f);

/* >>an eye's geometry */

/* OpenGL clip space (depth to [-1, 1], like m4_perspective_hfov): the frustum's four edges map to
 * NDC x = -1 (left), +1 (right), y = -1 (down), +1 (up). */
mat4 hmd_projection(const hmd_fov *f, float znear, float zfar);
hmd_pinhole hmd_eye_pinhole(const hmd_eye *e);
/* The display pixel eye-space direction d passes through (may lie outside the panel); false when d
 * does not point forward (d.z >= 0). */
bool hmd_dir_to_pixel(const hmd_eye *e, vec3 d, float *px, float *py);
/* The unit eye-space direction of the ray through display pixel position (px, py). */
vec3 hmd_pixel_to_dir(const hmd_eye *e, float px, float py);
/* The visual angle in degrees between the ray through (px, py) and the eye-space gaze direction. */
float hmd_pixel_angle_deg(const hmd_eye *e, float px, float py, vec3 gaze);
/* The eye as fovsim's display (core/display.h): a square-pixel pinhole of its panel's width with its
 * principal point off the centre (display_from_fov_angles). False when its field of view cannot be
 * one (180 degrees or more). */
bool hmd_eye_display(const hmd_eye *e, display_desc *out);
/* Pixels per degree at the principal point, horizontally and vertically. */
void hmd_ppd(const hmd_eye *e, float *ppd_x, float *ppd_y);

#endif
