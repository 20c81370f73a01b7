/* look_hints.c: the "look at it" lines of compare and demo (look_hints.h). */
#include "commands/look_hints.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "core/spawn.h"
#include "core/strbuf.h"

/* `dir/file`, shell-quoted, into q (reset first). */
static const char *quoted(sbuf *q, const char *dir, const char *file)
{
    char path[PATH_MAX + 64];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    free(q->p);
    *q = (sbuf){0};
    shell_quote(q, path);
    return q->p ? q->p : "''";
}

void look_hints_print(const look_hints_desc *h)
{
    char f0[128], seq[128], report[PATH_MAX + 16];
    snprintf(f0, sizeof f0, "%s.%04d.exr", h->name, h->first_frame);
    snprintf(seq, sizeof seq, "%s.%%04d.exr", h->name);
    snprintf(report, sizeof report, "%s/report.html", h->out);
    sbuf q = {0};
    printf("\nlook at it (part 0 of each frame is the side-by-side grid; part 'layers' has every image):\n");
    if (access(report, R_OK) == 0)
        printf("  xdg-open %s   # the report page: settings, summary table, charts, video\n",
               quoted(&q, h->out, "report.html"));
    printf("  oiiotool --info -v %s   # parts, layers, header attributes\n", quoted(&q, h->out, f0));
    char mp4[PATH_MAX + 16];
    snprintf(mp4, sizeof mp4, "%s/video.mp4", h->out);
    if (access(mp4, R_OK) == 0) { /* --video made it already */
        printf("  xdg-open %s   # the grid over time\n", quoted(&q, h->out, "video.mp4"));
    } else {
        printf("  ffmpeg -framerate %g", h->fps);
        if (h->first_frame)
            printf(" -start_number %d", h->first_frame);
        printf(" -apply_trc iec61966_2_1 -i %s", quoted(&q, h->out, seq));
        printf(" -pix_fmt yuv420p %s\n", quoted(&q, h->out, h->video));
    }
    printf("  oiiotool %s --subimage layers --fullpixels --ch %s.coverage -o coverage.png   # a layer, display-sized\n",
           quoted(&q, h->out, f0), h->mode);
    free(q.p);
}
