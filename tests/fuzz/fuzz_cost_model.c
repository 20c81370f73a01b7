/* fuzz_cost_model.c: the --cost-model file parser (cost_model_parse, docs/benchmarks.md "Cost model").
 *
 * Input: a model file's text (JSON as bench --calibrate writes it).
 * Checks beyond "no crash": a refused text says why in a message that names the file (it quotes
 * class names as the file spells them: log_error escapes control bytes when printing); an accepted
 * one has a class count in range, NUL-terminated names, coefficients that are finite and >= 0, and
 * it writes back (cost_model_json) to text that parses to the same classes and coefficients; a
 * prediction from it on finite counts is finite (or -1 for a class it has no fit for).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_common.h"
#include "perf/cost_model.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_init();
    if (size > 65536)
        return 0;
    char *text = malloc(size + 1);
    FUZZ_CHECK(text != NULL);
    memcpy(text, data, size);
    text[size] = '\0';

    static cost_model m, back; /* large: not on the stack */
    char err[512];
    fs_status st = cost_model_parse(text, "fuzz.json", &m, err, sizeof err);
    free(text);
    if (st != FS_OK) {
        FUZZ_CHECK(st == FS_ERR_USAGE);
        FUZZ_CHECK(memchr(err, '\0', sizeof err) != NULL && strncmp(err, "fuzz.json", 9) == 0);
        return 0;
    }
    FUZZ_CHECK(m.count >= 0 && m.count <= COST_MAX_CLASSES);
    FUZZ_CHECK(memchr(m.renderer, '\0', sizeof m.renderer) != NULL);
    for (int c = 0; c < m.count; c++) {
        FUZZ_CHECK(memchr(m.cls[c].name, '\0', sizeof m.cls[c].name) != NULL);
        for (int k = 0; k < COST_TERMS; k++)
            FUZZ_CHECK(!m.cls[c].fitted || (isfinite(m.cls[c].coef[k]) && m.cls[c].coef[k] >= 0.0));
    }
    /* Write -> parse round trip. */
    char *json = cost_model_json(&m);
    FUZZ_CHECK(json != NULL);
    FUZZ_CHECK(cost_model_parse(json, "back.json", &back, err, sizeof err) == FS_OK);
    free(json);
    FUZZ_CHECK(back.count == m.count && strcmp(back.renderer, m.renderer) == 0);
    for (int c = 0; c < m.count; c++) {
        FUZZ_CHECK(strcmp(back.cls[c].name, m.cls[c].name) == 0 && back.cls[c].fitted == m.cls[c].fitted);
        const double x[COST_COUNTS] = {1000.0, 1e6, 1e7};
        double a = cost_model_stage_ms(&m, m.cls[c].name, x);
        FUZZ_CHECK(a == -1.0 || (isfinite(a) && a >= 0.0));
    }
    return 0;
}
