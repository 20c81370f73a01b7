/* compare_foveation.c: the foveation study's table and foveation.csv (compare_foveation.h). */
#include "commands/compare_foveation.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/strbuf.h"
#include "output/out_path.h"

/* A figure for the table: "n/a" when not measured. */
static const char *fig(char *buf, size_t cap, const char *fmt, double v)
{
    snprintf(buf, cap, v < 0.0 ? "n/a" : fmt, v);
    return buf;
}

static void print_table(const fov_layout *l, const foveation_run *runs, int n)
{
    char rings[256];
    fov_layout_format(l, rings, sizeof rings);
    printf("\nfoveation study: the modes under each foveation, measured in rings %s; cov. K: coverage / the "
           "reference's in ring K; FLIP and temporal error over the display; shaded/px: what a GPU would shade per "
           "display pixel (covered fragments; VRS: coarse-shading invocations)\n", rings);
    printf("%-12s %-10s", "mode", "foveation");
    for (int k = 0; k < l->count; k++)
        printf("   cov. %d", k);
    printf(" %8s %9s %10s %9s\n", "FLIP", "temporal", "shaded/px", "frame ms");
    for (int m = 0; n > 0 && m < runs[0].count; m++)
        for (int f = 0; f < n; f++) {
            const foveation_row *r = &runs[f].rows[m];
            char b[32];
            printf("%-12s %-10s", f == 0 ? alpha_mode_name(r->mode) : "", runs[f].name);
            for (int k = 0; k < l->count; k++)
                printf(" %8s", fig(b, sizeof b, "%.3f", r->coverage[k]));
            printf(" %8s", fig(b, sizeof b, "%.4f", r->flip[l->count]));
            printf(" %9s", fig(b, sizeof b, "%.4f", r->temporal[l->count]));
            printf(" %10s", fig(b, sizeof b, "%.3f", r->shaded_per_px));
            printf(" %9.2f\n", r->frame_ms_median);
        }
    for (int f = 0; f < n; f++)
        printf("  %-5s %s\n", runs[f].name, runs[f].desc);
}

fs_status foveation_study_write(const char *out, const fov_layout *l, const foveation_run *runs, int n)
{
    print_table(l, runs, n);
    sbuf b = {0};
    /* desc last: a layout holds commas (quoted) */
    sb_puts(&b, "foveation,mode,ring,outer_deg,coverage_ratio,flip,temporal_error,shaded_per_px,frame_ms_median,"
                "foveation_desc\n");
    for (int f = 0; f < n; f++)
        for (int m = 0; m < runs[f].count; m++) {
            const foveation_row *r = &runs[f].rows[m];
            for (int k = 0; k <= l->count; k++) {
                double outer = k < l->count && !isinf(l->rings[k].outer_deg) ? l->rings[k].outer_deg : -1.0;
                sb_printf(&b, "%s,%s,%d,%.3f,%.6f,%.6f,%.6f,%.6f,%.4f,\"%s\"\n", runs[f].name,
                          alpha_mode_name(r->mode), k < l->count ? k : -1, outer, r->coverage[k], r->flip[k],
                          r->temporal[k], r->shaded_per_px, r->frame_ms_median, runs[f].desc);
            }
        }
    char path[1200];
    snprintf(path, sizeof path, "%s/foveation.csv", out);
    fs_status st = b.oom ? FS_ERR_NOMEM : out_write_atomic(path, b.p);
    free(b.p);
    if (st == FS_OK)
        printf("foveation.csv in %s/ (each run's own folder: %s/foveation-NAME/)\n", out, out);
    return st;
}
