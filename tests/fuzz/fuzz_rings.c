/* fuzz_rings.c: the --rings parser (fov_layout_parse; also a scene file's "rings").
 *
 * Input: the layout text as given on the command line ("10:1:0,25:1/2:0,*:1/4:0", "auto", "off").
 * Checks beyond "no crash": a refused layout leaves *out alone and says why; an accepted
 * one passes fov_layout_check, prints (fov_layout_format, as in EXR headers) to text that parses
 * back to the same rings, and its footprints, blend weights and composite tiles keep the
 * guarantees fov_ring.h states, for gaze at the centre, a corner, off the display and NaN.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fov/fov_ring.h"
#include "fuzz_common.h"

static bool same_rings(const fov_layout *a, const fov_layout *b)
{
    if (a->count != b->count)
        return false;
    for (int i = 0; i < a->count; i++)
        if (a->rings[i].outer_deg != b->rings[i].outer_deg || a->rings[i].scale_log2 != b->rings[i].scale_log2 ||
            a->rings[i].mip_bias != b->rings[i].mip_bias)
            return false;
    return true;
}

static void check_footprints(const display_desc *d, const fov_layout *l, float gx, float gy)
{
    fov_ring_rect prev = {0};
    for (int i = 0; i < l->count; i++) {
        fov_ring_rect r = fov_ring_footprint(d, l, i, gx, gy, FOV_MARGIN_BLOCKS);
        FUZZ_CHECK(r.block == 1 << l->rings[i].scale_log2);
        FUZZ_CHECK(r.x0 >= 0 && r.y0 >= 0 && r.x0 < r.x1 && r.y0 < r.y1);
        FUZZ_CHECK(r.x0 % r.block == 0 && r.y0 % r.block == 0);
        FUZZ_CHECK(r.x1 - d->width < r.block && r.y1 - d->height < r.block);
        FUZZ_CHECK(r.width >= 1 && r.height >= 1);
        FUZZ_CHECK(r.width == (r.x1 - r.x0) / r.block && r.height == (r.y1 - r.y0) / r.block);
        if (i > 0) /* frusta nest */
            FUZZ_CHECK(r.x0 <= prev.x0 && r.y0 <= prev.y0 && r.x1 >= prev.x1 && r.y1 >= prev.y1);
        if (i == l->count - 1)
            FUZZ_CHECK(r.x0 == 0 && r.y0 == 0 && r.x1 >= d->width && r.y1 >= d->height);
        prev = r;
        (void)fov_ring_crop(d, &r);
        (void)fov_ring_cull_deg(d, l, i);
    }
    long long per_ring[MAX_FOV_RINGS];
    FUZZ_CHECK(fov_shaded_pixels(d, l, gx, gy, FOV_MARGIN_BLOCKS, per_ring) > 0);

    int max = fov_tile_max(d);
    fov_tile *tiles = malloc((size_t)max * sizeof *tiles);
    FUZZ_CHECK(tiles != NULL);
    int n = fov_composite_tiles(d, l, gx, gy, tiles, max);
    FUZZ_CHECK(n >= 1 && n <= max);
    long long area = 0;
    for (int k = 0; k < n; k++) {
        FUZZ_CHECK(tiles[k].ring >= -1 && tiles[k].ring < l->count);
        area += (long long)(tiles[k].x1 - tiles[k].x0) * (tiles[k].y1 - tiles[k].y0);
    }
    FUZZ_CHECK(area == (long long)d->width * d->height); /* the rectangles partition the display */
    free(tiles);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_init();
    if (size > 4096) /* a command-line argument or a scene's "rings" string (255 bytes) */
        return 0;
    char *text = malloc(size + 1);
    FUZZ_CHECK(text != NULL);
    memcpy(text, data, size);
    text[size] = '\0';

    /* The default display; a small one keeps the per-tile work cheap, a huge-fov one reaches the
     * 90-degree cases. */
    static const display_desc displays[] = {{1280, 720, 90.0f, 0.0f, 0.0f}, {64, 48, 170.0f, 0.0f, 0.0f}};
    const display_desc *d = &displays[size % 2];

    fov_layout l = fov_layout_off();
    l.count = 77; /* sentinel: untouched on error */
    char err[256];
    fs_status s = fov_layout_parse(text, d, &l, err, sizeof err);
    if (s != FS_OK) {
        FUZZ_CHECK(s == FS_ERR_USAGE);
        FUZZ_CHECK(l.count == 77);
        /* Some text. It may quote the input raw (a newline included): every caller prints it through
         * log_error, which escapes it. */
        FUZZ_CHECK(err[0] != '\0' && memchr(err, '\0', sizeof err) != NULL);
        free(text);
        return 0;
    }
    FUZZ_CHECK(l.count >= 1 && l.count <= MAX_FOV_RINGS);
    FUZZ_CHECK(fov_layout_check(&l, err, sizeof err) == FS_OK);

    /* Format -> parse round trip (EXR headers and `fovsim plan` print layouts this way). */
    char buf[1024];
    fov_layout_format(&l, buf, sizeof buf);
    fov_layout back;
    FUZZ_CHECK(fov_layout_parse(buf, NULL, &back, err, sizeof err) == FS_OK);
    FUZZ_CHECK(same_rings(&l, &back));

    static const float e[] = {0.0f, 0.5f, 5.0f, 10.0f, 30.0f, 89.9f, 90.0f, 179.0f, 1e30f};
    for (size_t k = 0; k < sizeof e / sizeof e[0]; k++) {
        fov_blend b = fov_composite_weight(&l, e[k]);
        FUZZ_CHECK(b.ring >= 0 && b.ring < l.count);
        FUZZ_CHECK(b.next >= 0.0f && b.next <= 1.0f);
        FUZZ_CHECK(b.ring < l.count - 1 || b.next == 0.0f);
    }
    int worst;
    (void)fov_layout_acuity_margin(d, &l, 0.0f, 0.0f, &worst);
    FUZZ_CHECK(worst >= -1 && worst < l.count);

    const float w = (float)d->width, h = (float)d->height;
    check_footprints(d, &l, 0.5f * w, 0.5f * h);
    check_footprints(d, &l, 0.0f, h);
    check_footprints(d, &l, -3.0f * w, 0.25f * h);
    check_footprints(d, &l, NAN, INFINITY);
    free(text);
    return 0;
}
