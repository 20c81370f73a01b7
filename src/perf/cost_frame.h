/* cost_frame.h: a frame's predicted time from the stage cost model (cost_model.h) and the
 * renderer's per-stage counts of that frame (renderer_stats: pipeline statistics and footprint
 * bytes), as bench --accuracy, compare and demo report it beside the measured time. */
#ifndef FOVSIM_COST_FRAME_H
#define FOVSIM_COST_FRAME_H

#include "passes/renderer.h"
#include "perf/cost_model.h"

/* The sum of the predictions of rs's stages, drawn with alpha mode `mode` (its name): -1 when a
 * stage's counts are unknown (no pipeline statistics) or the model has no class for it; then
 * `missing` (cap bytes, may be NULL) names the first such class, or says the counts are unknown. */
double cost_frame_ms(const cost_model *m, const renderer_stats *rs, const char *mode, char *missing, size_t cap);

#endif
