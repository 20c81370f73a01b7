/* fuzz_hmd.c: the --display parser (hmd_parse, docs/hmd.md "The text form") and an eye's geometry.
 *
 * Input: the display's text as given on the command line ("hmd:quest-pro,width=1440,ipd=64").
 * Checks beyond "no crash": a refused text says why in one line; an accepted one has eyes in range
 * (angles within +-85 deg, left < right, down < up, panels within 16..MAX_DISPLAY_SIZE, the IPD and
 * refresh in range, the eyes at -+ipd/2), prints (hmd_format, as `fovsim plan` and the run record
 * do) to text that parses back to the same display, and each eye's principal point round-trips
 * through the pixel mapping to straight ahead with a finite projection.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/config.h"
#include "fuzz_common.h"
#include "hmd/hmd.h"

static bool same_desc(const hmd_desc *a, const hmd_desc *b)
{
    bool eq = !strcmp(a->preset, b->preset) && a->ipd_mm == b->ipd_mm && a->refresh_hz == b->refresh_hz;
    for (int e = 0; e < 2; e++)
        eq = eq && !memcmp(&a->eye[e].fov, &b->eye[e].fov, sizeof(hmd_fov)) && a->eye[e].width == b->eye[e].width &&
             a->eye[e].height == b->eye[e].height;
    return eq;
}

static void check_eye(const hmd_desc *d, int e)
{
    const hmd_eye *y = &d->eye[e];
    const float lim = (float)(HMD_ANGLE_MAX_DEG * FS_PI / 180.0) * 1.000001f;
    FUZZ_CHECK(fabsf(y->fov.left) <= lim && fabsf(y->fov.right) <= lim && fabsf(y->fov.up) <= lim &&
               fabsf(y->fov.down) <= lim);
    FUZZ_CHECK(y->fov.left < y->fov.right && y->fov.down < y->fov.up);
    FUZZ_CHECK(y->width >= 16 && y->width <= MAX_DISPLAY_SIZE && y->height >= 16 && y->height <= MAX_DISPLAY_SIZE);
    FUZZ_CHECK(y->position.x == (e == HMD_LEFT ? -0.0005f : 0.0005f) * d->ipd_mm);
    hmd_pinhole p = hmd_eye_pinhole(y);
    FUZZ_CHECK(isfinite(p.fx) && isfinite(p.fy) && isfinite(p.cx) && isfinite(p.cy) && p.fx > 0 && p.fy > 0);
    vec3 ahead = hmd_pixel_to_dir(y, p.cx, p.cy);
    FUZZ_CHECK(fabsf(ahead.x) < 1e-3f && fabsf(ahead.y) < 1e-3f && ahead.z < 0.0f);
    float px, py;
    FUZZ_CHECK(hmd_dir_to_pixel(y, v3(0, 0, -1), &px, &py));
    FUZZ_CHECK(fabsf(px - p.cx) <= 1e-3f * y->width && fabsf(py - p.cy) <= 1e-3f * y->height);
    mat4 m = hmd_projection(&y->fov, 0.1f, 100.0f);
    for (int i = 0; i < 16; i++)
        FUZZ_CHECK(isfinite(m.m[i]));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_init();
    if (size > 4096) /* a command-line argument */
        return 0;
    char *text = malloc(size + 1);
    FUZZ_CHECK(text != NULL);
    memcpy(text, data, size);
    text[size] = '\0';

    hmd_desc d;
    char err[320] = "";
    if (!hmd_parse(text, &d, err, sizeof err)) {
        FUZZ_CHECK(err[0] != '\0' && memchr(err, '\0', sizeof err) != NULL);
        free(text);
        return 0;
    }
    FUZZ_CHECK(d.ipd_mm >= HMD_IPD_MIN_MM && d.ipd_mm <= HMD_IPD_MAX_MM);
    FUZZ_CHECK(d.refresh_hz >= HMD_HZ_MIN && d.refresh_hz <= HMD_HZ_MAX);
    check_eye(&d, HMD_LEFT);
    check_eye(&d, HMD_RIGHT);

    char buf[1024];
    hmd_format(&d, buf, sizeof buf);
    hmd_desc back;
    FUZZ_CHECK(hmd_parse(buf, &back, err, sizeof err));
    FUZZ_CHECK(same_desc(&d, &back));
    free(text);
    return 0;
}
