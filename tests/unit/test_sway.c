/* Unit tests of wind sway (src/scene/sway.c, C twin of shaders/common/sway.glsl): the bending
 * shape, the wave, bounds, motion, the hard cases (NaN, infinities, hours of scene time, bad
 * heights), and the scene-file key "sway" with its errors. */
#include <float.h>
#include <string.h>

#include "common/shared_defs.h"
#include "scene/scene_json.h"
#include "scene/sway.h"
#include "test.h"

static const instance_sway k_tree = {.offset = {0.3f, 0.0f, 0.1f}, .height = 6.0f, .frequency = 0.4f, .phase = 0.25f};

TEST(weight_is_zero_at_the_base_and_one_at_the_top)
{
    CHECK(sway_weight(0.0f, 6.0f) == 0.0f);
    CHECK(sway_weight(-2.0f, 6.0f) == 0.0f);  /* roots below the origin stay put */
    CHECK(sway_weight(6.0f, 6.0f) == 1.0f);
    CHECK(sway_weight(60.0f, 6.0f) == 1.0f);  /* above the height: rigid, never more than 1 */
    CHECK_NEAR(sway_weight(3.0f, 6.0f), 0.25, 1e-7); /* quadratic */
    float prev = 0.0f;
    for (int i = 1; i <= 100; i++) { /* monotonic */
        float w = sway_weight(6.0f * (float)i / 100.0f, 6.0f);
        CHECK(w >= prev);
        prev = w;
    }
}

TEST(wave_is_a_sine_of_the_phase)
{
    CHECK_NEAR(sway_wave(0.4f, 0.25f, 0.0f), 1.0, 1e-6);           /* quarter cycle */
    CHECK_NEAR(sway_wave(0.4f, 0.0f, 0.625f), 1.0, 1e-5);          /* 0.4 Hz * 0.625 s = 1/4 */
    CHECK_NEAR(sway_wave(1.0f, 0.0f, 0.5f), 0.0, 1e-6);
    CHECK_NEAR(sway_wave(0.5f, 0.1f, 3.0f), sway_wave(0.5f, 0.1f, 1.0f), 1e-6); /* period 2 s */
    /* Hours of scene time: fract is taken before the sine, so the value stays in [-1, 1] and
     * periodic up to float rounding of frequency * t. */
    for (float t = 3600.0f; t < 36000.0f; t *= 1.37f) {
        float v = sway_wave(0.4f, 0.3f, t);
        CHECK(isfinite(v) && v >= -1.0f && v <= 1.0f);
    }
}

TEST(displacement_is_bounded_by_the_offset_and_motion_is_the_difference)
{
    double peak = 0.0;
    for (int i = 0; i <= 200; i++) {
        float t = (float)i * 0.0125f, y = (float)(i % 13) * 0.6f;
        vec3 d = sway_displacement(&k_tree, y, t);
        double len = sqrt((double)d.x * d.x + (double)d.y * d.y + (double)d.z * d.z);
        CHECK(len <= v3_len(k_tree.offset) * (1.0 + 1e-6));
        CHECK(d.y == 0.0f); /* along the offset only */
        peak = len > peak ? len : peak;
        vec3 m = sway_motion(&k_tree, y, t, t - 1.0f / 24.0f), a = sway_displacement(&k_tree, y, t - 1.0f / 24.0f);
        CHECK(m.x == a.x - d.x && m.y == a.y - d.y && m.z == a.z - d.z);
    }
    CHECK(peak > 0.9 * v3_len(k_tree.offset)); /* the top reaches the amplitude */
    vec3 m = sway_motion(&k_tree, 5.0f, 1.3f, 1.3f);
    CHECK(m.x == 0.0f && m.y == 0.0f && m.z == 0.0f); /* no time passed: no motion */
    const instance_sway still = {0};
    vec3 d = sway_displacement(&still, 3.0f, 1.0f);
    CHECK(d.x == 0.0f && d.y == 0.0f && d.z == 0.0f);
}

TEST(hard_cases_stay_finite)
{
    const float bad[] = {NAN, -NAN, INFINITY, -INFINITY, 0.0f, -0.0f, 1e-40f, -1e-40f, 1e30f, -1e30f, FLT_MAX, 0.5f};
    const int n = (int)(sizeof bad / sizeof bad[0]);
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++) {
            CHECK(isfinite(sway_weight(bad[a], bad[b])));
            CHECK(isfinite(sway_wave(bad[a], bad[b], bad[(a + b) % n])));
            instance_sway s = {.offset = {bad[a], 0.1f, bad[b]}, .height = bad[(a + 3) % n], .frequency = bad[b],
                               .phase = bad[a]};
            vec3 d = sway_displacement(&s, bad[(a + b) % n], bad[b]);
            CHECK(isfinite(d.x) && isfinite(d.y) && isfinite(d.z));
            vec3 m = sway_motion(&s, bad[a], bad[b], bad[(a + 1) % n]);
            CHECK(isfinite(m.x) && isfinite(m.y) && isfinite(m.z));
        }
    CHECK(sway_weight(3.0f, 0.0f) == 0.0f);   /* no height: no motion */
    CHECK(sway_weight(3.0f, -1.0f) == 0.0f);
    CHECK(sway_weight(NAN, 6.0f) == 0.0f);
    CHECK(sway_wave(NAN, 0.0f, 1.0f) == 0.0f);
}

/* >>scene file */

static fs_status load_text(const char *json, scene *sc)
{
    return scene_json_parse(json, strlen(json), "sway.json", NULL, sc);
}

#define SCENE_HEAD "{\"assets\": [{\"generator\": \"tree\"}], \"instances\": ["

TEST(scene_key_sway)
{
    scene sc;
    CHECK(load_text(SCENE_HEAD "{\"asset\": \"tree\"}, {\"asset\": \"tree\", \"translation\": [5, 0, 0], "
                               "\"sway\": {\"amplitude\": 0.2, \"frequency\": 0.5, \"direction\": [0, 0, 2], "
                               "\"wavelength\": 20}}]}",
                    &sc) == FS_OK);
    CHECK(sc.instance_count == 2);
    CHECK(!instance_sways(&sc.instances[0]));
    CHECK(scene_sway_count(&sc) == 1);
    const instance_sway *w = &sc.instances[1].sway;
    CHECK_NEAR(w->offset.z, 0.2, 1e-6); /* direction normalised, times the amplitude */
    CHECK(w->offset.x == 0.0f && w->offset.y == 0.0f);
    CHECK_NEAR(w->height, sc.assets[0].bounds_max.y, 1e-6); /* default: the asset's top */
    CHECK(w->frequency == 0.5f);
    CHECK(w->phase == 0.0f); /* x = 5 is across a wind along z */
    uint64_t h = scene_content_hash(&sc);
    scene_free(&sc);
    CHECK(load_text(SCENE_HEAD "{\"asset\": \"tree\"}, {\"asset\": \"tree\", \"translation\": [5, 0, 0], "
                               "\"sway\": {\"amplitude\": 0.3}}]}",
                    &sc) == FS_OK);
    CHECK(scene_content_hash(&sc) != h); /* the reference cache sees the sway */
    CHECK(sc.instances[1].sway.frequency == (float)SWAY_FREQUENCY_DEFAULT);
    CHECK_NEAR(sc.instances[1].sway.phase, 0.5, 1e-6); /* 5 m along a +x wind, 10 m wavelength */
    scene_free(&sc);
    /* scatter: every placed instance sways, each with its own phase */
    CHECK(load_text(SCENE_HEAD "{\"asset\": \"tree\", \"scatter\": {\"count\": 5, \"min\": [-9, 0, -9], "
                               "\"max\": [9, 0, 9]}, \"sway\": {\"amplitude\": 0.1, \"height\": 2}}]}",
                    &sc) == FS_OK);
    CHECK(scene_sway_count(&sc) == 5);
    CHECK(sc.instances[0].sway.height == 2.0f);
    CHECK(sc.instances[0].sway.phase != sc.instances[1].sway.phase);
    scene_free(&sc);
}

TEST(scene_key_sway_errors)
{
    static const char *const bad[] = {
        SCENE_HEAD "{\"asset\": \"tree\", \"sway\": {}}]}",
        SCENE_HEAD "{\"asset\": \"tree\", \"sway\": {\"amplitude\": -1}}]}",
        SCENE_HEAD "{\"asset\": \"tree\", \"sway\": {\"amplitude\": 0.1, \"frequency\": 0}}]}",
        SCENE_HEAD "{\"asset\": \"tree\", \"sway\": {\"amplitude\": 0.1, \"direction\": [0, 0, 0]}}]}",
        SCENE_HEAD "{\"asset\": \"tree\", \"sway\": {\"amplitude\": 0.1, \"height\": 0}}]}",
        SCENE_HEAD "{\"asset\": \"tree\", \"sway\": {\"amplitude\": 0.1, \"gust\": 1}}]}",
        SCENE_HEAD "{\"asset\": \"tree\", \"sway\": 0.3}]}",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        scene sc;
        CHECK(load_text(bad[i], &sc) == FS_ERR_SCENE);
        scene_free(&sc);
    }
}

int main(void)
{
    RUN(weight_is_zero_at_the_base_and_one_at_the_top);
    RUN(wave_is_a_sine_of_the_phase);
    RUN(displacement_is_bounded_by_the_offset_and_motion_is_the_difference);
    RUN(hard_cases_stay_finite);
    RUN(scene_key_sway);
    RUN(scene_key_sway_errors);
    return test_summary();
}
