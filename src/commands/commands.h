/* commands.h: the commands of fovsim, one file each in this folder, given a parsed run_desc
 * (cli.h). What they share (inputs checked before output, gaze per frame, the output folder's
 * record) is in src/session/.
 *
 *   fovsim render     render.c          fovsim compare, demo  compare.c
 *   fovsim plan       plan.c            fovsim bench --accuracy  bench_accuracy.c
 *   fovsim bench      bench.c           fovsim check      check.c (+ check_judge.c)
 *   fovsim reference  reference.c       fovsim sweep      sweep.c (+ sweep_manifest.c)
 *   fovsim view       src/view/view.c   fovsim merge      merge.c
 *
 * bench.c writes its report with bench_report.c (bench_internal.h); fovsim bench --calibrate,
 * bench_calibrate.c, measures with bench.c's phases and fits the cost model (src/perf/).
 *
 * dispatch.c maps a run_desc to its command (cli_parse's, or one check and sweep build with
 * cli_begin ... cli_finish); sweep, merge and check get their own arguments (run_desc.own). */
#ifndef FOVSIM_COMMANDS_H
#define FOVSIM_COMMANDS_H

#include "cli/cli.h"

/* Runs d->cmd (help, version and --list-gpus included). */
fs_status command_run(const run_desc *d);

fs_status cmd_render(const run_desc *d);
fs_status cmd_plan(const run_desc *d);
fs_status cmd_bench(const run_desc *d);
fs_status cmd_bench_accuracy(const run_desc *d);
fs_status cmd_bench_calibrate(const run_desc *d);
fs_status cmd_reference(const run_desc *d);
fs_status cmd_compare(const run_desc *d);
fs_status cmd_demo(const run_desc *d);

/* These parse their own options (argv[1] is the command's name; run_desc.own). */
fs_status cmd_check(int argc, char **argv);
fs_status cmd_sweep(int argc, char **argv);
fs_status cmd_merge(int argc, char **argv);

#endif
