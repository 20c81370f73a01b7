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
#include "core/log.h"
#include "core/progress.h"
#include "gl/gl_device.h"
#include "fov/fov_ring.h"
#include "gaze/gaze.h"
#include "passes/plan.h"
#include "passes/renderer.h"
#include "scene/frame.h"
#include "view/view.h"

static volatile sig_atomic_t g_interrupted;
static void on_sigint(int sig)
{
    (void)sig;
    g_interrupted = 1;
}

/* >>setup */
fs_status run_load_scene(const run_desc *d, scene *sc)
{
    fs_status st = d->scene_path ? scene_load_file(d->scene_path, sc) : scene_load_builtin(d->builtin, sc);
    if (st == FS_OK)
        st = scene_validate(sc);
    if (st != FS_OK)
        scene_free(sc);
    return st;
}

static int frame_count(const run_desc *d, const scene *sc)
{
    if (d->frames > 0)
        return d->frames;
    int n = (int)floorf(sc->duration * d->fps + 1e-3f) + 1;
    return n < 1 ? 1 : n > MAX_FRAMES ? MAX_FRAMES : n;
}

/* mkdir -p; prints the failing component. */
fs_status run_make_dirs(const char *path)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *p = buf + 1;; p++) {
        char c = *p;
        if (c == '/' || c == '\0') {
            *p = '\0';
            if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
                log_error("%s: cannot create directory: %s", buf, strerror(errno));
                return FS_ERR_IO;
            }
            struct stat sb;
            if (stat(buf, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
                log_error("%s: exists and is not a directory", buf);
                return FS_ERR_IO;
            }
            *p = c;
        }
        if (c == '\0')
            break;
    }
    return FS_OK;
}

static alpha_params run_alpha_params(const run_desc *d)
{
    alpha_params a = {.hash_scale = d->hash_scale, .anisotropic = d->hash_aniso, .no_fade = d->no_fade,
                      .fade_n = d->fade_n, .a2c_sharpen = d->a2c_sharpen};
    a.hash_kind = d->hash_kind >= 0 ? d->hash_kind : ALPHA_HASH_DEFAULT;
    return alpha_params_defaults(&a);
}

/* The ring layout of a run: --rings, else the scene file's, else auto; checked against the display. */
static fs_status resolve_layout(const run_desc *d, const scene *sc, int width, int height, fov_layout *out)
{
    const char *spec = d->rings ? d->rings : sc->rings[0] ? sc->rings : "auto";
    display_desc dd = {width > 0 ? width : sc->display.width, height > 0 ? height : sc->display.height,
                       sc->display.hfov_deg};
    char err[256];
    if (fov_layout_parse(spec, &dd, out, err, sizeof err) != FS_OK) {
        log_error("%s: %s", d->rings ? "--rings" : sc->path, err);
        return FS_ERR_USAGE;
    }
    /* An auto layout that would shade as many pixels as the display (small or coarse displays,
     * where the fovea already spans most of the view) only adds work: foveation off. */
    if (out->kind == FOV_LAYOUT_AUTO && out->count > 1 &&
        fov_shaded_pixels(&dd, out, 0.5f * (float)dd.width, 0.5f * (float)dd.height, FOV_MARGIN_BLOCKS, NULL) >=
            (long long)dd.width * dd.height) {
        log_info("FOV: auto rings would not save pixels on a %dx%d display; foveation off", dd.width, dd.height);
        *out = fov_layout_off();
    }
    return FS_OK;
}

fs_status run_plan_options(const run_desc *d, const scene *sc, plan_options *out)
{
    plan_options po = {.alpha_mode = d->alpha, .width = d->width, .height = d->height, .frames = frame_count(d, sc),
                       .overlay = d->overlay, .debug_channels = d->debug_channels, .alpha = run_alpha_params(d),
                       .taa = d->taa >= 0 ? d->taa == 1 : !sc->taa.off,
                       .taa_controls = {.blend = d->taa_blend > 0 ? d->taa_blend : sc->taa.blend,
                                        .gamma = d->taa_gamma > 0 ? d->taa_gamma : sc->taa.gamma,
                                        .jitter_length = d->jitter_length > 0 ? d->jitter_length : sc->taa.jitter_length}};
    *out = po;
    return resolve_layout(d, sc, d->width, d->height, &out->layout);
}

static fs_status build_plan(const run_desc *d, const scene *sc, plan *pl)
{
    plan_options po;
    fs_status st = run_plan_options(d, sc, &po);
    return st == FS_OK ? plan_build(sc, &po, pl) : st;
}

typedef struct session {
    scene sc;
    plan pl;
    renderer *r;
    gaze_trace gaze;    /* count == 0: no trace, fixation at the centre */
    bool gaze_ended;    /* the "trace ends before the sequence" note was printed */
} session;

static void session_end(session *s)
{
    renderer_destroy(s->r);
    gl_device_destroy();
    gaze_free(&s->gaze);
    scene_free(&s->sc);
}

/* Scene, plan, gaze trace, GL context and (with `with_renderer`) the renderer: everything that can
 * reject bad input, before anything is written. */
static fs_status session_begin(const run_desc *d, session *s, bool with_renderer)
{
    memset(s, 0, sizeof *s);
    fs_status st = run_load_scene(d, &s->sc);
    if (st != FS_OK)
        return st;
    st = build_plan(d, &s->sc, &s->pl);
    if (st == FS_OK && d->gaze_path)
        st = gaze_load(d->gaze_path, &(gaze_load_desc){.format = d->gaze_format, .eye = d->eye}, &s->gaze);
    if (st == FS_OK)
        st = gl_device_create(&(gl_device_desc){.gpu_index = d->gpu, .gl_debug = d->gl_debug});
    if (st == FS_OK) {
        log_info("SCENE: [%s] %d assets, %d instances, %.2f s camera path", s->sc.path, s->sc.asset_count,
                 s->sc.instance_count, s->sc.duration);
        if (s->gaze.count > 0)
            log_info("GAZE: [%s] %s, %d samples (%d valid) over %.2f s", s->gaze.path,
                     gaze_format_name(s->gaze.format), s->gaze.count, s->gaze.valid_count, s->gaze.duration);
        if (with_renderer)
            s->r = renderer_create(&(renderer_desc){.scene = &s->sc, .plan = &s->pl}, &st);
    }
    if (st != FS_OK)
        session_end(s);
    return st;
}

/* Frame `index` with its gaze (from the trace, or the centre) and ring footprints. */
static frame_record session_frame(session *s, int index, float time, float prev_time)
{
    frame_record fr = frame_record_at(&s->sc, index, time, prev_time, s->pl.width, s->pl.height);
    float gx = 0.5f, gy = 0.5f;
    if (s->gaze.count > 0) {
        bool beyond = false;
        gaze_point g = gaze_at(&s->gaze, time, &beyond);
        gx = g.x;
        gy = g.y;
        if (beyond && !s->gaze_ended) {
            log_warn("%s: the gaze trace ends at %.2f s; frames after it hold its last gaze", s->gaze.path,
                     s->gaze.duration);
            s->gaze_ended = true;
        }
    }
    display_desc dd = {s->pl.width, s->pl.height, fr.hfov_deg};
    frame_record_set_gaze(&fr, &s->pl.layout, &dd, gx, gy);
    return fr;
}

/* >>render */
void run_frame_attrs(exr_image *img, const scene *sc, const plan *pl, const gaze_trace *gz, const frame_record *fr)
{
    exr_image_set_string(img, "fovsim:version", FOVSIM_VERSION);
    exr_image_set_string(img, "fovsim:renderer", gl_device_renderer());
    exr_image_set_string(img, "fovsim:scene", sc->path);
    exr_image_set_int(img, "fovsim:frame", fr->index);
    exr_image_set_float(img, "fovsim:time", fr->time);
    exr_image_set_v2f(img, "fovsim:gaze", fr->gaze[0], fr->gaze[1]);
    exr_image_set_v2f(img, "fovsim:gaze_deg", fr->gaze_deg[0], fr->gaze_deg[1]);
    exr_image_set_string(img, "fovsim:alpha_mode", alpha_mode_name(pl->global_mode));
    char rings[256];
    fov_layout_format(&pl->layout, rings, sizeof rings);
    exr_image_set_string(img, "fovsim:rings", rings);
    exr_image_set_string(img, "fovsim:gaze_trace", gz->count > 0 ? gz->path : "centre fixation");
    char taa[128];
    if (pl->taa)
        snprintf(taa, sizeof taa, "on: blend %.3f, gamma %.2f, jitter Halton(2,3) x %d", pl->taa_controls.blend,
                 pl->taa_controls.gamma, pl->taa_controls.jitter_length);
    else
        snprintf(taa, sizeof taa, "off");
    exr_image_set_string(img, "fovsim:taa", taa);
    exr_image_set_float(img, "fovsim:hfov_deg", fr->hfov_deg);
    exr_image_set_string(img, "fovsim:channels",
                         "RGBA: linear premultiplied radiance; coverage: opacity of alpha-mapped surfaces");
}

/* Renders the sequence; *frames_out (may be NULL) gets the number of frames asked for. */
static fs_status run_render(const run_desc *d, const char *default_out, int *frames_out)
{
    session s;
    fs_status st = session_begin(d, &s, true);
    if (st != FS_OK)
        return st;
    const char *out = d->out_dir ? d->out_dir : default_out;
    int frames = frame_count(d, &s.sc);
    if (frames_out)
        *frames_out = frames;
    st = run_make_dirs(out);
    exr_writer *w = st == FS_OK ? exr_writer_create(&(exr_writer_desc){.compression = d->compression}) : NULL;
    if (st == FS_OK && !w)
        st = FS_ERR_NOMEM;
    signal(SIGINT, on_sigint);
    progress pr = progress_begin("frame", frames, d->quiet);
    double t0 = time_now();
    int done = 0;
    for (int i = 0; i < frames && st == FS_OK; i++) {
        if (g_interrupted) {
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
        run_frame_attrs(&img, &s.sc, &s.pl, &s.gaze, &fr);
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

static fs_status run_demo(const run_desc *d)
{
    /* The demo follows a built-in trace of fixations and saccades, so the rings visibly move. */
    run_desc dd = *d;
    if (!dd.gaze_path)
        dd.gaze_path = "builtin:fixation_saccade";
    d = &dd;
    int frames = 1;
    fs_status st = run_render(d, "out/demo", &frames);
    if (st != FS_OK)
        return st;
    const char *out = d->out_dir ? d->out_dir : "out/demo";
    int last = frames - 1;
    printf("\nlook at the frames (linear half-float RGBA + a coverage channel):\n"
           "  oiiotool --info -v %s/%s.0000.exr      # header: frame, time, renderer, alpha mode\n"
           "  oiiotool --frames 0-%d %s/%s.#.exr --ch R,G,B --colorconvert linear sRGB -o %s/%s.#.png\n"
           "  ffmpeg -framerate %g -i %s/%s.%%04d.png -pix_fmt yuv420p %s/demo.mp4\n"
           "  oiiotool %s/%s.0000.exr --ch coverage -o coverage.png   # where alpha-mapped foliage is\n",
           out, d->name, last, out, d->name, out, d->name, d->fps, out, d->name, out, out, d->name);
    return FS_OK;
}

/* >>plan */
static fs_status run_plan(const run_desc *d)
{
    scene sc;
    fs_status st = run_load_scene(d, &sc);
    if (st != FS_OK)
        return st;
    plan pl;
    st = build_plan(d, &sc, &pl);
    if (st == FS_OK)
        plan_print(&pl, &sc, stdout);
    scene_free(&sc);
    return st;
}

/* >>bench */
static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Quantile of a sorted array (linear interpolation). */
static double quantile(const double *v, int n, double q)
{
    if (n == 0)
        return 0;
    double pos = q * (n - 1);
    int i = (int)pos;
    return i + 1 < n ? v[i] + (v[i + 1] - v[i]) * (pos - i) : v[n - 1];
}

static void cpu_name(char *buf, size_t n)
{
    snprintf(buf, n, "unknown CPU");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f)
        return;
    char line[512];
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, "model name", 10)) {
            char *c = strchr(line, ':');
            if (c) {
                c += 2;
                c[strcspn(c, "\n")] = '\0';
                snprintf(buf, n, "%s", c);
            }
            break;
        }
    fclose(f);
}

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
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return (summary){quantile(v, n, 0.5), quantile(v, n, 0.1), quantile(v, n, 0.9), v[0], v[n - 1]};
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
    cpu_name(cpu, sizeof cpu);
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
    case CMD_BENCH: return run_bench(d);
    case CMD_VIEW: return view_run(d);
    case CMD_NONE: break;
    }
    return FS_ERR_INTERNAL;
}
