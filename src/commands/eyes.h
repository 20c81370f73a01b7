/* eyes.h: an hmd display's two eyes, drawn by render and compare as one run per eye into
 * OUT/eye-left/ and OUT/eye-right/, brought together (docs/hmd.md "Two eyes").
 *
 * What it does NOT do: draw (the runs do), choose an eye's camera, display or gaze (session.c).
 */
#ifndef FOVSIM_EYES_H
#define FOVSIM_EYES_H

#include "cli/cli.h"
#include "output/exr_write.h"

/* Eye e's run (1 left, 2 right) of d: eye_run set, out_dir OUT/eye-left or OUT/eye-right (in sub, cap
 * bytes), and a line saying so unless quiet. */
run_desc eyes_run_desc(const run_desc *d, const char *out, int e, char *sub, size_t cap);

/* Each frame's eyes from `first` to frames - 1, OUT/eye-left/NAME.####.exr and OUT/eye-right/..., joined into
 * OUT/NAME.####.exr: one multi-view EXR (views left, the default, and right; exr_write.h), written
 * atomically. part: which part of the eyes' files to join (0; compare's frames: their "layers"
 * part, 1, after a side-by-side grid of both eyes' part 0). */
fs_status eyes_join_frames(const char *out, const char *name, int first, int frames, exr_compression_kind compression,
                           int part);

/* compare: OUT/metrics.csv, the eyes' rows with a first column `eye` (left, right), and
 * OUT/summary.json: {"eyes": {"left": <its summary>, "right": ...}, "both": {"modes": [{"mode",
 * "rings": [{"ring", "coverage_ratio" (both eyes' coverage summed over the reference's), "flip",
 * "rmse", "temporal_error" (the eyes' means)}]}]}}, and the "both" table on stdout. Atomic writes. */
fs_status eyes_join_metrics(const char *out);
fs_status eyes_join_summary(const char *out);

#endif
