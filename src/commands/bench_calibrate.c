/* bench_calibrate.c: `fovsim bench --calibrate`: measures a fixed matrix of configurations of the
 * run's scene with bench.c's phases (each stage's wall clock with a glFinish around it, its GL
 * timer and its work counts), fits the stage cost model (src/perf/cost_model.h) on two thirds of
 * them, measures its error on the other third, and writes the model (docs/benchmarks.md "Cost
 * model"). */
#include "commands/bench_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/file_read.h"
#include "core/log.h"
#include "gl/gl_device.h"
#include "perf/cost_model.h"

#define CALIB_DEFAULT_WIDTH 640 /* the largest size of the matrix unless --width/--height */
#define CALIB_DEFAULT_HEIGHT 360
#define CALIB_DEFAULT_FRAMES 16
#define CALIB_DEFAULT_WARMUP 1

/* The sizes: the largest times 1/4, 2/4, 3/4 and 4/4 (at the smallest the default rings are
 * usually off: more samples of the full-resolution stages). */
static const int k_size_quarters[CALIB_SIZES] = {1, 2, 3, 4};
enum { CALIB_FULL, CALIB_RINGS, CALIB_AGGRESSIVE }; /* the layouts, in k_layout_names' order */
_Static_assert(CALIB_AGGRESSIVE + 1 == CALIB_LAYOUTS, "one name per layout");
static const char *const k_layout_names[CALIB_LAYOUTS] = {"full", "default rings", "aggressive rings"};

typedef struct calib_run {
    run_desc dd; /* the run's, with --calibrate's defaults */
    bench_run *b;
    int w, h;    /* the largest size */
    alpha_mode modes[ALPHA_MODE_COUNT]; /* --modes, default traditional and hashed */
    int nmodes;
    const char *path;
    char path_buf[1200];
    bool wall; /* time source: synced wall clock (software renderers), else GL timers */
    cost_sample *fit, *held;
    int nfit, nheld;
    cost_model m;
} calib_run;

/* A software rasteriser defers its work to the flush, so its GL timers read near zero. */
static bool software_renderer(void)
{
    const char *r = gl_device_renderer();
    return strstr(r, "llvmpipe") || strstr(r, "softpipe") || strstr(r, "swrast") || !gl_device_has_timer_query();
}

/* The configuration's ring layout at its size: the run's rings (auto and aggressive: made for this
 * size), or the aggressive ones. */
static fov_layout calib_rings(const bench_run *b, int layout, int w, int h)
{
    display_desc at = plan_display(&b->s.pl), dd = display_resized(&at, w, h);
    fov_layout_kind k = layout == CALIB_AGGRESSIVE ? FOV_LAYOUT_AGGRESSIVE : b->s.pl.layout.kind;
    return k == FOV_LAYOUT_AGGRESSIVE ? fov_layout_aggressive(&dd)
           : k == FOV_LAYOUT_AUTO     ? fov_layout_auto(&dd, 0.0f, 0.0f)
                                      : b->s.pl.layout;
}

/* Size s of the matrix along a side of `full` pixels (at least 8). */
static int calib_size(int full, int s)
{
    int v = full * k_size_quarters[s] / 4;
    return v < 8 ? 8 : v;
}

/* The matrix: sizes x layouts x modes x TAA. A configuration is held out when the sum of its
 * indices is a multiple of 3: every size, layout, mode and TAA state is in both sets. */
static void calib_list_configs(calib_run *c)
{
    bench_run *b = c->b;
    for (int s = 0; s < CALIB_SIZES; s++)
        for (int l = 0; l < CALIB_LAYOUTS; l++)
            for (int m = 0; m < c->nmodes; m++)
                for (int t = 0; t < 2; t++) {
                    bench_config *cf = &b->cfg[b->ncfg++];
                    cf->width = calib_size(c->w, s);
                    cf->height = calib_size(c->h, s);
                    cf->mode = c->modes[m];
                    cf->taa = t == 1;
                    cf->layout = l == CALIB_FULL ? BENCH_FULL : BENCH_RINGS;
                    cf->foveated = l != CALIB_FULL;
                    cf->rings = calib_rings(b, l, cf->width, cf->height);
                    cf->stages_only = true;
                    cf->held_out = (s + l + m + t) % 3 == 0;
                    snprintf(cf->name, sizeof cf->name, "%dx%d, %s, %s, TAA %s", cf->width, cf->height,
                             k_layout_names[l], alpha_mode_name(cf->mode), t ? "on" : "off");
                }
    b->nlayouts = 1;
    b->per_layout = 0; /* bench's speedups are not reported: they compare configurations 0 and 0 */
}

/* Whether the folder a file `path` would be written into exists. */
static bool folder_exists(const char *path)
{
    char dir[1200];
    const char *slash = strrchr(path, '/');
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) + 1 : 1, slash ? path : ".");
    struct stat st;
    return stat(dir, &st) == 0 && S_ISDIR(st.st_mode);
}

/* The run's options with --calibrate's defaults, its session and the output path. */
static fs_status calib_begin(calib_run *c, const run_desc *d)
{
    c->dd = *d;
    c->w = d->width ? d->width : CALIB_DEFAULT_WIDTH;
    c->h = d->height ? d->height : CALIB_DEFAULT_HEIGHT;
    c->dd.width = c->w;
    c->dd.height = c->h;
    if (!d->bench.warmup_set)
        c->dd.bench.warmup = CALIB_DEFAULT_WARMUP;
    for (int m = 0; m < d->bench_mode_count; m++)
        c->modes[c->nmodes++] = d->bench_modes[m];
    if (c->nmodes == 0) {
        c->modes[c->nmodes++] = ALPHA_MODE_TRADITIONAL;
        c->modes[c->nmodes++] = ALPHA_MODE_HASHED;
    }
    const char *out = d->out_dir ? d->out_dir : "out/bench";
    c->path = d->bench.cost_model;
    if (!c->path) {
        snprintf(c->path_buf, sizeof c->path_buf, "%s/cost-model.json", out);
        c->path = c->path_buf;
    }
    c->b = calloc(1, sizeof *c->b);
    if (!c->b)
        return FS_ERR_NOMEM;
    c->b->d = &c->dd;
    c->b->n = d->frames > 0 ? d->frames : CALIB_DEFAULT_FRAMES;
    fs_status st = session_begin(&c->dd, &c->b->s, false);
    if (st != FS_OK) {
        free(c->b);
        c->b = NULL;
        return st;
    }
    if (!gl_device_has_pipeline_stats()) {
        log_error("bench --calibrate: the model needs each stage's fragment-shader invocations, and %s has no "
                  "GL_ARB_pipeline_statistics_query", gl_device_renderer());
        return FS_ERR_GL;
    }
    if (!d->bench.cost_model)
        st = file_make_dirs(out);
    else if (!folder_exists(c->path)) { /* said now, not after the measurement */
        log_error("--cost-model %s: its folder does not exist", c->path);
        st = FS_ERR_IO;
    }
    return st;
}

/* The index of the class of a stage of kind k drawn with alpha mode `mode`, added to m if new. */
static int calib_class(cost_model *m, cost_kind k, alpha_mode mode)
{
    char name[COST_CLASS_NAME_MAX];
    cost_class_name(k, alpha_mode_name(mode), name, sizeof name);
    int at = cost_model_find(m, name);
    _Static_assert(COST_KINDS + 2 * ALPHA_MODE_COUNT <= COST_MAX_CLASSES, "a model holds every class");
    if (at < 0) {
        at = m->count++;
        snprintf(m->cls[at].name, sizeof m->cls[at].name, "%s", name);
    }
    return at;
}

/* One sample per configuration and stage: medians over the frames of its time and counts. */
static fs_status calib_samples(calib_run *c)
{
    bench_run *b = c->b;
    c->fit = calloc((size_t)b->ncfg * RENDERER_STATS_MAX, sizeof *c->fit);
    c->held = calloc((size_t)b->ncfg * RENDERER_STATS_MAX, sizeof *c->held);
    if (!c->fit || !c->held)
        return FS_ERR_NOMEM;
    for (int k = 0; k < b->ncfg; k++) {
        const bench_config *cf = &b->cfg[k];
        for (int p = 0; p < cf->names.pass_count; p++) {
            const summary *q = b->sum.stage_count[k][p];
            if (q[COUNT_READ].median < 0 || q[COUNT_WRITTEN].median < 0)
                continue; /* bytes not modelled */
            cost_kind kind = cost_kind_of_stage(cf->names.pass_names[p], cf->names.pass_geometry[p]);
            cost_sample s = {calib_class(&c->m, kind, cf->mode), {q[COUNT_PRIMS].median, q[COUNT_FS].median,
                              q[COUNT_READ].median + q[COUNT_WRITTEN].median},
                             c->wall ? b->sum.stage_wall[k][p].median : b->sum.stage_gl[k][p].median};
            log_info("calibrate sample: %s | %s | %s | %s | prims %.0f inv %.0f bytes %.0f | %.3f ms", cf->name,
                     cf->names.pass_names[p], c->m.cls[s.cls].name, cf->held_out ? "held" : "fit", s.x[0], s.x[1],
                     s.x[2], s.ms);
            if (cf->held_out)
                c->held[c->nheld++] = s;
            else
                c->fit[c->nfit++] = s;
        }
    }
    return FS_OK;
}

/* Per kind: samples, coefficients and errors, and which kinds exceed the bound. */
static void calib_print(const calib_run *c)
{
    const cost_model *m = &c->m;
    printf("\ncost model of %s (%s time per stage), %d configurations of %s, sizes up to %dx%d, %d frames each; "
           "%d stage samples fitted, %d held out\n\n",
           m->renderer, c->wall ? "wall clock with glFinish" : "GL timer", c->b->ncfg, c->b->s.sc.path, c->w, c->h,
           c->b->n, c->nfit, c->nheld);
    printf("| class | fitted | held out | ms / 1k primitives | ns / invocation | ns / byte | ms / stage | fit median "
           "| held-out median | held-out p90 | held-out max |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int k = 0; k < m->count; k++) {
        const cost_fit *f = &m->cls[k];
        if (!f->fitted)
            continue;
        printf("| %s | %d | %d | %.4f | %.4f | %.5f | %.3f | %.1f %% | %.1f %% | %.1f %% | %.1f %% |\n",
               f->name, f->fit.n, f->held.n, f->coef[COST_PRIMS] * 1e3, f->coef[COST_INV] * 1e6,
               f->coef[COST_BYTES] * 1e6, f->coef[COST_CONST], f->fit.median * 100, f->held.median * 100,
               f->held.p90 * 100, f->held.max * 100);
    }
    char over[128];
    if (cost_model_over_bound(m, over, sizeof over) > 0)
        log_warn("bench --calibrate: class %s: held-out p90 error over the bound of %.0f %%: --cost-model will refuse "
                 "this model (measure again with fewer other processes running, or more --frames)", over,
                 m->bound * 100.0);
    printf("\nbound: held-out p90 relative error <= %.0f %% per class; wrote %s\n", m->bound * 100.0, c->path);
}

/* Fits the model on the measured samples and writes it. A kind that cannot be fitted is said and
 * left out of the model: stages of that kind are then not predicted. */
static fs_status calib_fit(calib_run *c)
{
    fs_status st = calib_samples(c);
    if (st != FS_OK)
        return st;
    cost_model *m = &c->m;
    snprintf(m->renderer, sizeof m->renderer, "%s", gl_device_renderer());
    snprintf(m->time_source, sizeof m->time_source, "%s", c->wall ? COST_TIME_WALL : COST_TIME_GL);
    m->bound = COST_BOUND_DEFAULT;
    char err[512];
    if (!cost_model_fit(m, c->fit, c->nfit, c->held, c->nheld, err, sizeof err))
        log_warn("bench --calibrate: not fitted: %s", err);
    st = cost_model_write(m, c->path);
    if (st == FS_OK)
        calib_print(c);
    return st;
}

fs_status cmd_bench_calibrate(const run_desc *d)
{
    calib_run c = {0};
    fs_status st = calib_begin(&c, d);
    if (c.b) {
        c.wall = software_renderer();
        calib_list_configs(&c);
        if (st == FS_OK)
            st = bench_build_configs(c.b);
        if (st == FS_OK)
            st = bench_measure(c.b, st);
        if (st == FS_OK) {
            bench_summarise(c.b);
            st = calib_fit(&c);
        }
        bench_end(c.b);
    }
    free(c.fit);
    free(c.held);
    return st;
}
