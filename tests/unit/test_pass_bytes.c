/* Unit tests of pass_bytes (src/passes/pass_bytes.c): each stage's bytes from its targets'
 * footprints, against sums written out by hand. */
#include "passes/pass_bytes.h"
#include "test.h"

/* The renderer's formats: RGBA16F colour (8), R16F coverage (2), 24-bit depth (4: stored in 32
 * bits), RGBA16F motion (8), R32F history depth (4), RG32F debug (8). */
static const target_bytes k_plain = {.color = 8, .coverage = 2, .depth = 4, .history_color = 8,
                                     .history_coverage = 2, .out_color = 8, .out_coverage = 2};

TEST(forward_writes_targets_reads_depth)
{
    pass_bytes b = pass_bytes_forward(&k_plain, 100);
    CHECK(b.written == 100 * (8 + 2 + 4));
    CHECK(b.read == 100 * 4);
    target_bytes m = k_plain;
    m.motion = 8;
    b = pass_bytes_forward(&m, 10);
    CHECK(b.written == 10 * (8 + 2 + 8 + 4));
    CHECK(b.read == 10 * 4);
    CHECK(pass_bytes_forward(&k_plain, 0).written == 0);
}

TEST(forward_msaa_counts_samples_and_resolve)
{
    target_bytes m = k_plain;
    m.msaa_samples = 4;
    pass_bytes b = pass_bytes_forward(&m, 10);
    /* 4 samples of colour, coverage, depth written; resolve writes colour + coverage per pixel */
    CHECK(b.written == 4 * 10 * 14 + 10 * 10);
    /* depth test of 4 samples, resolve reads 4 samples of colour + coverage */
    CHECK(b.read == 4 * 10 * 4 + 4 * 10 * 10);
    m.taa = true; /* depth resolves too */
    b = pass_bytes_forward(&m, 10);
    CHECK(b.written == 4 * 10 * 14 + 10 * 14);
    CHECK(b.read == 4 * 10 * 4 + 4 * 10 * 14);
    m.msaa_samples = 1; /* one sample: no MSAA */
    CHECK(pass_bytes_forward(&m, 10).written == 10 * 14);
}

TEST(taa_reads_current_and_history_writes_history)
{
    target_bytes t = k_plain;
    t.taa = true;
    pass_bytes b = pass_bytes_taa(&t, 100, 80);
    CHECK(b.read == 100 * (8 + 2 + 4) + 80 * (8 + 2));
    CHECK(b.written == 100 * (8 + 2));
    t.history_depth = 4;
    t.motion = 8;
    b = pass_bytes_taa(&t, 100, 100);
    CHECK(b.read == 100 * (8 + 2 + 4 + 8) + 100 * (8 + 2 + 4));
    CHECK(b.written == 100 * (8 + 2 + 4));
}

TEST(composite_reads_rings_writes_display)
{
    const long long rings[3] = {400, 300, 200};
    pass_bytes b = pass_bytes_composite(&k_plain, rings, 3, 1000);
    CHECK(b.read == (400 + 300 + 200) * (8 + 2));
    CHECK(b.written == 1000 * (8 + 2));
    target_bytes t = k_plain;
    t.out_debug = 8;
    t.taa = true;
    t.history_color = 16; /* with TAA it reads the history's formats */
    b = pass_bytes_composite(&t, rings, 2, 1000);
    CHECK(b.read == (400 + 300) * (16 + 2));
    CHECK(b.written == 1000 * (8 + 2 + 8));
}

int main(void)
{
    RUN(forward_writes_targets_reads_depth);
    RUN(forward_msaa_counts_samples_and_resolve);
    RUN(taa_reads_current_and_history_writes_history);
    RUN(composite_reads_rings_writes_display);
    return test_summary();
}
