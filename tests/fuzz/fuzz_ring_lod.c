/* fuzz_ring_lod.c: the --ring-lod parser (ring_lod_parse; also a scene file's ring LOD string).
 *
 * Input: the text as given on the command line ("off", "simplify", "simplify:area=4",
 * "simplify:1,1,1/4,0.0625").
 * Checks beyond "no crash": a refused text leaves *out alone and says why in one line; an accepted
 * one prints (ring_lod_format) to text that parses back to the same spec, passes ring_lod_check
 * against a layout of as many rings as it has values, and every ring's law keeps the law's
 * promises: weights in [0, 1], scales finite and >= 0, E[g] gain = 1, u = 1 the identity.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fov/ring_lod.h"
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_init();
    if (size > 4096) /* a command-line argument or a scene's string */
        return 0;
    char *text = malloc(size + 1);
    FUZZ_CHECK(text != NULL);
    memcpy(text, data, size);
    text[size] = '\0';

    ring_lod_spec s = {.kind = RING_LOD_EXPLICIT, .count = 77}; /* sentinel: untouched on error */
    char err[256];
    fs_status st = ring_lod_parse(text, &s, err, sizeof err);
    if (st != FS_OK) {
        FUZZ_CHECK(st == FS_ERR_USAGE);
        FUZZ_CHECK(s.kind == RING_LOD_EXPLICIT && s.count == 77);
        FUZZ_CHECK(err[0] != '\0' && memchr(err, '\0', sizeof err) != NULL);
        free(text);
        return 0;
    }
    FUZZ_CHECK(s.kind == RING_LOD_OFF || s.kind == RING_LOD_SCHEDULE || s.kind == RING_LOD_EXPLICIT);

    /* Format -> parse round trip. */
    char buf[512];
    ring_lod_format(&s, buf, sizeof buf);
    ring_lod_spec back;
    FUZZ_CHECK(ring_lod_parse(buf, &back, err, sizeof err) == FS_OK);
    FUZZ_CHECK(back.kind == s.kind && back.count == s.count && ring_lod_area(&back) == ring_lod_area(&s));
    for (int i = 0; i < s.count; i++)
        FUZZ_CHECK(back.u[i] == s.u[i]);

    /* A layout with one ring per value (scales 1, 1/2, ...), or the five-ring default. */
    fov_layout l = fov_layout_off();
    l.kind = FOV_LAYOUT_EXPLICIT;
    l.count = s.kind == RING_LOD_EXPLICIT ? s.count : 5;
    for (int i = 0; i < l.count; i++) {
        l.rings[i].outer_deg = i == l.count - 1 ? INFINITY : 10.0f * (float)(i + 1);
        l.rings[i].scale_log2 = i < MAX_FOV_SCALE_LOG2 ? i : MAX_FOV_SCALE_LOG2;
        l.rings[i].mip_bias = 0.0f;
    }
    FUZZ_CHECK(ring_lod_check(&s, &l, err, sizeof err) == FS_OK);
    for (int i = 0; i < l.count; i++) {
        float u = ring_lod_u(&s, &l, i);
        FUZZ_CHECK(u > 0.0f && u <= 1.0f);
        ring_lod_law law = ring_lod_ring_law(&s, &l, i);
        FUZZ_CHECK(ring_lod_law_is_identity(&law) == (u == 1.0f));
        FUZZ_CHECK(isfinite(law.a) && isfinite(law.k) && law.k >= 0.0f && isfinite(law.gain) && law.gain >= 1.0f);
        FUZZ_CHECK(fabs(ring_lod_expected_weight(law.a, law.k) * law.gain - 1.0) < 1e-5);
        for (int j = 0; j <= 16; j++) {
            float r = j == 16 ? 1.0f - 0x1p-24f : (float)j / 16.0f;
            float g = ring_lod_weight(&law, r), sc = ring_lod_scale(&law, r);
            FUZZ_CHECK(g >= 0.0f && g <= 1.0f && isfinite(sc) && sc >= 0.0f);
        }
    }
    free(text);
    return 0;
}
