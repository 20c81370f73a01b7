#include "gl/shader_src.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/embedded.h"
#include "core/log.h"
#include "core/strbuf.h"
#include "common/shared_defs.h"

static int file_number(shader_src *s, const char *path)
{
    for (int i = 0; i < s->file_count; i++)
        if (strcmp(s->files[i], path) == 0)
            return i;
    if (s->file_count == SHADER_MAX_FILES)
        return -1;
    snprintf(s->files[s->file_count], sizeof s->files[0], "%s", path);
    return s->file_count++;
}

/* Appends `path` with includes expanded; `depth` guards against cycles. */
static fs_status expand(shader_src *s, sbuf *b, const char *path, const char *from, int from_line, int depth)
{
    const embedded_file *f = embedded_find(path);
    if (!f) {
        if (from)
            log_error("%s:%d: #include: no shader file %s", from, from_line, path);
        else
            log_error("%s: no such embedded shader", path);
        return FS_ERR_SHADER;
    }
    if (depth > 16) {
        log_error("%s:%d: #include nested deeper than 16 (a cycle?)", from, from_line);
        return FS_ERR_SHADER;
    }
    int num = file_number(s, path);
    if (num < 0) {
        log_error("%s: more than %d files in one shader", path, SHADER_MAX_FILES);
        return FS_ERR_SHADER;
    }
    sb_printf(b, "#line 1 %d\n", num);
    const char *p = f->data, *end = f->data + f->size;
    int line = 1;
    while (p < end) {
        const char *eol = memchr(p, '\n', (size_t)(end - p));
        size_t n = eol ? (size_t)(eol - p) : (size_t)(end - p);
        const char *q = p;
        while (q < p + n && isspace((unsigned char)*q))
            q++;
        if ((size_t)(p + n - q) > 8 && strncmp(q, "#include", 8) == 0) {
            const char *a = memchr(q, '"', (size_t)(p + n - q));
            const char *z = a ? memchr(a + 1, '"', (size_t)(p + n - a - 1)) : NULL;
            if (!a || !z || z == a + 1) {
                log_error("%s:%d: expected #include \"file.glsl\"", path, line);
                return FS_ERR_SHADER;
            }
            char inc[160];
            snprintf(inc, sizeof inc, "shaders/%.*s", (int)(z - a - 1), a + 1);
            fs_status st = expand(s, b, inc, path, line, depth + 1);
            if (st != FS_OK)
                return st;
            sb_printf(b, "#line %d %d\n", line + 1, num);
        } else {
            sb_append(b, p, n);
            sb_append(b, "\n", 1);
        }
        line++;
        p += n + 1;
    }
    return FS_OK;
}

fs_status shader_src_build(const char *path, const char *const *defines, int define_count, shader_src *out)
{
    memset(out, 0, sizeof *out);
    sbuf b = {0};
    sb_append(&b, "#version 450 core\n", 18);
    for (int i = 0; i < define_count; i++) {
        sb_append(&b, "#define ", 8);
        sb_append(&b, defines[i], strlen(defines[i]));
        sb_append(&b, "\n", 1);
    }
    /* The alpha modes' ids, which the shaders test ALPHA_MODE against: a mode's row in the table of
     * common/shared_defs.h, 1 for the first, as enum alpha_mode numbers them (GLSL cannot make a
     * #define from the table, so C writes them from it). */
    int id = 0;
#define FS_ALPHA_MODE_ID(NAME, name, colour, traits) sb_printf(&b, "#define ALPHA_MODE_ID_%s %d\n", #NAME, ++id);
    FS_ALPHA_MODES(FS_ALPHA_MODE_ID)
#undef FS_ALPHA_MODE_ID
    fs_status st = expand(out, &b, path, NULL, 0, 0);
    if (st == FS_OK && b.oom)
        st = FS_ERR_NOMEM;
    if (st != FS_OK) {
        free(b.p);
        memset(out, 0, sizeof *out);
        return st;
    }
    out->text = b.p;
    return FS_OK;
}

void shader_src_free(shader_src *s)
{
    if (!s)
        return;
    free(s->text);
    memset(s, 0, sizeof *s);
}

void shader_src_translate_log(const shader_src *s, const char *log, char *out, int out_size)
{
    int o = 0;
    out[0] = '\0';
    for (const char *p = log; *p && o < out_size - 1;) {
        const char *eol = strchr(p, '\n');
        int n = eol ? (int)(eol - p) : (int)strlen(p);
        int file = -1, line = -1, used = 0;
        /* Mesa: "0:12(3): error: ...". NVIDIA: "0(12) : error C0000: ...". */
        if (sscanf(p, "%d:%d(%*d): %n", &file, &line, &used) >= 2 && used > 0) {
        } else if (sscanf(p, "%d(%d) : %n", &file, &line, &used) >= 2 && used > 0) {
        } else {
            file = -1;
            used = 0;
        }
        int w;
        if (file >= 0 && file < s->file_count && line >= 0 && used <= n)
            w = snprintf(out + o, (size_t)(out_size - o), "%s:%d: %.*s\n", s->files[file], line, n - used, p + used);
        else
            w = snprintf(out + o, (size_t)(out_size - o), "%.*s\n", n, p);
        if (w < 0)
            break;
        o += w;
        if (o >= out_size)
            o = out_size - 1;
        if (!eol)
            break;
        p = eol + 1;
    }
    while (o > 0 && out[o - 1] == '\n')
        out[--o] = '\0';
}
