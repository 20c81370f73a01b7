/* cli_options.c: every option of the drawing commands in one table (cli_internal.h): its name,
 * value and range, the commands it applies to, its help, the run_desc field it sets, whether the
 * run record holds it and whether it belongs to the machine. cli.c parses with it, cli_help.c
 * prints --help from it, run_record.c and fovsim check classify options by its flags.
 * The table's order is the order of --help. docs/design-notes.md, "The command line from one table". */
#include "cli/cli_internal.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/config.h"
#include "core/log.h"
#include "fov/fov_ring.h"
#include "fov/vrs_map.h"

/* >>setters: the options a range or a list of names does not describe */

static bool set_builtin(const cli_option *o, run_desc *d, const char *v)
{
    (void)o;
    d->builtin = !strncmp(v, "builtin:", 8) ? v + 8 : v; /* as fovsim prints a built-in scene's path */
    return true;
}

static bool set_name(const cli_option *o, run_desc *d, const char *v)
{
    (void)o;
    d->name = v;
    if (*v && !strchr(v, '/'))
        return true;
    log_error("--name: expected a file prefix without '/', got '%s'", v);
    return false;
}

static bool set_asset_root(const cli_option *o, run_desc *d, const char *v)
{
    (void)o;
    d->asset_root = v;
    if (*v)
        return true;
    log_error("--asset-root: expected a folder, got ''");
    return false;
}

static bool set_alpha(const cli_option *o, run_desc *d, const char *v)
{
    (void)o;
    d->alpha = alpha_mode_parse(v);
    if (d->alpha != ALPHA_MODE_DEFAULT)
        return true;
    log_error("--alpha: unknown mode '%s' (modes: %s)", v, alpha_mode_list());
    return false;
}

static bool set_alpha_lod_max(const cli_option *o, run_desc *d, const char *v)
{
    (void)o;
    char *end;
    errno = 0;
    double x = strtod(v, &end);
    if (!strcmp(v, "off")) {
        d->alpha_lod = ALPHA_LOD_CLAMP_OFF;
        return true;
    }
    if (errno || end == v || *end || !isfinite(x) || x < 0.0 || x > ALPHA_LOD_MAX_LIMIT) {
        log_error("--alpha-lod-max: expected a mip level in [0, %g] or off, got '%s'", ALPHA_LOD_MAX_LIMIT, v);
        return false;
    }
    d->alpha_lod = ALPHA_LOD_CLAMP_LEVEL;
    d->alpha_lod_max = (float)x;
    return true;
}

static bool set_taa_sparse(const cli_option *o, run_desc *d, const char *v)
{
    if (!strcmp(v, "off")) {
        d->taa.sparse = -1.0f;
        return true;
    }
    return cli_parse_float_in(o->name, v, 0.0f, false, 1.0f, &d->taa.sparse, "off or a number in (0, 1]");
}

/* The layout parsed once, here; "auto" and "aggressive" (kinds FOV_LAYOUT_AUTO, _AGGRESSIVE) are
 * resolved against the display of the run's scene (session.c). */
static bool set_rings(const cli_option *o, run_desc *d, const char *v)
{
    char err[256];
    const display_desc any = {.width = 1280, .height = 720, .hfov_deg = 90.0f}; /* only the named layouts read it; their rings are redone */
    d->rings = v;
    if (fov_layout_parse(v, &any, &d->rings_layout, err, sizeof err) == FS_OK)
        return true;
    log_error("%s: %s", o->name, err);
    return false;
}

/* The rate map parsed once, here (vrs_map.h). */
static bool set_vrs(const cli_option *o, run_desc *d, const char *v)
{
    char err[256];
    d->vrs = v;
    if (vrs_spec_parse(v, &d->vrs_spec, err, sizeof err) == FS_OK)
        return true;
    log_error("%s: %s", o->name, err);
    return false;
}

/* --display: planar (the scene's planar display, whatever kind the scene gives) or an hmd, parsed
 * once here (hmd.h). */
static bool set_display(const cli_option *o, run_desc *d, const char *v)
{
    char err[320];
    d->display = v;
    if (!strcmp(v, "planar")) {
        d->display_kind = DISPLAY_PLANAR;
        return true;
    }
    d->display_kind = DISPLAY_HMD;
    if (hmd_parse(v, &d->display_hmd, err, sizeof err))
        return true;
    log_error("%s: %s", o->name, err);
    return false;
}

static bool set_samples(const cli_option *o, run_desc *d, const char *v)
{
    if (!cli_parse_int(o->name, v, 2, 4096, &d->ref.samples))
        return false;
    if (d->ref.samples % 2 == 0)
        return true;
    log_error("--samples: expected an even number (the two halves estimate convergence), got %d", d->ref.samples);
    return false;
}

static bool set_gaze_format(const cli_option *o, run_desc *d, const char *v)
{
    (void)o;
    d->gaze_format = gaze_format_parse(v);
    if (d->gaze_format != GAZE_FORMAT_AUTO)
        return true;
    log_error("--gaze-format: expected csv, pupil, eyelink, tobii or eyenav, got '%s'", v);
    return false;
}

/* --gaze-latency MS, or for compare and demo a list MS,MS,... (a latency study: every latency drawn
 * into a folder of its own, latency.csv across them; docs/latency.md). The first is the tracker's. */
/* The comma-separated item at *p into item (cap bytes), *p moved past it and its comma; false for
 * an empty item or one too long. *more: another item follows. */
static bool list_item(const char **p, char *item, size_t cap, bool *more)
{
    size_t n = strcspn(*p, ",");
    bool ok = n > 0 && n < cap;
    if (ok) {
        memcpy(item, *p, n);
        item[n] = '\0';
    }
    *more = (*p)[n] == ',';
    *p += n + *more;
    return ok;
}

static bool set_gaze_latency(const cli_option *o, run_desc *d, const char *v)
{
    d->gaze_latency_count = 0;
    bool more = true;
    for (const char *p = v; more;) {
        char item[64];
        float ms;
        if (!list_item(&p, item, sizeof item, &more) || d->gaze_latency_count == MAX_GAZE_LATENCIES) {
            log_error("%s: expected a latency in ms or up to %d of them separated by commas, got '%s'", o->name,
                      MAX_GAZE_LATENCIES, v);
            return false;
        }
        if (!cli_parse_float_in(o->name, item, 0.0f, true, (float)GAZE_TRACKER_MAX_LATENCY_MS, &ms, NULL))
            return false;
        for (int i = 0; i < d->gaze_latency_count; i++)
            if (d->gaze_latencies[i] == ms) {
                log_error("%s: latency %g ms given twice in '%s'", o->name, (double)ms, v);
                return false;
            }
        d->gaze_latencies[d->gaze_latency_count++] = ms;
    }
    d->tracker.desc.latency_ms = d->gaze_latencies[0];
    d->tracker.latency_set = true;
    return true;
}

/* --foveation KIND, or for compare a list of distinct kinds (a foveation study: each drawn into a
 * folder of its own, the modes side by side across them; docs/foveation.md). The first is the run's. */
static bool set_foveation(const cli_option *o, run_desc *d, const char *v)
{
    d->foveation_count = 0;
    bool more = true;
    for (const char *p = v; more;) {
        char item[16];
        foveation_kind k = FOVEATION_UNSET;
        if (!list_item(&p, item, sizeof item, &more) || !foveation_kind_parse(item, &k) || k == FOVEATION_UNSET) {
            log_error("%s: expected rings, vrs or off, or for compare a list of them separated by commas, got '%s'",
                      o->name, v);
            return false;
        }
        for (int i = 0; i < d->foveation_count; i++)
            if (d->foveations[i] == k) {
                log_error("%s: '%s' given twice in '%s'", o->name, item, v);
                return false;
            }
        d->foveations[d->foveation_count++] = k;
    }
    d->foveation = d->foveations[0];
    return true;
}

/* --head-place X,Y,Z[,YAW_DEG[,SCALE]] (docs/hmd.md "Placement"). */
static bool set_head_place(const cli_option *o, run_desc *d, const char *v)
{
    double x[5] = {0, 0, 0, 0, 1};
    int n = 0;
    bool ok = true;
    for (const char *p = v; ok; n++) {
        char *end;
        double t = strtod(p, &end);
        ok = n < 5 && end != p && isfinite(t) && fabs(t) <= 1e7 && (*end == ',' || *end == '\0');
        if (ok)
            x[n] = t;
        if (!ok || *end == '\0')
            break;
        p = end + 1;
    }
    if (!ok || n < 2 || !(x[4] > 0)) { /* n: the index of the last value read */
        log_error("%s: expected X,Y,Z[,YAW_DEG[,SCALE]] (scene units, degrees, scene units per metre > 0), got '%s'",
                  o->name, v);
        return false;
    }
    d->head_place = (pose_place){{x[0], x[1], x[2]}, x[3], x[4]};
    d->head_place_set = true;
    return true;
}

static bool set_gaze_screen(const cli_option *o, run_desc *d, const char *v)
{
    char err[256];
    if (gaze_screen_parse(v, &d->place.desc.screen, err, sizeof err))
        return true;
    log_error("%s: %s", o->name, err);
    return false;
}

static bool set_split(const cli_option *o, run_desc *d, const char *v)
{
    (void)o;
    char a[64], b[64];
    const char *comma = strchr(v, ',');
    snprintf(a, sizeof a, "%.*s", comma ? (int)(comma - v) : (int)strlen(v), v);
    snprintf(b, sizeof b, "%s", comma ? comma + 1 : "");
    d->view.split[0] = alpha_mode_parse(a);
    d->view.split[1] = alpha_mode_parse(b);
    if (d->view.split[0] != ALPHA_MODE_DEFAULT && d->view.split[1] != ALPHA_MODE_DEFAULT &&
        d->view.split[0] != d->view.split[1])
        return true;
    log_error("--split: expected two different alpha modes A,B (modes: %s), got '%s'", alpha_mode_list(), v);
    return false;
}

/* Items separated by commas, or all; an empty list or item (`''`, `,`, `a,,b`) is an error with a
 * message, never the default set. */
static bool set_modes(const cli_option *o, run_desc *d, const char *v)
{
    (void)o;
    d->bench_mode_count = 0;
    if (!strcmp(v, "all")) {
        for (int m = ALPHA_MODE_TRADITIONAL; m < ALPHA_MODE_COUNT; m++)
            d->bench_modes[d->bench_mode_count++] = (alpha_mode)m;
        return true;
    }
    for (const char *p = v;;) {
        const char *comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        char tok[32];
        if (len == 0 || len >= sizeof tok) {
            log_error("--modes: expected alpha modes separated by commas (modes: %s, or all), got '%s'",
                      alpha_mode_list(), v);
            return false;
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
            return false;
        }
        d->bench_modes[d->bench_mode_count++] = m;
        if (!comma)
            return true;
        p = comma + 1;
    }
}

/* >>names of the choices */

static const cli_choice k_on_off[] = {{"on", 1}, {"off", 0}, {NULL, 0}};
static const cli_choice k_off_on[] = {{"on", 0}, {"off", 1}, {NULL, 0}}; /* sets a no_... field */
static const cli_choice k_hash[] = {{"pcg", HASH_CHOICE_PCG}, {"sine", HASH_CHOICE_SINE}, {NULL, 0}};
static const cli_choice k_neighbourhood[] = {{"3x3", TAA_NEIGHBOURHOOD_3X3}, {"cross", TAA_NEIGHBOURHOOD_CROSS},
                                             {NULL, 0}};
static const cli_choice k_history[] = {{"catmull", TAA_HISTORY_CATMULL}, {"bilinear", TAA_HISTORY_BILINEAR},
                                       {NULL, 0}};
static const cli_choice k_nan[] = {{"tap", TAA_NAN_TAP}, {"set", TAA_NAN_SET}, {NULL, 0}};
static const cli_choice k_composite[] = {{"tiled", 0}, {"per-pixel", 1}, {NULL, 0}};
static const cli_choice k_eye[] = {{"left", GAZE_EYE_LEFT}, {"right", GAZE_EYE_RIGHT}, {"average", GAZE_EYE_AVERAGE},
                                   {NULL, 0}};
static const cli_choice k_gaze_loss[] = {{"hold", GAZE_LOSS_HOLD}, {"centre", GAZE_LOSS_CENTRE},
                                         {"full", GAZE_LOSS_FULL}, {NULL, 0}};
static const cli_choice k_gaze_map[] = {{"angle", GAZE_MAP_ANGLE}, {"normalized", GAZE_MAP_NORMALIZED}, {NULL, 0}};
static const cli_choice k_compression[] = {{"zip", EXR_COMPRESS_ZIP}, {"none", EXR_COMPRESS_NONE},
                                           {"piz", EXR_COMPRESS_PIZ}, {NULL, 0}};
static const cli_choice k_reference[] = {{"exact", REFERENCE_EXACT}, {"stochastic", REFERENCE_STOCHASTIC}, {NULL, 0}};
static const cli_choice k_error[] = {{"flip", ACC_ERROR_FLIP}, {"alpha_rmse", ACC_ERROR_ALPHA_RMSE},
                                     {"rmse", ACC_ERROR_RMSE}, {"temporal_error", ACC_ERROR_TEMPORAL}, {NULL, 0}};
static const cli_choice k_cost[] = {{"time", ACC_COST_TIME}, {"model", ACC_COST_MODEL}, {"work", ACC_COST_WORK},
                                    {NULL, 0}};
static const cli_choice k_vrs_tile[] = {{"8", 8}, {"16", 16}, {"32", 32}, {NULL, 0}};
static const cli_choice k_format[] = {{"text", 0}, {"json", 1}, {NULL, 0}};

/* >>the table */

#define FIELD(m) .field = offsetof(run_desc, m), .size = sizeof(((run_desc *)0)->m)
#define GIVEN(m) .given = offsetof(run_desc, m)

/* Where an option is refused, the line that says where it belongs; options that share one line
 * share the message. */
#define NOT_IN_VIEW "fovsim view runs until it is closed, captures next to --record and draws on the X server's " \
                    "GPU: --frames, --out, --name and --gpu are options of render"
#define ONLY_REFERENCE "--reference, --supersample, --samples, --ref-memory, --cache and --no-cache shape the " \
                       "reference: options of fovsim reference, compare, demo and bench --accuracy"
#define ONLY_RUN_FOLDER "--resume, --replace and --wait-lock are options of fovsim render, reference, compare and demo"
#define ONLY_FVVDP "--export-fvvdp and --fvvdp are options of fovsim compare and demo"
#define ONLY_VIEW "--script, --record and --split are options of fovsim view"
#define ALL_BUT_VIEW (CMDS_DRAWING & ~ON(CMD_VIEW))
#define HEAD_ONLY "--head and --head-place: a recording's head motion is replayed by render, compare, demo and bench --accuracy"
#define CMDS_PROGRESS (ALL_BUT_VIEW & ~ON(CMD_PLAN)) /* those with a progress line */

const cli_option k_cli_options[] = {
    /* what to draw */
    {"--scene", ARG_STRING, CMDS_DRAWING, "FILE", "scene JSON, or a .gltf/.glb asset to view on its own",
     FIELD(scene_path)},
    {"--builtin", ARG_CUSTOM, CMDS_DRAWING, "NAME", "built-in scene: {builtins} (default forest)", FIELD(builtin),
     .set = set_builtin},
    {"--frames", ARG_INT, ALL_BUT_VIEW & ~(ON(CMD_BENCH) | CTX_BENCH_ACCURACY), "N",
     "frames to draw (default: the camera path at --fps)", FIELD(frames), .lo = 1, .hi = MAX_FRAMES,
     .misuse = NOT_IN_VIEW},
    {"--frames", ARG_INT, ON(CMD_BENCH) | CTX_BENCH_ACCURACY, "N",
     "frames to measure, spread over the camera path (default 30;\nbench --accuracy: 12)", .flags = OPT_HELP_ONLY},
    {"--fps", ARG_FLOAT, CMDS_DRAWING, "F", "frames per second of the sequence, 0.001 to 1000 (default 24)",
     FIELD(fps), .lo = FPS_MIN, .hi = FPS_MAX, .flags = OPT_LO_CLOSED | OPT_RECORDED},
    {"--width", ARG_INT, CMDS_DRAWING & ~ON(CMD_DEMO), "W, --height H",
     "output size in pixels (default: the scene's display, 1280x720)", FIELD(width), .lo = 16,
     .hi = MAX_DISPLAY_SIZE, .flags = OPT_RECORDED},
    {"--width", ARG_INT, ON(CMD_DEMO), "W, --height H", "output size in pixels (default 640x360)", .flags = OPT_HELP_ONLY},
    {"--height", ARG_INT, CMDS_DRAWING, "H", NULL /* with --width */, FIELD(height), .lo = 16,
     .hi = MAX_DISPLAY_SIZE, .flags = OPT_RECORDED},
    {"--display", ARG_CUSTOM, CMDS_DRAWING, "SPEC",
     "planar (the scene's size and field of view) or a head-mounted\n"
     "display, hmd:PRESET[,KEY=VALUE...]: presets quest-pro, eyenavgs,\n"
     "custom; keys width, height, ipd (mm), hz, fov-left, fov-right\n"
     "(degrees L/R/U/D); only fovsim plan shows an hmd yet (docs/hmd.md)",
     FIELD(display), .set = set_display, .flags = OPT_RECORDED},
    /* the alpha test */
    {"--alpha", ARG_CUSTOM, CMDS_DRAWING, "MODE", "alpha test for MASK materials: {modes}", FIELD(alpha),
     .set = set_alpha, .flags = OPT_RECORDED},
    {"--hash-scale", ARG_FLOAT, CMDS_DRAWING, "S",
     "hashed modes: noise scale in pixels (default 1; the paper suggests\n0.3-0.5 with TAA, docs/hashed-alpha.md)",
     FIELD(hash_scale), .lo = 0, .hi = 64, .flags = OPT_RECORDED},
    {"--hash", ARG_CHOICE, CMDS_DRAWING, "H",
     "hashed modes: pcg (integer pcg3d, default) or sine (the paper's; not\nuniform on flat cards, "
     "docs/hashed-alpha.md)", FIELD(hash_kind), .choices = k_hash, .flags = OPT_RECORDED},
    {"--hash-aniso", ARG_FLAG, CMDS_DRAWING, NULL, "hashed modes: anisotropic (per-axis) pixel-scale noise",
     FIELD(hash_aniso), .flags = OPT_RECORDED},
    {"--fade-n", ARG_FLOAT, CMDS_DRAWING, "N",
     "hashed: mip levels over which noise fades in (default 6; earlier for\ntextures the traditional test erodes "
     "sooner)", FIELD(fade_n), .lo = 0, .hi = 16, .flags = OPT_RECORDED},
    {"--no-fade", ARG_FLAG, CMDS_DRAWING, NULL, "hashed: no fade-in, noise at every distance", FIELD(no_fade),
     .flags = OPT_RECORDED},
    {"--no-hash-offset", ARG_FLAG, CMDS_DRAWING, NULL,
     "hashed with TAA: thresholds stay put instead of moving by a\ngolden-ratio offset each frame "
     "(docs/hashed-alpha.md)", FIELD(no_hash_offset), .flags = OPT_RECORDED},
    {"--a2c-sharpen", ARG_FLAG, CMDS_DRAWING, NULL, "a2c: mip-level alpha scaling and fwidth sharpening (Golus)",
     FIELD(a2c_sharpen), .flags = OPT_RECORDED},
    {"--alpha-lod-max", ARG_CUSTOM, CMDS_DRAWING, "N|off",
     "alpha-tested materials read alpha at most at mip level N (0-16;\ncolour keeps the whole chain), unless a "
     "material sets its own\n\"alpha_lod_max\"; off: no clamp, the scene's neither (atlases seen\nfrom afar, "
     "docs/hashed-alpha.md \"Alpha LOD clamp\"; default none)", FIELD(alpha_lod), .set = set_alpha_lod_max,
     .flags = OPT_RECORDED},
    /* temporal antialiasing */
    {"--taa", ARG_CHOICE, CMDS_DRAWING, "on|off", "temporal antialiasing per ring (default on for more than one frame)",
     FIELD(taa.mode), .choices = k_on_off, .flags = OPT_RECORDED},
    {"--taa-blend", ARG_FLOAT, CMDS_DRAWING, "W", "weight of the current frame in the history (default 0.1)",
     FIELD(taa.blend), .lo = 0, .hi = 1, .flags = OPT_RECORDED},
    {"--taa-gamma", ARG_FLOAT, CMDS_DRAWING, "G", "history clipping box, in standard deviations (default 1)",
     FIELD(taa.gamma), .lo = 0, .hi = 16, .flags = OPT_RECORDED},
    {"--taa-sparse", ARG_CUSTOM, CMDS_DRAWING, "S|off",
     "how far the history's coverage may stay from each pixel's own\nsample: 1 - alpha of a one-sample test "
     "(docs/taa.md \"Sparse\ncoverage\"; default 0.95); off clamps it to the neighbourhood's range",
     FIELD(taa.sparse), .set = set_taa_sparse, .flags = OPT_RECORDED},
    {"--taa-disocclusion", ARG_CHOICE, CMDS_DRAWING, "on|off",
     "drop history whose nearest surface moved off the pixel\n(depth; default on; off to measure what it buys)",
     FIELD(taa.no_disocclusion), .choices = k_off_on, .flags = OPT_RECORDED},
    {"--taa-neighbourhood", ARG_CHOICE, CMDS_DRAWING, "3x3|cross",
     "taps of the history clipping box (docs/taa.md; default cross)", FIELD(taa.neighbourhood),
     .choices = k_neighbourhood, .flags = OPT_RECORDED},
    {"--taa-history", ARG_CHOICE, CMDS_DRAWING, "catmull|bilinear",
     "history fetch: 5-tap Catmull-Rom or one bilinear tap\n(default catmull)", FIELD(taa.history),
     .choices = k_history, .flags = OPT_RECORDED},
    {"--taa-nan", ARG_CHOICE, CMDS_DRAWING, "tap|set",
     "NaN/Inf checked per fetched tap or once per set of fetches (default tap)", FIELD(taa.nan), .choices = k_nan,
     .flags = OPT_RECORDED},
    {"--jitter-length", ARG_INT, CMDS_DRAWING, "N", "Halton (2,3) jitter period in frames (default 16)",
     FIELD(taa.jitter_length), .lo = 1, .hi = 1024, .flags = OPT_RECORDED},
    {"--object-motion", ARG_CHOICE, CMDS_DRAWING, "on|off",
     "TAA follows swaying instances' own motion (default on; off\nreprojects them as if still, to measure what it "
     "buys)", FIELD(taa.no_object_motion), .choices = k_off_on, .flags = OPT_RECORDED},
    /* foveation */
    {"--ring-cull", ARG_CHOICE, CMDS_DRAWING, "on|off",
     "rings skip instances that lie wholly where the finer ring is shown\nalone (default on; off draws them, to "
     "measure what it saves)", FIELD(no_ring_cull), .choices = k_off_on, .flags = OPT_RECORDED},
    {"--composite", ARG_CHOICE, CMDS_DRAWING, "tiled|per-pixel",
     "how the rings reach the display: tiled (default) draws\nthe tiles inside one ring without searching it per "
     "pixel; per-pixel\nsearches everywhere (same image, to measure what tiling saves)", FIELD(composite_per_pixel),
     .choices = k_composite, .flags = OPT_RECORDED},
    {"--rings", ARG_CUSTOM, CMDS_DRAWING, "SPEC",
     "foveation rings: auto (acuity model, default), aggressive (twice the MAR\nslope, +0.5 mip bias in reduced "
     "rings), off, or innermost first\nOUTER:SCALE:MIPBIAS,... with * for the last, e.g. 10:1:0,25:1/2:0,*:1/4:0.5", FIELD(rings), .set = set_rings, .flags = OPT_RECORDED},
    {"--foveation", ARG_CUSTOM, CMDS_DRAWING, "rings|vrs|off",
     "how to foveate: rings (default; --rings), vrs (variable-rate shading:\none pass at full resolution, a shading rate "
     "per tile, coarse shading\nemulated; render, compare, plan and bench --accuracy take it) or\noff (--rings off); "
     "compare takes a list, e.g. rings,vrs,off: the modes\nunder each side by side (foveation.csv)", FIELD(foveation),
     .set = set_foveation, .flags = OPT_RECORDED},
    {"--vrs", ARG_CUSTOM, CMDS_DRAWING, "SPEC",
     "VRS rate map: auto (acuity model, default) or innermost first\nOUTER:RATE,... with * for the last, rates 1x1, "
     "1x2, 2x1, 2x2, 2x4, 4x2,\n4x4, e.g. 10:1x1,25:2x2,*:4x4", FIELD(vrs), .set = set_vrs, .flags = OPT_RECORDED},
    {"--vrs-tile", ARG_CHOICE, CMDS_DRAWING, "8|16|32", "VRS tile size in pixels, one rate per tile (default 16)",
     FIELD(vrs_tile), .choices = k_vrs_tile, .flags = OPT_RECORDED},
    {"--ring-lod", ARG_STRING /* checked against the ring layout once the scene is known */, CMDS_DRAWING, "SPEC",
     "stochastic simplification of MASK foliage per ring (docs/ring-lod.md):\noff (default); simplify: in reduced "
     "rings each card keeps u = its area\nin ring pixels (at least 1/16), the kept ones enlarged to keep the\n"
     "covered area; simplify:area=A the same from A ring pixels; or\nsimplify:U1,... one keep fraction per ring, "
     "e.g. simplify:1,1,1/4,1/16", FIELD(ring_lod), .flags = OPT_RECORDED},
    /* gaze */
    {"--gaze", ARG_STRING, CMDS_DRAWING, "FILE",
     "gaze trace: fovsim CSV, Pupil Labs gaze_positions.csv, EyeLink .asc or\nTobii livedata.json, or "
     "builtin:NAME for a scripted trace in\ngaze_paths/ (default: fixation at the display centre; the demo\nuses "
     "builtin:demo_tour)", FIELD(gaze_path)},
    {"--gaze-format", ARG_CUSTOM, CMDS_DRAWING, "F", "csv, pupil, eyelink, tobii or eyenav (default: detected from the content)",
     FIELD(gaze_format), .set = set_gaze_format, .flags = OPT_RECORDED},
    {"--eye", ARG_CHOICE, CMDS_DRAWING, "E",
     "binocular traces: left, right or average (default: average of valid eyes)", FIELD(eye), .choices = k_eye,
     .flags = OPT_RECORDED},
    {"--gaze-map", ARG_CHOICE, CMDS_DRAWING, "M",
     "place the trace by angle (the recording's straight-ahead point at the\ndisplay centre, each sample at its visual "
     "angle; default) or by\nnormalized position (the recording's frame stretched onto the display)",
     FIELD(place.desc.map), .choices = k_gaze_map, GIVEN(place.map_set), .flags = OPT_RECORDED},
    {"--head", ARG_STRING, CMDS_HEAD, "FILE|off",
     "a VR recording's head motion replaces the scene's camera path (EyeNavGS\nCSV; default: the --gaze recording's "
     "when it has head poses; off: the\nscene's camera) (docs/hmd.md)", FIELD(head_path), .flags = OPT_RECORDED,
     .misuse = HEAD_ONLY},
    {"--head-place", ARG_CUSTOM, CMDS_HEAD, "X,Y,Z[,YAW[,S]]",
     "where the recording's world goes in the scene: its start position at\nX,Y,Z, turned YAW degrees about +y, S "
     "scene units per metre (default:\nthe recording's start on the scene camera's, facing its way)",
     FIELD(head_place), .set = set_head_place, GIVEN(head_place_set), .flags = OPT_RECORDED, .misuse = HEAD_ONLY},
    {"--gaze-screen", ARG_CUSTOM, CMDS_DRAWING, "S",
     "the recording's geometry, instead of the file's: W_MMxH_MM@DIST_MM (a\nscreen seen from DIST_MM, e.g. "
     "520x290@600) or HxVdeg (a camera's\nfield of view, e.g. 82x52deg) (docs/gaze-formats.md)",
     FIELD(place.desc.screen), .set = set_gaze_screen, GIVEN(place.screen_set), .flags = OPT_RECORDED},
    {"--gaze-latency", ARG_CUSTOM, CMDS_DRAWING, "MS",
     "eye tracker: frame t is rendered around the gaze the system had at\nt - MS (0 to 10000; default 0); metrics "
     "use the true gaze at t.\ncompare, demo: a list MS,MS,... is a latency study: each latency in\nOUT/latency-MS/, "
     "latency.csv and latency.png across them\n(docs/latency.md)", FIELD(tracker.desc.latency_ms),
     .set = set_gaze_latency, .flags = OPT_RECORDED},
    {"--gaze-rate", ARG_FLOAT, CMDS_DRAWING, "HZ",
     "eye tracker: samples at HZ from the trace start, held between them\n(default 0: the trace's own samples, "
     "interpolated)", FIELD(tracker.desc.rate_hz), .lo = 0, .hi = GAZE_TRACKER_MAX_RATE_HZ,
     GIVEN(tracker.rate_set), .flags = OPT_LO_CLOSED | OPT_RECORDED},
    {"--gaze-noise", ARG_FLOAT, CMDS_DRAWING, "DEG",
     "eye tracker: Gaussian noise per axis and tracker sample, standard\ndeviation DEG degrees of visual angle "
     "(0 to 30; default 0)", FIELD(tracker.desc.noise_deg), .lo = 0, .hi = GAZE_TRACKER_MAX_NOISE_DEG,
     GIVEN(tracker.noise_set), .flags = OPT_LO_CLOSED | OPT_RECORDED},
    {"--gaze-seed", ARG_INT, CMDS_DRAWING, "N",
     "seed of --gaze-noise (default 0): the same seed gives the same noise\nat any frame rate",
     FIELD(tracker.desc.seed), .lo = 0, .hi = 2147483647, GIVEN(tracker.seed_set), .flags = OPT_RECORDED},
    {"--gaze-loss", ARG_CHOICE, CMDS_DRAWING, "P",
     "eye tracker, lost samples and blinks: hold (the last good sample,\ndefault), centre (the display centre) or "
     "full (the frame drawn at\nfull resolution until the track returns)", FIELD(tracker.desc.loss), .choices = k_gaze_loss,
     GIVEN(tracker.loss_set), .flags = OPT_RECORDED},
    /* output */
    {"--overlay", ARG_FLAG, CMDS_DRAWING, NULL, "draw ring borders and the gaze marker into the frames (compare:\ninto the measured images; the grid's "
     "annotation is the clean way)",
     FIELD(overlay), .flags = OPT_RECORDED},
    {"--debug-channels", ARG_FLAG, CMDS_DRAWING, NULL, "add ring.id and eccentricity (degrees) channels to the EXR",
     FIELD(debug_channels), .flags = OPT_RECORDED},
    {"--out", ARG_STRING, ALL_BUT_VIEW, "DIR", "output directory (default out/<command>)", FIELD(out_dir),
     .misuse = NOT_IN_VIEW},
    {"--name", ARG_CUSTOM, ALL_BUT_VIEW, "NAME", "file prefix (default frame)", FIELD(name), .set = set_name,
     .flags = OPT_RECORDED, .misuse = NOT_IN_VIEW},
    {"--compression", ARG_CHOICE, CMDS_DRAWING, "C", "zip (default; demo: piz), none or piz", FIELD(compression),
     .choices = k_compression, GIVEN(compression_set), .flags = OPT_RECORDED},
    {"--resume", ARG_FLAG, CMDS_RUN_FOLDER, NULL,
     "keep the complete frames an interrupted run of the same configuration\nleft in DIR and draw the rest "
     "(DIR/fovsim-run.txt records it)", FIELD(resume), .misuse = ONLY_RUN_FOLDER},
    {"--replace", ARG_FLAG, CMDS_RUN_FOLDER, NULL, "write into a DIR another configuration wrote, removing its frames",
     FIELD(replace), .misuse = ONLY_RUN_FOLDER},
    {"--wait-lock", ARG_INT, CMDS_RUN_FOLDER, "S",
     "another run writing DIR (its lock, DIR/fovsim-run.lock): wait up to S\nseconds (1 to 86400) for it to end, "
     "then go on; without it, or when\nthe time is up, exit 12 naming that run", FIELD(wait_lock), .lo = 1,
     .hi = WAIT_LOCK_MAX_S, .flags = OPT_MACHINE, .misuse = ONLY_RUN_FOLDER},
    /* the machine */
    {"--gpu", ARG_INT, ALL_BUT_VIEW, "N", "EGL device index (default: first hardware device, else llvmpipe)",
     FIELD(gpu), .lo = 0, .hi = 15, .flags = OPT_MACHINE, .misuse = NOT_IN_VIEW},
    {"--gl-debug", ARG_FLAG, CMDS_DRAWING, NULL, "GL debug output on stderr (always on in debug builds)",
     FIELD(gl_debug), .flags = OPT_MACHINE},
    {"--quiet", ARG_FLAG, CMDS_DRAWING, NULL, "no progress line", FIELD(quiet), .flags = OPT_MACHINE},
    {"--progress-interval", ARG_FLOAT, CMDS_PROGRESS, "S",
     "when stderr is not a terminal, a progress line at the first frame,\nevery S seconds and at the last, 0 to 86400 (default 10; 0: every\nframe)",
     FIELD(progress_interval), .lo = 0, .hi = 86400, .flags = OPT_LO_CLOSED | OPT_MACHINE,
     .misuse = "--progress-interval is an option of fovsim render, reference, compare, demo and bench"},
    {"--verbose", ARG_FLAG, CMDS_DRAWING, NULL, "print the renderer and what is loaded", FIELD(verbose),
     .flags = OPT_MACHINE},
    {"--asset-root", ARG_CUSTOM, CMDS_DRAWING, "DIR",
     "glTF buffer and image URIs may also name files under DIR (default:\nonly under the glTF file's own folder; "
     "README \"Limits\")", FIELD(asset_root), .set = set_asset_root},
    {"--max-image-mpixels", ARG_INT, CMDS_DRAWING, "N",
     "decoded-pixel budget per glTF image, in Mpixel of 2^20 pixels\n(default 64 = 8192 x 8192), checked before "
     "decoding", FIELD(max_image_mpixels), .lo = 1, .hi = 4096},
    {"--max-scene-mpixels", ARG_INT, CMDS_DRAWING, "N", "the same budget summed over a scene's images (default 256)",
     FIELD(max_scene_mpixels), .lo = 1, .hi = 65536},
    /* bench --accuracy */
    {"--accuracy", ARG_FLAG, ON(CMD_BENCH), NULL,
     "the accuracy-vs-time matrix: modes x rings off/default/aggressive x TAA\noff/on (with --ring-lod also "
     "default+lod: the default rings with it),\nwith coverage, RMSE, alpha RMSE, FLIP and temporal error vs the\n"
     "reference, and each configuration's CPU time, page faults and work\ncounts; writes DIR/accuracy.csv, "
     "accuracy.md, accuracy.png (error vs\nframe time) and accuracy-fragments.png (error vs fragment-shader\n"
     "invocations per pixel; not drawn without\nGL_ARB_pipeline_statistics_query), gnuplot", FIELD(bench.accuracy),
     .misuse = "--accuracy is an option of fovsim bench"},
    {"--error", ARG_CHOICE, CTX_BENCH_ACCURACY, "E",
     "bench --accuracy: the error plotted and on which the Pareto fronts\nare taken: flip (default), alpha_rmse, "
     "rmse or temporal_error\n(docs/metrics.md)", FIELD(bench.error), .choices = k_error, GIVEN(bench.error_set),
     .misuse = "--error is an option of fovsim bench --accuracy"},
    {"--cost", ARG_CHOICE, CTX_BENCH_ACCURACY, "time|model|work",
     "bench --accuracy: the x axis of accuracy.png: the measured median frame\ntime (time, default), the time "
     "--cost-model predicts (model), or\ncovered fragments per display pixel, a count that does not depend on\n"
     "the device (work)", FIELD(bench.cost), .choices = k_cost,
     .misuse = "--cost is an option of fovsim bench --accuracy"},
    /* the reference */
    {"--reference", ARG_CHOICE, CMDS_REFERENCE, "KIND",
     "exact (default): each sub-sample is the expectation of stochastic\nalpha testing, from per-pixel fragment "
     "lists composited front to\nback; stochastic: the mean of K stochastic tests (a cross-check)", FIELD(ref.kind),
     .choices = k_reference, GIVEN(ref.kind_set), .flags = OPT_RECORDED, .misuse = ONLY_REFERENCE},
    {"--supersample", ARG_INT, CMDS_REFERENCE, "S", "reference: S x S sub-samples per pixel (default 4)",
     FIELD(ref.supersample), .lo = 1, .hi = 16, .flags = OPT_RECORDED, .misuse = ONLY_REFERENCE},
    {"--samples", ARG_CUSTOM, CMDS_REFERENCE, "K",
     "reference: stochastic alpha tests per sub-sample, even (default 64;\nexact: only for pixels whose fragment "
     "lists overflow)", FIELD(ref.samples), .set = set_samples, .flags = OPT_RECORDED, .misuse = ONLY_REFERENCE},
    {"--ref-memory", ARG_INT, CMDS_REFERENCE, "MB",
     "exact reference: budget of the fragment lists (default 2048; the\nGL's buffer-texture limit caps it)",
     FIELD(ref.memory_mb), .lo = 1, .hi = 1 << 20, .flags = OPT_RECORDED, .misuse = ONLY_REFERENCE},
    {"--cache", ARG_STRING, CMDS_REFERENCE, "DIR", "reference frame cache (default $XDG_CACHE_HOME/fovsim/reference)",
     FIELD(ref.cache_dir), .flags = OPT_MACHINE, .misuse = ONLY_REFERENCE},
    {"--no-cache", ARG_FLAG, CMDS_REFERENCE, NULL, "draw reference frames without reading or writing the cache",
     FIELD(ref.no_cache), .flags = OPT_MACHINE, .misuse = ONLY_REFERENCE},
    /* compare (and demo) */
    {"--first-frame", ARG_INT, ON(CMD_COMPARE), "F",
     "measure and write frames F.. only (a chunk of a longer sequence); the\nframes before are drawn without being "
     "written, for the TAA history", FIELD(compare.first_frame), .lo = 0, .hi = MAX_FRAMES - 1,
     .flags = OPT_RECORDED, .misuse = "--first-frame is an option of fovsim compare (a chunk of a longer sequence, "
                                      "as fovsim sweep --chunk-frames runs it)"},
    {"--warmup", ARG_INT, CTX_COMPARE_CHUNK, "W",
     "with --first-frame: draw at most W frames of history (default: back to\nframe 0 or the last camera cut, the "
     "same frames as an unbroken run)", .flags = OPT_HELP_ONLY},
    {"--modes", ARG_CUSTOM, ON(CMD_COMPARE) | ON(CMD_DEMO), "M,M,...",
     "alpha modes side by side (or all; default traditional,hashed)", FIELD(bench_mode_count), .set = set_modes,
     .flags = OPT_RECORDED, .misuse = "--modes is an option of fovsim bench, compare and demo (render and plan take "
                                      "--alpha)"},
    {"--export-fvvdp", ARG_FLAG, ON(CMD_COMPARE) | ON(CMD_DEMO), NULL,
     "also write FovVideoVDP's inputs to DIR/fvvdp/: 16-bit sRGB PNG\nsequences of every mode and the reference, "
     "the fixation per frame,\nthe display and run_fvvdp.py (see docs/metrics.md)", FIELD(compare.export_fvvdp),
     .flags = OPT_RECORDED, .misuse = ONLY_FVVDP},
    {"--fvvdp", ARG_FLAG, ON(CMD_COMPARE) | ON(CMD_DEMO), NULL,
     "--export-fvvdp, then run it with the python3 on PATH when that\nimports pyfvvdp, and put each mode's JOD "
     "into summary.json\n(a failed run: exit 6, its output in DIR/fvvdp/fvvdp.log)", FIELD(compare.run_fvvdp),
     .misuse = ONLY_FVVDP},
    {"--grid-annotate", ARG_CHOICE, ON(CMD_COMPARE) | ON(CMD_DEMO), "on|off",
     "labels, gaze marker and ring borders on part 0's grid (default on;\noff for a clean grid; never in the "
     "layers the metrics read)", FIELD(compare.no_grid_annotate), .choices = k_off_on, .flags = OPT_RECORDED,
     .misuse = "--grid-annotate is an option of fovsim compare and demo"},
    {"--video", ARG_CHOICE, ON(CMD_COMPARE) | ON(CMD_DEMO), "on|off",
     "write DIR/video.mp4 of the grid through the ffmpeg program (default:\non for demo, off for compare); "
     "without ffmpeg, or off, DIR/preview/\nholds small PNGs of the frames for report.html (--previews)", FIELD(compare.video),
     .choices = k_on_off, GIVEN(compare.video_set), .misuse = "--video is an option of fovsim compare and demo"},
    {"--previews", ARG_INT, ON(CMD_COMPARE) | ON(CMD_DEMO), "N",
     "without a video, at most N frames of the grid as PNG previews for\nreport.html's scrubber, evenly spaced "
     "(default 48; 0: none; a sweep's\ntasks: 0 unless its options say)", FIELD(compare.previews), .lo = 0,
     .hi = 100000, GIVEN(compare.previews_set), .misuse = "--previews is an option of fovsim compare and demo"},
    /* bench */
    {"--warmup", ARG_INT, ON(CMD_BENCH), "W", "frames drawn before timing (default 5)", FIELD(bench.warmup), .lo = 0,
     .hi = 10000, GIVEN(bench.warmup_set), .flags = OPT_RECORDED /* with --first-frame */,
     .misuse = "--warmup is an option of fovsim bench, and of compare with --first-frame"},
    {"--markdown", ARG_STRING, ON(CMD_BENCH), "FILE", "append the result as a Markdown section to FILE",
     FIELD(bench.markdown) /* no misuse: ignored by the other commands */},
    {"--format", ARG_CHOICE, ON(CMD_BENCH), "F", "text (default) or json (machine-readable, on stdout)",
     FIELD(bench.json), .choices = k_format, .misuse = "--format is an option of fovsim bench"},
    {"--modes", ARG_CUSTOM, ON(CMD_BENCH), "M,M,...",
     "alpha modes to compare in one run (or all); each gets its time\nrelative to traditional, A2C modes also "
     "traditional+MSAA", .flags = OPT_HELP_ONLY},
    {"--calibrate", ARG_FLAG, ON(CMD_BENCH), NULL,
     "fit this device's stage cost model: time = a*primitives +\nb*invocations + c*bytes + d per stage class, "
     "over a fixed matrix:\nsizes 1/4..4/4 of --width x --height (default 640x360), rings off,\nthe run's and "
     "aggressive, --modes (default traditional,hashed), TAA\noff/on; a third of the configurations held out to "
     "measure its\nerror (bound: p90 25 %); writes --cost-model (default\nDIR/cost-model.json; DIR: --out, "
     "default out/bench); --frames\ndefault 16, --warmup 1 (about 35 s on 2 cores)",
     FIELD(bench.calibrate), .misuse = "--calibrate is an option of fovsim bench"},
    {"--cost-model", ARG_STRING, ON(CMD_BENCH) | ON(CMD_COMPARE) | ON(CMD_DEMO), "FILE",
     "the stage cost model (bench --calibrate writes it): bench --accuracy,\ncompare and demo report the frame "
     "time it predicts beside the measured\none; refused when fitted on another renderer or over its error "
     "bound", FIELD(bench.cost_model), .flags = OPT_MACHINE,
     .misuse = "--cost-model is an option of fovsim bench, compare and demo"},
    /* view */
    {"--script", ARG_STRING, ON(CMD_VIEW), "FILE", "scripted input (frame N / move X Y / key NAME / capture / quit)",
     FIELD(view.script), .misuse = ONLY_VIEW},
    {"--record", ARG_STRING, ON(CMD_VIEW), "FILE",
     "where R records the gaze (fovsim CSV; default out/view/gaze-<n>.csv);\ncaptures go next to it",
     FIELD(view.record), .misuse = ONLY_VIEW},
    {"--split", ARG_CUSTOM, ON(CMD_VIEW), "A,B", "split screen: alpha mode A on the left, B on the right",
     FIELD(view.split), .set = set_split, .misuse = ONLY_VIEW},
};
const size_t k_cli_option_count = sizeof k_cli_options / sizeof k_cli_options[0];

const cli_option *cli_option_find(const char *name)
{
    for (size_t i = 0; i < k_cli_option_count; i++)
        if (!(k_cli_options[i].flags & OPT_HELP_ONLY) && !strcmp(k_cli_options[i].name, name))
            return &k_cli_options[i];
    return NULL;
}

unsigned cli_context(command cmd, const run_desc *d)
{
    unsigned c = ON(cmd);
    if (cmd == CMD_BENCH && (!d || d->bench.accuracy))
        c |= CTX_BENCH_ACCURACY;
    if (cmd == CMD_COMPARE && (!d || d->compare.first_frame))
        c |= CTX_COMPARE_CHUNK;
    return c;
}

const char *cli_machine_option(const char *arg, bool *takes_value)
{
    char name[64];
    snprintf(name, sizeof name, "%.*s", (int)strcspn(arg, "="), arg);
    const cli_option *o = cli_option_find(name);
    if (!o || !(o->flags & OPT_MACHINE))
        return NULL;
    if (takes_value)
        *takes_value = o->arg != ARG_FLAG && !strchr(arg, '=');
    return o->name;
}
