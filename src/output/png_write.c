/* png_write.c: see png_write.h. A PNG is a signature and chunks (length, type, data, CRC-32):
 * IHDR, one IDAT holding the zlib stream of the scanlines (each prefixed by filter type 0), IEND. */
#include "output/png_write.h"

#include <errno.h>
#include <stdbool.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include "core/log.h"
#include "output/out_path.h"

uint16_t png_srgb_quantise(float l, int bits)
{
    double x = l > 0.0f ? (l < 1.0f ? (double)l : 1.0) : 0.0; /* also NaN -> 0 */
    double v = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
    double top = bits == 16 ? 65535.0 : 255.0;
    v = v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0;
    return (uint16_t)nearbyint(v * top); /* the default rounding mode: half to even, as numpy */
}

static void put_be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

static bool write_chunk(FILE *f, const char type[4], const unsigned char *data, size_t n)
{
    unsigned char head[8];
    put_be32(head, (uint32_t)n);
    memcpy(head + 4, type, 4);
    uLong crc = crc32(0L, (const Bytef *)type, 4);
    if (n)
        crc = crc32(crc, data, (uInt)n);
    unsigned char tail[4];
    put_be32(tail, (uint32_t)crc);
    return fwrite(head, 1, 8, f) == 8 && (n == 0 || fwrite(data, 1, n, f) == n) && fwrite(tail, 1, 4, f) == 4;
}

fs_status png_write_srgb(const char *path, int width, int height, const float *const rgb[3], int bits)
{
    FS_ASSERT(path && rgb && (bits == 8 || bits == 16) && width > 0 && height > 0);
    size_t bpc = bits / 8, row = 1 + (size_t)width * 3 * bpc, raw_n = row * (size_t)height;
    unsigned char *raw = malloc(raw_n);
    uLongf z_n = compressBound((uLong)raw_n);
    unsigned char *z = malloc(z_n);
    if (!raw || !z) {
        free(raw);
        free(z);
        return FS_ERR_NOMEM;
    }
    for (int y = 0; y < height; y++) {
        unsigned char *p = raw + (size_t)y * row;
        *p++ = 0; /* filter: none */
        for (int x = 0; x < width; x++)
            for (int c = 0; c < 3; c++) {
                uint16_t q = png_srgb_quantise(rgb[c][(size_t)y * (size_t)width + (size_t)x], bits);
                if (bits == 16)
                    *p++ = (unsigned char)(q >> 8);
                *p++ = (unsigned char)q;
            }
    }
    int zr = compress2(z, &z_n, raw, (uLong)raw_n, 6);
    free(raw);
    if (zr != Z_OK) {
        free(z);
        log_error("%s: PNG compression failed (zlib %d)", path, zr);
        return FS_ERR_IO;
    }
    unsigned char ihdr[13];
    put_be32(ihdr, (uint32_t)width);
    put_be32(ihdr + 4, (uint32_t)height);
    ihdr[8] = (unsigned char)bits;
    ihdr[9] = 2; /* truecolour RGB */
    ihdr[10] = ihdr[11] = ihdr[12] = 0;
    char tmp[1400];
    if (!out_path_temp_name(path, tmp, sizeof tmp)) {
        free(z);
        log_error("%s: cannot write: the path is too long", path);
        return FS_ERR_IO;
    }
    FILE *f = fopen(tmp, "wb");
    bool ok = f != NULL;
    static const unsigned char sig[8] = {137, 'P', 'N', 'G', 13, 10, 26, 10};
    ok = ok && fwrite(sig, 1, 8, f) == 8 && write_chunk(f, "IHDR", ihdr, sizeof ihdr) &&
         write_chunk(f, "IDAT", z, z_n) && write_chunk(f, "IEND", NULL, 0);
    int err = errno;
    free(z);
    if (f && fclose(f) != 0 && ok) {
        ok = false;
        err = errno;
    }
    if (ok && rename(tmp, path) != 0) {
        ok = false;
        err = errno;
    }
    if (!ok) {
        log_error("%s: cannot write: %s", path, strerror(err));
        unlink(tmp);
        return FS_ERR_IO;
    }
    return FS_OK;
}
