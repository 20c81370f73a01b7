/* run.h: the commands of fovsim (render, plan, demo, bench, view), given a parsed run_desc. */
#ifndef FOVSIM_RUN_H
#define FOVSIM_RUN_H

#include "cli.h"
#include "passes/plan.h"
#include "scene/frame.h"

fs_status run(const run_desc *d);

/* >>shared with the viewer (src/view), so that its scenes, plans and EXR headers are exactly
 * those of `fovsim render` for the same options. */

/* Loads and validates --scene/--builtin; *sc is freed on failure. */
fs_status run_load_scene(const run_desc *d, scene *sc);
/* The plan options of a run: --alpha, the size, TAA and alpha controls (the CLI's, else the
 * scene's), and the ring layout (--rings, else the scene's, else auto; auto falls back to off where
 * it would not save pixels). One line and FS_ERR_USAGE for a bad layout. */
fs_status run_plan_options(const run_desc *d, const scene *sc, plan_options *out);
/* The fovsim:* header attributes of a rendered frame. */
void run_frame_attrs(exr_image *img, const scene *sc, const plan *pl, const gaze_trace *gz, const frame_record *fr);
/* mkdir -p; one line naming the failing component and FS_ERR_IO on failure. */
fs_status run_make_dirs(const char *path);

#endif
