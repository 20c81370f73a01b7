/* reference.c: `fovsim reference`: the converged ground truth of each frame as EXR files, drawn
 * or taken from the cache (src/reference/). */
#include "commands/commands.h"

#include <stdio.h>
#include <stdlib.h>

#include "common/shared_defs.h"
#include "core/log.h"
#include "core/proc_stats.h"
#include "core/progress.h"
#include "passes/abuffer.h"
#include "reference/reference.h"
#include "frame/frame.h"
#include "session/session.h"
#include "session/run_record.h"

fs_status cmd_reference(const run_desc *d)
{
    session s;
    fs_status st = session_begin(d, &s, false);
    if (st != FS_OK)
        return st;
    ref_progress rp = {0};
    reference *rf = session_reference(d, &s, &rp, &st);
    const char *out = d->out_dir ? d->out_dir : "out/reference";
    int frames = session_frame_count(d, &s.sc);
    run_folder fo = {0};
    if (st == FS_OK) /* reference frames are independent: --resume skips the kept ones */
        st = run_folder_open(&fo, out, d, &s, frames);
    double *errors = st == FS_OK ? calloc((size_t)frames, sizeof(double)) : NULL;
    if (st == FS_OK && !errors)
        st = FS_ERR_NOMEM;
    int passes = rf ? reference_pass_count(rf) : 0, drawn = 0, cached = 0, rebuilt = 0, done = 0, measured = 0;
    long overflow = 0, long_lists = 0;
    uint64_t nodes = 0;
    session_catch_sigint();
    rp.pr = progress_begin("reference pass", (frames - fo.kept_count) * passes, d->quiet, d->progress_interval);
    progress_per_frame(&rp.pr, passes, "reference");
    double t0 = time_now();
    for (int i = 0; i < frames && st == FS_OK; i++) {
        if (session_interrupted()) {
            st = FS_ERR_INTERRUPTED;
            break;
        }
        if (fo.kept[i])
            continue;
        rp.base = measured * passes;
        frame_record fr = frame_record_at(&s.sc, i, (float)i / d->fps, i > 0 ? (float)(i - 1) / d->fps : -1.0f,
                                          s.pl.width, s.pl.height);
        exr_image img;
        reference_info info;
        st = reference_frame(rf, &fr, &img, &info);
        if (st != FS_OK)
            break;
        errors[measured++] = info.error;
        overflow += info.overflow_pixels;
        long_lists += info.long_lists;
        nodes = info.list_nodes > nodes ? info.list_nodes : nodes;
        cached += info.cached;
        rebuilt += info.rebuilt;
        drawn += !info.cached;
        log_info("REFERENCE: frame %d %s, estimated error %.5f (%s)", i, info.cached ? "from the cache" : "drawn",
                 info.error, info.path[0] ? info.path : "no cache");
        session_frame_attrs(&img, &s, &fr);
        char mode[64];
        snprintf(mode, sizeof mode, "reference (%s)", reference_kind_name(reference_get_kind(rf)));
        exr_image_set_string(&img, "fovsim:alpha_mode", mode);
        exr_image_set_string(&img, "fovsim:rings", "off (full resolution)");
        exr_image_set_string(&img, "fovsim:gaze_trace", "none (the reference does not depend on the gaze)");
        exr_image_set_string(&img, "fovsim:taa", "off");
        char path[1200];
        snprintf(path, sizeof path, "%s/%s.%04d.exr", out, d->name, i);
        st = exr_write_file(path, &img, d->compression);
        exr_image_free(&img);
        done += st == FS_OK;
        progress_update(&rp.pr, measured * passes);
    }
    progress_end(&rp.pr);
    if (st == FS_OK)
        st = run_folder_complete(&fo);
    if (st == FS_OK) {
        double el = time_now() - t0;
        qsort(errors, (size_t)measured, sizeof *errors, stats_cmp_double);
        char buf[1024];
        const char *cache = session_cache_dir(d, buf, sizeof buf);
        printf("wrote %d reference frame%s (%dx%d, %s) to %s/%s.####.exr in %.1f s\n", done, done == 1 ? "" : "s",
               s.pl.width, s.pl.height, reference_describe(rf), out, d->name, el);
        run_folder_print_resume(&fo, 0, 0);
        printf("  %d drawn, %d from the cache%s%s%s", drawn, cached, cache ? " (" : " (no cache)", cache ? cache : "",
               cache ? ")" : "");
        if (rebuilt)
            printf(", %d cache entries were unusable (truncated, stale, tampered or not a file) and were redrawn", rebuilt);
        if (reference_get_kind(rf) == REFERENCE_EXACT) {
            int c = reference_compare_grid(rf);
            printf("\n  convergence, RMS difference of the %dx%d and %dx%d sub-sample frames (linear RGB): median %.5f, "
                   "max %.5f\n", reference_supersample(rf), reference_supersample(rf), c, c,
                   stats_quantile(errors, measured, 0.5), measured ? errors[measured - 1] : 0.0);
            if (drawn > 0)
                printf("  fragment lists: at most %llu nodes in one pass (%.0f MB); %ld sub-sample pixels had more "
                       "than %d fragments (sorted on the CPU); %ld overflowed sub-sample pixels took %d stochastic "
                       "tests instead\n", (unsigned long long)nodes,
                       (double)nodes * (double)sizeof(abuffer_node) / 1048576.0, long_lists, ABUFFER_RESOLVE_MAX,
                       overflow, reference_samples(rf));
        } else {
            printf("\n  convergence, RMS difference of the K/2 and K estimates (linear RGB): median %.5f, max %.5f\n",
                   stats_quantile(errors, measured, 0.5), measured ? errors[measured - 1] : 0.0);
        }
    } else if (st == FS_ERR_INTERRUPTED) {
        log_error("interrupted after %d complete frames in %s (no partial frame was left; --resume continues)",
                  done + fo.kept_count, out);
    }
    run_folder_close(&fo);
    free(errors);
    reference_destroy(rf);
    session_end(&s);
    return st;
}
