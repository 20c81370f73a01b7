/* fuzz_check_merge.c: the readers of files fovsim reads back from its own runs (docs/cluster.md, docs/check.md): merge's
 * task metrics.csv and summary.json (merge_check_metrics, merge_parse_summary) and check's baseline
 * check.json (check_baseline_parse, after cJSON).
 *
 * Input: one selector byte, then the file. b % 3: 0 = a task's metrics.csv, 1 = its summary.json,
 * 2 = a baseline's check.json.
 * Checks beyond "no crash": each reader returns FS_OK or its one refusal status; a refused summary
 * leaves *out NULL, an accepted one is a JSON object; an accepted baseline has 1..CHECK_MAX_ARGS
 * compare options, "compare" first, none of them one a baseline never stores (--cache, --gpu, ...),
 * and finite non-negative tolerances (or off = infinity). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "commands/check.h"
#include "commands/merge.h"
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_init();
    if (size < 1 || size > (1u << 16))
        return 0;
    size_t n = size - 1;
    char *text = malloc(n + 1); /* NUL-terminated at text[n], as file_read_all reads a file */
    FUZZ_CHECK(text != NULL);
    memcpy(text, data + 1, n);
    text[n] = '\0';
    switch (data[0] % 3) {
    case 0: {
        fs_status st = merge_check_metrics("metrics.csv", text, n);
        FUZZ_CHECK(st == FS_OK || st == FS_ERR_IO);
        break;
    }
    case 1: {
        cJSON *j = (cJSON *)1;
        fs_status st = merge_parse_summary("summary.json", text, n, &j);
        FUZZ_CHECK(st == FS_OK ? cJSON_IsObject(j) : st == FS_ERR_IO && j == NULL);
        cJSON_Delete(j);
        break;
    }
    default: {
        cJSON *root = cJSON_ParseWithLength(text, n);
        if (!root)
            break;
        const char *argv[CHECK_MAX_ARGS];
        int argc = 0;
        check_tols t;
        const char *version = NULL;
        fs_status st = check_baseline_parse("baseline", root, argv, &argc, &t, &version);
        FUZZ_CHECK(st == FS_OK || st == FS_ERR_USAGE);
        if (st == FS_OK) {
            FUZZ_CHECK(argc >= 1 && argc <= CHECK_MAX_ARGS && !strcmp(argv[0], "compare") && version != NULL);
            static const char *const never[] = {"--cache", "--gpu", "--out", "--no-cache"};
            for (int i = 1; i < argc; i++)
                for (size_t k = 0; k < sizeof never / sizeof never[0]; k++) {
                    size_t l = strlen(never[k]);
                    FUZZ_CHECK(!(strncmp(argv[i], never[k], l) == 0 && (argv[i][l] == '\0' || argv[i][l] == '=')));
                }
            for (int m = 0; m < CHECK_METRIC_COUNT; m++) {
                const check_tol *c = &t.t[m];
                FUZZ_CHECK(!(c->any < 0.0) && !isnan(c->any));
                FUZZ_CHECK(isnan(c->all) || c->all >= 0.0);
                for (int r = 0; r < MAX_FOV_RINGS; r++)
                    FUZZ_CHECK(isnan(c->ring[r]) || c->ring[r] >= 0.0);
            }
        }
        cJSON_Delete(root);
        break;
    }
    }
    free(text);
    return 0;
}
