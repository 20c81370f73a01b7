/* exr_read.c: reading EXR files back through the OpenEXR Core C API (tests, golden comparisons,
 * check): one part's channels as float and its attributes, after checking that every chunk of the
 * file lies inside it. See exr_write.h. */
#include "output/exr_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/log.h"

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

/* A stringvector attribute (multiView), through exr_image_set_string_vector: false when it
 * does not fit. Strings are copied into NUL-terminated buffers first: the Core's are counted,
 * not terminated. */
static bool copy_string_vector(exr_image *out, const exr_attribute_t *a)
{
    const exr_attr_string_vector_t *sv = a->stringvector;
    int n = sv ? sv->n_strings : 0;
    if (n < 0 || n > EXR_MAX_VECTOR_STRINGS || (n > 0 && !sv->strings) ||
        out->attr_count >= EXR_MAX_ATTRS ||
        strlen(a->name) >= sizeof out->attrs[0].name)
        return false;
    char buf[EXR_MAX_VECTOR_STRINGS][sizeof out->attrs[0].s];
    const char *values[EXR_MAX_VECTOR_STRINGS];
    size_t total = 0; /* checked here, so that the setter has no reason to warn as well */
    for (int k = 0; k < n; k++) {
        const exr_attr_string_t *str = &sv->strings[k];
        int32_t len = str->length;
        total += len < 0 ? 0 : (size_t)len + 1;
        /* A NUL inside a string would split it in exr_attr's packed form. */
        if (len < 0 || total > sizeof buf[k] || (len > 0 && !str->str) ||
            (len > 0 && memchr(str->str, '\0', (size_t)len)))
            return false;
        if (len > 0)
            memcpy(buf[k], str->str, (size_t)len);
        buf[k][len] = '\0';
        values[k] = buf[k];
    }
    return exr_image_set_string_vector(out, a->name, values, n);
}

static bool copy_attr(exr_image *out, const exr_attribute_t *a)
{
    if (exr_is_reserved_attr(a->name))
        return true;
    switch (a->type) {
    case EXR_ATTR_STRING:
    case EXR_ATTR_INT:
    case EXR_ATTR_FLOAT:
    case EXR_ATTR_V2F: break;
    case EXR_ATTR_STRING_VECTOR: return copy_string_vector(out, a);
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
            log_warn("EXR: attribute '%s' not kept (name too long, EXR_MAX_ATTRS reached, or a "
                     "string vector that does not fit)",
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
    /* O_NONBLOCK: a FIFO opens at once instead of waiting for a writer (README "Limits"), and is then
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
    init.error_handler_fn = exr_stream_error_handler;
    init.user_data = s;
    init.read_fn = stream_read;
    init.size_fn = stream_size;
    /* Do not guess at missing chunks of a truncated file: report it. */
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    s->prev_bound = exr_stream_bind(s); /* until close_read */
    exr_result_t rv = exr_start_read(ctxt, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        if (*ctxt)
            exr_finish(ctxt);
        exr_stream_unbind(s->prev_bound);
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
    exr_stream_unbind(s->prev_bound);
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
