/* view.h: `fovsim view`, the interactive viewer (docs/viewer.md).
 *
 * A GLFW window (gl_window) at the display size of the scene shows the frames of the same renderer,
 * shaders and plan as `fovsim render` (plans come from session_plan_options), with the mouse as the
 * gaze, or a --gaze trace replayed with pause and step. Keys change the alpha mode, TAA,
 * foveation, ring layout, mip bias and overlay (each rebuilds the plan and renderer), freeze the
 * camera, reset the TAA history, split the screen between two alpha modes, record the gaze as a
 * fovsim CSV trace (replayable by render) and capture the frame as EXR. --script FILE drives it
 * with scripted input events (view_input.h) for tests.
 *
 * Time is frames, not the wall clock: drawn frame k shows scene time tick/fps, tick advancing by
 * one per frame unless paused, and interactive runs are paced to at most --fps frames per second.
 * So a scripted run is deterministic, and a recorded trace replayed by `fovsim render` gives every
 * frame the gaze it had in the viewer.
 *
 * What it does NOT do: text drawn in the window (the title shows the state), camera control by the
 * user (the scene's camera path plays), more than two modes at once, hot reload.
 */
#ifndef FOVSIM_VIEW_H
#define FOVSIM_VIEW_H

#include "cli/cli.h"

/* Runs the viewer until its window is closed (or the script quits). Bad input (scene, trace,
 * script, layout) is rejected before a window opens; no X server / no GL 4.5: FS_ERR_GL. */
fs_status view_run(const run_desc *d);

#endif
