/* Unit tests of the per-ring simplification law (src/fov/ring_lod.c, C twin of
 * shaders/common/ring_lod.glsl): expected area preserved, bounds and monotonicity, u = 1 exactly
 * the identity, continuity in u at the documented rate, coverage of a field of identical cards with
 * the real ranks, the per-instance rank rotation, the default schedule and the text form. */
#include <float.h>
#include <stdint.h>
#include <string.h>

#include "common/shared_defs.h"
#include "fov/fov_ring.h"
#include "fov/ring_lod.h"
#include "scene/cards.h"
#include "test.h"

static const float k_us[] = {1.0f, 0.9f, 0.5f, 0.25f, 0.125f, 1.0f / 16.0f, 0.01f};
#define US_COUNT ((int)(sizeof k_us / sizeof k_us[0]))

static bool same_bits(float a, float b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* >>the law */

TEST(expected_area_is_preserved)
{
    /* Midpoint rule over 1e6 evenly spaced ranks: g is piecewise linear, so the rule is exact but
     * for the two kinks (error < 1 / N each). */
    const int N = 1000000;
    for (int i = 0; i < US_COUNT; i++) {
        ring_lod_law l = ring_lod_law_for(k_us[i]);
        double sum_g = 0.0, sum_ga = 0.0;
        for (int j = 0; j < N; j++) {
            float r = (float)(((double)j + 0.5) / N);
            float g = ring_lod_weight(&l, r), s = ring_lod_scale(&l, r);
            sum_g += g;
            sum_ga += (double)s * s; /* the drawn area, scale^2 = g gain */
        }
        CHECK_NEAR(sum_ga / N, 1.0, 1e-4);                              /* E[g A] = 1 */
        CHECK_NEAR(sum_g / N, k_us[i], 1e-5);                           /* E[g] = u */
        CHECK_NEAR(ring_lod_expected_weight(l.a, l.k), k_us[i], 1e-6);  /* the closed form */
        CHECK_NEAR(ring_lod_expected_weight(l.a, l.k) * l.gain, 1.0, 1e-6);
        CHECK_NEAR(l.gain, 1.0 / k_us[i], 1e-5 / k_us[i]);
    }
    /* The closed form for any ramp: inside [0, 1], crossing 0, crossing 1, crossing both, outside. */
    const float ak[][2] = {{0.2f, 4.0f}, {-0.1f, 2.0f}, {0.8f, 1.5f}, {-0.5f, 0.4f}, {1.2f, 3.0f}, {-2.0f, 1.0f},
                           {0.0f, 1.0f}, {0.5f, 1e-3f}};
    for (size_t i = 0; i < sizeof ak / sizeof ak[0]; i++) {
        ring_lod_law l = {.a = ak[i][0], .k = ak[i][1], .gain = 1.0f};
        double sum = 0.0;
        for (int j = 0; j < N; j++)
            sum += ring_lod_weight(&l, (float)(((double)j + 0.5) / N));
        CHECK_NEAR(ring_lod_expected_weight(l.a, l.k), sum / N, 1e-5);
    }
    CHECK(ring_lod_expected_weight(0.3f, 0.0f) == 1.0);
    CHECK(isnan(ring_lod_expected_weight(0.3f, -1.0f)));
}

TEST(weights_are_bounded_and_monotonic)
{
    const int R = 10001;
    for (int i = 0; i < US_COUNT; i++) {
        ring_lod_law l = ring_lod_law_for(k_us[i]);
        float prev = 2.0f;
        for (int j = 0; j < R; j++) {
            float g = ring_lod_weight(&l, (float)j / (float)R);
            CHECK(g >= 0.0f && g <= 1.0f);
            CHECK(g <= prev); /* non-increasing in r (float rounding is monotonic too) */
            prev = g;
        }
        CHECK(ring_lod_weight(&l, 0.0f) == 1.0f); /* the lowest ranks are always kept whole */
    }
    /* Non-decreasing in u, over a fine grid of u across both branches of the law. */
    for (int j = 0; j < 512; j++) {
        float r = ((float)j + 0.5f) / 512.0f, prev = 0.0f;
        for (int m = 1; m <= 1000; m++) {
            ring_lod_law l = ring_lod_law_for((float)m / 1000.0f);
            float g = ring_lod_weight(&l, r);
            CHECK((double)g >= (double)prev - 0x1p-23 * (2.0 + l.k)); /* float rounding of a, k, g */
            prev = g;
        }
    }
    /* At the lowest u some cards are dropped outright: g = 0 (and their scale 0). */
    ring_lod_law l = ring_lod_law_for(1.0f / 16.0f);
    CHECK(ring_lod_weight(&l, 0.5f) == 0.0f && ring_lod_scale(&l, 0.5f) == 0.0f);
}

TEST(u_one_is_exactly_the_identity)
{
    ring_lod_law l = ring_lod_law_for(1.0f);
    CHECK(ring_lod_law_is_identity(&l));
    CHECK(l.gain == 1.0f && l.k == 0.0f);
    const float ranks[] = {0.0f, 1e-7f, 0.25f, 0.5f, 0.999f, 1.0f - 0x1p-24f};
    for (size_t i = 0; i < sizeof ranks / sizeof ranks[0]; i++) {
        CHECK(ring_lod_weight(&l, ranks[i]) == 1.0f);
        CHECK(ring_lod_scale(&l, ranks[i]) == 1.0f);
    }
    for (int j = 0; j < 1000; j++) {
        float r = (float)j / 1000.0f, card[4] = {0.3f * (float)j, -7.1f, 1e-3f, r};
        vec3 p = v3(0.1f * (float)j, 2.0f / (float)(j + 1), -3.3f), q = ring_lod_apply(&l, p, card);
        CHECK(same_bits(p.x, q.x) && same_bits(p.y, q.y) && same_bits(p.z, q.z));
    }
    /* Out of (0, 1]: the identity, never a division by zero; below the floor: the floor's law
     * (finite, not infinite slopes and gains). */
    const float bad[] = {0.0f, -0.5f, 1.5f, NAN, INFINITY, -INFINITY};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ring_lod_law b = ring_lod_law_for(bad[i]);
        CHECK(ring_lod_law_is_identity(&b));
    }
    const float tiny[] = {1e-42f, 1e-20f, 1e-5f};
    ring_lod_law fl = ring_lod_law_for((float)RING_LOD_U_FLOOR);
    CHECK(isfinite(fl.k) && isfinite(fl.gain));
    CHECK_NEAR(fl.gain, 1.0 / RING_LOD_U_FLOOR, 1e-2);
    for (size_t i = 0; i < sizeof tiny / sizeof tiny[0]; i++) {
        ring_lod_law t = ring_lod_law_for(tiny[i]);
        CHECK(t.a == fl.a && t.k == fl.k && t.gain == fl.gain);
    }
    /* Just below 1: not the identity, but every card still nearly whole. */
    ring_lod_law n = ring_lod_law_for(1.0f - 0x1p-20f);
    CHECK(!ring_lod_law_is_identity(&n));
    CHECK(ring_lod_weight(&n, 1.0f - 0x1p-24f) > 0.9999f);
}

TEST(kept_rank_and_dropped_cards)
{
    ring_lod_law l = ring_lod_law_for(1.0f / 16.0f);
    const float keep[4] = {1.0f, 2.0f, 3.0f, (float)RING_LOD_RANK_KEEP};
    CHECK(ring_lod_weight(&l, keep[3]) == 1.0f && ring_lod_scale(&l, keep[3]) == 1.0f);
    vec3 p = v3(0.7f, -0.2f, 5.0f), q = ring_lod_apply(&l, p, keep);
    CHECK(same_bits(p.x, q.x) && same_bits(p.y, q.y) && same_bits(p.z, q.z));
    /* A dropped card: all its vertices land exactly on its centre (a zero-area card). */
    const float drop[4] = {1.0f, 2.0f, 3.0f, 0.75f};
    for (int j = 0; j < 3; j++) {
        vec3 v = ring_lod_apply(&l, v3((float)j * 0.37f, -1.0f * (float)j, 9.0f), drop);
        CHECK(v.x == 1.0f && v.y == 2.0f && v.z == 3.0f);
    }
    /* A kept card: scaled by sqrt(gain) = 4 about its centre. */
    const float kept[4] = {1.0f, 2.0f, 3.0f, 0.01f};
    vec3 v = ring_lod_apply(&l, v3(1.5f, 2.0f, 3.0f), kept);
    CHECK_NEAR(v.x, 1.0 + 0.5 * sqrt((double)l.gain), 1e-5);
    CHECK_NEAR(sqrt((double)l.gain), 4.0, 1e-5);
}

TEST(weights_change_continuously_with_u)
{
    /* |g(r, u2) - g(r, u1)| <= (u2 - u1) * max rate on [u1, u2] (the rate falls with u below u*
     * and is constant above, so the larger of the two ends), plus float rounding of a, k and g:
     * about 2^-23 (2 + k). Below u* the rate is (1 + B/2) / w, w = B u the band width: a card
     * crossing the band fades over it, never faster. */
    const double B = RING_LOD_BAND, us = 1.0 / (1.0 + 0.5 * B);
    CHECK_NEAR(ring_lod_max_rate(0.25f), (1.0 + 0.5 * B) / (B * 0.25), 1e-9);
    CHECK_NEAR(ring_lod_max_rate(0.95f), 2.0 * (1.0 + 0.5 * B) / B, 1e-9);
    double worst = 0.0;
    for (int m = 0; m < 4000; m++) {
        float u1 = 0.01f + 0.99f * (float)m / 4000.0f, u2 = 0.01f + 0.99f * (float)(m + 1) / 4000.0f;
        if (m == 3999)
            u2 = 1.0f;
        ring_lod_law l1 = ring_lod_law_for(u1), l2 = ring_lod_law_for(u2);
        double rate = fmax(ring_lod_max_rate(u1), ring_lod_max_rate(u2));
        double tol = (double)(u2 - u1) * rate + 0x1p-23 * (2.0 + l1.k + l2.k);
        for (int j = 0; j < 2048; j++) {
            float r = ((float)j + 0.5f) / 2048.0f;
            double d = fabs((double)ring_lod_weight(&l2, r) - (double)ring_lod_weight(&l1, r));
            CHECK(d <= tol);
            if (d / tol > worst)
                worst = d / tol;
        }
    }
    CHECK(worst > 0.5); /* the bound is tight, not vacuous */
    /* Near u = 1 too: from u = 1 - 1e-4 to 1 no card changes by more than 1e-4 * 18 (a law with the
     * band fixed at B u would move the card at r -> 1 by sqrt(2 * 1e-4 / B) = 0.028). */
    ring_lod_law a = ring_lod_law_for(1.0f - 1e-4f), b = ring_lod_law_for(1.0f);
    for (int j = 0; j < 4096; j++) {
        float r = ((float)j + 0.5f) / 4096.0f;
        CHECK(fabs((double)ring_lod_weight(&b, r) - (double)ring_lod_weight(&a, r)) <=
              1e-4 * 2.0 * (1.0 + 0.5 * B) / B + 1e-6);
    }
    CHECK(us > 0.88 && us < 0.89);
}

/* >>coverage of a field of identical cards */

TEST(coverage_of_identical_cards_is_preserved)
{
    /* N equal cards of area A0 with the real ranks (cards_stratified_ranks, then rotated for one
     * instance as the vertex shader does). The area drawn is sum(scale^2 A0) = A0 sum(g gain);
     * its expectation is N A0.
     *
     * Tolerance the issue asks for, from the binomial spread: with independent uniform ranks the
     * kept count would be ~Binomial(N, u), relative standard deviation sqrt((1 - u) / (N u)); the
     * transition band only lowers it (g in [0, 1], so Var g = E[g^2] - u^2 <= E[g] - u^2 =
     * u (1 - u), the binomial's). 4 sigma: 4 sqrt((1 - u) / (N u)) = 4 %, 7 %, 10.6 % at u = 1/2,
     * 1/4, 1/8 for N = 10000.
     *
     * The ranks are stratified (one per stratum [j/N, (j+1)/N), rotated as a whole), which bounds
     * the error deterministically: |sum g - N E[g]| <= the total variation of g around the circle,
     * 2 (Koksma-Hlawka, one point per interval), so |sum g gain - N| <= 2 gain = 2 / u, relative
     * 2 / (N u) = 0.04 %, 0.08 %, 0.16 %. Both are checked. */
    enum { N = 10000 };
    static float rank[N];
    CHECK(cards_stratified_ranks(N, 0, rank) == FS_OK);
    const float A0 = 0.01f, us[3] = {0.5f, 0.25f, 0.125f};
    const uint32_t keys[3] = {0, 7, 123456};
    for (int i = 0; i < 3; i++)
        for (int kk = 0; kk < 3; kk++) {
            ring_lod_law l = ring_lod_law_for(us[i]);
            double area = 0.0;
            int drawn = 0;
            for (int c = 0; c < N; c++) {
                float r = ring_lod_rank(rank[c], keys[kk]), s = ring_lod_scale(&l, r);
                area += (double)s * s * A0;
                drawn += s > 0.0f;
            }
            double rel = area / (N * (double)A0) - 1.0, u = us[i];
            CHECK(fabs(rel) <= 4.0 * sqrt((1.0 - u) / (N * u)));
            CHECK(fabs(rel) <= 2.0 / (N * u) + 1e-6);
            /* Cards drawn at all (the cost): u (1 + B/2) of them, to within the stratification. */
            CHECK(abs(drawn - (int)lround(N * u * (1.0 + 0.5 * RING_LOD_BAND))) <= 2);
        }
}

/* >>ranks per instance */

TEST(instance_rotation_is_exact_and_keeps_the_strata)
{
    enum { N = 4096 };
    static float rank[N];
    CHECK(cards_stratified_ranks(N, 1, rank) == FS_OK);
    CHECK(ring_lod_rank((float)RING_LOD_RANK_KEEP, 5) == (float)RING_LOD_RANK_KEEP);
    CHECK(isnan(ring_lod_rank(NAN, 5)) && ring_lod_rank(1.0f, 5) == 1.0f);
    uint32_t offsets[64];
    for (uint32_t key = 0; key < 64; key++) {
        offsets[key] = ring_lod_instance_offset(key);
        CHECK(offsets[key] < (1u << RING_LOD_RANK_BITS));
        static int stratum[N];
        memset(stratum, 0, sizeof stratum);
        for (int c = 0; c < N; c++) {
            float r = ring_lod_rank(rank[c], key);
            CHECK(r >= 0.0f && r < 1.0f);
            double k = (double)r * RING_LOD_RANK_ONE;
            CHECK(k == (double)(uint32_t)k);
            /* (rank + offset) mod 1, exactly */
            uint32_t want = ((uint32_t)((double)rank[c] * RING_LOD_RANK_ONE) + offsets[key]) & RING_LOD_RANK_MASK;
            CHECK((uint32_t)k == want);
            /* Rotated strata: shifting by the offset keeps one rank per stratum, up to the 2^-24
             * quantisation at stratum borders. */
            double x = fmod((double)r - (double)offsets[key] / RING_LOD_RANK_ONE + 1.0, 1.0) * N;
            int s = (int)(x + 1e-6);
            stratum[s < N ? s : s - N]++;
        }
        int ones = 0;
        for (int s = 0; s < N; s++)
            ones += stratum[s] == 1;
        CHECK(ones == N);
    }
    int distinct = 0; /* instances get different rotations */
    for (int i = 0; i < 64; i++) {
        bool dup = false;
        for (int j = 0; j < i; j++)
            dup = dup || offsets[i] == offsets[j];
        distinct += !dup;
    }
    CHECK(distinct == 64);
    /* Independent kept sets: at u = 1/4, two instances share about 1/4 of each other's cards
     * (0.25 +- 0.15 on average over pairs), not all of them. */
    ring_lod_law l = ring_lod_law_for(0.25f);
    double overlap = 0.0;
    for (uint32_t key = 0; key < 32; key++) {
        int both = 0, first = 0;
        for (int c = 0; c < N; c++) {
            bool a = ring_lod_weight(&l, ring_lod_rank(rank[c], key)) > 0.0f;
            bool b = ring_lod_weight(&l, ring_lod_rank(rank[c], key + 1000)) > 0.0f;
            first += a;
            both += a && b;
        }
        overlap += (double)both / first / 32.0;
    }
    CHECK(overlap > 0.1 && overlap < 0.4);
}

/* >>schedule and text form */

TEST(default_schedule)
{
    /* Per card: a card of a ring pixel or more keeps everything, a smaller one u = its area in ring
     * pixels, down to RING_LOD_U_MIN; continuous in the card's size. */
    CHECK(ring_lod_card_u(1.0f) == 1.0f && ring_lod_card_u(3.0f) == 1.0f && ring_lod_card_u(1e30f) == 1.0f);
    CHECK(ring_lod_card_u(0.5f) == 0.25f && ring_lod_card_u(0.25f) == (float)RING_LOD_U_MIN);
    CHECK(ring_lod_card_u(0.0f) == (float)RING_LOD_U_MIN && ring_lod_card_u(0.01f) == (float)RING_LOD_U_MIN);
    float prev = ring_lod_card_u(0.0f);
    for (int i = 1; i <= 2000; i++) {
        float u = ring_lod_card_u((float)i / 1000.0f);
        CHECK(u >= prev && u - prev <= 0.0041f); /* du/ds = 2 s <= 4 over steps of 0.001 */
        prev = u;
    }

    fov_layout l;
    char err[256];
    CHECK(fov_layout_parse("10:1:0,20:1/2:0,30:1/4:0,40:1/8:0,*:1/16:0", NULL, &l, err, sizeof err) == FS_OK);
    ring_lod_spec s;
    CHECK(ring_lod_parse("simplify", &s, err, sizeof err) == FS_OK && s.kind == RING_LOD_SCHEDULE);
    CHECK(ring_lod_check(&s, &l, err, sizeof err) == FS_OK);
    CHECK(!ring_lod_ring_is_per_card(&s, &l, 0));
    CHECK(ring_lod_u(&s, &l, 0) == 1.0f);
    for (int i = 1; i < 5; i++)
        CHECK(ring_lod_ring_is_per_card(&s, &l, i) && ring_lod_u(&s, &l, i) == (float)RING_LOD_U_MIN);
    ring_lod_law r0 = ring_lod_ring_law(&s, &l, 0), r1 = ring_lod_ring_law(&s, &l, 1);
    CHECK(ring_lod_law_is_identity(&r0) && !ring_lod_law_is_identity(&r1));
    CHECK(ring_lod_max_scale(&r1) == 4.0f); /* culling: kept cards grow to at most 4 times their side */
    CHECK(ring_lod_active(&s, &l));
    char buf[128];
    ring_lod_format_u(&s, &l, buf, sizeof buf);
    CHECK(strcmp(buf, "1,card,card,card,card") == 0);
    /* Foveation off: one full-resolution ring, nothing simplified; a zeroed spec is off. */
    fov_layout off = fov_layout_off();
    CHECK(!ring_lod_active(&s, &off) && !ring_lod_ring_is_per_card(&s, &off, 0));
    ring_lod_spec z;
    memset(&z, 0, sizeof z);
    CHECK(z.kind == RING_LOD_OFF && !ring_lod_active(&z, &l) && ring_lod_u(&z, &l, 4) == 1.0f);
    CHECK(!ring_lod_ring_is_per_card(&z, &l, 3));
    ring_lod_format_u(&z, &l, buf, sizeof buf);
    CHECK(strcmp(buf, "1,1,1,1,1") == 0);
}

TEST(text_form_parses_and_reports_errors)
{
    ring_lod_spec s;
    char err[256], buf[256];
    CHECK(ring_lod_parse("off", &s, err, sizeof err) == FS_OK && s.kind == RING_LOD_OFF);
    CHECK(ring_lod_parse(" simplify\n", &s, err, sizeof err) == FS_OK && s.kind == RING_LOD_SCHEDULE);
    CHECK(ring_lod_parse("simplify:1, 1/2 ,0.25,1 / 8,0.0625", &s, err, sizeof err) == FS_OK);
    CHECK(s.kind == RING_LOD_EXPLICIT && s.count == 5);
    CHECK(s.u[0] == 1.0f && s.u[1] == 0.5f && s.u[2] == 0.25f && s.u[3] == 0.125f && s.u[4] == 0.0625f);
    ring_lod_format(&s, buf, sizeof buf);
    CHECK(strcmp(buf, "simplify:1,0.5,0.25,0.125,0.0625") == 0);
    ring_lod_spec back;
    CHECK(ring_lod_parse(buf, &back, err, sizeof err) == FS_OK && memcmp(&back, &s, sizeof s) == 0);
    CHECK(ring_lod_parse("simplify:1/3", &s, err, sizeof err) == FS_OK);
    ring_lod_format(&s, buf, sizeof buf);
    CHECK(ring_lod_parse(buf, &back, err, sizeof err) == FS_OK && back.u[0] == s.u[0]);
    s.kind = RING_LOD_OFF;
    ring_lod_format(&s, buf, sizeof buf);
    CHECK(strcmp(buf, "off") == 0);
    s.kind = RING_LOD_SCHEDULE;
    s.area = 0.0f;
    ring_lod_format(&s, buf, sizeof buf);
    CHECK(strcmp(buf, "simplify") == 0 && ring_lod_area(&s) == (float)RING_LOD_AREA_REF);
    /* The per-card schedule with another area: parsed, formatted back, and checked. */
    CHECK(ring_lod_parse("simplify:area=16", &s, err, sizeof err) == FS_OK && s.kind == RING_LOD_SCHEDULE);
    CHECK(ring_lod_area(&s) == 16.0f);
    ring_lod_format(&s, buf, sizeof buf);
    CHECK(strcmp(buf, "simplify:area=16") == 0);
    CHECK(ring_lod_parse(buf, &back, err, sizeof err) == FS_OK && memcmp(&back, &s, sizeof s) == 0);
    CHECK(ring_lod_parse("simplify:area= 1/4 ", &s, err, sizeof err) == FS_OK && ring_lod_area(&s) == 0.25f);
    CHECK(ring_lod_parse("simplify:area=1", &s, err, sizeof err) == FS_OK);
    ring_lod_format(&s, buf, sizeof buf);
    CHECK(strcmp(buf, "simplify") == 0); /* the default area */
    static const char *const bad_area[] = {"simplify:area=", "simplify:area=0", "simplify:area=-1", "simplify:area=1000",
                                           "simplify:area=x", "simplify:area=nan", "simplify:area=4,1"};
    for (size_t i = 0; i < sizeof bad_area / sizeof bad_area[0]; i++) {
        CHECK(ring_lod_parse(bad_area[i], &s, err, sizeof err) == FS_ERR_USAGE);
        CHECK(strstr(err, "ring LOD area") != NULL);
    }
    CHECK(ring_lod_parse("simplify:0.5", NULL, err, sizeof err) == FS_OK); /* validation only */
    CHECK(ring_lod_parse("simplify:1/4096", &s, err, sizeof err) == FS_OK && s.u[0] == (float)RING_LOD_U_FLOOR);

    /* Errors: one line naming what was expected; *out untouched. */
    const struct {
        const char *text, *want;
    } bad[] = {
        {"", "expected off, simplify, simplify:area=A or simplify:U1,...,Un"},
        {"   ", "empty ring LOD"},
        {"on", "ring LOD 'on' is not understood (expected off, simplify"},
        {"simplifyx", "ring LOD 'simplifyx' is not understood"},
        {"simplify:", "ring LOD ring 1: keep fraction is empty"},
        {"simplify:0.5,,0.25", "ring LOD ring 2: keep fraction is empty"},
        {"simplify:1,0", "ring LOD ring 2: keep fraction '0' is not in [1/4096, 1] (e.g. 0.25 or 1/4)"},
        {"simplify:1.5", "ring LOD ring 1: keep fraction '1.5' is not in [1/4096, 1]"},
        {"simplify:-0.5", "keep fraction '-0.5' is not in [1/4096, 1]"},
        {"simplify:abc", "keep fraction 'abc' is not in [1/4096, 1]"},
        {"simplify:1/4097", "keep fraction '1/4097' is not in [1/4096, 1]"}, /* found by fuzzing: k was inf */
        {"simplify:2111/1111111111111111111111111111111111111111111115", "is not in [1/4096, 1]"},
        {"simplify:1/0", "keep fraction '1/0' is not in"},
        {"simplify:nan", "keep fraction 'nan'"},
        {"simplify:inf", "keep fraction 'inf'"},
        {"simplify:1e-50", "keep fraction '1e-50'"}, /* 0 as a float */
        {"simplify:1,1,1,1,1,1,1,1,1", "ring LOD ring 9: more than 8 rings"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ring_lod_spec keep = {.kind = RING_LOD_EXPLICIT, .count = 1, .u = {0.5f}}, t = keep;
        CHECK(ring_lod_parse(bad[i].text, &t, err, sizeof err) == FS_ERR_USAGE);
        CHECK(memcmp(&t, &keep, sizeof t) == 0);
        CHECK(strstr(err, bad[i].want) != NULL && strchr(err, '\n') == NULL);
        if (!strstr(err, bad[i].want))
            fprintf(stderr, "  '%s' -> '%s'\n", bad[i].text, err);
    }
    CHECK(ring_lod_parse(NULL, &s, err, sizeof err) == FS_ERR_USAGE);

    /* The count must match the layout's. */
    fov_layout l;
    CHECK(fov_layout_parse("10:1:0,20:1/2:0,30:1/4:0,40:1/8:0,*:1/16:0", NULL, &l, err, sizeof err) == FS_OK);
    CHECK(ring_lod_parse("simplify:1,0.5,0.25", &s, err, sizeof err) == FS_OK);
    CHECK(ring_lod_check(&s, &l, err, sizeof err) == FS_ERR_USAGE);
    CHECK(strcmp(err, "ring LOD: 3 keep fractions for 5 rings (expected one per ring)") == 0);
    fov_layout off = fov_layout_off();
    CHECK(ring_lod_check(&s, &off, err, sizeof err) == FS_ERR_USAGE);
    CHECK(strcmp(err, "ring LOD: 3 keep fractions for 1 ring (expected one per ring)") == 0);
    CHECK(ring_lod_parse("simplify:1,1,0.25,0.0625,0.0625", &s, err, sizeof err) == FS_OK);
    CHECK(ring_lod_check(&s, &l, err, sizeof err) == FS_OK);
    CHECK(ring_lod_u(&s, &l, 3) == 0.0625f && ring_lod_u(&s, &l, 7) == 1.0f);
    ring_lod_spec ones;
    CHECK(ring_lod_parse("simplify:1,1,1,1,1", &ones, err, sizeof err) == FS_OK);
    CHECK(!ring_lod_active(&ones, &l)); /* all 1: exactly no simplification */
}

int main(void)
{
    RUN(expected_area_is_preserved);
    RUN(weights_are_bounded_and_monotonic);
    RUN(u_one_is_exactly_the_identity);
    RUN(kept_rank_and_dropped_cards);
    RUN(weights_change_continuously_with_u);
    RUN(coverage_of_identical_cards_is_preserved);
    RUN(instance_rotation_is_exact_and_keeps_the_strata);
    RUN(default_schedule);
    RUN(text_form_parses_and_reports_errors);
    return test_summary();
}
