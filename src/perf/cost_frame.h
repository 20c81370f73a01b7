/* cost_frame.h: a frame's predicted time from the stage cost model (cost_model.h) and the
 * renderer's per-stage counts of that frame (renderer_stats: pipeline statistics and footprint
 * bytes), as bench --accuracy, compare and demo report it beside the measured time. */
#ifndef FOVSIM_COST_FRAME_H
#define FOVSIM_COST_FRAME_H

#include <stdbool.h>

#include "core/status.h"
#include "passes/renderer.h"
#include "perf/cost_model.h"

/* The sum of the predictions of rs's stages, drawn with alpha mode `mode` (its name): -1 when a
 * stage's counts are unknown (no pipeline statistics) or the model has no class for it; then
 * `missing` (cap bytes, may be NULL) names the first such class, or says the counts are unknown. */
double cost_frame_ms(const cost_model *m, const renderer_stats *rs, const char *mode, char *missing, size_t cap);

/* A --cost-model as a command uses it: loaded once (or none), a prediction per frame, and the first
 * reason a prediction is unknown said once. */
typedef struct cost_predictor {
    bool on;          /* a model was given */
    const char *path; /* its file, for messages */
    bool warned;      /* a prediction was unknown, and that was said */
    cost_model model;
} cost_predictor;
/* No model when path is NULL (FS_OK); else cost_model_load's checks and refusals for `renderer`. */
fs_status cost_predictor_open(cost_predictor *p, const char *path, const char *renderer);
/* The frame's predicted ms (cost_frame_ms), -1 without a model or where unknown: the first such
 * frame warns, naming the model, why and the mode. */
double cost_predictor_frame_ms(cost_predictor *p, const renderer_stats *rs, const char *mode);

#endif
