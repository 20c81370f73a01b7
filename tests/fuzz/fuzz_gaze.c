/* fuzz_gaze.c: the gaze trace parsers (gaze_parse), all four formats.
 *
 * Input: one selector byte, then the trace text. The selector picks the gaze_load_desc, so every
 * format's parser runs on every input, not only the one auto-detection would choose:
 *   format = b % 5  (0 auto, 1 fovsim CSV, 2 Pupil Labs, 3 EyeLink ASC, 4 Tobii livedata.json)
 *   eye    = b / 5 % 4  (auto, left, right, average)
 *   min_confidence = {default 0.6, -1 = keep all, 0.95, 1e-6}[b / 20 % 4]
 * Seeds: tests/fuzz/corpus/gaze/ (made by make_corpus.py). To run a file through fovsim itself:
 * `tail -c +2 FILE > trace.csv`, then `--gaze trace.csv --gaze-format NAME`.
 * Checks beyond "no crash": a loaded trace keeps gaze.h's promises (>= 1 sample, times re-based to 0
 * and strictly increasing, duration = last time, valid_count right, finite gaze everywhere, gaze_at
 * clamped to [0, 1]); a refused one is freed and zeroed.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_common.h"
#include "gaze/gaze.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_init();
    if (size < 1)
        return 0;
    static const float conf[4] = {0.0f, -1.0f, 0.95f, 1e-6f};
    const unsigned b = data[0];
    gaze_load_desc desc = {
        .format = (gaze_format)(b % 5),
        .eye = (gaze_eye)(b / 5 % 4),
        .min_confidence = conf[b / 20 % 4],
    };
    /* An exactly sized copy without a terminating NUL: gaze_parse takes a length. */
    size_t n = size - 1;
    char *text = malloc(n ? n : 1);
    FUZZ_CHECK(text != NULL);
    memcpy(text, data + 1, n);

    gaze_trace t;
    fs_status s = gaze_parse(n ? text : NULL, (long)n, "fuzz", &desc, &t);
    free(text);
    if (s != FS_OK) {
        FUZZ_CHECK(s == FS_ERR_GAZE);
        FUZZ_CHECK(t.samples == NULL && t.count == 0);
        return 0;
    }
    FUZZ_CHECK(desc.format == GAZE_FORMAT_AUTO || t.format == desc.format);
    FUZZ_CHECK(t.count >= 1 && t.samples != NULL);
    FUZZ_CHECK(t.samples[0].t == 0.0);
    int valid = 0;
    for (int i = 0; i < t.count; i++) {
        const gaze_sample *g = &t.samples[i];
        FUZZ_CHECK(isfinite(g->t) && isfinite(g->x) && isfinite(g->y));
        FUZZ_CHECK(i == 0 || g->t > t.samples[i - 1].t);
        valid += g->valid;
    }
    FUZZ_CHECK(valid == t.valid_count);
    FUZZ_CHECK(t.duration == t.samples[t.count - 1].t);
    FUZZ_CHECK(isfinite(t.time_offset));

    const double times[] = {-1.0, 0.0, 0.5 * t.duration, t.duration, t.duration + 1.0, 1e300};
    for (size_t k = 0; k < sizeof times / sizeof times[0]; k++) {
        bool end;
        gaze_point p = gaze_at(&t, times[k], &end);
        FUZZ_CHECK(p.x >= 0.0f && p.x <= 1.0f && p.y >= 0.0f && p.y <= 1.0f);
    }
    gaze_free(&t);
    return 0;
}
