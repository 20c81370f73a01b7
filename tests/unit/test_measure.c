/* test_measure.c: what compare and bench --accuracy sum over frames (src/commands/measure.c): the
 * coverage ratio over frames is the ratio of the coverage summed over the frames, not a mean of
 * per-frame ratios, and a ratio is reported only where the reference covers enough ring texels
 * (metrics.h METRICS_MIN_REF_TEXELS, the rule fovsim check judges by). Synthetic per-frame metrics
 * with known sums: no GL. */
#include "commands/measure.h"
#include "test.h"

/* One ring's metrics of one frame: `pixels` pixels, mean coverage cov of the method and ref of the
 * reference, the ratio as metrics_compute gives it. */
static ring_metrics frame_ring(long long pixels, double cov, double ref)
{
    ring_metrics m = {.pixels = pixels, .coverage = cov, .ref_coverage = ref, .temporal_error = -1.0,
                      .disoccluded = -1.0};
    m.coverage_ratio = cov < METRICS_EPS && ref < METRICS_EPS ? 1.0 : cov / (ref > METRICS_EPS ? ref : METRICS_EPS);
    return m;
}

/* The user's case (docs/metrics.md "Coverage ratio over frames"): the gaze rests on sky for a few frames, where the fovea's reference
 * covers 0 to 4 pixels. The mean of per-frame ratios read 4.2 to 6.8; the coverage summed over the
 * frames is what the summary reports. */
TEST(coverage_over_frames_is_the_ratio_of_sums)
{
    static mode_run mr;
    memset(&mr, 0, sizeof mr);
    const long long n = 10000;
    /* ring 0 (a full-resolution ring), then the whole display (the same pixels here) */
    const double cov[6] = {0.30, 0.32, 0.31, 0.005, 0.0002, 0.0}, ref[6] = {0.28, 0.29, 0.30, 0.0004, 0.0, 0.0};
    double cov_px = 0, ref_px = 0, mean = 0;
    int judged = 0;
    for (int f = 0; f < 6; f++) {
        ring_metrics rm[2] = {frame_ring(n, cov[f], ref[f]), frame_ring(n, cov[f], ref[f])};
        measure_accumulate(&mr, rm, 1, false);
        cov_px += cov[f] * (double)n;
        ref_px += ref[f] * (double)n;
        if (ref[f] > METRICS_EPS) { /* what the summary averaged before */
            mean += rm[0].coverage_ratio;
            judged++;
        }
    }
    mean /= judged;
    double r = measure_coverage_ratio(&mr, 0, 1);
    fprintf(stderr, "coverage ratio: of sums %.6f (%.1f / %.1f px), old mean of ratios %.3f\n", r, cov_px, ref_px, mean);
    CHECK_NEAR(r, cov_px / ref_px, 1e-12);
    CHECK_NEAR(mr.cov_px[0], cov_px, 1e-6);
    CHECK_NEAR(mr.ref_px[0], ref_px, 1e-6);
    CHECK(mean > 3.0); /* the frame with 4 px of reference alone reads 12.5 */
    CHECK(r > 1.0 && r < 1.1);
    CHECK(mr.err_n[0] == 6);
    /* The same sums in a 1/8 ring: 8.73e3 px of reference are 136 texels, enough; a ring whose
     * reference holds 3 texels is not (n/a, -1). */
    CHECK_NEAR(measure_coverage_ratio(&mr, 0, 8), cov_px / ref_px, 1e-12);
    static mode_run thin;
    memset(&thin, 0, sizeof thin);
    ring_metrics t[2] = {frame_ring(6400, 0.05, 3.0 * 64.0 / 6400.0), frame_ring(6400, 0.05, 3.0 * 64.0 / 6400.0)};
    measure_accumulate(&thin, t, 1, false);
    CHECK(measure_coverage_ratio(&thin, 0, 8) == -1.0);   /* 3 texels of 8x8 */
    CHECK(measure_coverage_ratio(&thin, 1, 1) > 1.0);     /* 192 px of 1x1 texels */
    /* Nothing at all: n/a, not a ratio of nothing (the old summary said 1). */
    static mode_run none;
    memset(&none, 0, sizeof none);
    ring_metrics z[2] = {frame_ring(100, 0.0, 0.0), frame_ring(100, 0.0, 0.0)};
    measure_accumulate(&none, z, 1, false);
    CHECK(measure_coverage_ratio(&none, 0, 1) == -1.0);
}

/* The rule itself: METRICS_MIN_REF_TEXELS texels of block x block display pixels. */
TEST(a_ratio_rests_on_4_ring_texels_of_reference)
{
    CHECK(METRICS_MIN_REF_TEXELS == 4.0);
    CHECK(metrics_coverage_ratio_rests(4.0, 1));
    CHECK(!metrics_coverage_ratio_rests(3.999, 1));
    CHECK(metrics_coverage_ratio_rests(256.0, 8));
    CHECK(!metrics_coverage_ratio_rests(255.9, 8));
    CHECK(metrics_coverage_ratio_rests(4.0, 0)); /* block < 1 counts as 1 */
    CHECK(!metrics_coverage_ratio_rests(NAN, 1));
    CHECK(metrics_coverage_ratio_of_sums(10.0, 5.0, 1) == 2.0);
    CHECK(metrics_coverage_ratio_of_sums(10.0, 3.0, 1) == -1.0);
    /* measure_block: the layout's ring texels, 1 for the whole display and without foveation */
    fov_layout l = {.count = 3, .rings = {{10.0f, 0, 0.0f}, {20.0f, 1, 0.0f}, {INFINITY, 3, 0.0f}}};
    CHECK(measure_block(&l, 0) == 1 && measure_block(&l, 1) == 2 && measure_block(&l, 2) == 8);
    CHECK(measure_block(&l, 3) == 1 && measure_block(NULL, 2) == 1);
}

/* Per frame (metrics.csv): a frame's ratio is -1 where its reference holds under 4 texels. */
TEST(per_frame_ratio_only_where_the_reference_holds_enough)
{
    fov_layout l = {.count = 2, .rings = {{10.0f, 0, 0.0f}, {INFINITY, 2, 0.0f}}};
    ring_metrics rm[3] = {frame_ring(1000, 0.01, 0.003), /* 3 px: too few */
                          frame_ring(1000, 0.2, 0.07),   /* 70 px = 4.4 texels of 4x4: enough */
                          frame_ring(2000, 0.105, 0.0365)};
    measure_gate_ratios(rm, 2, &l);
    CHECK(rm[0].coverage_ratio == -1.0);
    CHECK_NEAR(rm[1].coverage_ratio, 0.2 / 0.07, 1e-12);
    CHECK_NEAR(rm[2].coverage_ratio, 0.105 / 0.0365, 1e-12);
    ring_metrics r2[3] = {frame_ring(1000, 0.01, 0.005), frame_ring(1000, 0.2, 0.06), frame_ring(2000, 0.1, 0.0325)};
    measure_gate_ratios(r2, 2, &l);
    CHECK(r2[0].coverage_ratio > 0.0);   /* 5 px */
    CHECK(r2[1].coverage_ratio == -1.0); /* 60 px = 3.75 texels of 4x4 */
    /* A run at full resolution everywhere (no layout): texels are pixels, 6 px are enough. */
    ring_metrics r3[3] = {frame_ring(1000, 0.2, 0.006), frame_ring(1000, 0.2, 0.006), frame_ring(2000, 0.2, 0.006)};
    measure_gate_ratios(r3, 2, &l);
    CHECK(r3[0].coverage_ratio > 0.0 && r3[1].coverage_ratio == -1.0);
    ring_metrics r4[3] = {frame_ring(1000, 0.2, 0.006), frame_ring(1000, 0.2, 0.006), frame_ring(2000, 0.2, 0.006)};
    measure_gate_ratios(r4, 2, NULL);
    CHECK(r4[0].coverage_ratio > 0.0 && r4[1].coverage_ratio > 0.0 && r4[2].coverage_ratio > 0.0);
}

int main(void)
{
    RUN(coverage_over_frames_is_the_ratio_of_sums);
    RUN(a_ratio_rests_on_4_ring_texels_of_reference);
    RUN(per_frame_ratio_only_where_the_reference_holds_enough);
    return test_summary();
}
