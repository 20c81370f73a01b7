#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/config.h"
#include "common/shared_defs.h"
#include "core/log.h"
#include "passes/plan.h"
#include "output/out_path.h"
#include "scene/scene.h"

static const struct {
    const char *name;
    command cmd;
    const char *summary;
} k_commands[] = {
    {"render", CMD_RENDER, "render a scene to an EXR sequence"},
    {"plan", CMD_PLAN, "print the passes and shader variants a scene needs"},
    {"demo", CMD_DEMO, "render the built-in forest to ./out/demo/ (no arguments needed)"},
    {"bench", CMD_BENCH, "time a scene: median and spread of frame and pass times"},
    {"reference", CMD_REFERENCE, "render the ground truth (supersampled, exact alpha compositing; cached)"},
    {"compare", CMD_COMPARE, "render alpha modes side by side against the reference, with metrics"},
    {"view", CMD_VIEW, "interactive window: the mouse is the gaze (GLFW, OpenGL 4.5)"},
};

void cli_print_help(command cmd)
{
    switch (cmd) {
    case CMD_RENDER:
        printf("usage: fovsim render [SCENE | --scene FILE | --builtin NAME] [options]\n\n"
               "Renders the scene's camera path to DIR/<name>.<frame:04d>.exr (half RGBA + coverage, ZIP).\n\n");
        break;
    case CMD_PLAN:
        printf("usage: fovsim plan [SCENE | --scene FILE | --builtin NAME] [--alpha MODE] [--width W --height H]\n\n"
               "Prints which passes, shader variants and targets the scene needs, without drawing.\n\n");
        break;
    case CMD_DEMO:
        printf("usage: fovsim demo [options]\n\n"
               "Renders the built-in forest (camera dollying back through trees and a fence) with foveation\n"
               "following a built-in trace of fixations and saccades, to ./out/demo/, and prints how to look\n"
               "at the frames. Accepts the render options below.\n\n");
        break;
    case CMD_BENCH:
        printf("usage: fovsim bench [SCENE | --scene FILE | --builtin NAME] [--frames N] [--warmup W] [--markdown FILE]\n\n"
               "Draws N frames spread over the camera path after W warm-up frames and reports median and\n"
               "spread of the frame time (wall clock, glFinish), the process CPU time and minor page faults\n"
               "of the draw, GL time per stage (pass, or ring, TAA resolve and composite), and work counts\n"
               "that transfer to a GPU (GL_ARB_pipeline_statistics_query): vertex-shader invocations,\n"
               "primitives submitted and fragment-shader invocations, per stage and per frame; n/a (JSON\n"
               "-1) where the driver lacks the extension. Text is Markdown; --format json for scripts.\n"
               "Configurations per mode: full resolution, foveated (the run's rings, without ring LOD) and,\n"
               "with --ring-lod (or the scene's ring_lod), foveated + ring LOD, with its ratios to foveated\n"
               "per stage (time, CPU time, fragment-shader invocations, primitives).\n"
               "Defaults: N = 30, W = 5, the scene's display size. See docs/benchmarks.md.\n\n");
        break;
    case CMD_REFERENCE:
        printf("usage: fovsim reference [SCENE | --scene FILE | --builtin NAME] [--reference exact|stochastic]\n"
               "                        [--supersample S] [--samples K]\n\n"
               "Renders the ground truth of every frame: full resolution, S x S sub-samples per pixel, each\n"
               "the expectation of stochastic alpha testing (order-correct alpha compositing): exact from\n"
               "per-pixel fragment lists (default), or the mean of K stochastic tests. Frames are cached by\n"
               "a key of the scene, camera, size, kind, S and K (compare reuses them) and written to\n"
               "DIR/reference.<frame:04d>.exr; each frame's estimated error is printed (exact: S x S vs\n"
               "S/2 x S/2 sub-samples; stochastic: K/2 vs K tests).\n\n");
        break;
    case CMD_COMPARE:
        printf("usage: fovsim compare [SCENE | --scene FILE | --builtin NAME] --modes M,M,... [--gaze FILE] [options]\n\n"
               "Renders every mode with the same camera, gaze, jitter and seeds, and writes per frame one\n"
               "two-part EXR, DIR/compare.<frame:04d>.exr: part 'compare' is a grid of the modes and the\n"
               "reference (RGBA, what any viewer shows), part 'layers' holds <mode>.R/G/B/A, <mode>.coverage,\n"
               "<mode>.error, reference.* and ring.id. Metrics per frame, ring and mode go to DIR/metrics.csv,\n"
               "a summary to DIR/summary.json, and a table is printed. Default modes: traditional,hashed.\n\n");
        break;
    case CMD_VIEW:
        printf("usage: fovsim view [SCENE | --scene FILE | --builtin NAME] [options]\n\n"
               "Opens a window at the scene's display size and draws the scene as render would, with the\n"
               "mouse as the gaze (or --gaze FILE replayed). Keys: A alpha mode, T TAA, F foveation,\n"
               "L ring layout (auto, aggressive, off), [ ] mip bias, O ring overlay, C freeze camera,\n"
               "H reset history, S split screen, M right-hand mode, R record gaze, P capture EXR,\n"
               "SPACE pause, N step, ESC/Q quit. See docs/viewer.md.\n\n"
               "  --script FILE       scripted input (frame N / move X Y / key NAME / capture / quit)\n"
               "  --record FILE       where R records the gaze (fovsim CSV; default out/view/gaze-<n>.csv);\n"
               "                      captures go next to it\n"
               "  --split A,B         split screen: alpha mode A on the left, B on the right\n"
               "Render's options below apply (--gaze, --rings, --taa, --alpha, ...) except --frames, --out,\n"
               "--name and --gpu.\n\n");
        break;
    default:
        printf("fovsim %s: foveated rendering simulator for alpha-mapped foliage\n\n"
               "usage: fovsim <command> [options]\n       fovsim <command> --help\n\ncommands:\n",
               FOVSIM_VERSION);
        for (size_t i = 0; i < sizeof k_commands / sizeof k_commands[0]; i++)
            printf("  %-10s %s\n", k_commands[i].name, k_commands[i].summary);
        printf("  %-10s %s\n  %-10s %s\n", "sweep", "run scenes x gaze traces x configurations: here, as a jobs file or "
               "on Slurm", "merge", "gather a sweep's metrics into one CSV, summary and plot");
        printf("  %-10s %s\n", "check", "regression test: record a compare run as a baseline, or check one against it");
        printf("\nglobal options: --help, --version, --list-gpus\n\n");
        break;
    }
    if (cmd == CMD_NONE)
        return;
    printf("options:\n"
           "  SCENE               a scene file or built-in name, as --scene or --builtin\n"
           "  --scene FILE        scene JSON, or a .gltf/.glb asset to view on its own\n"
           "  --builtin NAME      built-in scene: %s (default forest)\n"
           "  --frames N          frames to draw (default: the camera path at --fps)\n"
           "  --fps F             frames per second of the sequence, 0.001 to 1000 (default 24)\n"
           "  --width W, --height H   output size in pixels (default: the scene's display, 1280x720)\n"
           "  --alpha MODE        alpha test for MASK materials: %s\n"
           "  --hash-scale S      hashed modes: noise scale in pixels (default 1; the paper suggests\n"
           "                      0.3-0.5 with TAA, docs/hashed-alpha.md)\n"
           "  --hash H            hashed modes: pcg (integer pcg3d, default) or sine (the paper's; not\n"
           "                      uniform on flat cards, docs/hashed-alpha.md)\n"
           "  --hash-aniso        hashed modes: anisotropic (per-axis) pixel-scale noise\n"
           "  --fade-n N          hashed: mip levels over which noise fades in (default 6; earlier for\n"
           "                      textures the traditional test erodes sooner)\n"
           "  --no-fade           hashed: no fade-in, noise at every distance\n"
           "  --no-hash-offset    hashed with TAA: thresholds stay put instead of moving by a\n"
           "                      golden-ratio offset each frame (docs/hashed-alpha.md)\n"
           "  --a2c-sharpen       a2c: mip-level alpha scaling and fwidth sharpening (Golus)\n"
           "  --alpha-lod-max N|off  alpha-tested materials read alpha at most at mip level N (0-16;\n"
           "                      colour keeps the whole chain), unless a material sets its own\n"
           "                      \"alpha_lod_max\"; off: no clamp, the scene's neither (atlases seen\n"
           "                      from afar, docs/hashed-alpha.md \"Alpha LOD clamp\"; default none)\n"
           "  --taa on|off        temporal antialiasing per ring (default on for more than one frame)\n"
           "  --taa-blend W       weight of the current frame in the history (default 0.1)\n"
           "  --taa-gamma G       history clipping box, in standard deviations (default 1)\n"
           "  --taa-sparse S|off  how far the history's coverage may stay from each pixel's own\n"
           "                      sample: 1 - alpha of a one-sample test (docs/taa.md \"Sparse\n"
           "                      coverage\"; default 0.95); off clamps it to the neighbourhood's range\n"
           "  --taa-disocclusion on|off  drop history whose nearest surface moved off the pixel\n"
           "                      (depth; default on; off to measure what it buys)\n"
           "  --taa-neighbourhood 3x3|cross  taps of the history clipping box (docs/taa.md; default cross)\n"
           "  --taa-history catmull|bilinear  history fetch: 5-tap Catmull-Rom or one bilinear tap\n"
           "                      (default catmull)\n"
           "  --taa-nan tap|set   NaN/Inf checked per fetched tap or once per set of fetches (default tap)\n"
           "  --jitter-length N   Halton (2,3) jitter period in frames (default 16)\n"
           "  --object-motion on|off  TAA follows swaying instances' own motion (default on; off\n"
           "                      reprojects them as if still, to measure what it buys)\n"
           "  --ring-cull on|off  rings skip instances that lie wholly where the finer ring is shown\n"
           "                      alone (default on; off draws them, to measure what it saves)\n"
           "  --composite tiled|per-pixel  how the rings reach the display: tiled (default) draws\n"
           "                      the tiles inside one ring without searching it per pixel; per-pixel\n"
           "                      searches everywhere (same image, to measure what tiling saves)\n"
           "  --rings SPEC        foveation rings: auto (acuity model, default), off, or innermost first\n"
           "                      OUTER:SCALE:MIPBIAS,... with * for the last, e.g. 10:1:0,25:1/2:0,*:1/4:0.5\n"
           "  --ring-lod SPEC     stochastic simplification of MASK foliage per ring (docs/ring-lod.md):\n"
           "                      off (default); simplify: in reduced rings each card keeps u = its area\n"
           "                      in ring pixels (at least 1/16), the kept ones enlarged to keep the\n"
           "                      covered area; simplify:area=A the same from A ring pixels; or\n"
           "                      simplify:U1,... one keep fraction per ring, e.g. simplify:1,1,1/4,1/16\n"
           "  --gaze FILE         gaze trace: fovsim CSV, Pupil Labs gaze_positions.csv, EyeLink .asc or\n"
           "                      Tobii livedata.json, or builtin:NAME for a scripted trace in\n"
           "                      gaze_paths/ (default: fixation at the display centre; the demo\n"
           "                      uses builtin:fixation_saccade)\n"
           "  --gaze-format F     csv, pupil, eyelink or tobii (default: detected from the content)\n"
           "  --eye E             binocular traces: left, right or average (default: average of valid eyes)\n"
           "  --overlay           draw ring borders and the gaze marker into the frames\n"
           "  --debug-channels    add ring.id and eccentricity (degrees) channels to the EXR\n"
           "  --out DIR           output directory (default out/<command>)\n"
           "  --name NAME         file prefix (default frame)\n"
           "  --compression C     zip (default), none or piz\n"
           "  --resume            keep the complete frames an interrupted run of the same configuration\n"
           "                      left in DIR and draw the rest (DIR/fovsim-run.txt records it)\n"
           "  --replace           write into a DIR another configuration wrote, removing its frames\n"
           "  --wait-lock S       another run writing DIR (its lock, DIR/fovsim-run.lock): wait up to S\n"
           "                      seconds (1 to 86400) for it to end, then go on; without it, or when\n"
           "                      the time is up, exit 12 naming that run\n"
           "  --gpu N             EGL device index (default: first hardware device, else llvmpipe)\n"
           "  --gl-debug          GL debug output on stderr (always on in debug builds)\n"
           "  --quiet             no progress line\n"
           "  --verbose           print the renderer and what is loaded\n"
           "  --asset-root DIR    glTF buffer and image URIs may also name files under DIR (default:\n"
           "                      only under the glTF file's own folder; README \"Limits\")\n"
           "  --max-image-mpixels N   decoded-pixel budget per glTF image, in Mpixel of 2^20 pixels\n"
           "                      (default 64 = 8192 x 8192), checked before decoding\n"
           "  --max-scene-mpixels N   the same budget summed over a scene's images (default 256)\n",
           scene_builtin_list(), alpha_mode_list());
    if (cmd == CMD_BENCH)
        printf("  --accuracy          the accuracy-vs-time matrix: modes x rings off/default/aggressive x TAA\n"
               "                      off/on (with --ring-lod also default+lod: the default rings with it),\n"
               "                      with coverage, RMSE, alpha RMSE, FLIP and temporal error vs the\n"
               "                      reference, and each configuration's CPU time, page faults and work\n"
               "                      counts; writes DIR/accuracy.csv, accuracy.md, accuracy.png (error vs\n"
               "                      frame time) and accuracy-fragments.png (error vs fragment-shader\n"
               "                      invocations per pixel; not drawn without\n"
               "                      GL_ARB_pipeline_statistics_query), gnuplot\n"
               "  --error E           bench --accuracy: the error plotted and on which the Pareto fronts\n"
               "                      are taken: flip (default), alpha_rmse, rmse or temporal_error\n"
               "                      (docs/metrics.md)\n");
    if (cmd == CMD_REFERENCE || cmd == CMD_COMPARE || cmd == CMD_DEMO || cmd == CMD_BENCH)
        printf("  --reference KIND    exact (default): each sub-sample is the expectation of stochastic\n"
               "                      alpha testing, from per-pixel fragment lists composited front to\n"
               "                      back; stochastic: the mean of K stochastic tests (a cross-check)\n"
               "  --supersample S     reference: S x S sub-samples per pixel (default 4)\n"
               "  --samples K         reference: stochastic alpha tests per sub-sample, even (default 64;\n"
               "                      exact: only for pixels whose fragment lists overflow)\n"
               "  --ref-memory MB     exact reference: budget of the fragment lists (default 2048; the\n"
               "                      GL's buffer-texture limit caps it)\n"
               "  --cache DIR         reference frame cache (default $XDG_CACHE_HOME/fovsim/reference)\n"
               "  --no-cache          draw reference frames without reading or writing the cache\n");
    if (cmd == CMD_COMPARE)
        printf("  --first-frame F     measure and write frames F.. only (a chunk of a longer sequence); the\n"
               "                      frames before are drawn without being written, for the TAA history\n"
               "  --warmup W          with --first-frame: draw at most W frames of history (default: back to\n"
               "                      frame 0 or the last camera cut, the same frames as an unbroken run)\n");
    if (cmd == CMD_COMPARE || cmd == CMD_DEMO)
        printf("  --modes M,M,...     alpha modes side by side (or all; default traditional,hashed)\n"
               "  --export-fvvdp      also write FovVideoVDP's inputs to DIR/fvvdp/: 16-bit sRGB PNG\n"
               "                      sequences of every mode and the reference, the fixation per frame,\n"
               "                      the display and run_fvvdp.py (see docs/metrics.md)\n"
               "  --fvvdp             --export-fvvdp, then run it with the python3 on PATH when that\n"
               "                      imports pyfvvdp, and put each mode's JOD into summary.json\n"
               "                      (a failed run: exit 6, its output in DIR/fvvdp/fvvdp.log)\n");
    if (cmd == CMD_BENCH)
        printf("  --warmup W          frames drawn before timing (default 5)\n"
               "  --markdown FILE     append the result as a Markdown section to FILE\n"
               "  --format F          text (default) or json (machine-readable, on stdout)\n"
               "  --modes M,M,...     alpha modes to compare in one run (or all); each gets its time\n"
               "                      relative to traditional, A2C modes also traditional+MSAA\n");
    printf("\nexit status: 0 ok, 1 fovsim check: a regression, 2 bad arguments, 3 bad scene, 4 bad asset, 5 bad\n"
           "             gaze trace, 6 I/O error, 7 no OpenGL 4.5 context, 8 shader error, 9 out of memory,\n"
           "             11 a sweep has missing or failed tasks, 12 another run is writing DIR, 130 interrupted\n");
}

/* An option with two values: *which = 0 for `a`, 1 for `b`; anything else is a one-line error. */
static bool parse_choice(const char *opt, const char *v, const char *a, const char *b, int *which)
{
    *which = !strcmp(v, b);
    if (!strcmp(v, a) || *which)
        return true;
    log_error("%s: expected %s or %s, got '%s'", opt, a, b, v);
    return false;
}

bool cli_parse_int(const char *opt, const char *v, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long x = strtol(v, &end, 10);
    if (errno || end == v || *end || x < lo || x > hi) {
        log_error("%s: expected an integer in [%d, %d], got '%s'", opt, lo, hi, v);
        return false;
    }
    *out = (int)x;
    return true;
}

/* A number for an option used as a 32-bit float, range-checked as that float (issue 28 part 5): a
 * value that is in range as a double but rounds to 0 or to a denormal (1e-300, 1e-40) would reach
 * the renderer as 0, which every consumer reads as "use the default", or be flushed to 0 on a GPU.
 * (lo, hi], or [lo, hi] with lo_closed. */
static bool parse_float_in(const char *opt, const char *v, float lo, bool lo_closed, float hi, float *out,
                           const char *expected)
{
    char *end;
    errno = 0;
    double x = strtod(v, &end);
    float f = (float)x;
    bool ok = !errno && end != v && !*end && isfinite(x) && isfinite(f) && (lo_closed ? f >= lo : f > lo) && f <= hi &&
              (x == 0.0 || isnormal(f));
    if (!ok) {
        bool tiny = !errno && end != v && !*end && (lo_closed ? x >= lo : x > lo) && x <= hi &&
                    x != 0.0 && !isnormal(f); /* in range as a double, not as the float */
        char range[96];
        snprintf(range, sizeof range, "a number in %c%g, %g]", lo_closed ? '[' : '(', lo, hi);
        log_error("%s: expected %s, got '%s'%s", opt, expected ? expected : range, v,
                  tiny ? " (too small for the 32-bit float it is used as)" : "");
        return false;
    }
    *out = f;
    return true;
}

static bool parse_float(const char *opt, const char *v, float lo, float hi, float *out)
{
    return parse_float_in(opt, v, lo, false, hi, out, NULL);
}

fs_status cli_parse(int argc, char **argv, run_desc *d)
{
    memset(d, 0, sizeof *d);
    d->gpu = -1;
    d->hash_kind = -1;
    d->taa = -1;
    d->fps = 24.0f;
    d->warmup = 5;
    if (argc < 2) {
        d->cmd = CMD_HELP;
        return FS_OK;
    }
    int i = 1;
    const char *c = argv[1];
    if (!strcmp(c, "--help") || !strcmp(c, "-h") || !strcmp(c, "help")) {
        d->cmd = CMD_HELP;
        if (argc > 2)
            for (size_t k = 0; k < sizeof k_commands / sizeof k_commands[0]; k++)
                if (!strcmp(argv[2], k_commands[k].name))
                    d->help_for = k_commands[k].cmd;
        return FS_OK;
    }
    if (!strcmp(c, "--version")) {
        d->cmd = CMD_VERSION;
        return FS_OK;
    }
    if (!strcmp(c, "--list-gpus")) {
        d->cmd = CMD_LIST_GPUS;
        return FS_OK;
    }
    for (size_t k = 0; k < sizeof k_commands / sizeof k_commands[0]; k++)
        if (!strcmp(c, k_commands[k].name))
            d->cmd = k_commands[k].cmd;
    if (d->cmd == CMD_NONE) {
        log_error("unknown command '%s' (commands: render, plan, demo, bench, reference, compare, view, sweep, merge, check; "
                  "see fovsim --help)", c);
        return FS_ERR_USAGE;
    }
    for (i = 2; i < argc; i++) {
        char opt[64];
        const char *a = argv[i], *val = NULL, *eq = strchr(a, '=');
        if (strncmp(a, "--", 2) != 0) {
            /* One positional argument: the scene (`fovsim plan scenes/x.json`, `fovsim render fence`). */
            if (d->cmd == CMD_DEMO || d->scene_path || d->builtin || a[0] == '-') {
                log_error("fovsim %s: unexpected argument '%s' (see fovsim %s --help)", c, a, c);
                return FS_ERR_USAGE;
            }
            /* A built-in's name is the built-in even where a file or folder of that name is in the
             * current folder (as in sweep manifests; ./fence is the file): a folder `fence` hid it.
             * Another word without '/' or '.' that names no file is taken for a built-in name, so
             * that scene_load_builtin lists the known ones. */
            if (!strncmp(a, "builtin:", 8))
                d->builtin = a + 8; /* as fovsim prints a built-in scene's path */
            else if (!strchr(a, '/') && !strchr(a, '.') && (scene_is_builtin(a) || access(a, F_OK) != 0))
                d->builtin = a;
            else
                d->scene_path = a;
            continue;
        }
        snprintf(opt, sizeof opt, "%.*s", eq ? (int)(eq - a) : (int)strlen(a), a);
        if (eq)
            val = eq + 1;
        /* flags */
        if (!strcmp(opt, "--help")) {
            d->help_for = d->cmd;
            d->cmd = CMD_HELP;
            return FS_OK;
        }
        bool *flag = !strcmp(opt, "--verbose")          ? &d->verbose
                     : !strcmp(opt, "--quiet")          ? &d->quiet
                     : !strcmp(opt, "--gl-debug")       ? &d->gl_debug
                     : !strcmp(opt, "--overlay")        ? &d->overlay
                     : !strcmp(opt, "--debug-channels") ? &d->debug_channels
                     : !strcmp(opt, "--hash-aniso")     ? &d->hash_aniso
                     : !strcmp(opt, "--no-fade")        ? &d->no_fade
                     : !strcmp(opt, "--no-hash-offset") ? &d->no_hash_offset
                     : !strcmp(opt, "--a2c-sharpen")    ? &d->a2c_sharpen
                     : !strcmp(opt, "--no-cache")       ? &d->no_cache
                     : !strcmp(opt, "--accuracy")       ? &d->accuracy
                     : !strcmp(opt, "--export-fvvdp")   ? &d->export_fvvdp
                     : !strcmp(opt, "--fvvdp")          ? &d->run_fvvdp
                     : !strcmp(opt, "--resume")         ? &d->resume
                     : !strcmp(opt, "--replace")        ? &d->replace
                                                        : NULL;
        if (flag) {
            if (val) {
                log_error("%s takes no value", opt);
                return FS_ERR_USAGE;
            }
            *flag = true;
            continue;
        }
        static const char *const with_value[] = {"--scene", "--builtin", "--frames", "--fps", "--out",
                                                 "--name", "--width", "--height", "--alpha", "--gpu",
                                                 "--warmup", "--first-frame", "--markdown", "--compression", "--rings", "--ring-lod",
                                                 "--gaze", "--gaze-format", "--eye", "--format", "--hash-scale",
                                                 "--hash", "--fade-n", "--alpha-lod-max", "--modes", "--taa", "--taa-blend",
                                                 "--taa-gamma", "--taa-sparse", "--taa-disocclusion", "--taa-neighbourhood", "--taa-history", "--taa-nan", "--jitter-length", "--object-motion", "--composite", "--ring-cull", "--supersample", "--samples",
                                                 "--reference", "--ref-memory", "--error", "--cache", "--script", "--record", "--split",
                                                 "--asset-root", "--max-image-mpixels", "--max-scene-mpixels", "--wait-lock"};
        bool known = false;
        for (size_t k = 0; k < sizeof with_value / sizeof with_value[0]; k++)
            known |= !strcmp(opt, with_value[k]);
        if (!known) {
            log_error("fovsim %s: unknown option '%s' (see fovsim %s --help)", c, opt, c);
            return FS_ERR_USAGE;
        }
        if (!val) {
            if (i + 1 >= argc) {
                log_error("%s: expected a value", opt);
                return FS_ERR_USAGE;
            }
            val = argv[++i];
        }
        bool ok = true;
        if (!strcmp(opt, "--scene"))
            d->scene_path = val;
        else if (!strcmp(opt, "--builtin"))
            d->builtin = !strncmp(val, "builtin:", 8) ? val + 8 : val;
        else if (!strcmp(opt, "--out"))
            d->out_dir = val;
        else if (!strcmp(opt, "--cache"))
            d->cache_dir = val;
        else if (!strcmp(opt, "--asset-root")) {
            d->asset_root = val;
            ok = *val != '\0';
            if (!ok)
                log_error("--asset-root: expected a folder, got ''");
        } else if (!strcmp(opt, "--wait-lock"))
            ok = cli_parse_int(opt, val, 1, WAIT_LOCK_MAX_S, &d->wait_lock);
        else if (!strcmp(opt, "--max-image-mpixels"))
            ok = cli_parse_int(opt, val, 1, 4096, &d->max_image_mpixels);
        else if (!strcmp(opt, "--max-scene-mpixels"))
            ok = cli_parse_int(opt, val, 1, 65536, &d->max_scene_mpixels);
        else if (!strcmp(opt, "--supersample"))
            ok = cli_parse_int(opt, val, 1, 16, &d->supersample);
        else if (!strcmp(opt, "--reference")) {
            ok = parse_choice(opt, val, "exact", "stochastic", &d->reference_kind);
            d->reference_set = true;
        } else if (!strcmp(opt, "--error")) {
            static const char *const names[4] = {"flip", "alpha_rmse", "rmse", "temporal_error"};
            ok = false;
            for (int k = 0; k < 4; k++)
                if (!strcmp(val, names[k])) {
                    d->acc_error = k;
                    ok = true;
                }
            if (!ok)
                log_error("--error: expected flip, alpha_rmse, rmse or temporal_error, got '%s'", val);
            d->acc_error_set = true;
        } else if (!strcmp(opt, "--ref-memory"))
            ok = cli_parse_int(opt, val, 1, 1 << 20, &d->ref_memory_mb);
        else if (!strcmp(opt, "--samples")) {
            ok = cli_parse_int(opt, val, 2, 4096, &d->samples);
            if (ok && d->samples % 2) {
                log_error("--samples: expected an even number (the two halves estimate convergence), got %d", d->samples);
                ok = false;
            }
        } else if (!strcmp(opt, "--markdown"))
            d->markdown = val;
        else if (!strcmp(opt, "--rings"))
            d->rings = val; /* checked against the display once the scene is known */
        else if (!strcmp(opt, "--ring-lod"))
            d->ring_lod = val; /* checked against the ring layout once the scene is known */
        else if (!strcmp(opt, "--gaze"))
            d->gaze_path = val;
        else if (!strcmp(opt, "--script"))
            d->script = val;
        else if (!strcmp(opt, "--record"))
            d->record = val;
        else if (!strcmp(opt, "--split")) {
            char a[64], b[64];
            const char *comma = strchr(val, ',');
            snprintf(a, sizeof a, "%.*s", comma ? (int)(comma - val) : (int)strlen(val), val);
            snprintf(b, sizeof b, "%s", comma ? comma + 1 : "");
            d->split[0] = alpha_mode_parse(a);
            d->split[1] = alpha_mode_parse(b);
            ok = d->split[0] != ALPHA_MODE_DEFAULT && d->split[1] != ALPHA_MODE_DEFAULT && d->split[0] != d->split[1];
            if (!ok)
                log_error("--split: expected two different alpha modes A,B (modes: %s), got '%s'", alpha_mode_list(), val);
        }
        else if (!strcmp(opt, "--gaze-format")) {
            d->gaze_format = gaze_format_parse(val);
            ok = d->gaze_format != GAZE_FORMAT_AUTO;
            if (!ok)
                log_error("--gaze-format: expected csv, pupil, eyelink or tobii, got '%s'", val);
        } else if (!strcmp(opt, "--eye")) {
            d->eye = !strcmp(val, "left") ? GAZE_EYE_LEFT : !strcmp(val, "right") ? GAZE_EYE_RIGHT
                     : !strcmp(val, "average") ? GAZE_EYE_AVERAGE : GAZE_EYE_AUTO;
            ok = d->eye != GAZE_EYE_AUTO;
            if (!ok)
                log_error("--eye: expected left, right or average, got '%s'", val);
        } else if (!strcmp(opt, "--hash-scale"))
            ok = parse_float(opt, val, 0.0f, 64.0f, &d->hash_scale);
        else if (!strcmp(opt, "--taa")) {
            ok = !strcmp(val, "on") || !strcmp(val, "off");
            d->taa = !strcmp(val, "on");
            if (!ok)
                log_error("--taa: expected on or off, got '%s'", val);
        } else if (!strcmp(opt, "--taa-blend"))
            ok = parse_float(opt, val, 0.0f, 1.0f, &d->taa_blend);
        else if (!strcmp(opt, "--taa-gamma"))
            ok = parse_float(opt, val, 0.0f, 16.0f, &d->taa_gamma);
        else if (!strcmp(opt, "--taa-sparse")) {
            if (!strcmp(val, "off"))
                d->taa_sparse = -1.0f;
            else
                ok = parse_float_in(opt, val, 0.0f, false, 1.0f, &d->taa_sparse, "off or a number in (0, 1]");
        }
        else if (!strcmp(opt, "--taa-neighbourhood")) {
            int k = 0;
            ok = parse_choice(opt, val, "3x3", "cross", &k);
            d->taa_neighbourhood = k ? TAA_NEIGHBOURHOOD_CROSS : TAA_NEIGHBOURHOOD_3X3;
        } else if (!strcmp(opt, "--taa-history")) {
            int k = 0;
            ok = parse_choice(opt, val, "catmull", "bilinear", &k);
            d->taa_history = k ? TAA_HISTORY_BILINEAR : TAA_HISTORY_CATMULL;
        } else if (!strcmp(opt, "--taa-nan")) {
            int k = 0;
            ok = parse_choice(opt, val, "tap", "set", &k);
            d->taa_nan = k ? TAA_NAN_SET : TAA_NAN_TAP;
        }
        else if (!strcmp(opt, "--jitter-length"))
            ok = cli_parse_int(opt, val, 1, 1024, &d->jitter_length);
        else if (!strcmp(opt, "--ring-cull")) {
            int k = 0;
            ok = parse_choice(opt, val, "on", "off", &k);
            d->no_ring_cull = k;
        }
        else if (!strcmp(opt, "--composite")) {
            int k = 0;
            ok = parse_choice(opt, val, "tiled", "per-pixel", &k);
            d->composite_per_pixel = k;
        }
        else if (!strcmp(opt, "--object-motion")) {
            int k = 0;
            ok = parse_choice(opt, val, "on", "off", &k);
            d->no_object_motion = k;
        }
        else if (!strcmp(opt, "--taa-disocclusion")) {
            int k = 0;
            ok = parse_choice(opt, val, "on", "off", &k);
            d->no_disocclusion = k;
        }
        else if (!strcmp(opt, "--modes")) {
            d->bench_mode_count = 0;
            if (!strcmp(val, "all")) {
                for (int m = ALPHA_MODE_TRADITIONAL; m < ALPHA_MODE_COUNT; m++)
                    d->bench_modes[d->bench_mode_count++] = (alpha_mode)m;
            } else {
                /* Items separated by commas; an empty list or item (`''`, `,`, `a,,b`) is an error
                 * with a message, never the default set. */
                const char *p = val;
                for (;;) {
                    const char *comma = strchr(p, ',');
                    size_t len = comma ? (size_t)(comma - p) : strlen(p);
                    char tok[32];
                    if (len == 0 || len >= sizeof tok) {
                        log_error("--modes: expected alpha modes separated by commas (modes: %s, or all), got '%s'",
                                  alpha_mode_list(), val);
                        ok = false;
                        break;
                    }
                    memcpy(tok, p, len);
                    tok[len] = '\0';
                    alpha_mode m = alpha_mode_parse(tok);
                    bool dup = false;
                    for (int k = 0; k < d->bench_mode_count; k++)
                        dup |= d->bench_modes[k] == m;
                    if (m == ALPHA_MODE_DEFAULT || dup) {
                        log_error("--modes: '%s' is %s (modes: %s, or all)", tok, dup ? "given twice" : "not a mode",
                                  alpha_mode_list());
                        ok = false;
                        break;
                    }
                    d->bench_modes[d->bench_mode_count++] = m;
                    if (!comma)
                        break;
                    p = comma + 1;
                }
            }
        } else if (!strcmp(opt, "--fade-n"))
            ok = parse_float(opt, val, 0.0f, 16.0f, &d->fade_n);
        else if (!strcmp(opt, "--alpha-lod-max")) {
            char *end;
            errno = 0;
            double x = strtod(val, &end);
            if (!strcmp(val, "off")) {
                d->alpha_lod = -1;
            } else if (errno || end == val || *end || !isfinite(x) || x < 0.0 || x > ALPHA_LOD_MAX_LIMIT) {
                log_error("--alpha-lod-max: expected a mip level in [0, %g] or off, got '%s'", ALPHA_LOD_MAX_LIMIT, val);
                ok = false;
            } else {
                d->alpha_lod = 1;
                d->alpha_lod_max = (float)x;
            }
        }
        else if (!strcmp(opt, "--hash")) {
            d->hash_kind = !strcmp(val, "pcg") ? ALPHA_HASH_PCG : !strcmp(val, "sine") ? ALPHA_HASH_SINE : -1;
            ok = d->hash_kind >= 0;
            if (!ok)
                log_error("--hash: expected pcg or sine, got '%s'", val);
        } else if (!strcmp(opt, "--format")) {
            ok = !strcmp(val, "json") || !strcmp(val, "text");
            d->json = !strcmp(val, "json");
            if (!ok)
                log_error("--format: expected text or json, got '%s'", val);
        }
        else if (!strcmp(opt, "--name")) {
            d->name = val;
            ok = *val && !strchr(val, '/');
            if (!ok)
                log_error("--name: expected a file prefix without '/', got '%s'", val);
        } else if (!strcmp(opt, "--frames"))
            ok = cli_parse_int(opt, val, 1, MAX_FRAMES, &d->frames);
        else if (!strcmp(opt, "--warmup"))
            ok = cli_parse_int(opt, val, 0, 10000, &d->warmup), d->warmup_set = true;
        else if (!strcmp(opt, "--first-frame"))
            ok = cli_parse_int(opt, val, 0, MAX_FRAMES - 1, &d->first_frame);
        else if (!strcmp(opt, "--width"))
            ok = cli_parse_int(opt, val, 16, MAX_DISPLAY_SIZE, &d->width);
        else if (!strcmp(opt, "--height"))
            ok = cli_parse_int(opt, val, 16, MAX_DISPLAY_SIZE, &d->height);
        else if (!strcmp(opt, "--gpu"))
            ok = cli_parse_int(opt, val, 0, 15, &d->gpu);
        else if (!strcmp(opt, "--fps"))
            ok = parse_float_in(opt, val, FPS_MIN, true, FPS_MAX, &d->fps, NULL);
        else if (!strcmp(opt, "--alpha")) {
            d->alpha = alpha_mode_parse(val);
            ok = d->alpha != ALPHA_MODE_DEFAULT;
            if (!ok)
                log_error("--alpha: unknown mode '%s' (modes: %s)", val, alpha_mode_list());
        } else if (!strcmp(opt, "--compression")) {
            if (!strcmp(val, "zip"))
                d->compression = EXR_COMPRESS_ZIP;
            else if (!strcmp(val, "none"))
                d->compression = EXR_COMPRESS_NONE;
            else if (!strcmp(val, "piz"))
                d->compression = EXR_COMPRESS_PIZ;
            else {
                log_error("--compression: expected zip, none or piz, got '%s'", val);
                ok = false;
            }
        }
        if (!ok)
            return FS_ERR_USAGE;
    }
    if (d->scene_path && d->builtin) {
        log_error("--scene and --builtin: give one of them, not both");
        return FS_ERR_USAGE;
    }
    if (d->cmd == CMD_DEMO && (d->scene_path || d->builtin)) {
        log_error("fovsim demo always renders the built-in forest; use fovsim render --scene/--builtin for others");
        return FS_ERR_USAGE;
    }
    if ((d->width > 0) != (d->height > 0)) {
        log_error("--width and --height: give both or neither");
        return FS_ERR_USAGE;
    }
    if (d->no_fade && d->fade_n > 0.0f) {
        log_error("--no-fade and --fade-n: give one of them, not both");
        return FS_ERR_USAGE;
    }
    if (d->bench_mode_count > 0 && d->cmd != CMD_BENCH && d->cmd != CMD_COMPARE && d->cmd != CMD_DEMO) {
        log_error("--modes is an option of fovsim bench, compare and demo (render and plan take --alpha)");
        return FS_ERR_USAGE;
    }
    if (d->acc_error_set && !(d->cmd == CMD_BENCH && d->accuracy)) {
        log_error("--error is an option of fovsim bench --accuracy");
        return FS_ERR_USAGE;
    }
    if ((d->export_fvvdp || d->run_fvvdp) && d->cmd != CMD_COMPARE && d->cmd != CMD_DEMO) {
        log_error("--export-fvvdp and --fvvdp are options of fovsim compare and demo");
        return FS_ERR_USAGE;
    }
    d->export_fvvdp |= d->run_fvvdp; /* running it needs its inputs */
    bool uses_reference = d->cmd == CMD_REFERENCE || d->cmd == CMD_COMPARE || d->cmd == CMD_DEMO ||
                          (d->cmd == CMD_BENCH && d->accuracy);
    if ((d->supersample || d->samples || d->reference_set || d->ref_memory_mb || d->cache_dir || d->no_cache) &&
        !uses_reference) {
        log_error("--reference, --supersample, --samples, --ref-memory, --cache and --no-cache shape the reference: "
                  "options of fovsim reference, compare, demo and bench --accuracy");
        return FS_ERR_USAGE;
    }
    if (d->cache_dir && d->no_cache) {
        log_error("--cache and --no-cache: give one of them, not both");
        return FS_ERR_USAGE;
    }
    if (d->accuracy && d->cmd != CMD_BENCH) {
        log_error("--accuracy is an option of fovsim bench");
        return FS_ERR_USAGE;
    }
    if (d->alpha != ALPHA_MODE_DEFAULT && (d->cmd == CMD_REFERENCE || d->cmd == CMD_COMPARE)) {
        log_error("fovsim %s: --alpha does not apply (%s)", c,
                  d->cmd == CMD_REFERENCE ? "the reference tests alpha stochastically" : "give the modes with --modes");
        return FS_ERR_USAGE;
    }
    if (d->json && d->cmd != CMD_BENCH) {
        log_error("--format is an option of fovsim bench");
        return FS_ERR_USAGE;
    }
    if ((d->gaze_format != GAZE_FORMAT_AUTO || d->eye != GAZE_EYE_AUTO) && !d->gaze_path) {
        log_error("--gaze-format and --eye describe a --gaze trace; give --gaze FILE");
        return FS_ERR_USAGE;
    }
    if ((d->script || d->record || d->split[0]) && d->cmd != CMD_VIEW) {
        log_error("--script, --record and --split are options of fovsim view");
        return FS_ERR_USAGE;
    }
    if (d->cmd == CMD_VIEW && (d->frames || d->out_dir || d->name || d->gpu >= 0)) {
        log_error("fovsim view runs until it is closed, captures next to --record and draws on the X server's GPU: "
                  "--frames, --out, --name and --gpu are options of render");
        return FS_ERR_USAGE;
    }
    if (d->split[0] && d->alpha) {
        log_error("--split and --alpha: give one of them, not both (--split A,B sets the left-hand mode)");
        return FS_ERR_USAGE;
    }
    if ((d->resume || d->replace || d->wait_lock) && d->cmd != CMD_RENDER && d->cmd != CMD_REFERENCE &&
        d->cmd != CMD_COMPARE && d->cmd != CMD_DEMO) {
        log_error("--resume, --replace and --wait-lock are options of fovsim render, reference, compare and demo");
        return FS_ERR_USAGE;
    }
    if (d->first_frame && d->cmd != CMD_COMPARE) {
        log_error("--first-frame is an option of fovsim compare (a chunk of a longer sequence, as fovsim sweep "
                  "--chunk-frames runs it)");
        return FS_ERR_USAGE;
    }
    if (d->warmup_set && d->cmd != CMD_BENCH && !(d->cmd == CMD_COMPARE && d->first_frame)) {
        log_error("--warmup is an option of fovsim bench, and of compare with --first-frame");
        return FS_ERR_USAGE;
    }
    if (d->first_frame && d->frames && d->first_frame >= d->frames) {
        log_error("--first-frame %d: expected less than --frames %d", d->first_frame, d->frames);
        return FS_ERR_USAGE;
    }
    if (d->resume && d->replace) {
        log_error("--resume and --replace: give one of them, not both (--resume keeps the folder's frames, --replace "
                  "removes them)");
        return FS_ERR_USAGE;
    }
    if (d->quiet && d->verbose) {
        log_error("--quiet and --verbose: give one of them, not both");
        return FS_ERR_USAGE;
    }
    if (!d->builtin && !d->scene_path)
        d->builtin = "forest";
    if (!d->name)
        d->name = d->cmd == CMD_REFERENCE ? "reference" : d->cmd == CMD_COMPARE || d->cmd == CMD_DEMO ? "compare" : "frame";
    /* Output paths that cannot be written fail here, not after the frames are drawn (issue 17). */
    char why[512];
    if (!out_path_check(d->out_dir, d->name, d->cache_dir, why, sizeof why)) {
        log_error("%s", why);
        return FS_ERR_USAGE;
    }
    return FS_OK;
}
