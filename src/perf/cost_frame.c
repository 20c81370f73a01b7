/* cost_frame.c: a frame's predicted time (cost_frame.h). */
#include "perf/cost_frame.h"

#include <stdio.h>

#include "core/log.h"

double cost_frame_ms(const cost_model *m, const renderer_stats *rs, const char *mode, char *missing, size_t cap)
{
    double sum = 0.0;
    for (int p = 0; p < rs->pass_count; p++) {
        double x[COST_COUNTS] = {(double)rs->pass_primitives[p], (double)rs->pass_fs_invocations[p],
                                 (double)(rs->pass_bytes_read[p] + rs->pass_bytes_written[p])};
        if (rs->pass_primitives[p] < 0 || rs->pass_fs_invocations[p] < 0 || rs->pass_bytes_read[p] < 0 ||
            rs->pass_bytes_written[p] < 0) {
            if (missing)
                snprintf(missing, cap, "counts of stage '%s' unknown", rs->pass_names[p]);
            return -1.0;
        }
        char name[COST_CLASS_NAME_MAX];
        cost_class_name(cost_kind_of_stage(rs->pass_names[p], rs->pass_geometry[p]), mode, name, sizeof name);
        double ms = cost_model_stage_ms(m, name, x);
        if (ms < 0) {
            if (missing)
                snprintf(missing, cap, "no class '%s' in the model", name);
            return -1.0;
        }
        sum += ms;
    }
    return sum;
}

fs_status cost_predictor_open(cost_predictor *p, const char *path, const char *renderer)
{
    *p = (cost_predictor){.on = path != NULL, .path = path};
    return p->on ? cost_model_load(path, renderer, &p->model) : FS_OK;
}

double cost_predictor_frame_ms(cost_predictor *p, const renderer_stats *rs, const char *mode)
{
    if (!p->on)
        return -1.0;
    char why[160];
    double ms = cost_frame_ms(&p->model, rs, mode, why, sizeof why);
    if (ms < 0 && !p->warned) {
        log_warn("--cost-model %s: %s (bench --calibrate --modes ... fits the alpha modes); no predicted time "
                 "where so, first for %s", p->path, why, mode);
        p->warned = true;
    }
    return ms;
}
