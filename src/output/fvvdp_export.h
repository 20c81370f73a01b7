/* fvvdp_export.h: the inputs of FovVideoVDP (Mantiuk et al. 2021), written for the user's own copy
 * of the tool (`fovsim compare --export-fvvdp`, docs/metrics.md "FovVideoVDP").
 *
 * FovVideoVDP's code and calibration data are licensed CC BY-NC 4.0, so fovsim includes none of
 * them. It writes, under DIR/fvvdp/:
 *   <name>/<name>.NNNN.png   16-bit sRGB PNGs of every mode and of the reference (png_write.h: the
 *                            encoding of ../shared/fixtures, reproduced bit for bit);
 *   fixation.csv             per frame the gaze, normalised and in FovVideoVDP's pixel convention
 *                            (fix = gaze * size - 0.5: pixel centres at integers);
 *   display.json             size, horizontal field of view, frame rate, the sequences;
 *   run_fvvdp.py             a script that runs pyfvvdp's Python API on them (foveated, the
 *                            standard_hmd photometry, the display's field of view) and writes
 *                            results.json with each mode's JOD.
 * fvvdp_run runs that script when the `fvvdp` command is installed.
 */
#ifndef FOVSIM_FVVDP_EXPORT_H
#define FOVSIM_FVVDP_EXPORT_H

#include "core/status.h"
#include "output/exr_write.h"
#include "frame/frame.h"

#define FVVDP_MAX_SEQUENCES 16

typedef struct fvvdp_export fvvdp_export;

/* Starts an export of `count` sequences (the last is the reference) of width x height frames,
 * hfov degrees, fps frames per second, into out_dir/fvvdp/. NULL with *st on failure (one line). */
fvvdp_export *fvvdp_export_begin(const char *out_dir, const char *const names[], int count, int width, int height,
                                 float hfov_deg, float fps, fs_status *st);
/* Frame `index`: one image per sequence (channels R, G, B, linear premultiplied) and its gaze. */
fs_status fvvdp_export_frame(fvvdp_export *e, int index, const frame_record *fr, const exr_image *const images[]);
/* Writes display.json and run_fvvdp.py, closes everything and frees e. */
fs_status fvvdp_export_end(fvvdp_export *e);

/* Whether the `fvvdp` command is on PATH. */
bool fvvdp_available(void);
/* Runs out_dir/fvvdp/run_fvvdp.py with python3 and reads the JOD of each test sequence (every name
 * but the last) from its results.json into jod[] (NaN where missing). FS_ERR_IO when it fails. */
fs_status fvvdp_run(const char *out_dir, const char *const names[], int count, double jod[]);

#endif
