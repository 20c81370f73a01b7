/* cost_frame.c: a frame's predicted time (cost_frame.h). */
#include "perf/cost_frame.h"

#include <stdio.h>

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
