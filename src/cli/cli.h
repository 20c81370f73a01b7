/* cli.h: argv -> run_desc (docs/design-notes.md, "The command line from one table"). No side
 * effects beyond printing usage errors; every range check happens here (cli_options.c's table) so
 * a bad argument never reaches the renderer. */
#ifndef FOVSIM_CLI_H
#define FOVSIM_CLI_H

#include <stdbool.h>

#include "common/shared_defs.h"
#include "core/status.h"
#include "fov/vrs_map.h"
#include "gaze/gaze.h"
#include "gaze/gaze_tracker.h"
#include "gaze/pose_trace.h"
#include "hmd/hmd.h"
#include "output/exr_write.h"
#include "passes/plan.h"
#include "reference/reference.h"
#include "scene/scene.h"

typedef enum command {
    CMD_NONE = 0,
    CMD_RENDER,
    CMD_PLAN,
    CMD_DEMO,
    CMD_BENCH,
    CMD_VIEW,
    CMD_HELP,
    CMD_VERSION,
    CMD_LIST_GPUS,
    CMD_REFERENCE,
    CMD_COMPARE,
    CMD_SWEEP, /* sweep, merge and check parse their own options from run_desc.own */
    CMD_MERGE,
    CMD_CHECK,
    CMD_COUNT
} command;

/* --taa on|off, or the scene's setting (on for more than one frame unless the scene says off). */
typedef enum taa_switch { TAA_SWITCH_SCENE = -1, TAA_SWITCH_OFF = 0, TAA_SWITCH_ON = 1 } taa_switch;
/* --hash pcg|sine, or the project's default (ALPHA_HASH_DEFAULT). */
typedef enum hash_choice { HASH_CHOICE_DEFAULT = -1, HASH_CHOICE_PCG = ALPHA_HASH_PCG,
                           HASH_CHOICE_SINE = ALPHA_HASH_SINE } hash_choice;
/* --alpha-lod-max: not given (the materials' own clamps), a level (alpha_lod_max), or off. */
typedef enum alpha_lod_choice { ALPHA_LOD_CLAMP_UNSET = 0, ALPHA_LOD_CLAMP_LEVEL = 1, ALPHA_LOD_CLAMP_OFF = -1 } alpha_lod_choice;
/* bench --accuracy --error: the error plotted and on which the Pareto fronts are taken. */
typedef enum acc_error_kind { ACC_ERROR_FLIP = 0, ACC_ERROR_ALPHA_RMSE, ACC_ERROR_RMSE, ACC_ERROR_TEMPORAL } acc_error_kind;
/* bench --accuracy --cost: the x axis of the accuracy-vs-cost plot (docs/benchmarks.md "Cost model"). */
typedef enum acc_cost_kind { ACC_COST_TIME = 0, ACC_COST_MODEL, ACC_COST_WORK } acc_cost_kind;

/* The runs that take --foveation vrs (the others refuse it: VRS_NOT_BUILT): plan, render, compare,
 * plain bench (its work counts price VRS's coarse shading) and bench --accuracy (its vrs rows); not
 * bench --calibrate. */
#define RUN_TAKES_VRS(d)                                                                                          \
    ((d)->cmd == CMD_PLAN || (d)->cmd == CMD_RENDER || (d)->cmd == CMD_COMPARE ||                                 \
     ((d)->cmd == CMD_BENCH && !(d)->bench.calibrate))

typedef struct run_desc {
    command cmd;
    command help_for;        /* CMD_HELP: which command's help (CMD_NONE = general) */
    const char *scene_path;  /* --scene FILE (.json, .gltf, .glb) */
    const char *builtin;     /* --builtin NAME; default "forest" when no --scene */
    int frames;              /* --frames, default: the camera path at --fps (min 1) */
    float fps;               /* --fps, default 24 */
    const char *out_dir;     /* --out, default out/<command> */
    const char *name;        /* --name: file prefix, default "frame" */
    int width, height;       /* --width/--height, 0 = the scene's display */
    const char *display;     /* --display planar|hmd:PRESET[,KEY=VALUE...]; NULL = the scene's display */
    display_kind display_kind; /* --display parsed: planar, or display_hmd (docs/hmd.md) */
    hmd_desc display_hmd;
    alpha_mode alpha;        /* --alpha, DEFAULT = the scene's */
    int gpu;                 /* --gpu N, -1 = auto */
    bool verbose, quiet, gl_debug;
    bool compression_set;    /* --compression was given (else zip, piz for demo) */
    float progress_interval; /* --progress-interval S: seconds between progress lines off a terminal */
    exr_compression_kind compression; /* --compression zip|none|piz */
    const char *rings;       /* --rings auto|off|SPEC; NULL = the scene's, else auto */
    fov_layout rings_layout; /* --rings parsed (FOV_LAYOUT_AUTO: resolved against the display per scene) */
    foveation_kind foveation; /* --foveation rings|vrs|off; UNSET = the scene's, else rings (off is --rings off) */
    foveation_kind foveations[3]; /* --foveation rings,vrs,...: compare's foveation study (foveation_count
                                     > 1); the first is also `foveation` */
    int foveation_count;
    const char *vrs;         /* --vrs auto|SPEC; NULL = the scene's, else auto */
    vrs_spec vrs_spec;       /* --vrs parsed */
    int vrs_tile;            /* --vrs-tile 8|16|32; 0 = the scene's, else VRS_TILE_DEFAULT */
    const char *ring_lod;    /* --ring-lod off|simplify[:U1,...]; NULL = the scene's, else off */
    const char *gaze_path;   /* --gaze FILE; NULL = fixation at the display centre */
    const char *head_path;   /* --head FILE|off: a recording's head motion replaces the scene's camera
                                path; NULL = the --gaze recording's when it has one (EyeNavGS) */
    pose_place head_place;   /* --head-place X,Y,Z[,YAW_DEG[,SCALE]]: the recording's world in the scene */
    bool head_place_set;
    gaze_format gaze_format; /* --gaze-format, default detected from the content */
    gaze_eye eye;            /* --eye left|right|average, default auto */
    gaze_tracker_opts tracker; /* --gaze-latency, --gaze-rate, --gaze-noise, --gaze-seed, --gaze-loss
                                  (each given or not: the scene file's "gaze" object fills the rest) */
    float gaze_latencies[MAX_GAZE_LATENCIES]; /* --gaze-latency MS,MS,...: compare and demo's latency
                                                  study (gaze_latency_count > 1); the first is also
                                                  tracker.desc.latency_ms */
    int gaze_latency_count;
    gaze_place_opts place;   /* --gaze-map angle|normalized, --gaze-screen W_MMxH_MM@DIST_MM|HxVdeg (each given or
                                not: the scene file's "gaze" "map" and "screen" fill the rest) */
    bool overlay;            /* --overlay: ring borders and gaze marker drawn into the frames */
    bool debug_channels;     /* --debug-channels: ring.id and eccentricity channels in the EXR */
    float hash_scale;        /* --hash-scale, 0 = default 1 */
    hash_choice hash_kind;   /* --hash pcg|sine */
    bool hash_aniso;         /* --hash-aniso */
    bool no_fade;            /* --no-fade */
    bool no_hash_offset;     /* --no-hash-offset */
    bool a2c_sharpen;        /* --a2c-sharpen */
    float fade_n;            /* --fade-n, 0 = default 6 */
    alpha_lod_choice alpha_lod; /* --alpha-lod-max N|off */
    float alpha_lod_max;     /* --alpha-lod-max N: mip level in [0, ALPHA_LOD_MAX_LIMIT] */
    bool no_ring_cull;       /* --ring-cull off: rings draw what only their hole would see */
    bool composite_per_pixel; /* --composite per-pixel: no tile classification (to measure it) */
    struct {
        taa_switch mode;          /* --taa on|off */
        float blend;              /* --taa-blend, 0 = default 0.1 */
        float gamma;              /* --taa-gamma, 0 = default 1 */
        float sparse;             /* --taa-sparse S|off, 0 = default TAA_SPARSE_SLACK, negative = off */
        int jitter_length;        /* --jitter-length, 0 = default 16 */
        bool no_object_motion;    /* --object-motion off: TAA ignores swaying instances' own motion */
        bool no_disocclusion;     /* --taa-disocclusion off: TAA keeps history whose surface moved away */
        taa_neighbourhood_kind neighbourhood; /* --taa-neighbourhood 3x3|cross */
        taa_history_kind history; /* --taa-history catmull|bilinear */
        taa_nan_kind nan;         /* --taa-nan tap|set */
    } taa;
    alpha_mode bench_modes[ALPHA_MODE_MAX]; /* bench, compare, demo: --modes a,b,c or all */
    int bench_mode_count;
    int eye_run;             /* not an option: 1 or 2, the left or right eye's run of an hmd display
                                (render and compare run one per eye, docs/hmd.md "Two eyes"); 0 otherwise */
    struct {                      /* fovsim bench */
        int warmup;               /* --warmup, default 5 (compare --first-frame: frames of history) */
        bool warmup_set;          /* --warmup was given (compare --first-frame: default all) */
        const char *markdown;     /* --markdown FILE, append a result table */
        bool json;                /* --format json */
        bool accuracy;            /* --accuracy, the accuracy-vs-time matrix */
        acc_error_kind error;     /* --accuracy --error */
        bool error_set;
        acc_cost_kind cost;       /* --accuracy --cost time|model|work */
        bool calibrate;           /* --calibrate: fit the stage cost model (bench_calibrate.c) */
        const char *cost_model;   /* --cost-model FILE: bench --calibrate writes it; bench --accuracy,
                                   * compare and demo predict with it */
    } bench;
    struct {                      /* the reference: fovsim reference, compare, demo, bench --accuracy */
        reference_kind kind;      /* --reference exact (default) or stochastic */
        bool kind_set;            /* --reference was given */
        int supersample;          /* --supersample S (S x S per pixel), 0 = default 4 */
        int samples;              /* --samples K per sub-sample (even), 0 = default 64 */
        int memory_mb;            /* --ref-memory MB, the exact kind's list budget, 0 = default */
        const char *cache_dir;    /* --cache DIR for reference frames, NULL = the default */
        bool no_cache;            /* --no-cache: draw references without reading or writing a cache */
    } ref;
    const char *asset_root;  /* --asset-root DIR: glTF URIs may also name files under it */
    int max_image_mpixels;   /* --max-image-mpixels N: decoded-pixel budget per image (0 = 64) */
    int max_scene_mpixels;   /* --max-scene-mpixels N: per scene (0 = 256) */
    struct {                      /* fovsim compare and demo */
        int first_frame;          /* --first-frame F, frames before F drawn only for the TAA history */
        bool export_fvvdp;        /* --export-fvvdp, FovVideoVDP's inputs in DIR/fvvdp/ */
        bool run_fvvdp;           /* --fvvdp, export and run the user's FovVideoVDP */
        bool no_grid_annotate;    /* --grid-annotate off: no labels, gaze marker or ring borders in the grid */
        bool video, video_set;    /* --video on|off (video_set: given; else on for demo only) */
        int previews;             /* --previews N: without a video, at most N PNG previews (given: previews_set) */
        bool previews_set;
    } compare;
    struct {                      /* fovsim view */
        const char *script;       /* --script FILE, scripted input events (docs/viewer.md) */
        const char *record;       /* --record FILE, where gaze recordings go (default out/view/gaze-<n>.csv) */
        alpha_mode split[2];      /* --split A,B, left and right alpha modes; DEFAULT = no split */
    } view;
    bool resume;             /* render/reference/compare/demo: --resume, keep the complete frames (run_record.h) */
    bool replace;            /* --replace: write into a folder another configuration wrote */
    int wait_lock;           /* --wait-lock S: wait up to S seconds for another run writing --out (0: refuse at once) */
    struct {                      /* sweep, merge, check: their arguments after the command's name */
        int argc;
        char **argv;
    } own;
} run_desc;

/* Parses argv; on error prints one line and returns FS_ERR_USAGE. */
fs_status cli_parse(int argc, char **argv, run_desc *out);

/* cli_parse in steps, for a run built from parts without an argv of its own (check's baseline,
 * a sweep's task): defaults for `cmd`; then options (and the positional scene) from lists of
 * arguments and single options (value NULL for a flag); then the checks across options and the
 * derived defaults. Each prints one line and returns FS_ERR_USAGE on error. Strings are kept by
 * pointer: they must outlive the run_desc. After --help (d->cmd becomes CMD_HELP) the rest is
 * ignored. */
void cli_begin(run_desc *d, command cmd);
fs_status cli_parse_args(run_desc *d, int argc, char *const *args);
fs_status cli_apply_option(run_desc *d, const char *name, const char *value);
fs_status cli_finish(run_desc *d);

/* A command's name ("compare"), "" for none. */
const char *cli_command_name(command cmd);

/* An integer option's value in [lo, hi]; else one line ("OPT: expected an integer in [lo, hi],
 * got 'V'") and false. */
bool cli_parse_int(const char *opt, const char *v, int lo, int hi, int *out);

/* When `arg` ("--gpu", "--cache=DIR") names an option of the machine that runs a command
 * (cli_options.c: OPT_MACHINE), its name ("--cache"), else NULL: fovsim check passes these to
 * compare and never stores them in a baseline. *takes_value (may be NULL): whether the value is
 * the next argument (an option with a value, written without '='). */
const char *cli_machine_option(const char *arg, bool *takes_value);

/* Prints the help text of a command (CMD_NONE: overview) on stdout (cli_help.c). */
void cli_print_help(command cmd);

#endif
