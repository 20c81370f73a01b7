/* sweep_manifest.h: a sweep's manifest (JSON, docs/cluster.md "The manifest") and the options of
 * each task's `fovsim compare`. Paths in the manifest are relative to its folder; a loaded
 * manifest holds them absolute, and so does the copy it writes into the sweep's folder, which is
 * what the tasks read (they may run in another working directory, on another machine). */
#ifndef FOVSIM_SWEEP_MANIFEST_H
#define FOVSIM_SWEEP_MANIFEST_H

#include <limits.h>
#include <stdbool.h>
#include <stddef.h>

#include "core/status.h"

#define SWEEP_MAX_LIST 256     /* entries per list (scenes, traces, layouts, options) */
#define SWEEP_MAX_ARGS 200     /* arguments of one task's compare */
#define SWEEP_DEFAULT_WARMUP 64 /* frames of TAA history before a chunk: 0.9^64 = 0.1 % at blend 0.1 */

/* The eye tracker's axes (docs/latency.md): manifest keys gaze_latency, gaze_rate, gaze_noise,
 * gaze_loss, each a value or a list, the options --gaze-latency ... of each task's compare. */
#define SWEEP_TRACKER_AXES 4

typedef struct sweep_task {
    int scene, gaze, rings, taa; /* indices into the manifest's lists */
    int tracker;                 /* the combination of tracker axis values (sweep_tracker_value) */
    int first, end;              /* frames [first, end); end = 0: the scene's whole sequence */
    char name[200];              /* its folder under tasks/, from its parameters */
} sweep_task;

typedef struct sweep_slurm {
    int cpus_per_task, max_running; /* max_running 0: no limit */
    char mem[32], time[32], partition[64];
    char *extra[16];                /* further "#SBATCH" lines, e.g. "--account=lab" */
    int nextra;
} sweep_slurm;

/* Command-line settings that replace the manifest's (NULL / 0 / -1: the manifest's). */
typedef struct sweep_overrides {
    const char *out;
    int chunk_frames, warmup, cpus_per_task, max_running;
    const char *mem, *time, *partition;
} sweep_overrides;

typedef struct sweep_manifest {
    char path[PATH_MAX];           /* as given */
    char out[700];                 /* the sweep's folder, absolute (short enough for a task's --out) */
    char frozen[PATH_MAX];         /* out/manifest-<hash>.json, what the tasks read */
    char *scenes[SWEEP_MAX_LIST];  /* "builtin:NAME" or an absolute path */
    int nscenes;
    char *gaze[SWEEP_MAX_LIST];    /* NULL: fixation at the centre; "builtin:NAME" or an absolute path */
    int ngaze;
    char modes[512];               /* "traditional,hashed" */
    char *rings[SWEEP_MAX_LIST];   /* "default" (the scene's) or a --rings value */
    int nrings;
    const char *taa[3];            /* "default", "on", "off" */
    int ntaa;
    char *tracker[SWEEP_TRACKER_AXES][SWEEP_MAX_LIST]; /* each axis' values as its option takes them;
                                                          NULL: not given (the scene's) */
    int ntracker_axis[SWEEP_TRACKER_AXES];             /* >= 1 */
    int ntracker;                  /* their product: the tracker combinations per scene, trace, ... */
    char gaze_seed[16];            /* --gaze-seed of every task; "" = not given */
    bool has_tracker;              /* an axis or the seed given: task names and merged tables say it */
    int width, height, frames;     /* 0: the scene's */
    double fps;                    /* 0: 24 */
    char reference[16];            /* "" (exact), "exact", "stochastic" */
    int supersample, samples;      /* 0: compare's defaults */
    char cache[800];               /* absolute; default out/cache */
    int chunk_frames, warmup;      /* 0: no chunks */
    char *options[SWEEP_MAX_LIST]; /* further compare options, e.g. "--hash-scale", "0.5" */
    int noptions;
    sweep_slurm slurm;
    int *chunks[SWEEP_MAX_LIST];   /* per scene with chunk_frames: its chunks' first frames and the
                                      end (nchunks[s] + 1 values); from the written copy's
                                      "chunk_starts", else found by sweep_build_tasks */
    int nchunks[SWEEP_MAX_LIST];
    sweep_task *tasks;             /* built by the sweep */
    int ntasks;
} sweep_manifest;

/* Tracker axis a's manifest key ("gaze_latency"), its option ("--gaze-latency") and its short
 * label in task names ("lat"). */
const char *sweep_tracker_key(int a);
const char *sweep_tracker_option(int a);
const char *sweep_tracker_label(int a);
/* Axis a's value in tracker combination t (NULL: not given). */
const char *sweep_tracker_value(const sweep_manifest *m, int t, int a);

/* Reads and checks the manifest at `path` (one line naming the JSON path of what is wrong, and
 * FS_ERR_USAGE). m->frozen is `path` until sweep_manifest_write. */
fs_status sweep_manifest_load(const char *path, const sweep_overrides *ov, sweep_manifest *m);
/* After sweep_build_tasks: creates the sweep's folder (and logs/) and writes the absolute-path
 * copies manifest.json and manifest-<hash>.json (with the chunks, so that no task loads a scene
 * to find them), and points m->frozen at the latter. */
fs_status sweep_manifest_write(sweep_manifest *m);
void sweep_manifest_free(sweep_manifest *m);
/* Reads the absolute-path copy in a sweep's folder (merge). */
fs_status sweep_manifest_load_dir(const char *sweep_dir, sweep_manifest *m);

/* The task list (sweep.c): scenes x traces x ring layouts x TAA settings x tracker combinations x
 * frame chunks, in that
 * nesting; with chunk_frames each scene is loaded to find its length and camera cuts. */
fs_status sweep_build_tasks(sweep_manifest *m);
/* A task's folder. */
void sweep_task_dir(const sweep_manifest *m, const sweep_task *k, char *out, size_t n);

/* A task's identity is everything that changes its output: the configuration its compare records
 * (run_record.h: modes, size, reference, options, warm-up, chunk, the scene's and trace's content
 * hashes, the executable), less the renderer line, and its frame count. A sweep_ident keeps the
 * loaded scene and trace between calls (one per command; tasks in their order load each once). */
typedef struct sweep_ident sweep_ident;
sweep_ident *sweep_ident_new(void);
void sweep_ident_free(sweep_ident *id);
/* Task k's configuration text as its compare would record it (malloc'd) and its frame count.
 * Loads (and so checks) the scene, the trace and the plan: one line and an error when bad. */
fs_status sweep_task_describe(const sweep_manifest *m, const sweep_task *k, sweep_ident *id, char **config,
                              int *frames);

/* Whether its folder's record says it completed (compare writes it last) with the configuration
 * the task would record now: todo (no record), incomplete (started, not finished, or no record of
 * fovsim's), done, or stale (complete, another configuration). With any_executable the record's
 * executable is left out of the comparison (merge compares the tasks' with each other instead).
 * Errors only when the task cannot be described. */
typedef enum sweep_task_state { TASK_TODO, TASK_INCOMPLETE, TASK_DONE, TASK_STALE } sweep_task_state;
typedef struct sweep_task_check {
    sweep_task_state state;
    char why[600]; /* stale: the first setting that differs (run_record_difference) */
    char exe[160]; /* done or stale: the record's "fovsim" line, the executable that wrote it */
} sweep_task_check;
fs_status sweep_task_status(const sweep_manifest *m, const sweep_task *k, sweep_ident *id, bool any_executable,
                            sweep_task_check *c);

/* Task k's options of fovsim compare (the scene first), each string malloc'd, NULL-terminated;
 * returns their count, or -1 (no memory, or more than cap - 3). The CLI's table parses them
 * (cli_parse_args); --list and the jobs file print them after "fovsim compare". */
int sweep_task_options(const sweep_manifest *m, const sweep_task *k, char **opts, int cap);
void sweep_task_options_free(char **opts, int n);

#endif
