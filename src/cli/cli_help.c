/* cli_help.c: `fovsim --help` and `fovsim COMMAND --help`: a command's description, then its
 * options' lines from the option table (cli_options.c), in the table's order. */
#include <stdio.h>
#include <string.h>

#include "cli/cli_internal.h"
#include "core/config.h"

static const char *command_intro(command cmd)
{
    switch (cmd) {
    case CMD_RENDER:
        return "usage: fovsim render [SCENE | --scene FILE | --builtin NAME] [options]\n\n"
               "Renders the scene's camera path to DIR/<name>.<frame:04d>.exr (half RGBA + coverage, ZIP).\n\n";
    case CMD_PLAN:
        return "usage: fovsim plan [SCENE | --scene FILE | --builtin NAME] [--alpha MODE] [--width W --height H]\n\n"
               "Prints which passes, shader variants and targets the scene needs, without drawing.\n\n";
    case CMD_DEMO:
        return "usage: fovsim demo [options]\n\n"
               "fovsim compare with defaults: the built-in forest (camera dollying back through trees and a\n"
               "fence) at 640x360, foveated around builtin:demo_tour (fixations, saccades, a smooth pursuit),\n"
               "TAA on, traditional and hashed against an exact reference (2x2 sub-samples), to ./out/demo/;\n"
               "prints the table and how to look at the frames. Accepts compare's options below.\n\n";
    case CMD_BENCH:
        return "usage: fovsim bench [SCENE | --scene FILE | --builtin NAME] [--frames N] [--warmup W] [--markdown FILE]\n\n"
               "Draws N frames spread over the camera path after W warm-up frames and reports median and\n"
               "spread of the frame time (wall clock, glFinish), the process CPU time and minor page faults\n"
               "of the draw, GL time per stage (pass, or ring, TAA resolve and composite), and work counts\n"
               "that transfer to a GPU (GL_ARB_pipeline_statistics_query): vertex-shader invocations,\n"
               "primitives submitted and after clipping, fragment-shader invocations, per stage and per\n"
               "frame; n/a (JSON -1) where the driver lacks the extension. Covered fragments per ring and\n"
               "pass come from one extra frame per measured frame drawn with a counting variant of the\n"
               "forward shader (never the timed one); invocations / covered (invocations are 2x2 quads on\n"
               "GPUs, 4x4 blocks on llvmpipe); bytes read and written per stage from the targets'\n"
               "footprints; the covered-fragment ideal beside the pixel ideal.\n"
               "Text is Markdown; --format json for scripts.\n"
               "Configurations per mode: full resolution, foveated (the run's rings, without ring LOD) and,\n"
               "with --ring-lod (or the scene's ring_lod), foveated + ring LOD, with its ratios to foveated\n"
               "per stage (time, CPU time, fragment-shader invocations, primitives).\n"
               "Defaults: N = 30, W = 5, the scene's display size. See docs/benchmarks.md.\n\n";
    case CMD_REFERENCE:
        return "usage: fovsim reference [SCENE | --scene FILE | --builtin NAME] [--reference exact|stochastic]\n"
               "                        [--supersample S] [--samples K]\n\n"
               "Renders the ground truth of every frame: full resolution, S x S sub-samples per pixel, each\n"
               "the expectation of stochastic alpha testing (order-correct alpha compositing): exact from\n"
               "per-pixel fragment lists (default), or the mean of K stochastic tests. Frames are cached by\n"
               "a key of the scene, camera, size, kind, S and K (compare reuses them) and written to\n"
               "DIR/reference.<frame:04d>.exr; each frame's estimated error is printed (exact: S x S vs\n"
               "S/2 x S/2 sub-samples; stochastic: K/2 vs K tests).\n\n";
    case CMD_COMPARE:
        return "usage: fovsim compare [SCENE | --scene FILE | --builtin NAME] --modes M,M,... [--gaze FILE] [options]\n\n"
               "Renders every mode with the same camera, gaze, jitter and seeds, and writes per frame one\n"
               "two-part EXR, DIR/compare.<frame:04d>.exr: part 'compare' is a grid of the modes and the\n"
               "reference (RGBA, what any viewer shows), part 'layers' holds <mode>.R/G/B/A, <mode>.coverage,\n"
               "<mode>.error, reference.* and ring.id. Metrics per frame, ring and mode go to DIR/metrics.csv,\n"
               "a summary to DIR/summary.json, and a table is printed. Default modes: traditional,hashed.\n\n";
    case CMD_VIEW:
        return "usage: fovsim view [SCENE | --scene FILE | --builtin NAME] [options]\n\n"
               "Opens a window at the scene's display size and draws the scene as render would, with the\n"
               "mouse as the gaze (or --gaze FILE replayed). Keys: A alpha mode, T TAA, F foveation,\n"
               "L ring layout (auto, aggressive, off), [ ] mip bias, O ring overlay, C freeze camera,\n"
               "H reset history, S split screen, M right-hand mode, R record gaze, P capture EXR,\n"
               "SPACE pause, N step, ESC/Q quit. See docs/viewer.md.\n"
               "Render's options apply (--gaze, --rings, --taa, --alpha, ...) except --frames, --out,\n"
               "--name and --gpu.\n\n";
    default: return NULL;
    }
}

/* Prints `text` with {builtins} and {modes} replaced by their lists. */
static void put_text(const char *text)
{
    for (const char *p = text; *p;) {
        const char *b = strchr(p, '{');
        if (b && !strncmp(b, "{builtins}", 10)) {
            printf("%.*s%s", (int)(b - p), p, scene_builtin_list());
            p = b + 10;
        } else if (b && !strncmp(b, "{modes}", 7)) {
            printf("%.*s%s", (int)(b - p), p, alpha_mode_list());
            p = b + 7;
        } else if (b) {
            printf("%.*s", (int)(b - p) + 1, p);
            p = b + 1;
        } else {
            printf("%s", p);
            break;
        }
    }
}

/* "  --name METAVAR      help", the help's further lines indented under its first. */
static void print_option(const cli_option *o)
{
    char left[64];
    snprintf(left, sizeof left, "%s%s%s", o->name, o->metavar ? " " : "", o->metavar ? o->metavar : "");
    printf("  %-18s  ", left);
    for (const char *p = o->help;;) {
        size_t len = strcspn(p, "\n");
        char line[256];
        snprintf(line, sizeof line, "%.*s", (int)len, p);
        put_text(line);
        printf("\n");
        if (!p[len])
            break;
        p += len + 1;
        printf("%22s", "");
    }
}

void cli_print_help(command cmd)
{
    const char *intro = command_intro(cmd);
    if (!intro) {
        printf("fovsim %s: foveated rendering simulator for alpha-mapped foliage\n\n"
               "usage: fovsim <command> [options]\n       fovsim <command> --help\n\ncommands:\n",
               FOVSIM_VERSION);
        cli_print_commands();
        printf("\nglobal options: --help, --version, --list-gpus\n\n");
        return;
    }
    printf("%s", intro);
    printf("options:\n"
           "  SCENE               a scene file or built-in name, as --scene or --builtin\n");
    unsigned ctx = cli_context(cmd, NULL);
    for (size_t i = 0; i < k_cli_option_count; i++)
        if ((k_cli_options[i].cmds & ctx) && k_cli_options[i].help)
            print_option(&k_cli_options[i]);
    printf("\nexit status: 0 ok, 1 fovsim check: a regression, 2 bad arguments, 3 bad scene, 4 bad asset, 5 bad\n"
           "             gaze trace, 6 I/O error, 7 no OpenGL 4.5 context, 8 shader error, 9 out of memory,\n"
           "             11 a sweep has missing or failed tasks, 12 another run is writing DIR, 130 interrupted\n");
}
