/* Unit tests of the stage cost model (src/perf/cost_model.c): exact recovery of known
 * coefficients, collinear terms, data whose least-squares fit would be negative (checked against
 * the optimality conditions of non-negative least squares), too few samples, stage kinds from
 * names, the JSON round trip, malformed model files (one line naming the file and JSON path), and a
 * frame's prediction from its stages (src/perf/cost_frame.c). */
#include <math.h>
#include <string.h>

#include "core/log.h"
#include "perf/cost_frame.h"
#include "perf/cost_model.h"
#include "test.h"

/* A deterministic pseudo-random number in [0, 1). */
static double rnd(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (double)(*state >> 8) / 16777216.0;
}

/* n samples of kind k with counts spread over decades, timed by coef exactly. */
static void synth(cost_sample *s, int n, int k, const double coef[COST_TERMS], unsigned seed)
{
    for (int i = 0; i < n; i++) {
        s[i].cls = k;
        s[i].x[COST_PRIMS] = 1000.0 + 50000.0 * rnd(&seed);
        s[i].x[COST_INV] = 1e4 + 2e6 * rnd(&seed);
        s[i].x[COST_BYTES] = 1e5 + 3e7 * rnd(&seed);
        s[i].ms = cost_predict(coef, s[i].x);
    }
}

TEST(recovers_known_coefficients)
{
    const double coef[COST_TERMS] = {2e-4, 3e-6, 1.5e-7, 0.4};
    cost_sample s[40];
    synth(s, 40, 0, coef, 7u);
    double got[COST_TERMS];
    char err[160];
    CHECK(cost_fit_class(s, 40, 0, got, err, sizeof err));
    for (int j = 0; j < COST_TERMS; j++)
        CHECK_NEAR(got[j] / coef[j], 1.0, 1e-9);
    cost_error e = cost_errors(s, 40, 0, got);
    CHECK(e.n == 40 && e.max < 1e-9);
}

TEST(other_kinds_are_ignored)
{
    const double a[COST_TERMS] = {1e-4, 0, 0, 0.2}, b[COST_TERMS] = {0, 5e-6, 0, 1.0};
    cost_sample s[30];
    synth(s, 15, 1, a, 3u);
    synth(s + 15, 15, 2, b, 4u);
    double got[COST_TERMS];
    char err[160];
    CHECK(cost_fit_class(s, 30, 2, got, err, sizeof err));
    for (int j = 0; j < COST_TERMS; j++)
        CHECK_NEAR(got[j], b[j], 1e-9 * (b[j] + 1e-6));
}

TEST(collinear_terms_predict_exactly)
{
    /* Full-screen stages: invocations proportional to bytes. The four-term problem is singular;
     * a smaller subset fits exactly. */
    const double coef[COST_TERMS] = {0, 2e-6, 1e-7, 0.3};
    cost_sample s[20];
    synth(s, 20, 2, coef, 11u);
    for (int i = 0; i < 20; i++) {
        s[i].x[COST_BYTES] = 24.0 * s[i].x[COST_INV];
        s[i].x[COST_PRIMS] = 1.0;
        s[i].ms = cost_predict(coef, s[i].x);
    }
    double got[COST_TERMS];
    char err[160];
    CHECK(cost_fit_class(s, 20, 2, got, err, sizeof err));
    for (int j = 0; j < COST_TERMS; j++)
        CHECK(got[j] >= 0.0 && isfinite(got[j]));
    CHECK_NEAR(got[COST_INV] + 24.0 * got[COST_BYTES] + got[COST_PRIMS], coef[COST_INV] + 24.0 * coef[COST_BYTES],
               1e-12);
    CHECK(cost_errors(s, 20, 2, got).max < 1e-9);
}

/* The gradient of sum((z·c - 1)²)/2 over the samples, per term (rows z scaled by 1/t), divided by
 * the term's column sum of |z| so that terms of any magnitude compare. */
static void gradient(const cost_sample *s, int n, const double c[COST_TERMS], double g[COST_TERMS])
{
    double col[COST_TERMS] = {0};
    memset(g, 0, sizeof(double) * COST_TERMS);
    for (int i = 0; i < n; i++) {
        double r = cost_predict(c, s[i].x) / s[i].ms - 1.0;
        for (int j = 0; j < COST_TERMS; j++) {
            double z = (j == COST_CONST ? 1.0 : s[i].x[j]) / s[i].ms;
            g[j] += r * z;
            col[j] += fabs(z);
        }
    }
    for (int j = 0; j < COST_TERMS; j++)
        g[j] /= col[j];
}

TEST(negative_coefficients_are_clamped_optimally)
{
    /* Time falls with invocations in this data: least squares would make b negative. */
    const double coef[COST_TERMS] = {3e-4, 0, 2e-7, 5.0};
    cost_sample s[30];
    synth(s, 30, 3, coef, 5u);
    unsigned seed = 99u;
    for (int i = 0; i < 30; i++)
        s[i].ms -= 1e-6 * s[i].x[COST_INV] * (0.5 + 0.5 * rnd(&seed));
    double got[COST_TERMS], g[COST_TERMS];
    char err[160];
    CHECK(cost_fit_class(s, 30, 3, got, err, sizeof err));
    CHECK(got[COST_INV] == 0.0);
    /* Karush-Kuhn-Tucker: zero gradient on the positive terms, non-negative on the zero ones. */
    gradient(s, 30, got, g);
    for (int j = 0; j < COST_TERMS; j++) {
        CHECK(got[j] >= 0.0);
        if (got[j] > 0.0)
            CHECK(fabs(g[j]) < 1e-9);
        else
            CHECK(g[j] > 1e-6); /* strictly: moving the term off zero would cost */
    }
}

TEST(too_few_samples_is_an_error)
{
    const double coef[COST_TERMS] = {1e-4, 1e-6, 1e-7, 0.1};
    cost_sample s[COST_MIN_SAMPLES];
    synth(s, COST_MIN_SAMPLES, 1, coef, 1u);
    s[0].ms = 0.0; /* a timer that read zero is not a sample */
    double got[COST_TERMS];
    char err[160] = "";
    CHECK(!cost_fit_class(s, COST_MIN_SAMPLES, 1, got, err, sizeof err));
    CHECK(strstr(err, "4 samples") && strstr(err, "at least"));
    cost_model m = {.bound = 0.25, .count = 2, .cls = {{.name = "ring/hashed"}, {.name = "taa"}}};
    CHECK(!cost_model_fit(&m, s, COST_MIN_SAMPLES, s, COST_MIN_SAMPLES, err, sizeof err));
    CHECK(!m.cls[1].fitted && strstr(err, "taa: 4 samples"));
}

TEST(stage_kinds_from_names)
{
    CHECK(cost_kind_of_stage("ring 0 (1/1, all passes)", true) == COST_KIND_RING);
    CHECK(cost_kind_of_stage("forward.mask[hashed]", true) == COST_KIND_FORWARD);
    CHECK(cost_kind_of_stage("ring 2 taa resolve", false) == COST_KIND_TAA);
    CHECK(cost_kind_of_stage("taa resolve", false) == COST_KIND_TAA);
    CHECK(cost_kind_of_stage("composite", false) == COST_KIND_COMPOSITE);
    CHECK(cost_kind_of_stage("list resolve", false) == COST_KIND_FULLSCREEN);
    char name[COST_CLASS_NAME_MAX];
    cost_class_name(COST_KIND_RING, "hashed", name, sizeof name);
    CHECK(strcmp(name, "ring/hashed") == 0);
    cost_class_name(COST_KIND_TAA, "hashed", name, sizeof name);
    CHECK(strcmp(name, "taa") == 0);
}

/* A fitted model of two kinds, held-out errors from other synthetic samples with noise. */
static cost_model fitted_model(void)
{
    const double a[COST_TERMS] = {2e-4, 3e-6, 1e-7, 0.5}, b[COST_TERMS] = {0, 1e-6, 2e-8, 0.1};
    cost_sample fit[40], held[40];
    synth(fit, 20, 0, a, 1u);
    synth(fit + 20, 20, 1, b, 2u);
    synth(held, 20, 0, a, 3u);
    synth(held + 20, 20, 1, b, 4u);
    for (int i = 0; i < 40; i++)
        held[i].ms *= 1.0 + 0.1 * (i % 3 - 1); /* errors 0, 0.1 / 1.1 and 0.1 / 0.9 */
    cost_model m = {.bound = 0.25, .count = 3, .cls = {{.name = "ring/hashed"}, {.name = "taa"}, {.name = "composite"}}};
    snprintf(m.renderer, sizeof m.renderer, "llvmpipe (LLVM 15.0.6, 256 bits)");
    snprintf(m.time_source, sizeof m.time_source, COST_TIME_WALL);
    char err[160];
    CHECK(!cost_model_fit(&m, fit, 40, held, 40, err, sizeof err)); /* composite: no samples */
    CHECK(strstr(err, "composite: 0 samples") != NULL);
    return m;
}

TEST(model_errors_and_bound)
{
    cost_model m = fitted_model();
    CHECK(m.cls[0].fitted && m.cls[1].fitted && !m.cls[2].fitted);
    CHECK(m.cls[0].fit.max < 1e-9);
    CHECK_NEAR(m.cls[0].held.max, 0.1 / 0.9, 1e-9);
    CHECK(m.cls[0].held.n == 20);
    char over[64];
    CHECK(cost_model_over_bound(&m, over, sizeof over) == 0 && over[0] == '\0');
    m.bound = 0.05;
    CHECK(cost_model_over_bound(&m, over, sizeof over) == 2 && strcmp(over, "ring/hashed, taa") == 0);
    double x[COST_COUNTS] = {1, 2, 3};
    CHECK(cost_model_stage_ms(&m, "composite", x) == -1.0);
    CHECK(cost_model_stage_ms(&m, "ring/traditional", x) == -1.0);
    CHECK(cost_model_stage_ms(&m, "taa", x) > 0.0);
}

TEST(json_round_trip)
{
    cost_model m = fitted_model(), back;
    char *text = cost_model_json(&m), err[256];
    CHECK(text != NULL);
    CHECK(cost_model_parse(text, "m.json", &back, err, sizeof err) == FS_OK);
    CHECK(strcmp(back.renderer, m.renderer) == 0 && strcmp(back.time_source, COST_TIME_WALL) == 0);
    CHECK_NEAR(back.bound, m.bound, 1e-9);
    CHECK(back.count == 2); /* the unfitted class is not written */
    for (int k = 0; k < back.count; k++) {
        CHECK(strcmp(back.cls[k].name, m.cls[k].name) == 0 && back.cls[k].fitted);
        for (int j = 0; j < COST_TERMS; j++)
            CHECK_NEAR(back.cls[k].coef[j], m.cls[k].coef[j], 1e-8 * fabs(m.cls[k].coef[j]));
        CHECK(back.cls[k].held.n == m.cls[k].held.n);
    }
    free(text);
}

/* Parses text (with `from` replaced by `to` in the written model) and expects an error whose text
 * names the file and `jpath`, on one line. */
static void expect_bad(const char *from, const char *to, const char *jpath)
{
    cost_model m = fitted_model(), back;
    char *text = cost_model_json(&m), err[256] = "", buf[4096];
    char *at = strstr(text, from);
    CHECK(at != NULL);
    if (!at) {
        free(text);
        return;
    }
    snprintf(buf, sizeof buf, "%.*s%s%s", (int)(at - text), text, to, at + strlen(from));
    CHECK(cost_model_parse(buf, "dir/model.json", &back, err, sizeof err) == FS_ERR_USAGE);
    CHECK(strncmp(err, "dir/model.json: ", 16) == 0);
    CHECK(strstr(err, jpath) != NULL);
    CHECK(strchr(err, '\n') == NULL);
    if (!strstr(err, jpath))
        fprintf(stderr, "  got: %s\n", err);
    free(text);
}

TEST(malformed_models_are_refused)
{
    expect_bad("\"format\": \"fovsim cost model\"", "\"format\": \"x\"", "format");
    expect_bad("\"version\": 1", "\"version\": 2", "version");
    expect_bad("\"renderer\": \"", "\"renderer\": 3, \"x\": \"", "renderer");
    expect_bad("\"time_source\": \"wall_synced\"", "\"time_source\": \"sundial\"", "time_source");
    expect_bad("\"bound_held_out_p90\": 0.25", "\"bound_held_out_p90\": -1", "bound_held_out_p90");
    expect_bad("\"ring/hashed\": {", "\"rings/hashed\": {", "classes.rings/hashed");
    expect_bad("\"ring/hashed\": {", "\"ring/\": {", "classes.ring/");
    expect_bad("\"taa\": {", "\"taa/hashed\": {", "classes.taa/hashed");
    expect_bad("\"taa\": {", "\"ring/hashed\": {", "each class once");
    expect_bad("\"per_byte\": ", "\"per_byte\": -", "classes.ring/hashed.coefficients_ms.per_byte");
    expect_bad("\"per_stage\": ", "\"per_stage\": \"x\", \"y\": ", "classes.ring/hashed.coefficients_ms.per_stage");
    expect_bad("\"held_out_error\": {\"samples\": 20", "\"held_out_error\": {\"samples\": 2.5",
               "classes.ring/hashed.held_out_error");
    expect_bad("\"fit_error\": {", "\"fit_error\": 1, \"z\": {", "classes.ring/hashed.fit_error");
    expect_bad("\n  }\n}", "\n  }\n", "(top level)");
    cost_model back;
    char err[256];
    CHECK(cost_model_parse("[]", "a.json", &back, err, sizeof err) == FS_ERR_USAGE && strstr(err, "a.json: "));
    CHECK(cost_model_parse("{\"format\": \"fovsim cost model\", \"version\": 1, \"renderer\": \"r\", \"time_source\": "
                           "\"gl_timer\", \"bound_held_out_p90\": 0.2, \"classes\": {}}",
                           "a.json", &back, err, sizeof err) == FS_ERR_USAGE &&
          strstr(err, "classes"));
}

/* A frame's stages as the renderer names them: ring 0's passes, its TAA resolve, the composite. */
static renderer_stats frame_stats(void)
{
    renderer_stats rs = {.pass_count = 3};
    const char *names[3] = {"ring 0 (1/1, all passes)", "ring 0 taa resolve", "composite"};
    for (int p = 0; p < 3; p++) {
        snprintf(rs.pass_names[p], sizeof rs.pass_names[p], "%s", names[p]);
        rs.pass_geometry[p] = p == 0;
        rs.pass_primitives[p] = p == 0 ? 20000 : 1;
        rs.pass_fs_invocations[p] = 100000 * (p + 1);
        rs.pass_bytes_read[p] = 300000;
        rs.pass_bytes_written[p] = 100000 * (p + 1);
    }
    return rs;
}

TEST(frame_prediction_sums_the_stages_classes)
{
    cost_model m = {.bound = 0.25, .count = 3,
                    .cls = {{.name = "ring/hashed", .fitted = true, .coef = {1e-4, 1e-5, 1e-6, 0.5}},
                            {.name = "taa", .fitted = true, .coef = {0, 2e-5, 0, 0.1}},
                            {.name = "composite", .fitted = true, .coef = {0, 0, 3e-6, 0.2}}}};
    renderer_stats rs = frame_stats();
    double want = (1e-4 * 20000 + 1e-5 * 100000 + 1e-6 * 400000 + 0.5) + (2e-5 * 200000 + 0.1) +
                  (3e-6 * 600000 + 0.2);
    char why[160] = "";
    CHECK_NEAR(cost_frame_ms(&m, &rs, "hashed", why, sizeof why), want, 1e-9);
    /* A mode the model was not calibrated for: unknown, and which class is missing. */
    CHECK(cost_frame_ms(&m, &rs, "stochastic", why, sizeof why) == -1.0);
    CHECK(strstr(why, "ring/stochastic") != NULL);
    /* Without pipeline statistics the counts are unknown (-1): so is the prediction. */
    rs.pass_fs_invocations[1] = -1;
    CHECK(cost_frame_ms(&m, &rs, "hashed", why, sizeof why) == -1.0);
    CHECK(strstr(why, "ring 0 taa resolve") != NULL);
}

int main(void)
{
    log_set_quiet_errors(true);
    RUN(recovers_known_coefficients);
    RUN(other_kinds_are_ignored);
    RUN(collinear_terms_predict_exactly);
    RUN(negative_coefficients_are_clamped_optimally);
    RUN(too_few_samples_is_an_error);
    RUN(stage_kinds_from_names);
    RUN(model_errors_and_bound);
    RUN(json_round_trip);
    RUN(malformed_models_are_refused);
    RUN(frame_prediction_sums_the_stages_classes);
    return test_summary();
}
