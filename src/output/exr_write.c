/* exr_write.c: half-float scanline EXR output through the OpenEXR Core C API, and the stream
 * behind every Core context (the reader's too). See exr_write.h; exr_internal.h says where the
 * rest of the EXR code lives. */
#include "output/exr_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <string.h>
#include <unistd.h>

#include "core/log.h"
#include "output/out_path.h"

/* Names the EXR format or OpenEXR itself gives a meaning; a custom attribute may not use them,
 * and the reader does not copy them into exr_image.attrs. */
static const char *const k_reserved_attrs[] = {
    "channels",   "compression", "dataWindow",         "displayWindow",     "lineOrder",
    "pixelAspectRatio",          "screenWindowCenter", "screenWindowWidth", "tiles",
    "type",       "name",        "version",            "chunkCount",        "maxSamplesPerPixel",
};

/* Longest name OpenEXR accepts without the long-name flag (which old readers reject). */
#define EXR_SHORT_NAME_MAX 31

bool exr_is_reserved_attr(const char *name)
{
    for (size_t i = 0; i < sizeof k_reserved_attrs / sizeof k_reserved_attrs[0]; i++)
        if (strcmp(name, k_reserved_attrs[i]) == 0)
            return true;
    return false;
}

// >>half

/* float -> IEEE 754 binary16 bits, round to nearest even. NaN becomes +0 and values beyond
 * ±65504 (the largest finite half) are clamped, so the result is always finite. The twin going
 * the other way is OpenEXR's own unpacker (decode pipeline with a FLOAT user type). */
static uint16_t float_to_half(float f)
{
    if (f != f)
        return 0;
    if (f > 65504.0f)
        f = 65504.0f;
    else if (f < -65504.0f)
        f = -65504.0f;
    uint32_t x;
    memcpy(&x, &f, sizeof x);
    uint32_t sign = (x >> 16) & 0x8000u;
    x &= 0x7fffffffu;
    if (x >= 0x38800000u) { /* >= 2^-14: a normal half */
        /* Add just under half an ulp of the half mantissa, plus one when the kept part is odd
         * (ties to even); a carry out of the mantissa bumps the exponent, as it must. */
        x += 0x0fffu + ((x >> 13) & 1u);
        x -= 112u << 23; /* rebias the exponent: 127 - 15 */
        return (uint16_t)(sign | (x >> 13));
    }
    if (x < 0x33000000u) /* < 2^-25: rounds to zero (2^-25 itself ties to the even 0) */
        return (uint16_t)sign;
    /* Subnormal half: value = m * 2^-24, so m = mantissa-with-implicit-bit >> (126 - exp). */
    uint32_t e = x >> 23;
    uint32_t m = (x & 0x7fffffu) | 0x800000u;
    uint32_t shift = 126u - e; /* 14..24 */
    uint32_t h = m >> shift;
    uint32_t rem = m & ((1u << shift) - 1u);
    uint32_t halfway = 1u << (shift - 1u);
    if (rem > halfway || (rem == halfway && (h & 1u)))
        h++; /* may carry into 0x400, the smallest normal: still the right encoding */
    return (uint16_t)(sign | h);
}

float exr_half_round(float f)
{
    uint32_t h = float_to_half(f), sign = (h & 0x8000u) << 16, e = (h >> 10) & 0x1fu, m = h & 0x3ffu;
    float v;
    if (e == 0) {
        v = ldexpf((float)m, -24); /* zero or subnormal */
    } else {
        uint32_t x = ((e + 112u) << 23) | (m << 13);
        memcpy(&v, &x, sizeof v);
    }
    uint32_t bits;
    memcpy(&bits, &v, sizeof bits);
    bits |= sign;
    memcpy(&v, &bits, sizeof v);
    return v;
}

// >>streams

/* The stream of the context this thread is driving, for exr_stream_error_handler. The handler gets
 * no user data, and it must not ask the Core for it: exr_get_user_data takes the context lock,
 * which a write context already holds while it reports an error from inside exr_write_header
 * (a disk full before the first byte), so asking deadlocked the writer. The
 * Core calls the handler on the thread that called into it, so a thread-local pointer, bound for
 * the context's whole life (exr_stream_bind .. exr_stream_unbind), is always the right stream. */
static _Thread_local exr_stream *tl_stream;

exr_stream *exr_stream_bind(exr_stream *s)
{
    exr_stream *prev = tl_stream;
    tl_stream = s;
    return prev;
}

void exr_stream_unbind(exr_stream *prev)
{
    tl_stream = prev;
}

/* Calls nothing of the Core that takes the context lock (see tl_stream). */
void exr_stream_error_handler(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt;
    exr_stream *s = tl_stream;
    if (!s)
        return;
    if (s->msg[0] == '\0')
        snprintf(s->msg, sizeof s->msg, "%s", msg ? msg : exr_get_default_error_message(code));
}

static int64_t stream_write(exr_const_context_t ctxt, void *ud, const void *buf, uint64_t sz,
                            uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    exr_stream *s = ud;
    const uint8_t *p = buf;
    uint64_t done = 0;
    while (done < sz) {
        ssize_t n = pwrite(s->fd, p + done, (size_t)(sz - done), (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            /* A regular file reports a full disk as ENOSPC; 0 bytes written would loop forever. */
            const char *why = n < 0 ? strerror(errno) : "short write";
            if (error_cb)
                error_cb(ctxt, EXR_ERR_WRITE_IO, "%s", why);
            return -1;
        }
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

/* The reason for a failed Core call: its own message if it gave one, else the generic text. */
const char *exr_reason(const exr_stream *s, exr_result_t rv)
{
    return s->msg[0] ? s->msg : exr_get_default_error_message(rv);
}

// >>write

static exr_compression_t core_compression(exr_compression_kind k)
{
    switch (k) {
    case EXR_COMPRESS_NONE: return EXR_COMPRESSION_NONE;
    case EXR_COMPRESS_PIZ: return EXR_COMPRESSION_PIZ;
    case EXR_COMPRESS_ZIP:
    default: return EXR_COMPRESSION_ZIP;
    }
}

/* The temporary name next to `path` (out_path_temp_name: `<dir>/.<base>.tmp.<host>.<pid>.<n>`), so
 * the final rename(2) stays on one file system. <n> is new for every call: two writes in flight at
 * once (writer threads, or callers of exr_write_file on their own threads) never share a temporary
 * file, even when their paths name the same file in different spellings ("a/x.exr", "a//x.exr", a
 * symlinked directory); the host and pid keep other processes' and machines' writes apart.
 * Returns a malloc'd string or NULL. */
static char *temp_path_for(const char *path)
{
    size_t cap = strlen(path) + 128;
    char *tmp = malloc(cap);
    if (tmp && !out_path_temp_name(path, tmp, cap)) {
        free(tmp);
        tmp = NULL;
    }
    return tmp;
}

/* Checks one part for what the Core would reject later with a less helpful message. NULL when
 * fine. */
static const char *check_one(const exr_image *img, char *buf, size_t cap)
{
    if (img->width <= 0 || img->height <= 0)
        return "image has no pixels (exr_image_init not called?)";
    if (img->channel_count <= 0 || img->channel_count > EXR_MAX_CHANNELS)
        return "image has no channels";
    for (int c = 0; c < img->channel_count; c++) {
        if (!img->planes[c] || img->channel_names[c][0] == '\0') {
            snprintf(buf, cap, "channel %d has no name or no pixels", c);
            return buf;
        }
    }
    for (int a = 0; a < img->attr_count && a < EXR_MAX_ATTRS; a++) {
        if (exr_is_reserved_attr(img->attrs[a].name)) {
            snprintf(buf, cap, "attribute '%s' is reserved by the EXR format",
                     img->attrs[a].name);
            return buf;
        }
    }
    return NULL;
}

/* check_one for every part, plus what a multi-part file needs: a name per part, no two alike
 * (readers select parts by name). Messages name the part when there is more than one. */
static const char *check_image(const exr_image *img, char *buf, size_t cap)
{
    bool multi = img->next_part != NULL;
    int k = 0;
    for (const exr_image *p = img; p; p = p->next_part, k++) {
        char inner[128];
        const char *why = check_one(p, inner, sizeof inner);
        if (!why && multi && p->part_name[0] == '\0')
            why = "no part name (every part of a multi-part file needs one)";
        for (const exr_image *q = img; !why && multi && q != p; q = q->next_part)
            if (strcmp(q->part_name, p->part_name) == 0)
                why = "part name used twice";
        if (why) {
            /* A single-part image keeps the messages it always had. */
            if (multi)
                snprintf(buf, cap, "part %d '%s': %s", k, p->part_name, why);
            else
                snprintf(buf, cap, "%s", why);
            return buf;
        }
    }
    return NULL;
}

static bool needs_long_names(const exr_image *img)
{
    for (; img; img = img->next_part) {
        for (int c = 0; c < img->channel_count; c++)
            if (strlen(img->channel_names[c]) > EXR_SHORT_NAME_MAX)
                return true;
        for (int a = 0; a < img->attr_count; a++)
            if (strlen(img->attrs[a].name) > EXR_SHORT_NAME_MAX)
                return true;
    }
    return false;
}

static exr_result_t set_string_vector(exr_context_t ctxt, int part, const exr_attr *at)
{
    const char *strings[EXR_MAX_VECTOR_STRINGS];
    if (at->i < 0 || at->i > EXR_MAX_VECTOR_STRINGS)
        return EXR_ERR_INVALID_ATTR;
    for (int k = 0; k < at->i; k++)
        strings[k] = exr_attr_string_at(at, k);
    return exr_attr_set_string_vector(ctxt, part, at->name, at->i, strings);
}

/* Declares one part: windows, compression, channels and custom attributes. `display` is the
 * display window every part shares (see exr_write.h). */
static exr_result_t declare_part(exr_context_t ctxt, const exr_image *img, exr_compression_t comp,
                                 int zip_level, exr_attr_box2i_t display)
{
    int part = 0;
    exr_result_t rv = exr_add_part(ctxt, img->part_name[0] ? img->part_name : NULL,
                                   EXR_STORAGE_SCANLINE, &part);
    /* Data and display window (0,0)-(w-1,h-1), aspect 1, INCREASING_Y. */
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctxt, part, img->width, img->height, comp);
    if (rv == EXR_ERR_SUCCESS && (display.max.x != img->width - 1 ||
                                  display.max.y != img->height - 1))
        rv = exr_set_display_window(ctxt, part, &display);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_set_lineorder(ctxt, part, EXR_LINEORDER_INCREASING_Y);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_set_compression(ctxt, part, comp);
    /* Not stored in the file: it only steers the deflate encoder of this context. */
    if (rv == EXR_ERR_SUCCESS && comp == EXR_COMPRESSION_ZIP)
        rv = exr_set_zip_compression_level(ctxt, part, zip_level);
    /* The Core keeps the channel list sorted by name, as the format requires; the encoder below
     * finds each plane by name, so the caller's order does not matter. */
    for (int c = 0; c < img->channel_count && rv == EXR_ERR_SUCCESS; c++)
        rv = exr_add_channel(ctxt, part, img->channel_names[c], EXR_PIXEL_HALF,
                             EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    for (int a = 0; a < img->attr_count && rv == EXR_ERR_SUCCESS; a++) {
        const exr_attr *at = &img->attrs[a];
        switch (at->type) {
        case FS_EXR_ATTR_STRING: rv = exr_attr_set_string(ctxt, part, at->name, at->s); break;
        case FS_EXR_ATTR_INT: rv = exr_attr_set_int(ctxt, part, at->name, at->i); break;
        case FS_EXR_ATTR_FLOAT: rv = exr_attr_set_float(ctxt, part, at->name, at->f[0]); break;
        case FS_EXR_ATTR_V2F: {
            exr_attr_v2f_t v;
            v.x = at->f[0];
            v.y = at->f[1];
            rv = exr_attr_set_v2f(ctxt, part, at->name, &v);
            break;
        }
        case FS_EXR_ATTR_STRING_VECTOR: rv = set_string_vector(ctxt, part, at); break;
        default: rv = EXR_ERR_INVALID_ATTR; break;
        }
    }
    return rv;
}

/* Encodes every scanline chunk of part `part` (declared by declare_part, header written). */
static exr_result_t encode_part(exr_context_t ctxt, int part, const exr_image *img)
{
    int32_t lines_per_chunk = 1;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, part, &lines_per_chunk);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    const size_t w = (size_t)img->width;
    const int nch = img->channel_count;
    /* One chunk of half pixels, planar per channel: what the default packer expects. */
    uint16_t *halves = malloc(w * (size_t)lines_per_chunk * (size_t)nch * sizeof *halves);
    if (!halves)
        return EXR_ERR_OUT_OF_MEMORY;

    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    bool enc_ready = false;
    for (int y = 0; y < img->height && rv == EXR_ERR_SUCCESS; y += lines_per_chunk) {
        exr_chunk_info_t cinfo;
        rv = exr_write_scanline_chunk_info(ctxt, part, y, &cinfo);
        if (rv != EXR_ERR_SUCCESS)
            break;
        rv = enc_ready ? exr_encoding_update(ctxt, part, &cinfo, &enc)
                       : exr_encoding_initialize(ctxt, part, &cinfo, &enc);
        if (rv != EXR_ERR_SUCCESS)
            break;
        const size_t lines = (size_t)cinfo.height;
        for (int k = 0; k < enc.channel_count; k++) {
            exr_coding_channel_info_t *ch = &enc.channels[k];
            const float *src = exr_image_channel(img, ch->channel_name);
            FS_ASSERT(src); /* the Core's list holds exactly our names */
            src += (size_t)cinfo.start_y * w;
            uint16_t *dst = halves + (size_t)k * w * (size_t)lines_per_chunk;
            for (size_t i = 0; i < lines * w; i++)
                dst[i] = float_to_half(src[i]);
            ch->user_data_type = EXR_PIXEL_HALF;
            ch->user_bytes_per_element = 2;
            ch->user_pixel_stride = 2;
            ch->user_line_stride = (int32_t)(w * 2);
            ch->encode_from_ptr = (const uint8_t *)dst;
        }
        if (!enc_ready) {
            rv = exr_encoding_choose_default_routines(ctxt, part, &enc);
            if (rv != EXR_ERR_SUCCESS)
                break;
            enc_ready = true;
        }
        rv = exr_encoding_run(ctxt, part, &enc);
    }
    exr_encoding_destroy(ctxt, &enc);
    free(halves);
    return rv;
}

/* 1..9, 0 or less meaning EXR_ZIP_LEVEL_DEFAULT. That default is 4, measured (zlib 1.2.13,
 * OpenEXR 3.1.5, one core of this 2-core machine, best of 5 writes of RGBA + coverage):
 *                                       level 1          level 4          level 6 (zlib default)
 *   synthetic 1280x720, gradient+noise  2.85 MB  68 ms   2.73 MB  85 ms   2.65 MB 113 ms
 *   rendered garden 640x360 (llvmpipe)  512 KB   17 ms   474 KB   21 ms   463 KB   36 ms
 *   golden forest_t1 192x108            44.6 KB 2.8 ms   41.7 KB 3.0 ms   40.8 KB 3.7 ms
 * Level 4 costs 2.4-3 % in size for 25-41 % less time; level 1 costs 7-11 %, too much. */
int exr_clamp_zip_level(int level)
{
    return level <= 0 ? EXR_ZIP_LEVEL_DEFAULT : level > 9 ? 9 : level;
}

/* Writes one file atomically. On failure fills `err` (err_size bytes) with the one-line message
 * and logs nothing: the caller decides whether it is the error to report (the writer's workers
 * report only the first, so a full disk that fails two concurrent writes still prints one line). */
fs_status exr_write_file_quiet(const char *path, const exr_image *img, exr_compression_kind compression,
                               int zip_level, char *err, size_t err_size)
{
    FS_ASSERT(path && img && err);
    char why_buf[256];
    const char *why = check_image(img, why_buf, sizeof why_buf);
    if (why) {
        snprintf(err, err_size, "%s: cannot write EXR: %s", path, why);
        return FS_ERR_IO;
    }
    char *tmp = temp_path_for(path);
    if (!tmp) {
        snprintf(err, err_size, "%s: cannot write EXR: out of memory", path);
        return FS_ERR_IO;
    }

    exr_stream s = {.fd = -1};
    exr_stream *prev_stream = tl_stream; /* bound to &s while the context lives */
    exr_context_t ctxt = NULL;
    exr_result_t rv = EXR_ERR_SUCCESS;
    char sys_msg[300] = "";

    s.fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (s.fd < 0) {
        snprintf(sys_msg, sizeof sys_msg, "cannot create %s: %s", tmp, strerror(errno));
        goto fail;
    }
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_stream_error_handler;
    init.user_data = &s;
    init.write_fn = stream_write;
    prev_stream = exr_stream_bind(&s);
    rv = exr_start_write(&ctxt, tmp, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS && needs_long_names(img))
        rv = exr_set_longname_support(ctxt, 1);
    exr_attr_box2i_t display;
    memset(&display, 0, sizeof display);
    for (const exr_image *p = img; p; p = p->next_part) {
        if (p->width - 1 > display.max.x)
            display.max.x = p->width - 1;
        if (p->height - 1 > display.max.y)
            display.max.y = p->height - 1;
    }
    const exr_compression_t comp = core_compression(compression);
    for (const exr_image *p = img; p && rv == EXR_ERR_SUCCESS; p = p->next_part)
        rv = declare_part(ctxt, p, comp, exr_clamp_zip_level(zip_level), display);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctxt);
    /* The Core takes part data in part order (openexr_context.h, exr_start_write). */
    int part = 0;
    for (const exr_image *p = img; p && rv == EXR_ERR_SUCCESS; p = p->next_part)
        rv = encode_part(ctxt, part++, p);
    /* exr_finish writes the chunk offset table, so its result matters as much as the rest. */
    exr_result_t frv = exr_finish(&ctxt);
    exr_stream_unbind(prev_stream);
    if (rv == EXR_ERR_SUCCESS)
        rv = frv;
    if (rv != EXR_ERR_SUCCESS)
        goto fail;
    /* No fsync: the rename already keeps a killed or failed run from leaving a truncated frame
     * under the final name (what --resume relies on). Surviving a power cut as well would
     * need an fsync of the file and its directory per frame (milliseconds each on common file
     * systems), for frames that a rerun regenerates anyway. */
    int fd = s.fd;
    s.fd = -1;
    if (close(fd) != 0) { /* NFS and quotas can report a failed write only here */
        snprintf(sys_msg, sizeof sys_msg, "closing %s: %s", tmp, strerror(errno));
        goto fail;
    }
    if (rename(tmp, path) != 0) {
        snprintf(sys_msg, sizeof sys_msg, "renaming %s: %s", tmp, strerror(errno));
        goto fail;
    }
    free(tmp);
    return FS_OK;

fail:
    if (ctxt)
        exr_finish(&ctxt);
    exr_stream_unbind(prev_stream);
    if (s.fd >= 0)
        close(s.fd);
    unlink(tmp); /* ENOENT when it was never created: harmless */
    snprintf(err, err_size, "%s: cannot write EXR: %s", path, sys_msg[0] ? sys_msg : exr_reason(&s, rv));
    free(tmp);
    return FS_ERR_IO;
}

fs_status exr_write_file(const char *path, const exr_image *img, exr_compression_kind compression)
{
    char err[1600];
    fs_status st = exr_write_file_quiet(path, img, compression, EXR_ZIP_LEVEL_DEFAULT, err, sizeof err);
    if (st != FS_OK)
        log_error("%s", err);
    return st;
}
