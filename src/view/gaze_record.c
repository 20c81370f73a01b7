/* gaze_record.c: fovsim CSV gaze traces written one flushed line per frame. */
#include "view/gaze_record.h"

#include <errno.h>
#include <string.h>
#include <unistd.h>

#include "core/log.h"
#include "output/out_path.h"

void gaze_recorder_begin(gaze_recorder *r, const char *path, const char *comment)
{
    memset(r, 0, sizeof *r);
    snprintf(r->path, sizeof r->path, "%s", path);
    snprintf(r->comment, sizeof r->comment, "%s", comment ? comment : "");
}

bool gaze_recorder_is_open(const gaze_recorder *r)
{
    return r->path[0] != '\0';
}

static fs_status fail(gaze_recorder *r, const char *what)
{
    log_error("%s: cannot %s the gaze recording: %s", r->path, what, strerror(errno));
    if (r->f)
        fclose(r->f);
    r->f = NULL;
    r->path[0] = '\0';
    return FS_ERR_IO;
}

fs_status gaze_recorder_add(gaze_recorder *r, double t, float x, float y, bool valid)
{
    if (!gaze_recorder_is_open(r))
        return FS_OK;
    if (r->samples > 0 && !(t > r->last_t))
        return FS_OK; /* the loader needs strictly increasing time */
    char buf[1024], tmp[1200] = "";
    int n = 0;
    if (!r->f) {
        /* Created under a temporary name and renamed once it holds its first sample, so the final
         * name never shows an empty file; the stream stays open on the renamed file. */
        if (!out_path_temp_name(r->path, tmp, sizeof tmp)) {
            tmp[0] = '\0';
            errno = ENAMETOOLONG;
            return fail(r, "create");
        }
        r->f = fopen(tmp, "w");
        if (!r->f)
            return fail(r, "create");
        n += snprintf(buf + n, sizeof buf - (size_t)n, "t,x,y,confidence\n");
        for (const char *c = r->comment; *c && n < (int)sizeof buf - 4;) {
            size_t len = strcspn(c, "\n");
            n += snprintf(buf + n, sizeof buf - (size_t)n, "# %.*s\n", (int)len, c);
            c += len + (c[len] == '\n');
        }
    }
    if (n < (int)sizeof buf - 64)
        n += snprintf(buf + n, sizeof buf - (size_t)n, "%.17g,%.9g,%.9g,%d\n", t, (double)x, (double)y, valid ? 1 : 0);
    /* One fwrite + fflush per sample: the file only ever grows by whole lines. */
    if (fwrite(buf, 1, (size_t)n, r->f) != (size_t)n || fflush(r->f) != 0) {
        if (tmp[0])
            remove(tmp);
        return fail(r, "write");
    }
    if (tmp[0] && rename(tmp, r->path) != 0) {
        remove(tmp);
        return fail(r, "create");
    }
    r->samples++;
    r->last_t = t;
    return FS_OK;
}

fs_status gaze_recorder_end(gaze_recorder *r)
{
    fs_status st = FS_OK;
    if (r->f && fclose(r->f) != 0) {
        log_error("%s: cannot close the gaze recording: %s", r->path, strerror(errno));
        st = FS_ERR_IO;
    }
    r->f = NULL;
    r->path[0] = '\0';
    return st;
}
