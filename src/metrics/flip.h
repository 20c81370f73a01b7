/* flip.h: LDR-FLIP, a per-pixel perceptual difference between a test image and a reference, as
 * seen when flipping between the two (docs/metrics.md "FLIP").
 *
 * From: P. Andersson, J. Nilsson, T. Akenine-Moller, M. Oskarsson, K. Astrom, M. D. Fairchild,
 * "FLIP: A Difference Evaluator for Alternating Images", HPG 2020. Constants and kernel
 * construction as in NVlabs/flip v1.6, BSD-3-Clause.
 *
 * The error of a pixel is in [0, 1]: 0 where the two images cannot be told apart, 1 for the
 * largest difference (green against blue). Two pipelines, combined as dE_c ^ (1 - dE_f):
 *   - colour: both images go to YCxCz, each channel is low-passed by the contrast sensitivity
 *     of the eye at the given ppd (so detail too fine to see stops counting), back to linear RGB
 *     clamped to [0, 1], to CIELab with the Hunt adjustment, and the HyAB distance is remapped;
 *   - features: edges (1st derivative of a Gaussian) and points (2nd derivative) of the
 *     achromatic channel, 0.082 degrees wide; a feature present in one image only raises the
 *     colour error towards 1.
 * Everything is computed in float, in the official tool's order of operations, so the maps agree
 * with the tool's to float rounding (tests/unit/test_flip.c; measured in docs/metrics.md).
 *
 * Usage:
 *   float *err = malloc(w * h * sizeof *err);
 *   flip_ldr(ref_planes, test_planes, w, h, flip_ppd(0.7, 3840, 0.7), err);
 *   double m = flip_mean(err, w, h);
 *
 * What it does NOT do: HDR-FLIP (exposure sweep and tone mapping), weighted-histogram pooling,
 * the magma colour map, reading images. Inputs are linear; flip_srgb_to_linear converts 8-bit
 * sRGB codes exactly as the tool loads PNG files.
 */
#ifndef FOVSIM_FLIP_H
#define FOVSIM_FLIP_H

#include "core/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The largest ppd flip_ldr accepts. Filter radii grow with ppd (about 0.14 * ppd pixels); 1000
 * ppd is far beyond any display and keeps the kernels small. */
#define FLIP_MAX_PPD 1000.0

/* LDR-FLIP error map of test against reference. Inputs: linear RGB in [0, 1] (values outside are
 * clamped, NaN reads as 0), three planes of width*height floats each, rows top first. ppd: pixels
 * per degree of visual angle. Writes width*height per-pixel errors in [0, 1] to err
 * (caller-allocated). Returns FS_OK, FS_ERR_NOMEM, or FS_ERR_USAGE for bad sizes or a ppd
 * outside (0, FLIP_MAX_PPD]; err is untouched on error. ppd is used in float, as the tool does. */
fs_status flip_ldr(const float *const ref[3], const float *const test[3], int width, int height,
                   double ppd, float *err);

/* Pixels per degree of a monitor resolution_x pixels and monitor_width_m wide, seen from
 * distance_m, in the tool's float arithmetic. FLIP's default viewing condition, a 0.7 m wide
 * 3840-pixel monitor at 0.7 m: flip_ppd(0.7, 3840, 0.7) = 67.0206451. */
double flip_ppd(double distance_m, double resolution_x, double monitor_width_m);

/* Mean of an error map, accumulated in double (0 for an empty map). */
double flip_mean(const float *err, int width, int height);

/* Linear value of an 8-bit sRGB code, as the FLIP tool computes it: code / 255 in float, then the
 * sRGB transfer function in float (threshold 0.04045). */
float flip_srgb_to_linear(unsigned char code);

#ifdef __cplusplus
}
#endif

#endif
