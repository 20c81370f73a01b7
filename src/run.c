/* run.c: what each command does. Everything that can fail on bad input (scene, plan, GL context,
 * shaders) is done before the output directory is touched, so a bad run leaves nothing behind. */
#include "run.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/utsname.h>
#include <unistd.h>

#include "common/shared_defs.h"
#include "core/file_read.h"
#include "core/log.h"
#include "core/progress.h"
#include "gl/gl_device.h"
#include "fov/fov_ring.h"
#include "gaze/gaze.h"
#include "passes/plan.h"
#include "passes/renderer.h"
#include "reference/reference.h"
#include "scene/frame.h"
#include "compare.h"
#include "session.h"
#include "view/view.h"

/* >>render */
/* Renders the sequence; *frames_out (may be NULL) gets the number of frames asked for. */
static fs_status run_render(const run_desc *d, const char *default_out, int *frames_out)
{
    session s;
    fs_status st = session_begin(d, &s, true);
    if (st != FS_OK)
        return st;
    const char *out = d->out_dir ? d->out_dir : default_out;
    int frames = session_frame_count(d, &s.sc);
    if (frames_out)
        *frames_out = frames;
    st = file_make_dirs(out);
    exr_writer *w = st == FS_OK ? exr_writer_create(&(exr_writer_desc){.compression = d->compression}) : NULL;
    if (st == FS_OK && !w)
        st = FS_ERR_NOMEM;
    session_catch_sigint();
    progress pr = progress_begin("frame", frames, d->quiet);
    double t0 = time_now();
    int done = 0;
    for (int i = 0; i < frames && st == FS_OK; i++) {
        if (session_interrupted()) {
            st = FS_ERR_INTERRUPTED;
            break;
        }
        frame_record fr = session_frame(&s, i, (float)i / d->fps, i > 0 ? (float)(i - 1) / d->fps : -1.0f);
        exr_image img;
        st = renderer_draw(s.r, &fr);
        if (st == FS_OK)
            st = renderer_read(s.r, &img);
        if (st != FS_OK)
            break;
        session_frame_attrs(&img, &s, &fr);
        char path[1200];
        snprintf(path, sizeof path, "%s/%s.%04d.exr", out, d->name, i);
        st = exr_writer_submit(w, path, &img);
        done += st == FS_OK;
        progress_update(&pr, done);
    }
    if (w) {
        fs_status wst = exr_writer_finish(w);
        if (st == FS_OK)
            st = wst;
    }
    progress_end(&pr);
    double el = time_now() - t0;
    if (st == FS_OK) {
        char rings[256];
        fov_layout_format(&s.pl.layout, rings, sizeof rings);
        printf("wrote %d frames (%dx%d, alpha %s, rings %s) to %s/%s.####.exr in %.1f s (%.2f fps) on %s\n",
               frames, s.pl.width, s.pl.height, alpha_mode_name(s.pl.global_mode), rings, out, d->name, el,
               frames / el, gl_device_renderer());
    } else if (st == FS_ERR_INTERRUPTED) {
        log_error("interrupted after %d complete frames in %s (no partial frame was left)", done, out);
    } else if (done > 0) {
        /* The failing write already printed the one error line; this is context for --verbose. */
        log_info("RENDER: stopped; frames written before the failure in %s are complete, no partial frame was left", out);
    }
    session_end(&s);
    return st;
}

static fs_status run_reference(const run_desc *d)
{
    session s;
    fs_status st = session_begin(d, &s, false);
    if (st != FS_OK)
        return st;
    ref_progress rp = {0};
    reference *rf = session_reference(d, &s, &rp, &st);
    const char *out = d->out_dir ? d->out_dir : "out/reference";
    int frames = session_frame_count(d, &s.sc);
    if (st == FS_OK)
        st = file_make_dirs(out);
    double *errors = st == FS_OK ? calloc((size_t)frames, sizeof(double)) : NULL;
    if (st == FS_OK && !errors)
        st = FS_ERR_NOMEM;
    int passes = rf ? reference_pass_count(rf) : 0, drawn = 0, cached = 0, rebuilt = 0, done = 0;
    session_catch_sigint();
    rp.pr = progress_begin("reference pass", frames * passes, d->quiet);
    double t0 = time_now();
    for (int i = 0; i < frames && st == FS_OK; i++) {
        if (session_interrupted()) {
            st = FS_ERR_INTERRUPTED;
            break;
        }
        rp.base = i * passes;
        frame_record fr = frame_record_at(&s.sc, i, (float)i / d->fps, i > 0 ? (float)(i - 1) / d->fps : -1.0f,
                                          s.pl.width, s.pl.height);
        exr_image img;
        reference_info info;
        st = reference_frame(rf, &fr, &img, &info);
        if (st != FS_OK)
            break;
        errors[i] = info.error;
        cached += info.cached;
        rebuilt += info.rebuilt;
        drawn += !info.cached;
        log_info("REFERENCE: frame %d %s, estimated error %.5f (%s)", i, info.cached ? "from the cache" : "drawn",
                 info.error, info.path[0] ? info.path : "no cache");
        session_frame_attrs(&img, &s, &fr);
        exr_image_set_string(&img, "fovsim:alpha_mode", "reference (stochastic)");
        exr_image_set_string(&img, "fovsim:rings", "off (full resolution)");
        exr_image_set_string(&img, "fovsim:gaze_trace", "none (the reference does not depend on the gaze)");
        exr_image_set_string(&img, "fovsim:taa", "off");
        char path[1200];
        snprintf(path, sizeof path, "%s/%s.%04d.exr", out, d->name, i);
        st = exr_write_file(path, &img, d->compression);
        exr_image_free(&img);
        done += st == FS_OK;
        progress_update(&rp.pr, (i + 1) * passes);
    }
    progress_end(&rp.pr);
    if (st == FS_OK) {
        double el = time_now() - t0;
        qsort(errors, (size_t)frames, sizeof *errors, stats_cmp_double);
        char buf[1024];
        const char *cache = session_cache_dir(d, buf, sizeof buf);
        printf("wrote %d reference frames (%dx%d, %dx%d sub-samples x %d stochastic alpha tests) to %s/%s.####.exr "
               "in %.1f s\n", frames, s.pl.width, s.pl.height, reference_supersample(rf), reference_supersample(rf),
               reference_samples(rf), out, d->name, el);
        printf("  %d drawn, %d from the cache%s%s%s", drawn, cached, cache ? " (" : " (no cache)", cache ? cache : "",
               cache ? ")" : "");
        if (rebuilt)
            printf(", %d cache entries were truncated or stale and were redrawn", rebuilt);
        printf("\n  convergence, RMS difference of the K/2 and K estimates (linear RGB): median %.5f, max %.5f\n",
               stats_quantile(errors, frames, 0.5), errors[frames - 1]);
    } else if (st == FS_ERR_INTERRUPTED) {
        log_error("interrupted after %d complete frames in %s (no partial frame was left)", done, out);
    }
    free(errors);
    reference_destroy(rf);
    session_end(&s);
    return st;
}

/* >>plan */
static fs_status run_plan(const run_desc *d)
{
    scene sc;
    fs_status st = session_load_scene(d, &sc);
    if (st != FS_OK)
        return st;
    plan pl;
    st = session_build_plan(d, &sc, &pl);
    if (st == FS_OK)
        plan_print(&pl, &sc, stdout);
    scene_free(&sc);
    return st;
}

/* >>bench */
/* One measured configuration of the bench (full resolution, or the run's ring layout). */
typedef struct bench_config {
    char name[64];
    alpha_mode mode;    /* the global alpha mode of this configuration */
    bool foveated;      /* the run's ring layout (else full resolution) */
    bool msaa_only;     /* traditional test drawn through the MSAA targets (A2C cost split) */
    plan pl;
    renderer *r;
    double *wall, *stage_wall, *stage_gl, *frags, *shaded; /* n, n * stages, n * stages, n, n */
    renderer_stats names;                                  /* stage names */
} bench_config;

typedef struct summary {
    double median, p10, p90, min, max;
} summary;

/* Sorts v (n values) and summarises it. */
static summary summarise(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, stats_cmp_double);
    return (summary){stats_quantile(v, n, 0.5), stats_quantile(v, n, 0.1), stats_quantile(v, n, 0.9), v[0], v[n - 1]};
}

static bool bench_alloc(bench_config *c, int n)
{
    c->wall = calloc((size_t)n, sizeof(double));
    c->stage_wall = calloc((size_t)n * RENDERER_STATS_MAX, sizeof(double));
    c->stage_gl = calloc((size_t)n * RENDERER_STATS_MAX, sizeof(double));
    c->frags = calloc((size_t)n, sizeof(double));
    c->shaded = calloc((size_t)n, sizeof(double));
    return c->wall && c->stage_wall && c->stage_gl && c->frags && c->shaded;
}

static void bench_free(bench_config *c)
{
    free(c->wall);
    free(c->stage_wall);
    free(c->stage_gl);
    free(c->frags);
    free(c->shaded);
}

/* Draws frame k of config c twice: once as the renderer runs it (timed to glFinish), once with a
 * finish after every stage (per-stage wall times). Records when k >= 0. */
static void bench_frame(session *s, bench_config *c, int k, float t, int n)
{
    frame_record fr = frame_record_at(&s->sc, k < 0 ? 0 : k, t, -1.0f, c->pl.width, c->pl.height);
    float gx = 0.5f, gy = 0.5f;
    if (s->gaze.count > 0) {
        gaze_point g = gaze_at(&s->gaze, t, NULL);
        gx = g.x;
        gy = g.y;
    }
    display_desc dd = {c->pl.width, c->pl.height, fr.hfov_deg};
    frame_record_set_gaze(&fr, &c->pl.layout, &dd, gx, gy);
    renderer_set_pass_sync(c->r, false);
    double t0 = time_now();
    renderer_draw(c->r, &fr);
    renderer_finish(c->r);
    double t1 = time_now();
    renderer_stats rs = renderer_last_stats(c->r);
    renderer_set_pass_sync(c->r, true);
    renderer_draw(c->r, &fr);
    renderer_stats sync = renderer_last_stats(c->r);
    c->names = rs;
    if (k < 0)
        return;
    c->wall[k] = (t1 - t0) * 1e3;
    for (int p = 0; p < rs.pass_count; p++) {
        c->stage_wall[(size_t)p * (size_t)n + (size_t)k] = sync.pass_wall_ms[p];
        c->stage_gl[(size_t)p * (size_t)n + (size_t)k] = rs.pass_ms[p];
    }
    c->frags[k] = (double)rs.fragments;
    c->shaded[k] = (double)rs.shaded_pixels;
}

static fs_status run_bench(const run_desc *d)
{
    session s;
    fs_status st = session_begin(d, &s, false); /* every configuration gets its own renderer */
    if (st != FS_OK)
        return st;
    int n = d->frames > 0 ? d->frames : 30;
    /* Configurations: for each alpha mode asked for (--modes, default the run's), full resolution
     * and, when the run has rings, foveated; plus traditional through the MSAA targets when an A2C
     * mode is measured, so the MSAA cost can be told from the A2C test's own. */
    alpha_mode modes[ALPHA_MODE_COUNT];
    int nmodes = 0;
    bool want_msaa = false;
    for (int m = 0; m < d->bench_mode_count; m++)
        modes[nmodes++] = d->bench_modes[m];
    if (nmodes == 0)
        modes[nmodes++] = s.pl.global_mode;
    for (int m = 0; m < nmodes; m++)
        want_msaa |= modes[m] == ALPHA_MODE_A2C || modes[m] == ALPHA_MODE_HASHED_A2C;
    enum { MAX_CFG = 2 * (ALPHA_MODE_COUNT + 1) };
    bench_config cfg[MAX_CFG];
    memset(cfg, 0, sizeof cfg);
    int ncfg = 0;
    for (int lay = 0; lay < (s.pl.rings ? 2 : 1); lay++)
        for (int m = 0; m < nmodes + (want_msaa ? 1 : 0); m++) {
            bench_config *c = &cfg[ncfg++];
            c->foveated = lay == 1;
            c->msaa_only = m == nmodes;
            c->mode = c->msaa_only ? ALPHA_MODE_TRADITIONAL : modes[m];
            snprintf(c->name, sizeof c->name, "%s%s, %s", alpha_mode_name(c->mode), c->msaa_only ? "+MSAA" : "",
                     c->foveated ? "foveated" : "full resolution");
        }
    for (int c = 0; c < ncfg && st == FS_OK; c++) {
        plan_options po = {.alpha_mode = cfg[c].mode, .width = d->width, .height = d->height, .frames = n,
                           .alpha = s.pl.alpha, .force_msaa = cfg[c].msaa_only, .taa = s.pl.taa,
                           .taa_controls = s.pl.taa_controls};
        if (cfg[c].foveated)
            po.layout = s.pl.layout;
        st = plan_build(&s.sc, &po, &cfg[c].pl);
        if (st == FS_OK)
            cfg[c].r = renderer_create(&(renderer_desc){.scene = &s.sc, .plan = &cfg[c].pl, .timers = true}, &st);
    }
    for (int c = 0; c < ncfg && st == FS_OK; c++)
        if (!bench_alloc(&cfg[c], n))
            st = FS_ERR_NOMEM;
    float span = s.sc.duration;
    progress pr = progress_begin("bench", d->warmup + n, d->quiet);
    /* Frames spread evenly over the camera path (and gaze trace), configs interleaved per frame so
     * both see the same machine state. */
    for (int i = 0; i < d->warmup + n && st == FS_OK; i++) {
        int k = i < d->warmup ? -1 : i - d->warmup;
        int kk = k < 0 ? i : k;
        float t = n > 1 ? span * (float)kk / (float)(n - 1) : 0.0f;
        for (int c = 0; c < ncfg; c++)
            bench_frame(&s, &cfg[c], k, t, n);
        progress_update(&pr, i + 1);
    }
    progress_end(&pr);

    char cpu[256];
    session_cpu_name(cpu, sizeof cpu);
    struct utsname un;
    uname(&un);
    double px = (double)s.pl.width * s.pl.height;
    char rings[256];
    fov_layout_format(&s.pl.layout, rings, sizeof rings);
    summary wall[MAX_CFG], shaded[MAX_CFG], frags[MAX_CFG];
    summary stage_wall[MAX_CFG][RENDERER_STATS_MAX], stage_gl[MAX_CFG][RENDERER_STATS_MAX];
    for (int c = 0; c < ncfg && st == FS_OK; c++) {
        wall[c] = summarise(cfg[c].wall, n);
        shaded[c] = summarise(cfg[c].shaded, n);
        frags[c] = summarise(cfg[c].frags, n);
        for (int p = 0; p < cfg[c].names.pass_count; p++) {
            stage_wall[c][p] = summarise(&cfg[c].stage_wall[(size_t)p * (size_t)n], n);
            stage_gl[c][p] = summarise(&cfg[c].stage_gl[(size_t)p * (size_t)n], n);
        }
    }
    /* Foveation's speedup: the first mode, full resolution vs foveated. */
    int per_layout = ncfg / (s.pl.rings ? 2 : 1);
    bool has_fov = s.pl.rings && st == FS_OK;
    double speedup = has_fov ? wall[0].median / wall[per_layout].median : 1.0;
    double ideal = has_fov ? px / shaded[per_layout].median : 1.0;

    /* Each configuration's frame time relative to traditional in the same layout (seed 000
     * Table 1's comparison); 0 when traditional was not measured. */
    double rel[MAX_CFG] = {0};
    for (int c = 0; c < ncfg && st == FS_OK; c++)
        for (int b = 0; b < ncfg; b++)
            if (cfg[b].mode == ALPHA_MODE_TRADITIONAL && !cfg[b].msaa_only && cfg[b].foveated == cfg[c].foveated)
                rel[c] = wall[c].median / wall[b].median;
    char *report = malloc(65536);
    int o = 0;
    if (!report)
        st = FS_ERR_NOMEM;
    if (st == FS_OK && d->json) {
#define OUT(...) o += snprintf(report + o, 65536 - (size_t)o, __VA_ARGS__)
        OUT("{\n  \"scene\": \"%s\",\n  \"width\": %d,\n  \"height\": %d,\n  \"alpha_mode\": \"%s\",\n", s.sc.path,
            s.pl.width, s.pl.height, alpha_mode_name(s.pl.global_mode));
        OUT("  \"rings\": \"%s\",\n  \"gaze\": \"%s\",\n  \"renderer\": \"%s\",\n  \"machine\": \"%s, %ld cores\",\n",
            rings, s.gaze.count ? s.gaze.path : "centre", gl_device_renderer(), cpu, sysconf(_SC_NPROCESSORS_ONLN));
        OUT("  \"frames\": %d,\n  \"warmup\": %d,\n  \"display_pixels\": %.0f,\n  \"configs\": [\n", n, d->warmup, px);
        for (int c = 0; c < ncfg; c++) {
            char spec[256];
            fov_layout_format(&cfg[c].pl.layout, spec, sizeof spec);
            OUT("    {\"name\": \"%s\", \"alpha_mode\": \"%s\", \"msaa_only\": %s, \"rings\": \"%s\", "
                "\"shaded_pixels\": %.0f, \"relative_to_traditional\": %.4f,\n",
                cfg[c].name, alpha_mode_name(cfg[c].mode), cfg[c].msaa_only ? "true" : "false", spec,
                shaded[c].median, rel[c]);
            OUT("     \"frame_ms\": {\"median\": %.3f, \"p10\": %.3f, \"p90\": %.3f, \"min\": %.3f, \"max\": %.3f},\n",
                wall[c].median, wall[c].p10, wall[c].p90, wall[c].min, wall[c].max);
            OUT("     \"fragments_per_pixel\": %.3f,\n     \"stages\": [", frags[c].median >= 0 ? frags[c].median / px : -1.0);
            for (int p = 0; p < cfg[c].names.pass_count; p++)
                OUT("%s\n       {\"name\": \"%s\", \"wall_ms_median\": %.3f, \"gl_timer_ms_median\": %.3f}", p ? "," : "",
                    cfg[c].names.pass_names[p], stage_wall[c][p].median, stage_gl[c][p].median);
            OUT("]}%s\n", c + 1 < ncfg ? "," : "");
        }
        OUT("  ],\n  \"speedup\": %.4f,\n  \"ideal_speedup\": %.4f,\n  \"achieved_fraction_of_ideal\": %.4f\n}\n", speedup,
            ideal, speedup / ideal);
    } else if (st == FS_OK) {
        OUT("### %s, %dx%d, alpha %s, rings %s\n\n", s.sc.path, s.pl.width, s.pl.height,
            alpha_mode_name(s.pl.global_mode), rings);
        OUT("- machine: %s, %s %s (%ld cores online)\n", cpu, un.sysname, un.machine, sysconf(_SC_NPROCESSORS_ONLN));
        OUT("- renderer: %s (OpenGL %s, %s)\n", gl_device_renderer(), gl_device_version(), gl_device_description());
        OUT("- %d frames spread over the %.2f s camera path after %d warm-up frames; gaze: %s\n\n", n, span, d->warmup,
            s.gaze.count ? s.gaze.path : "fixation at the centre");
        OUT("| configuration | measure | median | p10 | p90 | min | max |\n|---|---|---|---|---|---|---|\n");
        for (int c = 0; c < ncfg; c++) {
            OUT("| %s | frame, wall clock incl. finish (ms) | %.2f | %.2f | %.2f | %.2f | %.2f |\n", cfg[c].name,
                wall[c].median, wall[c].p10, wall[c].p90, wall[c].min, wall[c].max);
            for (int p = 0; p < cfg[c].names.pass_count; p++)
                OUT("| %s | %s, wall clock with glFinish (ms) | %.2f | %.2f | %.2f | %.2f | %.2f |\n", cfg[c].name,
                    cfg[c].names.pass_names[p], stage_wall[c][p].median, stage_wall[c][p].p10, stage_wall[c][p].p90,
                    stage_wall[c][p].min, stage_wall[c][p].max);
            for (int p = 0; p < cfg[c].names.pass_count; p++)
                OUT("| %s | %s, GL timer query (ms) | %.2f | %.2f | %.2f | %.2f | %.2f |\n", cfg[c].name,
                    cfg[c].names.pass_names[p], stage_gl[c][p].median, stage_gl[c][p].p10, stage_gl[c][p].p90,
                    stage_gl[c][p].min, stage_gl[c][p].max);
            OUT("| %s | shaded pixels / display pixels | %.3f | %.3f | %.3f | %.3f | %.3f |\n", cfg[c].name,
                shaded[c].median / px, shaded[c].p10 / px, shaded[c].p90 / px, shaded[c].min / px, shaded[c].max / px);
            if (frags[c].min >= 0)
                OUT("| %s | fragment shader invocations / display pixel | %.2f | %.2f | %.2f | %.2f | %.2f |\n",
                    cfg[c].name, frags[c].median / px, frags[c].p10 / px, frags[c].p90 / px, frags[c].min / px,
                    frags[c].max / px);
        }
        if (ncfg > 1) {
            OUT("\n| configuration | frame (ms, median) | relative to traditional |\n|---|---|---|\n");
            for (int c = 0; c < ncfg; c++)
                OUT("| %s | %.2f | %.2fx |\n", cfg[c].name, wall[c].median, rel[c]);
        }
        if (has_fov)
            OUT("\nfoveated vs full resolution (%s): speedup %.2fx (median frame times), ideal %.2fx (display pixels / "
                "shaded pixels), achieved %.0f %% of ideal\n", alpha_mode_name(cfg[0].mode), speedup, ideal,
                100.0 * speedup / ideal);
#undef OUT
    }
    if (st == FS_OK) {
        fputs(report, stdout);
        if (d->markdown) {
            FILE *f = fopen(d->markdown, "a");
            if (!f || fprintf(f, "\n%s", report) < 0 || fclose(f) != 0) {
                log_error("%s: cannot append the bench report: %s", d->markdown, strerror(errno));
                st = FS_ERR_IO;
            } else if (!d->json) {
                printf("appended to %s\n", d->markdown);
            }
        }
    }
    free(report);
    for (int c = 0; c < ncfg; c++) {
        bench_free(&cfg[c]);
        renderer_destroy(cfg[c].r);
    }
    session_end(&s);
    return st;
}

fs_status run(const run_desc *d)
{
    log_set_verbose(d->verbose);
    switch (d->cmd) {
    case CMD_HELP: cli_print_help(d->help_for); return FS_OK;
    case CMD_VERSION: printf("fovsim %s\n", FOVSIM_VERSION); return FS_OK;
    case CMD_LIST_GPUS: gl_device_list(); return FS_OK;
    case CMD_PLAN: return run_plan(d);
    case CMD_RENDER: return run_render(d, "out/render", NULL);
    case CMD_DEMO: return run_demo(d);
    case CMD_BENCH: return d->accuracy ? run_bench_accuracy(d) : run_bench(d);
    case CMD_REFERENCE: return run_reference(d);
    case CMD_COMPARE: return run_compare(d);
    case CMD_VIEW: return view_run(d);
    case CMD_NONE: break;
    }
    return FS_ERR_INTERNAL;
}
