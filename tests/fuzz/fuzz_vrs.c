/* fuzz_vrs.c: the --vrs parser (vrs_spec_parse; also a scene file's "vrs") and the rate map.
 *
 * Input: the rate map's text as given on the command line ("auto", "10:1x1,25:2x2,*:4x4").
 * Checks beyond "no crash": a refused map leaves *out alone and says why; an accepted one prints
 * (vrs_spec_format, as `fovsim plan` does) to text that parses back to the same bands, and its maps
 * (small displays, every tile size, gaze at the centre, a corner, off the display and NaN) hold only
 * the seven rates, an explicit map's only its bands' rates, and statistics that sum to the display.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fov/vrs_map.h"
#include "fuzz_common.h"

static bool same_spec(const vrs_spec *a, const vrs_spec *b)
{
    if (a->is_auto != b->is_auto || (!a->is_auto && a->count != b->count))
        return false;
    for (int i = 0; !a->is_auto && i < a->count; i++)
        if (a->outer_deg[i] != b->outer_deg[i] || a->rate[i] != b->rate[i])
            return false;
    return true;
}

static void check_map(const display_desc *d, const vrs_spec *s, int tile, float gx, float gy)
{
    int nx, ny;
    vrs_tile_grid(d, tile, &nx, &ny);
    vrs_rate *rates = malloc((size_t)nx * (size_t)ny);
    FUZZ_CHECK(rates != NULL);
    vrs_map_fill(d, s, tile, gx, gy, rates);
    for (int i = 0; i < nx * ny; i++) {
        FUZZ_CHECK(vrs_rate_index(rates[i]) >= 0);
        bool in_bands = s->is_auto;
        for (int k = 0; !s->is_auto && k < s->count; k++)
            in_bands |= rates[i] == s->rate[k];
        FUZZ_CHECK(in_bands);
    }
    vrs_stats st = vrs_map_stats(d, tile, rates);
    long long px = 0;
    for (int i = 0; i < VRS_RATE_COUNT; i++)
        px += st.pixels[i];
    FUZZ_CHECK(px == (long long)d->width * d->height);
    FUZZ_CHECK(st.saving >= 0.0 && st.saving <= 15.0 / 16.0 + 1e-12);
    free(rates);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_init();
    if (size > 4096) /* a command-line argument or a scene's "vrs" string (127 bytes) */
        return 0;
    char *text = malloc(size + 1);
    FUZZ_CHECK(text != NULL);
    memcpy(text, data, size);
    text[size] = '\0';

    vrs_spec s = {.is_auto = false, .count = 77}; /* sentinel: untouched on error */
    char err[256];
    fs_status st = vrs_spec_parse(text, &s, err, sizeof err);
    if (st != FS_OK) {
        FUZZ_CHECK(st == FS_ERR_USAGE);
        FUZZ_CHECK(!s.is_auto && s.count == 77);
        FUZZ_CHECK(err[0] != '\0' && memchr(err, '\0', sizeof err) != NULL);
        free(text);
        return 0;
    }
    FUZZ_CHECK(s.is_auto || (s.count >= 1 && s.count <= VRS_MAX_BANDS && isinf(s.outer_deg[s.count - 1])));

    char buf[1024];
    vrs_spec_format(&s, buf, sizeof buf);
    vrs_spec back;
    FUZZ_CHECK(vrs_spec_parse(buf, &back, err, sizeof err) == FS_OK);
    FUZZ_CHECK(same_spec(&s, &back));

    /* Small displays keep the per-tile work cheap; the wide one reaches large eccentricities. */
    static const display_desc displays[] = {{97, 61, 90.0f, 0.0f, 0.0f}, {64, 48, 170.0f, 0.0f, 0.0f}};
    const display_desc *d = &displays[size % 2];
    static const int tiles[] = {8, 16, 32};
    const float w = (float)d->width, h = (float)d->height;
    check_map(d, &s, tiles[size % 3], 0.5f * w, 0.5f * h);
    check_map(d, &s, tiles[(size + 1) % 3], 0.0f, h);
    check_map(d, &s, tiles[(size + 2) % 3], -3.0f * w, 0.25f * h);
    check_map(d, &s, 16, NAN, INFINITY);
    free(text);
    return 0;
}
