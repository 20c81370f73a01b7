/* sweep.h: `fovsim sweep MANIFEST` and `fovsim merge SWEEP_DIR` (issue 18; docs/cluster.md).
 *
 * A manifest (JSON) names scenes, gaze traces, alpha modes, ring layouts, TAA settings, the
 * display and the reference; the sweep is the product of scenes x traces x ring layouts x TAA
 * settings (x frame chunks with --chunk-frames), each task one `fovsim compare` of every mode into
 * SWEEP/tasks/<a name derived from its parameters>/. The task list is run by the same binary in
 * three ways: a jobs file (one shell command per line, for GNU parallel or any farm), a Slurm array
 * script (sbatch), or --local N processes here. Every way runs `fovsim sweep MANIFEST --task I`,
 * which skips a task whose folder's record says complete (run_record.h) and redraws one that is
 * not, so running the list again resumes it. `fovsim merge` gathers the tasks' metrics.
 *
 * What a sweep writes, all under SWEEP (the manifest's "out", or --out):
 *   manifest.json           the manifest with absolute paths (what merge reads)
 *   manifest-<hash>.json    the same, under a name of its content: the jobs and the Slurm script
 *                           read this one, so editing the manifest never changes a running task
 *   tasks/<task>/           each task's compare output (frames, metrics.csv, summary.json, record)
 *   logs/                   each task's output (task-NNNN.log; Slurm: slurm-<job>_<index>.out/.err)
 *   jobs.txt, sweep.sbatch  with --jobs-file / --slurm
 *   metrics.csv, summary.json, accuracy.csv, accuracy.png   by merge */
#ifndef FOVSIM_SWEEP_H
#define FOVSIM_SWEEP_H

#include "core/status.h"

/* argv as main's, argv[1] == "sweep" / "merge". */
fs_status sweep_main(int argc, char **argv);
fs_status merge_main(int argc, char **argv);

#endif
