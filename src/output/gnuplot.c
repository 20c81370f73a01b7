/* gnuplot.c: see gnuplot.h. */
#include "output/gnuplot.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/log.h"
#include "core/spawn.h"
#include "output/out_path.h"

void gnuplot_str(sbuf *b, const char *s)
{
    sb_append(b, "'", 1);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '\'')
            sb_append(b, "''", 2);
        else if (c < 0x20 || c == 0x7f)
            sb_append(b, "?", 1);
        else
            sb_append(b, s, 1);
    }
    sb_append(b, "'", 1);
}

bool gnuplot_available(void)
{
    char exe[PATH_MAX];
    return spawn_find("gnuplot", exe, sizeof exe);
}

fs_status gnuplot_run(const char *dir, const char *name, const sbuf *script)
{
    if (script->oom)
        return FS_ERR_NOMEM;
    char gp[PATH_MAX + 64], arg[300];
    snprintf(gp, sizeof gp, "%s/%s", dir, name);
    snprintf(arg, sizeof arg, "./%s", name);
    fs_status st = out_write_atomic(gp, script->p);
    if (st != FS_OK)
        return st;
    char *argv[] = {"gnuplot", arg, NULL};
    int rc = spawn_run(argv, &(spawn_opts){.dir = dir, .output = "gnuplot.log"});
    if (rc != 0) {
        if (rc == SPAWN_NOT_FOUND)
            log_error("%s: gnuplot is not installed (Debian package gnuplot-nox)", gp);
        else if (rc == SPAWN_FAILED)
            log_error("%s: cannot run gnuplot: %s", gp, strerror(errno));
        else
            log_error("%s: gnuplot failed with status %d (see %s/gnuplot.log)", gp, rc, dir);
        return FS_ERR_IO;
    }
    char log[PATH_MAX + 64];
    snprintf(log, sizeof log, "%s/gnuplot.log", dir);
    unlink(log); /* kept only when gnuplot failed */
    return FS_OK;
}

fs_status gnuplot_png(const char *dir, const char *stem, int width, int height, const sbuf *plot)
{
    char png[PATH_MAX + 64], tmp[PATH_MAX + 96], gp[300];
    snprintf(png, sizeof png, "%s/%s.png", dir, stem);
    if (!out_path_temp_name(png, tmp, sizeof tmp)) {
        log_error("%s: cannot write: the path is too long", png);
        return FS_ERR_IO;
    }
    sbuf b = {0};
    sb_printf(&b, "set terminal pngcairo size %d,%d noenhanced\nset output ", width, height);
    gnuplot_str(&b, strrchr(tmp, '/') ? strrchr(tmp, '/') + 1 : tmp); /* gnuplot runs in dir */
    sb_puts(&b, "\n");
    sb_append(&b, plot->p ? plot->p : "", plot->len);
    b.oom |= plot->oom;
    snprintf(gp, sizeof gp, "%s.gp", stem);
    fs_status st = gnuplot_run(dir, gp, &b);
    free(b.p);
    if (st == FS_OK && rename(tmp, png) != 0) {
        log_error("%s: cannot rename to %s: %s", tmp, png, strerror(errno));
        st = FS_ERR_IO;
    }
    if (st != FS_OK)
        unlink(tmp);
    return st;
}
