/* png_write.h: sRGB PNG files from linear images, for tools that read PNG (FovVideoVDP).
 *
 * The encoding is fixed so that the files are reproducible bit for bit (../shared/fixtures/README.md
 * section 1.2, which made the FovVideoVDP fixtures): each linear value l is clamped to [0, 1] in
 * double, encoded with the sRGB OETF (12.92 l up to 0.0031308, else 1.055 l^(1/2.4) - 0.055) and
 * quantised to round(V * 65535) (16 bit) or round(V * 255) (8 bit), rounding half to even.
 * Premultiplied colour is written as it is: composited over black. NaN counts as 0.
 *
 * Files are written to a temporary name and renamed, like every output of fovsim.
 */
#ifndef FOVSIM_PNG_WRITE_H
#define FOVSIM_PNG_WRITE_H

#include <stdint.h>

#include "core/status.h"

/* The sRGB-encoded, quantised value of linear l: 0 .. 65535 (bits 16) or 0 .. 255 (bits 8). */
uint16_t png_srgb_quantise(float l, int bits);

/* Writes an RGB PNG of 8 or 16 bits per channel from three linear planes (rows top first).
 * FS_ERR_IO (with a one-line message naming the file) or FS_ERR_NOMEM on failure; no partial file
 * is left behind. */
fs_status png_write_srgb(const char *path, int width, int height, const float *const rgb[3], int bits);

#endif
