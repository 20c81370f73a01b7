/* exr_write.c: half-float scanline EXR output through the OpenEXR Core C API, a reader for tests,
 * and the background writer thread. See exr_write.h. */
#include "output/exr_write.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openexr.h>

#include "core/config.h"
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

static bool is_reserved_attr(const char *name)
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

// >>image

bool exr_image_init(exr_image *img, int width, int height)
{
    FS_ASSERT(img);
    memset(img, 0, sizeof *img);
    /* Keep width * height * 4 bytes well inside size_t and int arithmetic. */
    if (width <= 0 || height <= 0 || (size_t)width > (size_t)INT_MAX / (size_t)height / 4u)
        return false;
    img->width = width;
    img->height = height;
    return true;
}

float *exr_image_add_channel(exr_image *img, const char *name)
{
    FS_ASSERT(img && name);
    if (img->width <= 0 || img->height <= 0 || img->channel_count >= EXR_MAX_CHANNELS)
        return NULL;
    size_t len = strlen(name);
    if (len == 0 || len >= sizeof img->channel_names[0] || exr_image_channel(img, name))
        return NULL;
    float *plane = calloc((size_t)img->width * (size_t)img->height, sizeof *plane);
    if (!plane)
        return NULL;
    int c = img->channel_count++;
    memcpy(img->channel_names[c], name, len + 1);
    img->planes[c] = plane;
    return plane;
}

float *exr_image_channel(const exr_image *img, const char *name)
{
    FS_ASSERT(img && name);
    for (int c = 0; c < img->channel_count; c++)
        if (strcmp(img->channel_names[c], name) == 0)
            return img->planes[c];
    return NULL;
}

const exr_attr *exr_image_attr(const exr_image *img, const char *name)
{
    FS_ASSERT(img && name);
    for (int a = 0; a < img->attr_count; a++)
        if (strcmp(img->attrs[a].name, name) == 0)
            return &img->attrs[a];
    return NULL;
}

/* The slot for attribute `name` (an existing one is replaced), or NULL with a warning. Setters
 * return void, and a dropped attribute must not go unnoticed, hence the warning. */
static exr_attr *attr_slot(exr_image *img, const char *name, exr_attr_type type)
{
    FS_ASSERT(img && name);
    size_t len = strlen(name);
    if (len == 0 || len >= sizeof img->attrs[0].name) {
        log_warn("EXR: attribute name '%s' is empty or longer than %zu characters; dropped", name,
                 sizeof img->attrs[0].name - 1);
        return NULL;
    }
    exr_attr *a = (exr_attr *)exr_image_attr(img, name);
    if (!a) {
        if (img->attr_count >= EXR_MAX_ATTRS) {
            log_warn("EXR: more than EXR_MAX_ATTRS (%d) attributes; '%s' dropped", EXR_MAX_ATTRS,
                     name);
            return NULL;
        }
        a = &img->attrs[img->attr_count++];
    }
    memset(a, 0, sizeof *a);
    memcpy(a->name, name, len + 1);
    a->type = type;
    return a;
}

void exr_image_set_string(exr_image *img, const char *name, const char *value)
{
    FS_ASSERT(value);
    exr_attr *a = attr_slot(img, name, FS_EXR_ATTR_STRING);
    if (!a)
        return;
    size_t len = strlen(value);
    if (len >= sizeof a->s) {
        log_warn("EXR: attribute '%s': value longer than %zu characters, truncated", name,
                 sizeof a->s - 1);
        len = sizeof a->s - 1;
    }
    memcpy(a->s, value, len);
    a->s[len] = '\0';
}

void exr_image_set_int(exr_image *img, const char *name, int value)
{
    exr_attr *a = attr_slot(img, name, FS_EXR_ATTR_INT);
    if (a)
        a->i = value;
}

void exr_image_set_float(exr_image *img, const char *name, float value)
{
    exr_attr *a = attr_slot(img, name, FS_EXR_ATTR_FLOAT);
    if (a)
        a->f[0] = value;
}

void exr_image_set_v2f(exr_image *img, const char *name, float x, float y)
{
    exr_attr *a = attr_slot(img, name, FS_EXR_ATTR_V2F);
    if (a) {
        a->f[0] = x;
        a->f[1] = y;
    }
}

bool exr_image_set_part_name(exr_image *img, const char *name)
{
    FS_ASSERT(img && name);
    size_t len = strlen(name);
    if (len >= sizeof img->part_name)
        return false;
    memcpy(img->part_name, name, len + 1);
    return true;
}

bool exr_image_append_part(exr_image *first, exr_image *part)
{
    FS_ASSERT(first && part);
    if (part == first)
        return false;
    exr_image *node = malloc(sizeof *node);
    if (!node)
        return false;
    *node = *part; /* planes and the rest of part's chain move with it */
    exr_image *tail = first;
    while (tail->next_part)
        tail = tail->next_part;
    tail->next_part = node;
    memset(part, 0, sizeof *part);
    return true;
}

int exr_image_part_count(const exr_image *img)
{
    int n = 0;
    for (; img; img = img->next_part)
        n++;
    return n;
}

exr_image *exr_image_part(const exr_image *img, int index)
{
    for (int i = 0; img && i < index; i++)
        img = img->next_part;
    return index < 0 ? NULL : (exr_image *)img;
}

static void free_planes(exr_image *img)
{
    for (int c = 0; c < img->channel_count && c < EXR_MAX_CHANNELS; c++)
        free(img->planes[c]);
}

void exr_image_free(exr_image *img)
{
    if (!img)
        return;
    /* The head is the caller's; every further part is a heap node of the chain. A loop, not
     * recursion: a chain's length has no limit. */
    exr_image *next = img->next_part;
    free_planes(img);
    memset(img, 0, sizeof *img);
    while (next) {
        exr_image *node = next;
        next = node->next_part;
        free_planes(node);
        free(node);
    }
}

// >>streams

/* Our own stream behind each Core context: we open the file ourselves (so a failure to create
 * the temporary file names the real errno), and the error handler keeps the first message of the
 * Core for the one-line diagnostic instead of letting it print to stderr. */
typedef struct exr_stream {
    int fd;
    char msg[256]; /* first error reported by the Core, "" if none */
    struct exr_stream *prev_bound; /* reader: what stream_bind replaced (see tl_stream) */
} exr_stream;

/* The stream of the context this thread is driving, for stream_error_handler. The handler gets
 * no user data, and it must not ask the Core for it: exr_get_user_data takes the context lock,
 * which a write context already holds while it reports an error from inside exr_write_header
 * (a disk full before the first byte), so asking deadlocked the writer (issue 17, defect 1). The
 * Core calls the handler on the thread that called into it, so a thread-local pointer, bound for
 * the context's whole life (stream_bind .. stream_unbind), is always the right stream. */
static _Thread_local exr_stream *tl_stream;

static exr_stream *stream_bind(exr_stream *s)
{
    exr_stream *prev = tl_stream;
    tl_stream = s;
    return prev;
}

static void stream_unbind(exr_stream *prev)
{
    tl_stream = prev;
}

/* Calls nothing of the Core that takes the context lock (see tl_stream). */
static void stream_error_handler(exr_const_context_t ctxt, exr_result_t code, const char *msg)
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

static int64_t stream_read(exr_const_context_t ctxt, void *ud, void *buf, uint64_t sz,
                           uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    exr_stream *s = ud;
    uint8_t *p = buf;
    uint64_t done = 0;
    while (done < sz) {
        ssize_t n = pread(s->fd, p + done, (size_t)(sz - done), (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            if (error_cb)
                error_cb(ctxt, EXR_ERR_READ_IO, "%s", strerror(errno));
            return -1;
        }
        if (n == 0)
            break; /* end of file: the Core checks the count and reports a short read */
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

static int64_t stream_size(exr_const_context_t ctxt, void *ud)
{
    (void)ctxt;
    exr_stream *s = ud;
    struct stat st;
    return fstat(s->fd, &st) == 0 ? (int64_t)st.st_size : -1;
}

/* The reason for a failed Core call: its own message if it gave one, else the generic text. */
static const char *exr_reason(const exr_stream *s, exr_result_t rv)
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
        if (is_reserved_attr(img->attrs[a].name)) {
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
static int clamp_zip_level(int level)
{
    return level <= 0 ? EXR_ZIP_LEVEL_DEFAULT : level > 9 ? 9 : level;
}

/* Writes one file atomically. On failure fills `err` (err_size bytes) with the one-line message
 * and logs nothing: the caller decides whether it is the error to report (the writer's workers
 * report only the first, so a full disk that fails two concurrent writes still prints one line). */
static fs_status write_file(const char *path, const exr_image *img, exr_compression_kind compression, int zip_level,
                            char *err, size_t err_size)
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
    init.error_handler_fn = stream_error_handler;
    init.user_data = &s;
    init.write_fn = stream_write;
    prev_stream = stream_bind(&s);
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
        rv = declare_part(ctxt, p, comp, clamp_zip_level(zip_level), display);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctxt);
    /* The Core takes part data in part order (openexr_context.h, exr_start_write). */
    int part = 0;
    for (const exr_image *p = img; p && rv == EXR_ERR_SUCCESS; p = p->next_part)
        rv = encode_part(ctxt, part++, p);
    /* exr_finish writes the chunk offset table, so its result matters as much as the rest. */
    exr_result_t frv = exr_finish(&ctxt);
    stream_unbind(prev_stream);
    if (rv == EXR_ERR_SUCCESS)
        rv = frv;
    if (rv != EXR_ERR_SUCCESS)
        goto fail;
    /* No fsync: the rename already keeps a killed or failed run from leaving a truncated frame
     * under the final name (what a future --resume would rely on; there is none yet, issue 17). Surviving a power cut as well would
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
    stream_unbind(prev_stream);
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
    fs_status st = write_file(path, img, compression, EXR_ZIP_LEVEL_DEFAULT, err, sizeof err);
    if (st != FS_OK)
        log_error("%s", err);
    return st;
}

// >>read

static bool copy_attr(exr_image *out, const exr_attribute_t *a)
{
    if (is_reserved_attr(a->name))
        return true;
    switch (a->type) {
    case EXR_ATTR_STRING:
    case EXR_ATTR_INT:
    case EXR_ATTR_FLOAT:
    case EXR_ATTR_V2F: break;
    default: return true; /* other types are not part of exr_image */
    }
    if (out->attr_count >= EXR_MAX_ATTRS || strlen(a->name) >= sizeof out->attrs[0].name)
        return false;
    exr_attr *d = &out->attrs[out->attr_count++];
    memset(d, 0, sizeof *d);
    snprintf(d->name, sizeof d->name, "%s", a->name);
    switch (a->type) {
    case EXR_ATTR_STRING: {
        d->type = FS_EXR_ATTR_STRING;
        int32_t len = a->string ? a->string->length : 0;
        if (len < 0)
            len = 0;
        if ((size_t)len >= sizeof d->s)
            len = (int32_t)sizeof d->s - 1;
        if (len > 0)
            memcpy(d->s, a->string->str, (size_t)len);
        d->s[len] = '\0';
        break;
    }
    case EXR_ATTR_INT:
        d->type = FS_EXR_ATTR_INT;
        d->i = a->i;
        break;
    case EXR_ATTR_FLOAT:
        d->type = FS_EXR_ATTR_FLOAT;
        d->f[0] = a->f;
        break;
    default:
        d->type = FS_EXR_ATTR_V2F;
        d->f[0] = a->v2f->x;
        d->f[1] = a->v2f->y;
        break;
    }
    return true;
}

/* Whether every chunk of every scanline part lies inside the file. The Core reads only the chunks
 * of the part asked for, so without this a file cut inside part 1 would still read part 0 as if
 * it were complete. Costs one small read per chunk (the chunk leader), nothing decoded. */
static exr_result_t check_complete(exr_context_t ctxt, const exr_stream *s, const char **why)
{
    int nparts = 0;
    exr_result_t rv = exr_get_count(ctxt, &nparts);
    int64_t fsize = stream_size(ctxt, (void *)s);
    for (int p = 0; p < nparts && rv == EXR_ERR_SUCCESS; p++) {
        exr_storage_t storage;
        exr_attr_box2i_t dw;
        int32_t lines = 1;
        rv = exr_get_storage(ctxt, p, &storage);
        if (rv != EXR_ERR_SUCCESS || storage != EXR_STORAGE_SCANLINE)
            continue; /* other storage: refused by read_part when it is the part asked for */
        rv = exr_get_data_window(ctxt, p, &dw);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_get_scanlines_per_chunk(ctxt, p, &lines);
        for (int64_t y = dw.min.y; rv == EXR_ERR_SUCCESS && y <= dw.max.y; y += lines) {
            exr_chunk_info_t cinfo;
            rv = exr_read_scanline_chunk_info(ctxt, p, (int)y, &cinfo);
            if (rv == EXR_ERR_SUCCESS &&
                (fsize < 0 || cinfo.data_offset + cinfo.packed_size > (uint64_t)fsize)) {
                *why = "truncated file (a chunk ends past the end of the file)";
                rv = EXR_ERR_READ_IO;
            }
        }
    }
    return rv;
}

/* Fills `out` with part `part` of the open context; on failure sets *why (a static text), or
 * writes into why_buf and points *why at it, or leaves the Core's message in the stream, and
 * returns the Core's result. */
static exr_result_t read_part(exr_context_t ctxt, int part, exr_image *out, const char **why,
                              char *why_buf, size_t why_cap)
{
    int nparts = 0;
    exr_result_t rv = exr_get_count(ctxt, &nparts);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    if (part < 0 || part >= nparts) {
        snprintf(why_buf, why_cap, "no part %d (the file has %d)", part, nparts);
        *why = why_buf;
        return EXR_ERR_ARGUMENT_OUT_OF_RANGE;
    }
    exr_storage_t storage;
    rv = exr_get_storage(ctxt, part, &storage);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    if (storage != EXR_STORAGE_SCANLINE) {
        *why = "only flat scanline files are supported (tiled or deep file)";
        return EXR_ERR_FEATURE_NOT_IMPLEMENTED;
    }
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *chl = NULL;
    rv = exr_get_data_window(ctxt, part, &dw);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_channels(ctxt, part, &chl);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w > INT_MAX || h > INT_MAX || !exr_image_init(out, (int)w, (int)h)) {
        *why = "bad data window";
        return EXR_ERR_INVALID_ATTR;
    }
    if (!chl || chl->num_channels <= 0 || chl->num_channels > EXR_MAX_CHANNELS) {
        *why = "no channels, or more than EXR_MAX_CHANNELS";
        return EXR_ERR_INVALID_ATTR;
    }
    for (int c = 0; c < chl->num_channels; c++) {
        const exr_attr_chlist_entry_t *e = &chl->entries[c];
        if (e->x_sampling != 1 || e->y_sampling != 1) {
            *why = "subsampled channels are not supported";
            return EXR_ERR_FEATURE_NOT_IMPLEMENTED;
        }
        if (!exr_image_add_channel(out, e->name.str)) {
            *why = "bad channel name, or out of memory";
            return EXR_ERR_OUT_OF_MEMORY;
        }
    }

    int32_t nattr = 0;
    rv = exr_get_attribute_count(ctxt, part, &nattr);
    for (int32_t i = 0; i < nattr && rv == EXR_ERR_SUCCESS; i++) {
        const exr_attribute_t *a = NULL;
        rv = exr_get_attribute_by_index(ctxt, part, EXR_ATTR_LIST_FILE_ORDER, i, &a);
        /* The part name comes from the attribute list rather than exr_get_name, which reports
         * an unnamed single part as an error (into the stream's message). */
        if (rv == EXR_ERR_SUCCESS && a && a->type == EXR_ATTR_STRING &&
            strcmp(a->name, "name") == 0 && a->string && a->string->str) {
            int32_t len = a->string->length;
            if (len >= 0 && (size_t)len < sizeof out->part_name) {
                memcpy(out->part_name, a->string->str, (size_t)len);
                out->part_name[len] = '\0';
            } else {
                log_warn("EXR: part name longer than %zu characters; not kept",
                         sizeof out->part_name - 1);
            }
        } else if (rv == EXR_ERR_SUCCESS && a && !copy_attr(out, a))
            log_warn("EXR: attribute '%s' not kept (name too long or EXR_MAX_ATTRS reached)",
                     a->name);
    }
    if (rv != EXR_ERR_SUCCESS)
        return rv;

    int32_t lines_per_chunk = 1;
    rv = exr_get_scanlines_per_chunk(ctxt, part, &lines_per_chunk);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    bool dec_ready = false;
    for (int64_t y = dw.min.y; y <= dw.max.y && rv == EXR_ERR_SUCCESS; y += lines_per_chunk) {
        exr_chunk_info_t cinfo;
        rv = exr_read_scanline_chunk_info(ctxt, part, (int)y, &cinfo);
        if (rv != EXR_ERR_SUCCESS)
            break;
        rv = dec_ready ? exr_decoding_update(ctxt, part, &cinfo, &dec)
                       : exr_decoding_initialize(ctxt, part, &cinfo, &dec);
        if (rv != EXR_ERR_SUCCESS)
            break;
        size_t row0 = (size_t)((int64_t)cinfo.start_y - dw.min.y);
        for (int k = 0; k < dec.channel_count; k++) {
            exr_coding_channel_info_t *ch = &dec.channels[k];
            float *plane = exr_image_channel(out, ch->channel_name);
            FS_ASSERT(plane);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = 4;
            ch->user_pixel_stride = 4;
            ch->user_line_stride = (int32_t)(w * 4);
            ch->decode_to_ptr = (uint8_t *)(plane + row0 * (size_t)w);
        }
        if (!dec_ready) {
            rv = exr_decoding_choose_default_routines(ctxt, part, &dec);
            if (rv != EXR_ERR_SUCCESS)
                break;
            dec_ready = true;
        }
        rv = exr_decoding_run(ctxt, part, &dec);
    }
    exr_decoding_destroy(ctxt, &dec);
    return rv;
}

/* Opens `path` for reading through our stream; on failure prints `path: what` and returns false.
 * *s must stay where it is while ctxt lives (the Core keeps a pointer to it). */
static bool open_read(const char *path, exr_stream *s, exr_context_t *ctxt)
{
    memset(s, 0, sizeof *s);
    *ctxt = NULL;
    /* O_NONBLOCK: a FIFO opens at once instead of waiting for a writer (issue 17), and is then
     * refused below with everything else that is not a regular file. No effect on files. */
    s->fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (s->fd < 0) {
        log_error("%s: cannot read EXR: %s", path, strerror(errno));
        return false;
    }
    struct stat sb;
    int fst = fstat(s->fd, &sb);
    if (fst != 0 || !S_ISREG(sb.st_mode)) {
        log_error("%s: cannot read EXR: %s", path, fst != 0 ? strerror(errno)
                                                   : S_ISDIR(sb.st_mode) ? "is a directory"
                                                                         : "not a regular file");
        close(s->fd);
        s->fd = -1;
        return false;
    }
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = stream_error_handler;
    init.user_data = s;
    init.read_fn = stream_read;
    init.size_fn = stream_size;
    /* Do not guess at missing chunks of a truncated file: report it. */
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    s->prev_bound = stream_bind(s); /* until close_read */
    exr_result_t rv = exr_start_read(ctxt, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        if (*ctxt)
            exr_finish(ctxt);
        stream_unbind(s->prev_bound);
        close(s->fd);
        s->fd = -1;
        log_error("%s: cannot read EXR: %s", path, exr_reason(s, rv));
        return false;
    }
    return true;
}

static void close_read(exr_stream *s, exr_context_t *ctxt)
{
    if (*ctxt)
        exr_finish(ctxt);
    stream_unbind(s->prev_bound);
    if (s->fd >= 0)
        close(s->fd);
    s->fd = -1;
}

fs_status exr_read_part(const char *path, int part_index, exr_image *out)
{
    FS_ASSERT(path && out);
    memset(out, 0, sizeof *out);
    exr_stream s;
    exr_context_t ctxt;
    if (!open_read(path, &s, &ctxt))
        return FS_ERR_IO;
    const char *why = NULL;
    char why_buf[96];
    exr_result_t rv = check_complete(ctxt, &s, &why);
    if (rv == EXR_ERR_SUCCESS)
        rv = read_part(ctxt, part_index, out, &why, why_buf, sizeof why_buf);
    close_read(&s, &ctxt);
    if (rv != EXR_ERR_SUCCESS) {
        exr_image_free(out);
        log_error("%s: cannot read EXR: %s", path, why ? why : exr_reason(&s, rv));
        return FS_ERR_IO;
    }
    return FS_OK;
}

fs_status exr_read_file(const char *path, exr_image *out)
{
    return exr_read_part(path, 0, out);
}

fs_status exr_file_part_count(const char *path, int *count)
{
    FS_ASSERT(path && count);
    *count = 0;
    exr_stream s;
    exr_context_t ctxt;
    if (!open_read(path, &s, &ctxt))
        return FS_ERR_IO;
    exr_result_t rv = exr_get_count(ctxt, count);
    close_read(&s, &ctxt);
    if (rv != EXR_ERR_SUCCESS) {
        *count = 0;
        log_error("%s: cannot read EXR: %s", path, exr_reason(&s, rv));
        return FS_ERR_IO;
    }
    return FS_OK;
}

// >>writer thread

typedef struct exr_job {
    char *path;
    exr_image img;
} exr_job;

typedef struct exr_worker {
    pthread_t thread;
    exr_writer *w;
    const char *busy_path; /* the path it is writing, NULL when idle; guarded by w->mu */
} exr_worker;

/* Jobs leave the ring in submission order. A worker takes the oldest job unless another worker
 * is still writing that job's path: then every worker waits (the queue head blocks) until that
 * write is done, and the worker that did it takes the job. So writes to one path never overlap
 * and the last one submitted is what stays on disk, as with a single thread. */
struct exr_writer {
    pthread_mutex_t mu;
    pthread_cond_t not_empty; /* the oldest job may be free to take, or stop was set */
    pthread_cond_t not_full;  /* a job was taken off the queue, or err was set */
    exr_compression_kind compression;
    int zip_level;
    exr_job *ring; /* queue_depth slots */
    int queue_depth, head, count;
    exr_worker *workers; /* thread_count slots; the first `started` run */
    int thread_count, started;
    bool stop;     /* set by finish: drain the queue, then exit */
    fs_status err; /* first failure, sticky */
};

exr_writer_desc exr_writer_desc_defaults(const exr_writer_desc *d)
{
    exr_writer_desc r = d ? *d : (exr_writer_desc){0};
    if (r.compression != EXR_COMPRESS_NONE && r.compression != EXR_COMPRESS_PIZ)
        r.compression = EXR_COMPRESS_ZIP;
    if (r.queue_depth <= 0)
        r.queue_depth = EXR_QUEUE_DEPTH;
    if (r.thread_count <= 0) {
        long n = sysconf(_SC_NPROCESSORS_ONLN); /* -1 when unknown */
        r.thread_count = n > EXR_MAX_WRITER_THREADS ? EXR_MAX_WRITER_THREADS : n < 1 ? 1 : (int)n;
    }
    if (r.thread_count > EXR_MAX_WRITER_THREADS)
        r.thread_count = EXR_MAX_WRITER_THREADS;
    r.zip_level = clamp_zip_level(r.zip_level);
    return r;
}

static bool path_in_flight(const exr_writer *w, const char *path)
{
    for (int i = 0; i < w->thread_count; i++)
        if (w->workers[i].busy_path && strcmp(w->workers[i].busy_path, path) == 0)
            return true;
    return false;
}

static void *writer_main(void *arg)
{
    exr_worker *me = arg;
    exr_writer *w = me->w;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        while ((w->count == 0 && !w->stop) ||
               (w->count > 0 && path_in_flight(w, w->ring[w->head].path)))
            pthread_cond_wait(&w->not_empty, &w->mu);
        if (w->count == 0) {
            /* Stop requested and queue drained. Others may still be waiting for a path that was
             * busy when finish woke them: they must see this too. */
            pthread_cond_broadcast(&w->not_empty);
            break;
        }
        exr_job job = w->ring[w->head];
        memset(&w->ring[w->head], 0, sizeof w->ring[w->head]);
        w->head = (w->head + 1) % w->queue_depth;
        w->count--;
        me->busy_path = job.path;
        pthread_cond_signal(&w->not_full);
        /* Pass the wake-up on: the new oldest job may be free for an idle worker. (A worker that
         * finishes a write needs no wake-up: it loops and takes the head itself.) */
        if (w->count > 0)
            pthread_cond_signal(&w->not_empty);
        pthread_mutex_unlock(&w->mu);

        /* Jobs accepted before a failure are still written: each write is atomic, so a complete
         * frame is never worse than none. */
        char err[1600];
        fs_status st = write_file(job.path, &job.img, w->compression, w->zip_level, err, sizeof err);
        exr_image_free(&job.img);

        pthread_mutex_lock(&w->mu);
        me->busy_path = NULL;
        free(job.path); /* only after busy_path no longer points at it */
        if (st != FS_OK && w->err == FS_OK) {
            log_error("%s", err); /* the first failure only: the run stops on it */
            w->err = st;
            pthread_cond_broadcast(&w->not_full); /* blocked submitters return the error */
        }
    }
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

/* Stops the started workers (after they drain the queue), frees everything and returns the first
 * error. */
static fs_status writer_shutdown(exr_writer *w)
{
    pthread_mutex_lock(&w->mu);
    w->stop = true;
    pthread_cond_broadcast(&w->not_empty);
    pthread_mutex_unlock(&w->mu);
    for (int i = 0; i < w->started; i++)
        pthread_join(w->workers[i].thread, NULL);
    fs_status st = w->err; /* every worker has been joined: no lock needed */
    pthread_cond_destroy(&w->not_full);
    pthread_cond_destroy(&w->not_empty);
    pthread_mutex_destroy(&w->mu);
    free(w->workers);
    free(w->ring);
    free(w);
    return st;
}

exr_writer *exr_writer_create(const exr_writer_desc *desc)
{
    exr_writer_desc d = exr_writer_desc_defaults(desc);
    exr_writer *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->ring = calloc((size_t)d.queue_depth, sizeof *w->ring);
    w->workers = calloc((size_t)d.thread_count, sizeof *w->workers);
    if (!w->ring || !w->workers)
        goto fail_mu;
    w->queue_depth = d.queue_depth;
    w->thread_count = d.thread_count;
    w->compression = d.compression;
    w->zip_level = d.zip_level;
    w->err = FS_OK;
    if (pthread_mutex_init(&w->mu, NULL) != 0)
        goto fail_mu;
    if (pthread_cond_init(&w->not_empty, NULL) != 0)
        goto fail_ne;
    if (pthread_cond_init(&w->not_full, NULL) != 0)
        goto fail_nf;
    for (int i = 0; i < d.thread_count; i++) {
        w->workers[i].w = w;
        if (pthread_create(&w->workers[i].thread, NULL, writer_main, &w->workers[i]) != 0)
            break;
        w->started++;
    }
    if (w->started == 0) {
        (void)writer_shutdown(w);
        return NULL;
    }
    /* Fewer threads (a process or system thread limit) are slower, not wrong. */
    if (w->started < d.thread_count)
        log_warn("EXR: started %d of %d writer threads", w->started, d.thread_count);
    return w;

fail_nf:
    pthread_cond_destroy(&w->not_empty);
fail_ne:
    pthread_mutex_destroy(&w->mu);
fail_mu:
    free(w->workers);
    free(w->ring);
    free(w);
    return NULL;
}

fs_status exr_writer_submit(exr_writer *w, const char *path, exr_image *img)
{
    FS_ASSERT(w && path && img);
    char *path_copy = strdup(path);
    pthread_mutex_lock(&w->mu);
    FS_ASSERT(!w->stop);
    while (w->count == w->queue_depth && w->err == FS_OK)
        pthread_cond_wait(&w->not_full, &w->mu);
    fs_status st = w->err;
    if (st == FS_OK && !path_copy) {
        log_error("%s: cannot queue EXR write: out of memory", path);
        st = FS_ERR_NOMEM;
    }
    if (st == FS_OK) {
        /* count < queue_depth here: either it was below, or err is set (handled above). */
        int tail = (w->head + w->count) % w->queue_depth;
        w->ring[tail].path = path_copy;
        w->ring[tail].img = *img; /* the planes move to the queue */
        w->count++;
        pthread_cond_signal(&w->not_empty);
    }
    pthread_mutex_unlock(&w->mu);
    if (st == FS_OK) {
        memset(img, 0, sizeof *img);
    } else {
        free(path_copy);
        exr_image_free(img);
    }
    return st;
}

fs_status exr_writer_finish(exr_writer *w)
{
    if (!w)
        return FS_OK;
    return writer_shutdown(w);
}
