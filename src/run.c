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

#include "core/log.h"
#include "core/progress.h"
#include "gl/gl_device.h"
#include "passes/plan.h"
#include "passes/renderer.h"
#include "scene/frame.h"

static volatile sig_atomic_t g_interrupted;
static void on_sigint(int sig)
{
    (void)sig;
    g_interrupted = 1;
}

/* >>setup */
static fs_status load_scene(const run_desc *d, scene *sc)
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
static fs_status make_dirs(const char *path)
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

typedef struct session {
    scene sc;
    plan pl;
    renderer *r;
} session;

static void session_end(session *s)
{
    renderer_destroy(s->r);
    gl_device_destroy();
    scene_free(&s->sc);
}

/* Scene, plan, GL context, renderer: everything that can reject bad input. */
static fs_status session_begin(const run_desc *d, session *s, bool timers)
{
    memset(s, 0, sizeof *s);
    fs_status st = load_scene(d, &s->sc);
    if (st != FS_OK)
        return st;
    plan_options po = {.alpha_mode = d->alpha, .width = d->width, .height = d->height, .frames = frame_count(d, &s->sc)};
    st = plan_build(&s->sc, &po, &s->pl);
    if (st == FS_OK)
        st = gl_device_create(&(gl_device_desc){.gpu_index = d->gpu, .gl_debug = d->gl_debug});
    if (st == FS_OK) {
        log_info("SCENE: [%s] %d assets, %d instances, %.2f s camera path", s->sc.path, s->sc.asset_count,
                 s->sc.instance_count, s->sc.duration);
        s->r = renderer_create(&(renderer_desc){.scene = &s->sc, .plan = &s->pl, .timers = timers}, &st);
    }
    if (st != FS_OK)
        session_end(s);
    return st;
}

/* >>render */
static void set_frame_attrs(exr_image *img, const session *s, const frame_record *fr)
{
    exr_image_set_string(img, "fovsim:version", FOVSIM_VERSION);
    exr_image_set_string(img, "fovsim:renderer", gl_device_renderer());
    exr_image_set_string(img, "fovsim:scene", s->sc.path);
    exr_image_set_int(img, "fovsim:frame", fr->index);
    exr_image_set_float(img, "fovsim:time", fr->time);
    exr_image_set_v2f(img, "fovsim:gaze", fr->gaze[0], fr->gaze[1]);
    exr_image_set_v2f(img, "fovsim:gaze_deg", 0.0f, 0.0f); /* gaze = view centre until gaze traces land */
    exr_image_set_string(img, "fovsim:alpha_mode", alpha_mode_name(s->pl.global_mode));
    exr_image_set_string(img, "fovsim:rings", "off (full resolution)");
    exr_image_set_float(img, "fovsim:hfov_deg", fr->hfov_deg);
    exr_image_set_string(img, "fovsim:channels",
                         "RGBA: linear premultiplied radiance; coverage: opacity of alpha-mapped surfaces");
}

static fs_status run_render(const run_desc *d, const char *default_out)
{
    session s;
    fs_status st = session_begin(d, &s, false);
    if (st != FS_OK)
        return st;
    const char *out = d->out_dir ? d->out_dir : default_out;
    int frames = frame_count(d, &s.sc);
    st = make_dirs(out);
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
        frame_record fr = frame_record_make(&s.sc, i, d->fps, s.pl.width, s.pl.height);
        exr_image img;
        st = renderer_draw(s.r, &fr);
        if (st == FS_OK)
            st = renderer_read(s.r, &img);
        if (st != FS_OK)
            break;
        set_frame_attrs(&img, &s, &fr);
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
        printf("wrote %d frames (%dx%d, alpha %s) to %s/%s.####.exr in %.1f s (%.2f fps) on %s\n", frames,
               s.pl.width, s.pl.height, alpha_mode_name(s.pl.global_mode), out, d->name, el, frames / el,
               gl_device_renderer());
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
    fs_status st = run_render(d, "out/demo");
    if (st != FS_OK)
        return st;
    const char *out = d->out_dir ? d->out_dir : "out/demo";
    scene sc; /* only to know the frame count the render used */
    int last = 0;
    if (scene_load_builtin(d->builtin, &sc) == FS_OK) {
        last = frame_count(d, &sc) - 1;
        scene_free(&sc);
    }
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
    fs_status st = load_scene(d, &sc);
    if (st != FS_OK)
        return st;
    plan pl;
    plan_options po = {.alpha_mode = d->alpha, .width = d->width, .height = d->height, .frames = frame_count(d, &sc)};
    st = plan_build(&sc, &po, &pl);
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

static fs_status run_bench(const run_desc *d)
{
    session s;
    fs_status st = session_begin(d, &s, true);
    if (st != FS_OK)
        return st;
    int n = d->frames > 0 ? d->frames : 30;
    double *wall = calloc((size_t)n, sizeof *wall);
    double *pass = calloc((size_t)n * PLAN_MAX_PASSES, sizeof *pass);
    double *gltime = calloc((size_t)n * PLAN_MAX_PASSES, sizeof *gltime);
    double *frags = calloc((size_t)n, sizeof *frags);
    if (!wall || !pass || !gltime || !frags) {
        free(wall); free(pass); free(gltime); free(frags);
        session_end(&s);
        return FS_ERR_NOMEM;
    }
    /* Frames spread evenly over the camera path, so the numbers stand for the whole sequence. */
    float span = s.sc.duration;
    progress pr = progress_begin("bench", d->warmup + n, d->quiet);
    renderer_stats rs = {0};
    for (int i = 0; i < d->warmup + n; i++) {
        int k = i < d->warmup ? i : i - d->warmup;
        float t = n > 1 ? span * (float)k / (float)(n - 1) : 0.0f;
        frame_record fr = frame_record_at(&s.sc, k, t, -1.0f, s.pl.width, s.pl.height);
        /* 1: the frame as the renderer runs it, finished once at the end. */
        renderer_set_pass_sync(s.r, false);
        double t0 = time_now();
        renderer_draw(s.r, &fr);
        renderer_finish(s.r);
        double t1 = time_now();
        rs = renderer_last_stats(s.r);
        /* 2: the same frame again with a finish after every pass, for per-pass wall times. */
        renderer_set_pass_sync(s.r, true);
        renderer_draw(s.r, &fr);
        renderer_stats sync = renderer_last_stats(s.r);
        if (i >= d->warmup) {
            wall[k] = (t1 - t0) * 1e3;
            for (int p = 0; p < rs.pass_count; p++) {
                pass[(size_t)p * (size_t)n + (size_t)k] = sync.pass_wall_ms[p];
                gltime[(size_t)p * (size_t)n + (size_t)k] = rs.pass_ms[p];
            }
            frags[k] = (double)rs.fragments;
        }
        progress_update(&pr, i + 1);
    }
    progress_end(&pr);

    char cpu[256];
    cpu_name(cpu, sizeof cpu);
    struct utsname un;
    uname(&un);
    qsort(wall, (size_t)n, sizeof *wall, cmp_double);
    qsort(frags, (size_t)n, sizeof *frags, cmp_double);
    long long tris = 0;
    for (int p = 0; p < s.pl.pass_count; p++)
        tris += s.pl.passes[p].triangles;
    double px = (double)s.pl.width * s.pl.height;

    char report[8192];
    int o = 0;
#define OUT(...) o += snprintf(report + o, sizeof report - (size_t)o, __VA_ARGS__)
    OUT("### %s, %dx%d, alpha %s\n\n", s.sc.path, s.pl.width, s.pl.height, alpha_mode_name(s.pl.global_mode));
    OUT("- machine: %s, %s %s (%ld cores online)\n", cpu, un.sysname, un.machine, sysconf(_SC_NPROCESSORS_ONLN));
    OUT("- renderer: %s (OpenGL %s, %s)\n", gl_device_renderer(), gl_device_version(), gl_device_description());
    OUT("- %d frames spread over the %.2f s camera path after %d warm-up frames; %lld triangles/frame\n\n", n, span,
        d->warmup, tris);
    OUT("| measure | median | p10 | p90 | min | max |\n|---|---|---|---|---|---|\n");
    OUT("| frame, wall clock incl. finish (ms) | %.2f | %.2f | %.2f | %.2f | %.2f |\n", quantile(wall, n, 0.5),
        quantile(wall, n, 0.1), quantile(wall, n, 0.9), wall[0], wall[n - 1]);
    for (int p = 0; p < rs.pass_count; p++) {
        double *v = &pass[(size_t)p * (size_t)n];
        qsort(v, (size_t)n, sizeof *v, cmp_double);
        OUT("| pass %s, wall clock with glFinish (ms) | %.2f | %.2f | %.2f | %.2f | %.2f |\n", rs.pass_names[p],
            quantile(v, n, 0.5), quantile(v, n, 0.1), quantile(v, n, 0.9), v[0], v[n - 1]);
    }
    for (int p = 0; p < rs.pass_count; p++) {
        double *v = &gltime[(size_t)p * (size_t)n];
        qsort(v, (size_t)n, sizeof *v, cmp_double);
        OUT("| pass %s, GL timer query (ms) | %.2f | %.2f | %.2f | %.2f | %.2f |\n", rs.pass_names[p],
            quantile(v, n, 0.5), quantile(v, n, 0.1), quantile(v, n, 0.9), v[0], v[n - 1]);
    }
    if (frags[0] >= 0)
        OUT("| fragment shader invocations / pixel | %.2f | %.2f | %.2f | %.2f | %.2f |\n", quantile(frags, n, 0.5) / px,
            quantile(frags, n, 0.1) / px, quantile(frags, n, 0.9) / px, frags[0] / px, frags[n - 1] / px);
    OUT("\nshaded pixels per frame: %.0f (one forward sample per display pixel; rings not implemented yet)\n", px);
#undef OUT
    fputs(report, stdout);
    if (d->markdown) {
        FILE *f = fopen(d->markdown, "a");
        if (!f || fprintf(f, "\n%s", report) < 0 || fclose(f) != 0) {
            log_error("%s: cannot append the bench report: %s", d->markdown, strerror(errno));
            st = FS_ERR_IO;
        } else {
            printf("appended to %s\n", d->markdown);
        }
    }
    free(wall);
    free(pass);
    free(gltime);
    free(frags);
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
    case CMD_RENDER: return run_render(d, "out/render");
    case CMD_DEMO: return run_demo(d);
    case CMD_BENCH: return run_bench(d);
    case CMD_NONE: break;
    }
    return FS_ERR_INTERNAL;
}
