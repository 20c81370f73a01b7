/* cli.h: argv -> run_desc (STYLE.md: parse, then run). No side effects beyond printing usage
 * errors; all range checks happen here so a bad argument never reaches the renderer. */
#ifndef FOVSIM_CLI_H
#define FOVSIM_CLI_H

#include <stdbool.h>

#include "core/status.h"
#include "gaze/gaze.h"
#include "output/exr_write.h"
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
} command;

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
    alpha_mode alpha;        /* --alpha, DEFAULT = the scene's */
    int gpu;                 /* --gpu N, -1 = auto */
    bool verbose, quiet, gl_debug;
    int warmup;              /* bench: --warmup, default 5 */
    const char *markdown;    /* bench: --markdown FILE, append a result table */
    exr_compression_kind compression; /* --compression zip|none|piz */
    const char *rings;       /* --rings auto|off|SPEC; NULL = the scene's, else auto */
    const char *ring_lod;    /* --ring-lod off|simplify[:U1,...]; NULL = the scene's, else off */
    const char *gaze_path;   /* --gaze FILE; NULL = fixation at the display centre */
    gaze_format gaze_format; /* --gaze-format, default detected from the content */
    gaze_eye eye;            /* --eye left|right|average, default auto */
    bool overlay;            /* --overlay: ring borders and gaze marker drawn into the frames */
    bool debug_channels;     /* --debug-channels: ring.id and eccentricity channels in the EXR */
    bool json;               /* bench: --format json */
    float hash_scale;        /* --hash-scale, 0 = default 1 */
    int hash_kind;           /* --hash pcg|sine, -1 = default */
    bool hash_aniso;         /* --hash-aniso */
    bool no_fade;            /* --no-fade */
    bool no_hash_offset;     /* --no-hash-offset */
    bool a2c_sharpen;        /* --a2c-sharpen */
    int taa;                 /* --taa on|off: 1 / 0; -1 = the scene's, else on (for more than one frame) */
    float taa_blend;         /* --taa-blend, 0 = default 0.1 */
    float taa_gamma;         /* --taa-gamma, 0 = default 1 */
    float taa_sparse;        /* --taa-sparse S|off, 0 = default TAA_SPARSE_SLACK, negative = off */
    int jitter_length;       /* --jitter-length, 0 = default 16 */
    bool no_object_motion;   /* --object-motion off: TAA ignores swaying instances' own motion */
    bool no_disocclusion;    /* --taa-disocclusion off: TAA keeps history whose surface moved away */
    bool no_ring_cull;       /* --ring-cull off: rings draw what only their hole would see */
    bool composite_per_pixel; /* --composite per-pixel: no tile classification (to measure it) */
    int taa_neighbourhood;   /* --taa-neighbourhood 3x3|cross: TAA_NEIGHBOURHOOD_* (plan.h), 0 = default */
    int taa_history;         /* --taa-history catmull|bilinear: TAA_HISTORY_* (plan.h), 0 = default */
    int taa_nan;             /* --taa-nan tap|set: TAA_NAN_* (plan.h), 0 = default */
    float fade_n;            /* --fade-n, 0 = default 6 */
    int alpha_lod;           /* --alpha-lod-max: 0 not given, 1 a level (alpha_lod_max), -1 off */
    float alpha_lod_max;     /* --alpha-lod-max N: mip level in [0, ALPHA_LOD_MAX_LIMIT] */
    alpha_mode bench_modes[ALPHA_MODE_COUNT]; /* bench, compare, demo: --modes a,b,c or all */
    int bench_mode_count;
    int supersample;         /* reference: --supersample S (S x S per pixel), 0 = default 4 */
    int samples;             /* reference: --samples K per sub-sample (even), 0 = default 64 */
    int reference_kind;      /* reference: --reference exact (0, default) or stochastic (1) */
    bool reference_set;      /* --reference was given */
    int ref_memory_mb;       /* reference: --ref-memory MB, the exact kind's list budget, 0 = default */
    const char *asset_root;  /* --asset-root DIR: glTF URIs may also name files under it */
    int max_image_mpixels;   /* --max-image-mpixels N: decoded-pixel budget per image (0 = 64) */
    int max_scene_mpixels;   /* --max-scene-mpixels N: per scene (0 = 256) */
    const char *cache_dir;   /* --cache DIR for reference frames, NULL = the default */
    bool no_cache;           /* --no-cache: draw references without reading or writing a cache */
    bool accuracy;           /* bench: --accuracy, the accuracy-vs-time matrix */
    bool export_fvvdp;       /* compare/demo: --export-fvvdp, FovVideoVDP's inputs in DIR/fvvdp/ */
    int acc_error;           /* bench --accuracy --error: 0 flip (default), 1 alpha_rmse, 2 rmse,
                              * 3 temporal_error */
    bool acc_error_set;
    bool run_fvvdp;          /* compare/demo: --fvvdp, export and run the user's FovVideoVDP */
    const char *script;      /* view: --script FILE, scripted input events (docs/viewer.md) */
    const char *record;      /* view: --record FILE, where gaze recordings go (default out/view/gaze-<n>.csv) */
    alpha_mode split[2];     /* view: --split A,B, left and right alpha modes; DEFAULT = no split */
    int first_frame;         /* compare: --first-frame F, frames before F drawn only for the TAA history */
    bool warmup_set;         /* --warmup was given (compare --first-frame: frames of history; default all) */
    bool resume;             /* render/reference/compare/demo: --resume, keep the complete frames (run_record.h) */
    bool replace;            /* --replace: write into a folder another configuration wrote */
    int wait_lock;           /* --wait-lock S: wait up to S seconds for another run writing --out (0: refuse at once) */
} run_desc;

/* Parses argv; on error prints one line and returns FS_ERR_USAGE. */
fs_status cli_parse(int argc, char **argv, run_desc *out);
/* An integer option's value in [lo, hi]; else one line ("OPT: expected an integer in [lo, hi],
 * got 'V'") and false. */
bool cli_parse_int(const char *opt, const char *v, int lo, int hi, int *out);
/* Prints the help text of a command (CMD_NONE: overview) on stdout. */
void cli_print_help(command cmd);

#endif
