/* gnuplot.c: see gnuplot.h. */
#include "output/gnuplot.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
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
