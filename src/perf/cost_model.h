/* cost_model.h: a per-device cost model of the renderer's stages (docs/benchmarks.md "Cost model"):
 * per stage kind, time ≈ a·primitives + b·invocations + c·bytes + d, fitted by non-negative least
 * squares on relative error from samples `fovsim bench --calibrate` measures, checked on samples
 * of configurations the fit did not see, and kept as a small JSON file with the renderer string it
 * was measured on. Pure C: no GL; the unit tests call it directly.
 *
 * What it does NOT do: measure (bench_calibrate.c does), or know which stage is which beyond its
 * name (cost_kind_of_stage). */
#ifndef FOVSIM_COST_MODEL_H
#define FOVSIM_COST_MODEL_H

#include <stdbool.h>
#include <stddef.h>

#include "core/status.h"

/* The terms of the model, in coefficient order: primitives submitted, fragment-shader invocations,
 * bytes read + written (footprints), and a constant per stage. */
enum { COST_PRIMS, COST_INV, COST_BYTES, COST_CONST, COST_TERMS };
#define COST_COUNTS 3 /* the terms that are counts (all but the constant) */

/* Stage kinds. Rings off: each forward pass is a stage ("forward"); rings on: each ring's passes
 * together ("ring"). TAA resolves, the composite, and other full-screen stages (the exact
 * reference's list resolve). The model fits one class per kind, and the two kinds that draw the
 * scene once per alpha mode ("ring/hashed"): a mode's test costs its own per fragment. */
typedef enum cost_kind {
    COST_KIND_FORWARD,
    COST_KIND_RING,
    COST_KIND_TAA,
    COST_KIND_COMPOSITE,
    COST_KIND_FULLSCREEN,
    COST_KINDS
} cost_kind;

/* Samples a class needs to be fitted; fewer is an error. */
#define COST_MIN_SAMPLES 5
/* The default bound on the held-out p90 relative error (docs/benchmarks.md "Cost model" says why). */
#define COST_BOUND_DEFAULT 0.25

/* The most classes a model holds. */
#define COST_MAX_CLASSES 48
#define COST_CLASS_NAME_MAX 48
/* The largest coefficient a model file may hold (ms per primitive, invocation, byte or stage). */
#define COST_MAX_COEF_MS 1000.0

/* One measured stage: its class (an index the caller gives), counts (COST_PRIMS .. COST_BYTES)
 * and time (ms). */
typedef struct cost_sample {
    int cls;
    double x[COST_COUNTS];
    double ms;
} cost_sample;

/* Relative errors |predicted - measured| / measured over a set of samples; n = 0: none (-1s). */
typedef struct cost_error {
    int n;
    double median, p90, max;
} cost_error;

/* One class's model. */
typedef struct cost_fit {
    char name[COST_CLASS_NAME_MAX]; /* cost_class_name */
    bool fitted;
    double coef[COST_TERMS]; /* ms per primitive, per invocation, per byte; ms per stage */
    cost_error fit, held;    /* on the samples fitted, on the held-out ones */
} cost_fit;

typedef struct cost_model {
    char renderer[160];    /* GL_RENDERER of the device it was measured on */
    char time_source[32];  /* COST_TIME_WALL or COST_TIME_GL */
    double bound;          /* the held-out p90 relative error above which a class is refused */
    int count;             /* classes */
    cost_fit cls[COST_MAX_CLASSES];
} cost_model;

#define COST_TIME_WALL "wall_synced" /* each stage's wall clock with a glFinish around it */
#define COST_TIME_GL "gl_timer"      /* GL_TIME_ELAPSED queries */

/* "forward", "ring", "taa", "composite", "fullscreen". */
const char *cost_kind_name(cost_kind k);
/* The kind of a renderer stage from its name (renderer_stats.pass_names) and whether it draws the
 * scene (pass_geometry). */
cost_kind cost_kind_of_stage(const char *name, bool geometry);
/* The class of a stage of kind k drawn with alpha mode `mode`: "ring/hashed", "forward/traditional";
 * the kind's name for full-screen kinds. */
void cost_class_name(cost_kind k, const char *mode, char *out, size_t cap);

/* Fits class `cls` on its samples in s[0..n): the non-negative coefficients minimising the sum of
 * squared relative errors (an exhaustive search over the subsets of terms, which is exact for four
 * terms and handles collinear ones). Fewer than COST_MIN_SAMPLES samples of the class with a
 * positive time, or no subset that can be solved: false and a reason in err. */
bool cost_fit_class(const cost_sample *s, int n, int cls, double coef[COST_TERMS], char *err, size_t cap);
/* coef · (x, 1). */
double cost_predict(const double coef[COST_TERMS], const double x[COST_COUNTS]);
/* The relative errors of coef on the samples of class cls (those with a positive time). */
cost_error cost_errors(const cost_sample *s, int n, int cls, const double coef[COST_TERMS]);

/* Fits classes 0 .. m->count - 1 (their names set by the caller) on their samples in `fit` and
 * measures them on `held`. A class with too few samples to fit is left unfitted and named in err
 * (the others are still fitted): false. */
bool cost_model_fit(cost_model *m, const cost_sample *fit, int nfit, const cost_sample *held, int nheld,
                    char *err, size_t cap);
/* The class named `name`, -1 when the model has none. */
int cost_model_find(const cost_model *m, const char *name);
/* The fitted classes whose held-out p90 exceeds the bound, or that have no held-out sample, named
 * in `out` (comma separated; "" when none). Returns how many. */
int cost_model_over_bound(const cost_model *m, char *out, size_t cap);

/* The model as JSON text (malloc'd; NULL when out of memory). */
char *cost_model_json(const cost_model *m);
/* Writes it to path atomically; one line on failure. */
fs_status cost_model_write(const cost_model *m, const char *path);
/* Parses a model; on bad input one line in err naming `path` and the JSON path, FS_ERR_USAGE (a bad
 * --cost-model). */
fs_status cost_model_parse(const char *text, const char *path, cost_model *m, char *err, size_t cap);
/* Reads and parses `path`, and refuses (one line, FS_ERR_USAGE) a model measured on another
 * renderer than `renderer` or with a class over its bound. */
fs_status cost_model_load(const char *path, const char *renderer, cost_model *m);
/* The predicted time (ms) of a stage of class `name`, -1 when the model has no fit for it. */
double cost_model_stage_ms(const cost_model *m, const char *name, const double x[COST_COUNTS]);

#endif
