/* bench_report.c: the reports of `fovsim bench` (bench.c measures): JSON (--format json) or
 * Markdown, per configuration and per stage, with the work counts (docs/benchmarks.md "What bench
 * reports", "Work counts") and the ring LOD comparison. */
#include "commands/bench_internal.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <unistd.h>

#include "core/log.h"
#include "fov/ring_lod.h"
#include "gl/gl_device.h"

static const char *const k_count_keys[BENCH_COUNTS] = {"vs_invocations", "primitives", "fs_invocations",
                                                       "clipped_primitives", "covered_fragments", "bytes_read",
                                                       "bytes_written", "shaded_fragments"};
static const char *const k_count_names[BENCH_COUNTS] = {"vertex shader invocations", "primitives submitted",
                                                        "fragment shader invocations", "primitives after clipping",
                                                        "covered fragments", "bytes read (footprints)",
                                                        "bytes written (footprints)", "shaded fragments"};

enum { BENCH_REPORT_CAP = 1 << 20 };

/* Appends to the report (BENCH_REPORT_CAP bytes); *o counts what was asked for, so an overflow
 * shows as *o >= BENCH_REPORT_CAP. */
static void report_printf(char *report, int *o, const char *fmt, ...)
{
    if (*o >= BENCH_REPORT_CAP - 1) {
        *o = BENCH_REPORT_CAP;
        return;
    }
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(report + *o, (size_t)(BENCH_REPORT_CAP - *o), fmt, ap);
    va_end(ap);
    *o = k < 0 || k >= BENCH_REPORT_CAP - *o ? BENCH_REPORT_CAP : *o + k;
}

/* One cell of a count: the integer, or n/a when unknown (< 0). */
static void out_count(char *report, int *o, double v)
{
    if (v < 0)
        report_printf(report, o, " n/a |");
    else
        report_printf(report, o, " %.0f |", v);
}

/* One row of the bench table: the summary / scale with `decimals` digits; n/a where unknown (< 0). */
static void bench_row(char *report, int *o, const char *cfg, const char *measure, summary v, double scale,
                      int decimals)
{
    const double x[5] = {v.median, v.p10, v.p90, v.min, v.max};
    report_printf(report, o, "| %s | %s |", cfg, measure);
    for (int i = 0; i < 5; i++) {
        if (x[i] < 0)
            report_printf(report, o, " n/a |");
        else
            report_printf(report, o, " %.*f |", decimals, x[i] / scale);
    }
    report_printf(report, o, "\n");
}

/* The ring a stage draws ("ring 2 (1/4, all passes)"), -1 for any other stage. */
static int stage_ring(const char *name)
{
    int ring = -1, at = 0;
    return sscanf(name, "ring %d (%n", &ring, &at) == 1 && at > 0 ? ring : -1;
}

/* What one fragment-shader invocation of the pipeline statistics is: GPUs shade 2x2 quads,
 * llvmpipe whole 4x4 blocks (docs/benchmarks.md "Work counts"). */
static const char *bench_invocation_unit(void)
{
    return strstr(gl_device_renderer(), "llvmpipe") ? "4x4 blocks (llvmpipe)" : "2x2 quads (GPU)";
}

#define OUT(...) report_printf(b->report, &b->o, __VA_ARGS__)

/* --json: one configuration's object. */
static void bench_json_config(bench_run *b, int c)
{
    const bench_config *cf = &b->cfg[c];
    const bench_summaries *u = &b->sum;
    char spec[256];
    fov_layout_format(&cf->pl.layout, spec, sizeof spec);
    char lu[160] = "off";
    if (cf->pl.ring_lod)
        ring_lod_format_u(&cf->pl.ring_lod_spec, &cf->pl.layout, lu, sizeof lu);
    OUT("    {\"name\": \"%s\", \"alpha_mode\": \"%s\", \"msaa_only\": %s, \"rings\": \"%s\", "
        "\"ring_lod_u\": \"%s\", \"shaded_pixels\": %.0f, \"relative_to_traditional\": %.4f,\n",
        cf->name, alpha_mode_name(cf->mode), cf->msaa_only ? "true" : "false", spec, lu, u->shaded[c].median,
        u->rel[c]);
    OUT("     \"frame_ms\": {\"median\": %.3f, \"p10\": %.3f, \"p90\": %.3f, \"min\": %.3f, \"max\": %.3f},\n",
        u->wall[c].median, u->wall[c].p10, u->wall[c].p90, u->wall[c].min, u->wall[c].max);
    OUT("     \"cpu_ms\": {\"median\": %.3f, \"p10\": %.3f, \"p90\": %.3f, \"min\": %.3f, \"max\": %.3f},\n",
        u->cpu[c].median, u->cpu[c].p10, u->cpu[c].p90, u->cpu[c].min, u->cpu[c].max);
    OUT("     \"minor_faults\": {\"median\": %.0f, \"p10\": %.0f, \"p90\": %.0f, \"min\": %.0f, \"max\": %.0f},\n",
        u->faults[c].median, u->faults[c].p10, u->faults[c].p90, u->faults[c].min, u->faults[c].max);
    for (int q = 0; q < BENCH_COUNTS; q++)
        OUT("     \"%s\": {\"median\": %.0f, \"p10\": %.0f, \"p90\": %.0f, \"min\": %.0f, \"max\": %.0f, "
            "\"all_frames\": %.0f},\n", k_count_keys[q], u->count[c][q].median, u->count[c][q].p10,
            u->count[c][q].p90, u->count[c][q].min, u->count[c][q].max, u->count_all[c][q]);
    OUT("     \"ring_instances_median\": [");
    for (int i = 0; i < cf->pl.layout.count; i++)
        OUT("%s%.0f", i ? ", " : "", u->instances[c][i].median);
    OUT("],\n");
    double frags = u->count[c][2].median;
    OUT("     \"fragments_per_pixel\": %.3f,\n", frags >= 0 ? frags / b->px : -1.0);
    OUT("     \"geometry_covered_fragments_all_frames\": %.0f, \"geometry_fs_invocations_per_covered\": %.4f,\n",
        u->geom_covered[c], ratio_known(u->geom_fs[c], u->geom_covered[c]));
    OUT("     \"stages\": [");
    int ring = 0;
    for (int p = 0; p < cf->names.pass_count; p++) {
        bool geom = cf->names.pass_geometry[p];
        OUT("%s\n       {\"name\": \"%s\", \"geometry\": %s, \"wall_ms_median\": %.3f, \"gl_timer_ms_median\": %.3f",
            p ? "," : "", cf->names.pass_names[p], geom ? "true" : "false", u->stage_wall[c][p].median,
            u->stage_gl[c][p].median);
        for (int q = 0; q < BENCH_COUNTS; q++)
            OUT(",\n        \"%s_median\": %.0f, \"%s_all_frames\": %.0f", k_count_keys[q],
                u->stage_count[c][p][q].median, k_count_keys[q], u->stage_count_all[c][p][q]);
        OUT(",\n        \"fs_invocations_per_covered\": %.4f",
            ratio_known(u->stage_count_all[c][p][COUNT_FS], u->stage_count_all[c][p][COUNT_COVERED]));
        if (geom && cf->pl.composite) { /* a ring: its forward passes' covered fragments */
            OUT(",\n        \"covered_fragments_by_pass\": [");
            for (int i = 0; i < cf->pl.pass_count; i++)
                OUT("%s{\"pass\": \"%s\", \"all_frames\": %.0f}", i ? ", " : "", cf->pl.passes[i].name,
                    cf->ring_pass_covered[ring][i]);
            OUT("]");
            ring++;
        }
        OUT("}");
    }
    OUT("]}%s\n", c + 1 < b->ncfg ? "," : "");
}

/* --json: each mode's ring LOD configuration against its plain rings: time ratios of medians,
 * count ratios of the totals over the same frames; -1 = unknown. */
static void bench_json_ring_lod(bench_run *b)
{
    const bench_summaries *u = &b->sum;
    int per_layout = b->per_layout;
    OUT("  \"ring_lod_vs_rings\": [");
    for (int c = 2 * per_layout; c < b->ncfg; c++) {
        int w = c - per_layout;
        const bench_config *cf = &b->cfg[c];
        OUT("%s\n    {\"name\": \"%s\", \"without\": \"%s\", \"frame_ms_ratio\": %.4f, \"cpu_ms_ratio\": %.4f",
            c > 2 * per_layout ? "," : "", cf->name, b->cfg[w].name, ratio_known(u->wall[c].median, u->wall[w].median),
            ratio_known(u->cpu[c].median, u->cpu[w].median));
        for (int q = 0; q < BENCH_COUNTS; q++)
            OUT(", \"%s_ratio\": %.4f", k_count_keys[q], ratio_known(u->count_all[c][q], u->count_all[w][q]));
        OUT(",\n     \"stages\": [");
        for (int p = 0; p < cf->names.pass_count; p++) {
            OUT("%s\n       {\"name\": \"%s\", \"wall_ms_ratio\": %.4f", p ? "," : "", cf->names.pass_names[p],
                ratio_known(u->stage_wall[c][p].median, u->stage_wall[w][p].median));
            for (int q = 0; q < BENCH_COUNTS; q++)
                OUT(", \"%s_ratio\": %.4f", k_count_keys[q],
                    ratio_known(u->stage_count_all[c][p][q], u->stage_count_all[w][p][q]));
            OUT("}");
        }
        OUT("]}");
    }
    OUT("\n  ],\n");
}

/* The --json report. */
static void bench_report_json(bench_run *b, const char *cpu_name)
{
    const session *s = &b->s;
    const bench_summaries *u = &b->sum;
    OUT("{\n  \"scene\": \"%s\",\n  \"width\": %d,\n  \"height\": %d,\n  \"alpha_mode\": \"%s\",\n", s->sc.path,
        s->pl.width, s->pl.height, alpha_mode_name(s->pl.global_mode));
    OUT("  \"rings\": \"%s\",\n  \"gaze\": \"%s\",\n  \"renderer\": \"%s\",\n  \"machine\": \"%s, %ld cores\",\n",
        b->rings, s->gaze.count ? s->gaze.path : "centre", gl_device_renderer(), cpu_name,
        sysconf(_SC_NPROCESSORS_ONLN));
    OUT("  \"ring_lod\": \"%s\",\n", b->lod_text);
    OUT("  \"pipeline_statistics\": %s,\n", gl_device_has_pipeline_stats() ? "true" : "false");
    OUT("  \"fs_invocation_unit\": \"%s\",\n", bench_invocation_unit());
    OUT("  \"frames\": %d,\n  \"warmup\": %d,\n  \"display_pixels\": %.0f,\n  \"configs\": [\n", b->n,
        b->d->bench.warmup, b->px);
    for (int c = 0; c < b->ncfg; c++)
        bench_json_config(b, c);
    OUT("  ],\n");
    if (b->lod)
        bench_json_ring_lod(b);
    OUT("  \"speedup\": %.4f,\n  \"ideal_speedup\": %.4f,\n  \"achieved_fraction_of_ideal\": %.4f,\n", u->speedup,
        u->ideal, u->speedup / u->ideal);
    OUT("  \"speedup_without_composite\": %.4f,\n", u->has_fov ? u->speedup_no_composite : -1.0);
    OUT("  \"covered_fragment_ideal_speedup\": %.4f,\n  \"achieved_fraction_of_covered_fragment_ideal\": %.4f\n}\n",
        u->covered_ideal, u->covered_ideal > 0 ? u->speedup / u->covered_ideal : -1.0);
}

/* The text report's first table: every measure of configuration c, one row each. */
static void bench_text_measures(bench_run *b, int c)
{
    const bench_config *cf = &b->cfg[c];
    const bench_summaries *u = &b->sum;
    const char *cn = cf->name;
    bench_row(b->report, &b->o, cn, "frame, wall clock incl. finish (ms)", u->wall[c], 1.0, 2);
    bench_row(b->report, &b->o, cn, "frame, process CPU time, all threads (ms)", u->cpu[c], 1.0, 2);
    bench_row(b->report, &b->o, cn, "frame, minor page faults", u->faults[c], 1.0, 0);
    for (int i = 0; i < cf->pl.layout.count; i++) {
        char m[96];
        snprintf(m, sizeof m, "ring %d, instances drawn", i);
        bench_row(b->report, &b->o, cn, cf->pl.layout.count > 1 ? m : "instances drawn", u->instances[c][i], 1.0, 0);
    }
    for (int p = 0; p < cf->names.pass_count; p++) {
        char m[96];
        snprintf(m, sizeof m, "%s, wall clock with glFinish (ms)", cf->names.pass_names[p]);
        bench_row(b->report, &b->o, cn, m, u->stage_wall[c][p], 1.0, 2);
    }
    for (int p = 0; p < cf->names.pass_count; p++) {
        char m[96];
        snprintf(m, sizeof m, "%s, GL timer query (ms)", cf->names.pass_names[p]);
        bench_row(b->report, &b->o, cn, m, u->stage_gl[c][p], 1.0, 2);
    }
    bench_row(b->report, &b->o, cn, "shaded pixels / display pixels", u->shaded[c], b->px, 3);
    for (int q = 0; q < BENCH_COUNTS; q++) {
        char m[96];
        snprintf(m, sizeof m, "frame, %s", k_count_names[q]);
        bench_row(b->report, &b->o, cn, m, u->count[c][q], 1.0, 0);
    }
    bench_row(b->report, &b->o, cn, "fragment shader invocations / display pixel", u->count[c][2], b->px, 2);
}

/* The text report's ring LOD table: configuration c (with ring LOD) against w, the same rings
 * without it, per stage and for the frame. */
static void bench_text_ring_lod(bench_run *b, int c, int w)
{
    const bench_config *cf = &b->cfg[c];
    const bench_summaries *u = &b->sum;
    for (int p = 0; p <= cf->names.pass_count; p++) {
        bool frame = p == cf->names.pass_count;
        summary tb = frame ? u->wall[w] : u->stage_wall[w][p], tc = frame ? u->wall[c] : u->stage_wall[c][p];
        OUT("| %s | %s | %.2f | %.2f | %.2fx |", cf->name, frame ? "**frame**" : cf->names.pass_names[p], tb.median,
            tc.median, ratio_known(tc.median, tb.median));
        for (int q = 2; q > 0; q--) { /* fragments, then primitives */
            double vb = frame ? u->count_all[w][q] : u->stage_count_all[w][p][q];
            double vc = frame ? u->count_all[c][q] : u->stage_count_all[c][p][q];
            out_count(b->report, &b->o, vb < 0 ? -1.0 : vb / b->n);
            out_count(b->report, &b->o, vc < 0 ? -1.0 : vc / b->n);
            double r = ratio_known(vc, vb);
            if (r < 0)
                OUT(" n/a |");
            else
                OUT(" %.3fx |", r);
        }
        int ring = frame ? -1 : stage_ring(cf->names.pass_names[p]);
        if (ring >= 0)
            OUT(" %.0f | %.0f |\n", u->instances[w][ring].median, u->instances[c][ring].median);
        else
            OUT(" | |\n");
    }
    OUT("| %s | **frame, process CPU time** | %.2f | %.2f | %.2fx | | | | | | | | |\n", cf->name, u->cpu[w].median,
        u->cpu[c].median, ratio_known(u->cpu[c].median, u->cpu[w].median));
}

/* The Markdown report (without --json). */
static void bench_report_text(bench_run *b, const char *cpu_name)
{
    const session *s = &b->s;
    const bench_summaries *u = &b->sum;
    struct utsname un;
    uname(&un);
    OUT("### %s, %dx%d, alpha %s, rings %s%s%s\n\n", s->sc.path, s->pl.width, s->pl.height,
        alpha_mode_name(s->pl.global_mode), b->rings, b->lod ? ", ring LOD " : "", b->lod ? b->lod_text : "");
    OUT("- machine: %s, %s %s (%ld cores online)\n", cpu_name, un.sysname, un.machine, sysconf(_SC_NPROCESSORS_ONLN));
    OUT("- renderer: %s (OpenGL %s, %s)%s\n", gl_device_renderer(), gl_device_version(), gl_device_description(),
        gl_device_has_pipeline_stats() ? "" : "; no GL_ARB_pipeline_statistics_query: work counts n/a");
    OUT("- %d frames spread over the %.2f s camera path after %d warm-up frames; gaze: %s\n\n", b->n, b->span,
        b->d->bench.warmup, s->gaze.count ? s->gaze.path : "fixation at the centre");
    OUT("| configuration | measure | median | p10 | p90 | min | max |\n|---|---|---|---|---|---|---|\n");
    for (int c = 0; c < b->ncfg; c++)
        bench_text_measures(b, c);
    OUT("\nWork per stage (medians over the frames; the frame row is the median of the per-frame totals). "
        "Covered fragments come from a frame drawn with the counting variant (not the timed one); "
        "full-screen stages cover the pixels they draw. A fragment shader invocation here is one pixel "
        "of the %s the rasteriser shades; invocations / covered is over all frames:\n\n"
        "| configuration | stage |", bench_invocation_unit());
    for (int q = 0; q < BENCH_COUNTS; q++)
        OUT(" %s |", k_count_names[q]);
    OUT(" invocations / covered |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int c = 0; c < b->ncfg; c++) {
        for (int p = 0; p <= b->cfg[c].names.pass_count; p++) {
            bool frame = p == b->cfg[c].names.pass_count;
            OUT("| %s | %s |", b->cfg[c].name, frame ? "**frame**" : b->cfg[c].names.pass_names[p]);
            for (int q = 0; q < BENCH_COUNTS; q++)
                out_count(b->report, &b->o, frame ? u->count[c][q].median : u->stage_count[c][p][q].median);
            double r = frame ? ratio_known(u->count_all[c][COUNT_FS], u->count_all[c][COUNT_COVERED])
                             : ratio_known(u->stage_count_all[c][p][COUNT_FS], u->stage_count_all[c][p][COUNT_COVERED]);
            if (r < 0)
                OUT(" n/a |\n");
            else
                OUT(" %.2f |\n", r);
        }
    }
    if (b->ncfg > 1) {
        OUT("\n| configuration | frame (ms, median) | relative to traditional |\n|---|---|---|\n");
        for (int c = 0; c < b->ncfg; c++)
            OUT("| %s | %.2f | %.2fx |\n", b->cfg[c].name, u->wall[c].median, u->rel[c]);
    }
    if (b->lod) {
        OUT("\nRing LOD against the same rings without it (%s): times are medians, counts are means per frame "
            "over the same frames; ratio = with / without:\n\n| configuration | stage | ms without | ms with | "
            "ratio | fragment shader invocations without | with | ratio | primitives without | with | ratio | "
            "instances without | with |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n", b->lod_text);
        for (int c = 2 * b->per_layout; c < b->ncfg; c++)
            bench_text_ring_lod(b, c, c - b->per_layout);
    }
    if (u->has_fov)
        OUT("\nfoveated vs full resolution (%s): speedup %.2fx (median frame times), ideal %.2fx (display pixels / "
            "shaded pixels), achieved %.0f %% of ideal\n", alpha_mode_name(b->cfg[0].mode), u->speedup, u->ideal,
            100.0 * u->speedup / u->ideal);
    if (u->has_fov && u->speedup_no_composite > 0)
        OUT("without the composite (its synced stage time taken off each foveated frame): speedup %.2fx\n",
            u->speedup_no_composite);
    if (u->has_fov && u->covered_ideal > 0)
        OUT("covered-fragment ideal %.2fx (full resolution's covered fragments / the foveated frame's, over the "
            "stages that draw the scene): achieved %.0f %% of it\n", u->covered_ideal,
            100.0 * u->speedup / u->covered_ideal);
}

#undef OUT

fs_status bench_report(bench_run *b)
{
    const run_desc *d = b->d;
    char cpu_name[256];
    session_cpu_name(cpu_name, sizeof cpu_name);
    fov_layout_format(&b->s.pl.layout, b->rings, sizeof b->rings);
    snprintf(b->lod_text, sizeof b->lod_text, "off");
    if (b->lod) { /* "simplify (u = 1,1,0.25,0.0625)" */
        char u[160];
        ring_lod_format(&b->s.pl.ring_lod_spec, b->lod_text, sizeof b->lod_text);
        ring_lod_format_u(&b->s.pl.ring_lod_spec, &b->s.pl.layout, u, sizeof u);
        snprintf(b->lod_text + strlen(b->lod_text), sizeof b->lod_text - strlen(b->lod_text), " (u = %s)", u);
    }
    b->report = malloc(BENCH_REPORT_CAP);
    b->o = 0;
    if (!b->report)
        return FS_ERR_NOMEM;
    if (d->bench.json)
        bench_report_json(b, cpu_name);
    else
        bench_report_text(b, cpu_name);
    if (b->o >= BENCH_REPORT_CAP) {
        log_error("bench: the report outgrew its %d-byte buffer", BENCH_REPORT_CAP);
        return FS_ERR_INTERNAL;
    }
    fputs(b->report, stdout);
    if (d->bench.markdown) {
        FILE *f = fopen(d->bench.markdown, "a");
        if (!f || fprintf(f, "\n%s", b->report) < 0 || fclose(f) != 0) {
            log_error("%s: cannot append the bench report: %s", d->bench.markdown, strerror(errno));
            return FS_ERR_IO;
        } else if (!d->bench.json) {
            printf("appended to %s\n", d->bench.markdown);
        }
    }
    return FS_OK;
}
