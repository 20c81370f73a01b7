/* alpha_hash: the hashed / stochastic alpha thresholds of seed 000 (§4-6, Listing 1, Eq. 1-3).
 *
 * What is asserted, and why these bounds:
 *   - every threshold is finite and in (0, 1] for the hard cases of docs/design.md "Hard cases and where they are tested" (interpolation factor
 *     0, 1, 0.5 and within 1e-7 of 0 or 1; derivatives 0, denormal, 1e-30, 1e30, NaN, inf;
 *     coordinates +-1e7, exact integers, -0, NaN, inf), both hashes, anisotropic on and off;
 *   - alpha = 0 never passes and alpha = 1 always does, for every strategy;
 *   - uniformity: chi-square over 64 bins of 2^20 thresholds below the 0.999 quantile of chi2(63)
 *     (~103.4); the inputs are fixed (seeded), so this is a deterministic check that fails for a
 *     good hash with probability 0.001 only if the seed is changed;
 *   - stability: the measured fractions for sub-pixel shifts against the closed forms derived in
 *     docs/hashed-alpha.md, with margins;
 *   - the a2c masks' popcounts and layer decorrelation, the fade ramp, the texture LOD.
 * Measured numbers (chi2 of sine vs pcg at small and large coordinates, stability, ns per
 * threshold) are printed to stderr; docs/hashed-alpha.md quotes them. */
#include "passes/alpha_hash.h"

#include <float.h>
#include <stdint.h>
#include <time.h>

#include "common/shared_defs.h"
#include "test.h"

/* >>helpers */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint64_t rng_u64(void)
{
    /* splitmix64 */
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1). */
static double rng01(void)
{
    return (double)(rng_u64() >> 11) * (1.0 / 9007199254740992.0);
}

static float rngf(double lo, double hi)
{
    return (float)(lo + (hi - lo) * rng01());
}

/* Draws in a fixed order (the order of evaluation of function arguments is unspecified in C, so
 * v3(rngf(), rngf(), rngf()) would give different inputs with different compilers). */
static vec3 rand_v3(double lo, double hi)
{
    float x = rngf(lo, hi);
    float y = rngf(lo, hi);
    float z = rngf(lo, hi);
    return v3(x, y, z);
}

static void deriv_pair(double level, double dir, vec3 *dx, vec3 *dy);

/* deriv_pair at a random level in [lo, hi) and a random direction. */
static void rand_derivs(double lo, double hi, vec3 *dx, vec3 *dy)
{
    double level = rngf(lo, hi);
    double dir = rng01();
    deriv_pair(level, dir, dx, dy);
}

enum { BINS = 64 };

typedef struct hist {
    long long n[BINS];
    long long total;
} hist;

static void hist_add(hist *h, float t)
{
    int b = (int)(t * BINS);
    if (b >= BINS) /* t = 1 (possible: thresholds live in (0, 1]) */
        b = BINS - 1;
    if (b < 0)
        b = 0;
    h->n[b]++;
    h->total++;
}

static double hist_chi2(const hist *h)
{
    double e = (double)h->total / BINS, c = 0;
    for (int i = 0; i < BINS; i++)
        c += (h->n[i] - e) * (h->n[i] - e) / e;
    return c;
}

/* Upper p-quantile of chi2 with k degrees of freedom (Wilson-Hilferty; 0.999 and k = 63 gives
 * 103.5, the exact value is 103.44). z is the standard normal quantile (3.0902 for 0.999). */
static double chi2_quantile(double k, double z)
{
    double s = 2.0 / (9.0 * k);
    double c = 1.0 - s + z * sqrt(s);
    return k * c * c * c;
}

static double chi2_crit_0999(void)
{
    return chi2_quantile(BINS - 1, 3.0902);
}

static bool in_unit(float t)
{
    return isfinite(t) && t > 0.0f && t <= 1.0f;
}

static vec3 scaled(vec3 a, float s)
{
    return v3(a.x * s, a.y * s, a.z * s);
}

/* A derivative pair whose log2 interpolation factor sweeps [0, 1) continuously with u (hash scale
 * 1): max(|dx|, |dy|) = 2^-(k + u), the direction and the minor axis vary with `dir`. */
static void deriv_pair(double level, double dir, vec3 *dx, vec3 *dy)
{
    float d = (float)exp2(-level);
    double a = 2.0 * 3.14159265358979 * dir;
    *dx = v3(d * (float)cos(a), d * (float)sin(a), 0.0f);
    *dy = v3(-d * 0.7f * (float)sin(a), d * 0.7f * (float)cos(a), d * 0.1f);
}

/* >>hard-cases */

TEST(cdf_hard_cases_are_finite_and_monotonic)
{
    const float lerps[] = {0.0f, 1.0f, 0.5f, 1e-7f, 1.0f - 1e-7f, 1e-30f, 1e-45f, FLT_MIN,
                           0x1.fffffep-1f, 0x1p-24f, 0.25f, 0.75f, 0.3333333f, -0.0f};
    int bad = 0, nonmono = 0;
    for (size_t i = 0; i < sizeof lerps / sizeof lerps[0]; i++) {
        float f = lerps[i];
        float prev = -1.0f;
        for (int k = 0; k <= 4096; k++) {
            float x = k == 4096 ? 1.0f : (float)k / 4096.0f;
            float c = alpha_hash_cdf(x, f);
            if (!(isfinite(c) && c >= 0.0f && c <= 1.0f))
                bad++;
            if (c < prev - 1e-6f)
                nonmono++;
            prev = c;
        }
        /* The branch boundaries themselves, and their neighbours. */
        float a = fminf(f, 1.0f - f);
        const float xs[] = {a, nextafterf(a, 0.0f), nextafterf(a, 1.0f), 1.0f - a, nextafterf(1.0f - a, 0.0f),
                            nextafterf(1.0f - a, 2.0f), 0.0f, FLT_MIN, 0x1.fffffep-1f, 1.0f};
        for (size_t j = 0; j < sizeof xs / sizeof xs[0]; j++) {
            float c = alpha_hash_cdf(xs[j], f);
            if (!(isfinite(c) && c >= 0.0f && c <= 1.0f))
                bad++;
        }
    }
    CHECK(bad == 0);
    CHECK(nonmono == 0);
    /* a = 0: the CDF of a single uniform is the identity. a = 0.5: the triangle distribution. */
    for (int k = 0; k < 100; k++) {
        float x = (float)k / 100.0f;
        CHECK(alpha_hash_cdf(x, 0.0f) == x);
        CHECK(alpha_hash_cdf(x, 1.0f) == x);
        double tri = x < 0.5f ? 2.0 * x * x : 1.0 - 2.0 * (1.0 - x) * (1.0 - x);
        CHECK_NEAR(alpha_hash_cdf(x, 0.5f), tri, 1e-6);
    }
    /* Eq. 1's middle branch, a = 0.25. */
    CHECK_NEAR(alpha_hash_cdf(0.5f, 0.25f), (0.5 - 0.125) / 0.75, 1e-6);
}

TEST(thresholds_are_in_range_for_every_hard_case)
{
    const float coords[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, -0.5f, 0.25f, 3.0f, 1e-40f, -1e-40f, 1e-30f,
                            123456.0f, -98765.0f, 1e5f, -1e5f, 1e7f, -1e7f, 16777216.0f, 1e7f + 0.5f,
                            3e38f, -3e38f, NAN, INFINITY, -INFINITY};
    const float derivs[] = {0.0f, 1e-40f, 1e-30f, 1e-7f, 1e-3f, 0.01f, 0.37f, 1.0f, 3.0f, 1e30f, 3e38f,
                            NAN, INFINITY, 0x1p-10f, 0x1p-10f * 1.0000001f, 0x1p-10f * 0.9999999f, 0.5f * 1.0000001f};
    const float scales[] = {1.0f, 0.3f, 0.0f, -1.0f, NAN, INFINITY, 1e-30f, 1e30f};
    const int ncoord = (int)(sizeof coords / sizeof coords[0]);
    const int nderiv = (int)(sizeof derivs / sizeof derivs[0]);
    const int nscale = (int)(sizeof scales / sizeof scales[0]);
    long long combos = 0, bad = 0;
    for (int kind = 0; kind <= 2; kind++) /* pcg, sine, and an unknown kind (falls back to pcg) */
        for (int aniso = 0; aniso <= 1; aniso++)
            for (int ci = 0; ci < ncoord; ci++)
                for (int cj = 0; cj < ncoord; cj += 3)
                    for (int di = 0; di < nderiv; di++)
                        for (int dj = 0; dj < nderiv; dj += 2) {
                            vec3 obj = v3(coords[ci], coords[cj], coords[(ci + cj) % ncoord]);
                            vec3 dx = v3(derivs[di], 0.0f, derivs[dj]);
                            vec3 dy = v3(0.0f, derivs[dj], derivs[di] * 0.5f);
                            float hs = scales[(ci + di + dj) % nscale];
                            float t = alpha_hashed_threshold(obj, dx, dy, hs, kind == 2 ? 7 : kind, aniso);
                            combos++;
                            if (!in_unit(t) || t < (float)ALPHA_THRESHOLD_MIN) {
                                if (bad < 5)
                                    fprintf(stderr, "  bad threshold %g: obj (%g %g %g) d %g %g hs %g kind %d aniso %d\n",
                                            t, obj.x, obj.y, obj.z, derivs[di], derivs[dj], hs, kind, aniso);
                                bad++;
                            }
                        }
    /* Interpolation factor exactly 0, 0.5 and within 1e-7 of 0 or 1 (level 10 +- 1e-7). */
    const double levels[] = {10.0, 10.5, 10.0 + 1e-7, 10.0 - 1e-7, 11.0 - 1e-7, -3.0, -3.0 + 1e-7, 0.0, 1e-7, -1e-7};
    for (size_t li = 0; li < sizeof levels / sizeof levels[0]; li++)
        for (int i = 0; i < 2000; i++) {
            vec3 dx, dy;
            deriv_pair(levels[li], rng01(), &dx, &dy);
            vec3 obj = rand_v3(-50, 50);
            float t = alpha_hashed_threshold(obj, dx, dy, 1.0f, i & 1, (i >> 1) & 1);
            combos++;
            bad += !in_unit(t);
        }
    fprintf(stderr, "  %lld combinations, %lld out of (0,1]\n", combos, bad);
    CHECK(combos > 10000);
    CHECK(bad == 0);
    /* The clamped log2 scale: zero derivatives -> finest (+60), infinite -> coarsest (-60). */
    CHECK(alpha_hash_log2_scale(v3(0, 0, 0), v3(0, 0, 0), 1.0f) == (float)ALPHA_HASH_LOG2_CLAMP);
    CHECK(alpha_hash_log2_scale(v3(1e-40f, 0, 0), v3(0, 0, 0), 1.0f) == (float)ALPHA_HASH_LOG2_CLAMP);
    CHECK(alpha_hash_log2_scale(v3(1e30f, 0, 0), v3(0, 0, 0), 1.0f) == -(float)ALPHA_HASH_LOG2_CLAMP);
    CHECK(alpha_hash_log2_scale(v3(INFINITY, 0, 0), v3(0, 0, 0), 1.0f) == -(float)ALPHA_HASH_LOG2_CLAMP);
    CHECK(alpha_hash_log2_scale(v3(NAN, 0, 0), v3(0.25f, 0, 0), 1.0f) == 2.0f); /* NaN axis ignored */
    CHECK(alpha_hash_log2_scale(v3(0.25f, 0, 0), v3(0, 0, 0), NAN) == 2.0f);   /* default scale */
    /* NaN coordinates hash as 0: the same threshold as the origin. */
    vec3 d = v3(0.01f, 0, 0), e = v3(0, 0.01f, 0);
    CHECK(alpha_hashed_threshold(v3(NAN, NAN, NAN), d, e, 1, ALPHA_HASH_PCG, false) ==
          alpha_hashed_threshold(v3(0, 0, 0), d, e, 1, ALPHA_HASH_PCG, false));
    CHECK(alpha_hashed_threshold(v3(-0.0f, -0.0f, -0.0f), d, e, 1, ALPHA_HASH_SINE, false) ==
          alpha_hashed_threshold(v3(0, 0, 0), d, e, 1, ALPHA_HASH_SINE, false));
}

/* The per-cell guards were replaced by one test per coordinate (docs/hashed-alpha.md, "Cost"):
 * coordinates outside [2^-62, 2^63) in magnitude (0, tiny, huge, NaN, inf) hash as 0, at every
 * level from the finest (+60, anisotropic +64) to the coarsest (-60), so every cell is finite and
 * exact and no product is denormal; the ends of the kept range are hashed as they are. */
TEST(coordinates_outside_the_hashed_range_hash_as_zero)
{
    const float outside[] = {NAN, INFINITY, -INFINITY, 1e30f, -3e38f, 0x1p63f, -0x1p63f, 1e-40f, -1e-40f, -1e-30f,
                             0x1p-63f, -0x1.fffffep-63f, -0.0f};
    const float d[] = {0.0f, 1e-30f, 0x1p-10f, 0.37f, 1e30f, INFINITY};
    int bad = 0, n = 0;
    for (int kind = 0; kind <= 1; kind++)
        for (int aniso = 0; aniso <= 1; aniso++)
            for (size_t di = 0; di < sizeof d / sizeof d[0]; di++)
                for (size_t i = 0; i < sizeof outside / sizeof outside[0]; i++) {
                    vec3 dx = v3(d[di], 0.0f, 0.0f), dy = v3(0.0f, 0.5f * d[di], 0.0f);
                    float o = outside[i];
                    float ref = alpha_hashed_threshold(v3(0.0f, 0.25f, 0.0f), dx, dy, 1.0f, kind, aniso);
                    float t = alpha_hashed_threshold(v3(o, 0.25f, o), dx, dy, 1.0f, kind, aniso);
                    n++;
                    bad += t != ref || !in_unit(t);
                }
    CHECK(n > 0);
    CHECK(bad == 0);
    /* Inside the range, at the finest level: 2^-62 * 2^60 = 0.25 -> cell 0, -2^-62 -> cell -1. */
    float zero = alpha_hashed_threshold(v3(0, 0, 0), v3(0, 0, 0), v3(0, 0, 0), 1.0f, ALPHA_HASH_PCG, false);
    float neg = alpha_hashed_threshold(v3(-0x1p-62f, 0, 0), v3(0, 0, 0), v3(0, 0, 0), 1.0f, ALPHA_HASH_PCG, false);
    CHECK(neg != zero);
}

/* Listing 1 written out literally (exp2, all three CDF cases), with each level's hash keyed by
 * alpha_hash_level_key, agrees with the implementation on ordinary inputs, where the hard-case
 * guards do nothing. */
TEST(matches_listing_1_on_ordinary_inputs)
{
    int worst_i = -1;
    double worst = 0;
    for (int i = 0; i < 100000; i++) {
        vec3 obj = rand_v3(-20, 20);
        vec3 dx, dy;
        rand_derivs(-2, 12, &dx, &dy);
        int kind = i & 1;
        float max_deriv = fmaxf(sqrtf(dx.x * dx.x + dx.y * dx.y + dx.z * dx.z), sqrtf(dy.x * dy.x + dy.y * dy.y + dy.z * dy.z));
        float pix_scale = 1.0f / (1.0f * max_deriv);
        float s0 = exp2f(floorf(log2f(pix_scale))), s1 = exp2f(ceilf(log2f(pix_scale)));
        /* The one departure this keeps: each level hashes its own lattice (docs/hashed-alpha.md "Assets a pixel or two wide"). */
        uint32_t k0 = alpha_hash_level_key((int)floorf(log2f(pix_scale)));
        uint32_t k1 = alpha_hash_level_key((int)ceilf(log2f(pix_scale)));
        float h0 = alpha_hash_kind_layer(v3(floorf(s0 * obj.x), floorf(s0 * obj.y), floorf(s0 * obj.z)), kind, k0);
        float h1 = alpha_hash_kind_layer(v3(floorf(s1 * obj.x), floorf(s1 * obj.y), floorf(s1 * obj.z)), kind, k1);
        float lf = log2f(pix_scale) - floorf(log2f(pix_scale));
        float x = (1 - lf) * h0 + lf * h1;
        float a = fminf(lf, 1 - lf);
        float cx = x * x / (2 * a * (1 - a)), cy = (x - 0.5f * a) / (1 - a), cz = 1.0f - ((1 - x) * (1 - x) / (2 * a * (1 - a)));
        float ref = (x < (1 - a)) ? ((x < a) ? cx : cy) : cz;
        ref = fminf(fmaxf(ref, 1e-6f), 1.0f);
        float t = alpha_hashed_threshold(obj, dx, dy, 1.0f, kind, false);
        double err = fabs((double)t - ref);
        if (err > worst) {
            worst = err;
            worst_i = i;
        }
    }
    fprintf(stderr, "  largest difference to a literal Listing 1: %.3g (input %d)\n", worst, worst_i);
    CHECK(worst < 1e-5);
}

/* >>pass-fail */

TEST(alpha_zero_never_passes_alpha_one_always_does)
{
    long long n = 0, bad = 0;
    for (int i = 0; i < 200000; i++) {
        vec3 obj = rand_v3(-1e4, 1e4);
        vec3 dx, dy;
        rand_derivs(-20, 30, &dx, &dy);
        float t = alpha_hashed_threshold(obj, dx, dy, rngf(0.2, 2), i & 1, (i >> 1) & 1);
        float cutoff = (i % 7 == 0) ? 0.0f : (i % 7 == 1) ? 1.0f : rngf(0, 1);
        float lod = rngf(-4, 12);
        float f = alpha_hashed_fade(cutoff, t, lod, (i % 5 == 0) ? 0.0f : 6.0f);
        float s = alpha_stochastic_threshold((uint32_t)i, (uint32_t)(i * 7), (uint32_t)(i >> 3), 0u);
        uint32_t nsamp = 1u << (i % 5);
        uint32_t all = nsamp == 32u ? 0xffffffffu : (1u << nsamp) - 1u;
        float xi1 = rngf(0, 1), xi2 = rngf(0, 1);
        uint32_t m0 = alpha_hashed_a2c_mask(0.0f, (int)nsamp, xi1, xi2, t);
        uint32_t m1 = alpha_hashed_a2c_mask(1.0f, (int)nsamp, xi2, xi1, t);
        n++;
        bad += (0.0f >= t) || !(1.0f >= t);
        bad += (0.0f >= f) || !(1.0f >= f);
        bad += (0.0f >= s) || !(1.0f >= s);
        bad += m0 != 0u || m1 != all;
    }
    CHECK(bad == 0);
    /* The extreme stochastic values: 2^-24 is the smallest, 1 is reachable (the +1 of the formula). */
    float lo = 1.0f, hi = 0.0f;
    for (uint32_t y = 0; y < 1024; y++)
        for (uint32_t x = 0; x < 1024; x++) {
            float s = alpha_stochastic_threshold(x, y, 3u, 0u);
            lo = fminf(lo, s);
            hi = fmaxf(hi, s);
        }
    CHECK(lo >= 0x1p-24f);
    CHECK(hi <= 1.0f);
    fprintf(stderr, "  %lld inputs; stochastic range over 2^20 pixels [%g, %g]\n", n, lo, hi);
}

/* >>uniformity */

/* chi2 of 2^20 hashed thresholds whose interpolation factor sweeps [0, 1) continuously. With
 * flat_z finite, every point lies on the plane z = flat_z (a leaf card in its own plane) instead of
 * filling a volume. */
static double threshold_chi2_on(int kind, bool aniso, double clo, double chi, bool correct, double flat_z)
{
    hist h = {{0}, 0};
    rng_state = 12345;
    for (int i = 0; i < (1 << 20); i++) {
        float c[3];
        for (int k = 0; k < 3; k++) {
            double sgn = rng01() < 0.5 ? -1 : 1;
            c[k] = (float)(sgn * (clo + (chi - clo) * rng01()));
        }
        if (isfinite(flat_z))
            c[2] = (float)flat_z;
        vec3 obj = v3(c[0], c[1], c[2]);
        vec3 dx, dy;
        /* The level sweeps 4 octaves continuously (0.5 .. 8 pixels per unit at small coordinates;
         * at large ones the same ratios around a coarser base, so that cells stay above one ulp). */
        double base = clo > 1000 ? -6.0 : 0.0;
        deriv_pair(base + 4.0 * (double)i / (1 << 20), rng01(), &dx, &dy);
        if (correct) {
            hist_add(&h, alpha_hashed_threshold(obj, dx, dy, 1.0f, kind, aniso));
        } else {
            /* Listing 1 without the CDF correction: the plain lerp of the two hashes. */
            float l = alpha_hash_log2_scale(dx, dy, 1.0f), f = l - floorf(l);
            float s0 = exp2f(floorf(l)), s1 = exp2f(ceilf(l));
            float h0 = alpha_hash_kind(v3(floorf(s0 * obj.x), floorf(s0 * obj.y), floorf(s0 * obj.z)), kind);
            float h1 = alpha_hash_kind(v3(floorf(s1 * obj.x), floorf(s1 * obj.y), floorf(s1 * obj.z)), kind);
            hist_add(&h, (1 - f) * h0 + f * h1);
        }
    }
    return hist_chi2(&h);
}

static double threshold_chi2(int kind, bool aniso, double clo, double chi, bool correct)
{
    return threshold_chi2_on(kind, aniso, clo, chi, correct, INFINITY);
}

TEST(hashed_thresholds_are_uniform_on_flat_cards)
{
    /* Points on one plane, as on a leaf card: the random-volume test above cannot see a hash that
     * is only uniform when all three coordinates vary. pcg3d stays uniform on every card; the
     * paper's sine hash does not (measured, reported; docs/hashed-alpha.md), which is why pcg3d is
     * the default. */
    double crit = chi2_crit_0999();
    static const double planes[] = {0.0, 0.37, 12.5, 1000.25};
    double worst_pcg = 0, worst_sine = 0, best_sine = INFINITY;
    for (size_t i = 0; i < sizeof planes / sizeof planes[0]; i++) {
        double p = threshold_chi2_on(ALPHA_HASH_PCG, false, 0.0, 100.0, true, planes[i]);
        double q = threshold_chi2_on(ALPHA_HASH_SINE, false, 0.0, 100.0, true, planes[i]);
        fprintf(stderr, "  flat card z = %-7g chi2 pcg %8.1f   sine %9.1f\n", planes[i], p, q);
        worst_pcg = fmax(worst_pcg, p);
        worst_sine = fmax(worst_sine, q);
        best_sine = fmin(best_sine, q);
        CHECK(p < crit);
    }
    fprintf(stderr, "  flat cards: pcg at most %.1f, sine %.1f .. %.1f (critical value %.1f)\n", worst_pcg, best_sine,
            worst_sine, crit);
}

TEST(hashed_thresholds_are_uniform)
{
    double crit = chi2_crit_0999();
    double pcg_small = threshold_chi2(ALPHA_HASH_PCG, false, 0.0, 100.0, true);
    double sine_small = threshold_chi2(ALPHA_HASH_SINE, false, 0.0, 100.0, true);
    double pcg_large = threshold_chi2(ALPHA_HASH_PCG, false, 1e5, 1e7, true);
    double sine_large = threshold_chi2(ALPHA_HASH_SINE, false, 1e5, 1e7, true);
    double pcg_1e6 = threshold_chi2(ALPHA_HASH_PCG, false, 1e6, 2e6, true);
    double sine_1e6 = threshold_chi2(ALPHA_HASH_SINE, false, 1e6, 2e6, true);
    double pcg_aniso = threshold_chi2(ALPHA_HASH_PCG, true, 0.0, 100.0, true);
    double sine_aniso = threshold_chi2(ALPHA_HASH_SINE, true, 0.0, 100.0, true);
    double pcg_raw = threshold_chi2(ALPHA_HASH_PCG, false, 0.0, 100.0, false);
    fprintf(stderr, "  chi2(63 dof), 2^20 thresholds, critical value at p = 0.001: %.1f\n", crit);
    fprintf(stderr, "  |p| < 100:       pcg %8.1f   sine %8.1f\n", pcg_small, sine_small);
    fprintf(stderr, "  |p| in 1e6..2e6: pcg %8.1f   sine %8.1f\n", pcg_1e6, sine_1e6);
    fprintf(stderr, "  |p| in 1e5..1e7: pcg %8.1f   sine %8.1f\n", pcg_large, sine_large);
    fprintf(stderr, "  anisotropic:     pcg %8.1f   sine %8.1f\n", pcg_aniso, sine_aniso);
    fprintf(stderr, "  pcg without the Eq. 1 CDF correction: %.0f\n", pcg_raw);
    CHECK(pcg_small < crit);
    CHECK(pcg_1e6 < crit);
    CHECK(pcg_large < crit);
    CHECK(pcg_aniso < crit);
    CHECK(sine_small < crit);
    CHECK(sine_aniso < crit);
    /* Eq. 1 matters: the plain lerp of two uniforms is far from uniform. */
    CHECK(pcg_raw > 10 * crit);
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

static int distinct_values(float *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_float);
    int d = n > 0;
    for (int i = 1; i < n; i++)
        d += v[i] != v[i - 1];
    return d;
}

TEST(hashes_are_uniform_on_integer_lattices)
{
    /* The raw hashes on consecutive integer cells, the way Listing 1 feeds them: a block of 16
     * z-slices, and one flat card (a single z, like a leaf in its own plane). The sine hash's
     * fract(1e4 ...) keeps ~10 bits at its usual magnitude, so its values repeat: few distinct
     * values, lumpy bins. Reported for sine, asserted for pcg. */
    double crit = chi2_crit_0999();
    const double bases[] = {0.0, 1e6, -1e7};
    enum { NXY = 256 * 256, NZ = 16 };
    float *vp = malloc(sizeof(float) * NXY * NZ), *vs = malloc(sizeof(float) * NXY * NZ);
    if (!vp || !vs) {
        CHECK(vp && vs);
        free(vp);
        free(vs);
        return;
    }
    for (size_t b = 0; b < sizeof bases / sizeof bases[0]; b++)
        for (int nz = NZ; nz >= 1; nz -= NZ - 1) {
            hist hp = {{0}, 0}, hs = {{0}, 0};
            int k = 0;
            for (int z = 0; z < nz; z++)
                for (int y = 0; y < 256; y++)
                    for (int x = 0; x < 256; x++, k++) {
                        vec3 p = v3((float)(bases[b] + x), (float)(bases[b] + y * 3), (float)(bases[b] + z * 17));
                        vp[k] = alpha_hash_pcg(p);
                        vs[k] = alpha_hash_sine(p);
                        hist_add(&hp, vp[k]);
                        hist_add(&hs, vs[k]);
                    }
            double cp = hist_chi2(&hp), cs = hist_chi2(&hs);
            int dp = distinct_values(vp, k), ds = distinct_values(vs, k);
            fprintf(stderr, "  lattice at %-6g %2d slice(s), %7d cells: chi2 pcg %6.1f sine %8.1f; distinct values pcg %7d sine %7d\n",
                    bases[b], nz, k, cp, cs, dp, ds);
            CHECK(cp < crit);
            /* 24-bit outputs: an ideal hash of k cells gives 2^24 (1 - exp(-k / 2^24)) distinct values. */
            double ideal = 16777216.0 * -expm1(-(double)k / 16777216.0);
            CHECK(fabs(dp - ideal) < 0.001 * k);
        }
    free(vp);
    free(vs);
}

/* >>stability */

/* Fraction of thresholds unchanged when obj moves by `shift` pixel footprints along dx (screen x),
 * derivatives fixed. */
static double shift_unchanged(int kind, bool aniso, float shift, double *mean_delta)
{
    int same = 0, n = 200000;
    double sum = 0;
    rng_state = 777;
    for (int i = 0; i < n; i++) {
        vec3 obj = rand_v3(-30, 30);
        vec3 dx, dy;
        rand_derivs(2, 8, &dx, &dy);
        float t0 = alpha_hashed_threshold(obj, dx, dy, 1.0f, kind, aniso);
        vec3 o1 = v3(obj.x + shift * dx.x, obj.y + shift * dx.y, obj.z + shift * dx.z);
        float t1 = alpha_hashed_threshold(o1, dx, dy, 1.0f, kind, aniso);
        same += t0 == t1;
        sum += fabs((double)t1 - t0);
    }
    if (mean_delta)
        *mean_delta = sum / n;
    return (double)same / n;
}

TEST(stable_under_sub_pixel_translation)
{
    /* Closed form (docs/hashed-alpha.md): the finer of the two noise grids has cells of
     * 2^(f - 1) pixels (f = the interpolation factor, uniform), the coarser grid nests it, so a shift
     * of s pixels along an axis keeps the threshold with probability 1 - s 2^(1-f) (for s < 2^(f-1)),
     * i.e. 1 - s / ln 2 on average when the shift is along a grid axis: 0.64 for s = 0.25, 0.86 for
     * s = 0.1. Directions here are random, so a shift crosses x and y cell walls: a little less. */
    double d25, d10, d25a, d25s;
    double s25 = shift_unchanged(ALPHA_HASH_PCG, false, 0.25f, &d25);
    double s10 = shift_unchanged(ALPHA_HASH_PCG, false, 0.10f, &d10);
    double s25sine = shift_unchanged(ALPHA_HASH_SINE, false, 0.25f, &d25s);
    double s25a = shift_unchanged(ALPHA_HASH_PCG, true, 0.25f, &d25a);
    double s100 = shift_unchanged(ALPHA_HASH_PCG, false, 1.0f, NULL);
    /* Stochastic alpha for comparison: new thresholds every frame. */
    int st_same = 0;
    for (uint32_t i = 0; i < 200000; i++)
        st_same += alpha_stochastic_threshold(i % 512u, i / 512u, 0u, 0u) == alpha_stochastic_threshold(i % 512u, i / 512u, 1u, 0u);
    /* The closed form itself: axis-aligned footprint, shift along x. */
    int same_axis = 0;
    const int n_axis = 200000;
    for (int i = 0; i < n_axis; i++) {
        float d = (float)exp2(-rngf(2, 8));
        vec3 o = rand_v3(-30, 30);
        vec3 dx = v3(d, 0, 0), dy = v3(0, d, 0);
        same_axis += alpha_hashed_threshold(o, dx, dy, 1, ALPHA_HASH_PCG, false) ==
                     alpha_hashed_threshold(v3(o.x + 0.25f * d, o.y, o.z), dx, dy, 1, ALPHA_HASH_PCG, false);
    }
    double axis = (double)same_axis / n_axis, expect_axis = 1.0 - 0.25 / log(2.0);
    fprintf(stderr, "  axis-aligned 0.25 px shift: %.2f%% unchanged (closed form %.2f%%)\n", 100 * axis, 100 * expect_axis);
    CHECK(fabs(axis - expect_axis) < 0.01);
    fprintf(stderr, "  unchanged after a shift of 0.25 px: pcg %.1f%% (mean |dt| %.3f), sine %.1f%%, "
                    "pcg anisotropic %.1f%%; 0.1 px: %.1f%%; 1 px: %.1f%%; stochastic next frame %.3f%%\n",
            100 * s25, d25, 100 * s25sine, 100 * s25a, 100 * s10, 100 * s100, 100.0 * st_same / 200000);
    CHECK(s25 >= 0.50);
    CHECK(s10 >= 0.75);
    CHECK(s25sine >= 0.50);
    CHECK(s25a >= 0.40);
    CHECK(s100 < s25);
    CHECK(st_same < 200);
}

TEST(continuous_under_z_translation)
{
    /* Moving along the view axis scales the derivatives; Listing 1 interpolates between the two
     * nearest power-of-two noise scales, so a 1% zoom moves the interpolation factor by
     * log2(1.01) = 0.0144 and the threshold by about that times E|u1 - u2| = 1/3, not by a fresh
     * random value (E|u1 - u2| = 1/3). Across a whole octave the thresholds keep their continuity
     * (the factor wraps where one grid takes the other's place). */
    const int n = 200000;
    double sum_iso = 0, sum_sine = 0, max_jump_at_wrap = 0;
    long long unchanged = 0;
    rng_state = 99;
    for (int i = 0; i < n; i++) {
        vec3 obj = rand_v3(-30, 30);
        vec3 dx, dy;
        rand_derivs(2, 8, &dx, &dy);
        float t0 = alpha_hashed_threshold(obj, dx, dy, 1.0f, ALPHA_HASH_PCG, false);
        float t1 = alpha_hashed_threshold(obj, scaled(dx, 1.01f), scaled(dy, 1.01f), 1.0f, ALPHA_HASH_PCG, false);
        float s0 = alpha_hashed_threshold(obj, dx, dy, 1.0f, ALPHA_HASH_SINE, false);
        float s1 = alpha_hashed_threshold(obj, scaled(dx, 1.01f), scaled(dy, 1.01f), 1.0f, ALPHA_HASH_SINE, false);
        sum_iso += fabs((double)t1 - t0);
        sum_sine += fabs((double)s1 - s0);
        unchanged += t0 == t1;
        /* Straddling an integer level: factor just below 1 vs just above 0. */
        vec3 ex, ey;
        double lev = (double)(2 + (i % 6));
        deriv_pair(lev - 1e-4, 0.3, &ex, &ey);
        float a = alpha_hashed_threshold(obj, ex, ey, 1.0f, ALPHA_HASH_PCG, false);
        deriv_pair(lev + 1e-4, 0.3, &ex, &ey);
        float b = alpha_hashed_threshold(obj, ex, ey, 1.0f, ALPHA_HASH_PCG, false);
        max_jump_at_wrap = fmax(max_jump_at_wrap, fabs((double)a - b));
    }
    fprintf(stderr, "  1%% zoom: mean |dt| pcg %.4f, sine %.4f (a fresh random threshold: 0.333); "
                    "unchanged %.1f%%; largest jump across an octave boundary +-1e-4: %.4f\n",
            sum_iso / n, sum_sine / n, 100.0 * unchanged / n, max_jump_at_wrap);
    CHECK(sum_iso / n < 0.02);
    CHECK(sum_sine / n < 0.02);
    CHECK(max_jump_at_wrap < 0.01);
}

TEST(anisotropic_option_gives_pixel_scale_noise_along_the_minor_axis)
{
    /* An oblique fence: 4 object units per pixel along x (dx), 1 along y (dy). Isotropic cells are
     * sized by the major axis, so neighbouring pixels in y mostly share a cell; the anisotropic option
     * refines y by 4 and neighbours differ about as often as across x. */
    const int n = 100000;
    int diff_iso_y = 0, diff_aniso_y = 0, diff_aniso_x = 0;
    rng_state = 4242;
    for (int i = 0; i < n; i++) {
        float d = (float)exp2(-rngf(3, 6));
        vec3 dx = v3(4 * d, 0, 0), dy = v3(0, d, 0);
        vec3 o = rand_v3(-50, 50);
        vec3 oy = v3(o.x, o.y + d, o.z), ox = v3(o.x + 4 * d, o.y, o.z);
        diff_iso_y += alpha_hashed_threshold(o, dx, dy, 1, ALPHA_HASH_PCG, false) != alpha_hashed_threshold(oy, dx, dy, 1, ALPHA_HASH_PCG, false);
        diff_aniso_y += alpha_hashed_threshold(o, dx, dy, 1, ALPHA_HASH_PCG, true) != alpha_hashed_threshold(oy, dx, dy, 1, ALPHA_HASH_PCG, true);
        diff_aniso_x += alpha_hashed_threshold(o, dx, dy, 1, ALPHA_HASH_PCG, true) != alpha_hashed_threshold(ox, dx, dy, 1, ALPHA_HASH_PCG, true);
    }
    fprintf(stderr, "  one pixel step along the minor axis changes the threshold: isotropic %.1f%%, anisotropic %.1f%% "
                    "(major axis, anisotropic: %.1f%%)\n", 100.0 * diff_iso_y / n, 100.0 * diff_aniso_y / n, 100.0 * diff_aniso_x / n);
    CHECK(diff_iso_y < 0.45 * n);
    CHECK(diff_aniso_y > 0.85 * n);
    CHECK(fabs((double)diff_aniso_y - diff_aniso_x) < 0.1 * n);
    /* Isotropic derivatives: the option changes only the axis along the normal (constant on the surface). */
    int equal_xy = 0;
    for (int i = 0; i < 1000; i++) {
        float ox = rngf(-5, 5), oy = rngf(-5, 5);
        vec3 o = v3(ox, oy, 0.0f);
        equal_xy += alpha_hashed_threshold(o, v3(0.01f, 0, 0), v3(0, 0.01f, 0), 1, ALPHA_HASH_PCG, true) ==
                    alpha_hashed_threshold(o, v3(0.01f, 0, 0), v3(0, 0.01f, 0), 1, ALPHA_HASH_PCG, false);
    }
    CHECK(equal_xy == 1000); /* z = 0: the finer z grid still gives cell 0 */
}

/* >>stochastic */

TEST(stochastic_is_uniform_and_new_every_frame)
{
    hist h = {{0}, 0};
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    const uint32_t w = 1024, hgt = 1024;
    for (uint32_t y = 0; y < hgt; y++)
        for (uint32_t x = 0; x < w; x++) {
            float a = alpha_stochastic_threshold(x, y, 41u, 0u);
            float b = alpha_stochastic_threshold(x, y, 42u, 0u);
            hist_add(&h, a);
            sx += a;
            sy += b;
            sxx += (double)a * a;
            syy += (double)b * b;
            sxy += (double)a * b;
        }
    double n = (double)w * hgt;
    double r = (sxy / n - sx / n * sy / n) / sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
    /* Neighbouring pixels in one frame, too. */
    double nx = 0, nxy = 0, m = 0;
    for (uint32_t i = 0; i < 200000; i++) {
        float a = alpha_stochastic_threshold(i % 1000u, i / 1000u, 7u, 0u);
        float b = alpha_stochastic_threshold(i % 1000u + 1u, i / 1000u, 7u, 0u);
        nxy += ((double)a - 0.5) * ((double)b - 0.5);
        nx += ((double)a - 0.5) * ((double)a - 0.5);
        m++;
    }
    double r_nb = nxy / nx;
    /* A salt separates streams: the same pixel and frame with another salt is unrelated. */
    int salt_same = 0;
    for (uint32_t i = 0; i < 100000; i++)
        salt_same += alpha_stochastic_threshold(i, 5u, 9u, 0u) == alpha_stochastic_threshold(i, 5u, 9u, 0x5bd1e995u);
    fprintf(stderr, "  stochastic chi2 %.1f (critical %.1f), frame-to-frame correlation %.5f, "
                    "neighbour correlation %.5f, salt collisions %d\n",
            hist_chi2(&h), chi2_crit_0999(), r, r_nb, salt_same);
    CHECK(hist_chi2(&h) < chi2_crit_0999());
    CHECK(fabs(r) < 0.005); /* sd of r for 2^20 independent pairs ~ 0.001 */
    CHECK(fabs(r_nb) < 0.01);
    CHECK(salt_same < 10);
    (void)m;
}

/* >>a2c */

static int popcount32(uint32_t m)
{
    int c = 0;
    for (; m; m &= m - 1)
        c++;
    return c;
}

TEST(hashed_a2c_thresholds_and_masks)
{
    /* Each fragment's thresholds are a permutation of the strata (chi + k) / n (seed 000 Eq. 5). */
    for (int t = 0; t < 2000; t++) {
        int n = 1 << (t % 5);
        float xi1 = rngf(0, 1), xi2 = rngf(0, 1), chi = 1.0f - rngf(0, 1);
        int seen[16] = {0};
        for (int i = 0; i < n; i++) {
            float th = alpha_hashed_a2c_threshold(i, n, xi1, xi2, chi);
            int k = (int)floorf(th * n - chi + 0.5f);
            CHECK(k >= 0 && k < n);
            if (k >= 0 && k < n)
                seen[k]++;
            CHECK_NEAR(th, (chi + k) / n, 1e-6);
        }
        for (int k = 0; k < n; k++)
            CHECK(seen[k] == 1);
    }
    /* alpha = k/n sets exactly k bits, whatever xi and chi. */
    int wrong = 0;
    for (int t = 0; t < 20000; t++) {
        int n = 1 << (t % 5);
        int k = (int)(rng01() * (n + 1));
        float chi = (t % 3 == 0) ? 1.0f : 1.0f - rngf(0, 1);
        float xi1 = rngf(0, 1), xi2 = rngf(0, 1);
        uint32_t m = alpha_hashed_a2c_mask((float)k / (float)n, n, xi1, xi2, chi);
        wrong += popcount32(m) != k;
        wrong += (m >> n) != 0u;
    }
    CHECK(wrong == 0);
    /* Expected coverage = alpha for any alpha; two layers decorrelate (union = 1 - (1 - a)^2),
     * whereas a fixed pattern (traditional A2C: the same thresholds in every layer) gives union = a. */
    const int n = 4, trials = 400000;
    const float alphas[] = {0.1f, 0.3f, 0.37f, 0.5f, 0.8f};
    for (size_t ai = 0; ai < sizeof alphas / sizeof alphas[0]; ai++) {
        float a = alphas[ai];
        double cov = 0, uni = 0, uni_fixed = 0;
        for (int t = 0; t < trials; t++) {
            float chi1 = 1.0f - rngf(0, 1), chi2 = 1.0f - rngf(0, 1);
            float u1 = rngf(0, 1), u2 = rngf(0, 1), u3 = rngf(0, 1), u4 = rngf(0, 1);
            uint32_t m1 = alpha_hashed_a2c_mask(a, n, u1, u2, chi1);
            uint32_t m2 = alpha_hashed_a2c_mask(a, n, u3, u4, chi2);
            float xi1 = rngf(0, 1), xi2 = rngf(0, 1);
            uint32_t f1 = alpha_hashed_a2c_mask(a, n, xi1, xi2, chi1), f2 = alpha_hashed_a2c_mask(a, n, xi1, xi2, chi1);
            cov += popcount32(m1) / (double)n;
            uni += popcount32(m1 | m2) / (double)n;
            uni_fixed += popcount32(f1 | f2) / (double)n;
        }
        cov /= trials;
        uni /= trials;
        uni_fixed /= trials;
        double indep = 1.0 - (1.0 - a) * (1.0 - a);
        fprintf(stderr, "  alpha %.2f: coverage %.4f, two layers %.4f (independent %.4f, fixed pattern %.4f)\n", a, cov, uni,
                indep, uni_fixed);
        CHECK(fabs(cov - a) < 0.003);
        CHECK(fabs(uni - indep) < 0.005);
        CHECK(fabs(uni_fixed - cov) < 1e-9);
        CHECK(fabs(uni - indep) < fabs(uni_fixed - indep));
    }
    /* Bad n: rounded down to a power of two in [1, 16]. */
    CHECK(alpha_hashed_a2c_mask(1.0f, 6, 0.3f, 0.6f, 0.5f) == 0xfu);
    CHECK(alpha_hashed_a2c_mask(1.0f, 0, 0.3f, 0.6f, 0.5f) == 0x1u);
    CHECK(alpha_hashed_a2c_mask(1.0f, 64, 0.3f, 0.6f, 0.5f) == 0xffffu);
    CHECK(alpha_hashed_a2c_mask(1.0f, 4, NAN, NAN, NAN) == 0xfu);
    CHECK(alpha_hashed_a2c_mask(0.0f, 4, NAN, NAN, NAN) == 0u);
}

/* >>fade */

TEST(fade_ramp_is_quadratic_in_lod)
{
    const float n = (float)ALPHA_FADE_N_DEFAULT;
    /* b(x) = (x / n)^2: with cutoff 0.5 and threshold 1, the result is 0.5 + 0.5 b. */
    CHECK(alpha_hashed_fade(0.5f, 1.0f, 0.0f, n) == 0.5f);
    CHECK(alpha_hashed_fade(0.5f, 1.0f, -3.0f, n) == 0.5f);
    CHECK(alpha_hashed_fade(0.5f, 1.0f, n, n) == 1.0f);
    CHECK(alpha_hashed_fade(0.5f, 1.0f, 40.0f, n) == 1.0f);
    for (int k = 1; k < 60; k++) {
        float lod = (float)k / 10.0f;
        double b = (lod / n) * (lod / n);
        CHECK_NEAR(alpha_hashed_fade(0.5f, 1.0f, lod, n), 0.5 + 0.5 * b, 1e-6);
        CHECK_NEAR(alpha_hashed_fade(0.3f, 0.1f, lod, n), 0.3 - 0.2 * b, 1e-6);
    }
    /* fade_n <= 0 disables the fade. */
    CHECK(alpha_hashed_fade(0.5f, 0.123f, 0.0f, 0.0f) == 0.123f);
    CHECK(alpha_hashed_fade(0.5f, 0.123f, 0.0f, -2.0f) == 0.123f);
    CHECK(alpha_hashed_fade(0.5f, 0.123f, 0.0f, NAN) == 0.123f);
    /* Hard cases: cutoff 0 or 1, NaN everywhere: always in (0, 1]. */
    const float v[] = {0.0f, -0.0f, 1.0f, 0.5f, 1e-7f, 2.0f, -1.0f, NAN, INFINITY, -INFINITY, 1e30f};
    int bad = 0;
    for (size_t a = 0; a < 11; a++)
        for (size_t b = 0; b < 11; b++)
            for (size_t c = 0; c < 11; c++)
                for (size_t d = 0; d < 11; d++)
                    bad += !in_unit(alpha_hashed_fade(v[a], v[b], v[c], (a + b + d) % 3 ? 6.0f : v[(c + d) % 11]));
    CHECK(bad == 0);
    /* Cutoff 0 still rejects alpha 0: the cutoff is kept >= ALPHA_THRESHOLD_MIN. */
    CHECK(alpha_hashed_fade(0.0f, 0.5f, 0.0f, n) > 0.0f);
    CHECK(alpha_hashed_fade(0.5f, NAN, 6.0f, n) == 0.5f);
}

/* >>lod */

TEST(texture_lod_follows_the_long_axis)
{
    const float size[2] = {256, 128};
    /* One texel per pixel: lod 0. */
    float lod = alpha_texture_lod((float[2]){1.0f / 256, 0}, (float[2]){0, 1.0f / 128}, size);
    CHECK_NEAR(lod, 0.0, 1e-6);
    /* 4 texels per pixel: lod 2. */
    lod = alpha_texture_lod((float[2]){4.0f / 256, 0}, (float[2]){0, 4.0f / 128}, size);
    CHECK_NEAR(lod, 2.0, 1e-6);
    /* 8 x 2 texels: the longer axis decides the lod (3). */
    lod = alpha_texture_lod((float[2]){8.0f / 256, 0}, (float[2]){0, 2.0f / 128}, size);
    CHECK_NEAR(lod, 3.0, 1e-6);
    /* A diagonal footprint uses the length; a line footprint (minor axis 0) its length too. */
    lod = alpha_texture_lod((float[2]){3.0f / 256, 4.0f / 128}, (float[2]){0, 0}, size);
    CHECK_NEAR(lod, log2(5.0), 1e-6);
    /* Degenerate: zero and NaN -> lod 0; infinite -> the clamp. */
    CHECK(alpha_texture_lod((float[2]){0, 0}, (float[2]){0, 0}, size) == 0.0f);
    CHECK(alpha_texture_lod((float[2]){NAN, 0}, (float[2]){0, 1}, size) == 0.0f);
    CHECK(alpha_texture_lod((float[2]){1, 0}, (float[2]){0, 1}, (float[2]){NAN, 4}) == 0.0f);
    CHECK(alpha_texture_lod((float[2]){INFINITY, 0}, (float[2]){0, INFINITY}, size) == (float)ALPHA_HASH_LOG2_CLAMP);
    CHECK(isfinite(alpha_texture_lod((float[2]){1e-40f, 0}, (float[2]){0, 1e-40f}, size)));
}

/* The alpha LOD clamp (docs/hashed-alpha.md "Alpha LOD clamp"): the level the alpha test reads is
 * min(level, lod_max); a negative or NaN lod_max is no clamp. */
TEST(alpha_lod_clamp_is_min_of_level_and_clamp)
{
    CHECK(alpha_lod_clamp(8.2f, 4.0f) == 4.0f);
    CHECK(alpha_lod_clamp(3.5f, 4.0f) == 3.5f);
    CHECK(alpha_lod_clamp(4.0f, 4.0f) == 4.0f);
    CHECK(alpha_lod_clamp(0.7f, 0.0f) == 0.0f);
    CHECK(alpha_lod_clamp(0.0f, 0.0f) == 0.0f);
    CHECK(alpha_lod_clamp(8.2f, (float)ALPHA_LOD_OFF) == 8.2f);
    CHECK(alpha_lod_clamp(8.2f, -1e30f) == 8.2f);
    CHECK(alpha_lod_clamp(8.2f, NAN) == 8.2f);
    CHECK(alpha_lod_clamp(60.0f, (float)ALPHA_LOD_MAX_LIMIT) == (float)ALPHA_LOD_MAX_LIMIT);
    /* Composed with the fade level, as the forward shader does: a 256 x 128 texture seen at 64 x 64
     * texels per pixel reads level 6, clamped to 4. */
    const float size[2] = {256, 128};
    float level = alpha_texture_fade_level((float[2]){64.0f / 256, 0}, (float[2]){0, 64.0f / 128}, size, 1.0f);
    CHECK_NEAR(level, 6.0, 1e-6);
    CHECK(alpha_lod_clamp(level, 4.0f) == 4.0f);
    CHECK(alpha_lod_clamp(level, 7.0f) == level);
}

/* The forward shader's hashed test takes the fade level from the uv derivatives in one log2
 * (alpha_texture_fade_level): the level the trilinear lookup reads, alpha_texture_lod's lod biased
 * and clamped at 0 as the sampler does, and nothing more for anisotropy (docs/hashed-alpha.md "The fade and anisotropy": the level
 * already follows the footprint's long axis; adding log2(pmax / pmin) completed the fade up to 4
 * levels early on grazing surfaces). Finite and in [0, 60] always. */
TEST(texture_fade_level_is_the_trilinear_level)
{
    const float size[2] = {256, 128};
    /* Grazing footprints: 8 x 2 and 16 x 1 texels read levels 3 and 4 (not 3 + 2 and 4 + 4). */
    CHECK_NEAR(alpha_texture_fade_level((float[2]){8.0f / 256, 0}, (float[2]){0, 2.0f / 128}, size, 1.0f), 3.0, 1e-6);
    CHECK_NEAR(alpha_texture_fade_level((float[2]){0, 1.0f / 128}, (float[2]){16.0f / 256, 0}, size, 1.0f), 4.0, 1e-6);
    /* ... and with a mip bias of -1, levels 2 and 3. */
    CHECK_NEAR(alpha_texture_fade_level((float[2]){8.0f / 256, 0}, (float[2]){0, 2.0f / 128}, size, 0.5f), 2.0, 1e-6);
    CHECK_NEAR(alpha_texture_fade_level((float[2]){0, 1.0f / 128}, (float[2]){16.0f / 256, 0}, size, 0.5f), 3.0, 1e-6);
    double worst = 0;
    for (int i = 0; i < 100000; i++) {
        float dx[2] = {rngf(-0.05, 0.05), rngf(-0.05, 0.05)}, dy[2] = {rngf(-0.05, 0.05), rngf(-0.05, 0.05)};
        if (i % 7 == 0) /* a line footprint */
            dy[0] = dy[1] = 0.0f;
        float bias = (float)(i % 5) * 0.5f - 1.0f;
        float ref = fmaxf(alpha_texture_lod(dx, dy, size) + bias, 0.0f);
        float got = alpha_texture_fade_level(dx, dy, size, exp2f(bias));
        worst = fmax(worst, fabs((double)got - ref));
    }
    fprintf(stderr, "  texture fade level vs max(lod + bias, 0): largest difference %.3g\n", worst);
    CHECK(worst < 1e-5);
    const float v[] = {0.0f, -0.0f, 1e-40f, 1e-20f, 0.01f, 1.0f, 1e20f, 3e38f, NAN, INFINITY, -INFINITY};
    const float scales[] = {1.0f, 0.0f, 0.5f, 2.0f, 1e-30f, 1e19f};
    int bad = 0;
    for (size_t a = 0; a < 11; a++)
        for (size_t b = 0; b < 11; b++)
            for (size_t c = 0; c < 11; c++)
                for (size_t k = 0; k < 6; k++) {
                    float x = alpha_texture_fade_level((float[2]){v[a], v[b]}, (float[2]){v[c], v[(a + c) % 11]},
                                                       (float[2]){v[(b + k) % 11], 256.0f}, scales[k]);
                    bad += !(x >= 0.0f && x <= 60.0f);
                }
    CHECK(bad == 0);
    float zero[2] = {0, 0};
    CHECK(alpha_texture_fade_level(zero, zero, size, 1.0f) == 0.0f);
}

/* >>cost */

static double seconds_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Throughput (independent pixels, results stored), not latency: what a rasteriser sees. */
TEST(report_cpu_cost_per_threshold)
{
    enum { N = 1 << 12, REPS = 500 };
    static vec3 obj[N], dx[N], dy[N];
    static float out[N];
    for (int i = 0; i < N; i++) {
        obj[i] = rand_v3(-30, 30);
        rand_derivs(2, 8, &dx[i], &dy[i]);
    }
    const char *names[] = {"pcg", "sine"};
    double check = 0;
    for (int kind = 0; kind <= 1; kind++)
        for (int aniso = 0; aniso <= 1; aniso++) {
            double t0 = seconds_now();
            for (int r = 0; r < REPS; r++) {
                for (int i = 0; i < N; i++)
                    out[i] = alpha_hashed_threshold(obj[i], dx[i], dy[i], 1.0f, kind, aniso);
                check += out[r % N];
            }
            double ns = (seconds_now() - t0) * 1e9 / ((double)N * REPS);
            fprintf(stderr, "  %s%s: %.1f ns per threshold\n", names[kind], aniso ? " anisotropic" : "", ns);
        }
    double t0 = seconds_now();
    for (int r = 0; r < REPS; r++) {
        for (int i = 0; i < N; i++)
            out[i] = alpha_stochastic_threshold((uint32_t)i & 63u, (uint32_t)i >> 6, (uint32_t)r, 0u);
        check += out[r % N];
    }
    fprintf(stderr, "  stochastic: %.1f ns per threshold\n", (seconds_now() - t0) * 1e9 / ((double)N * REPS));
    CHECK(check > 0); /* keeps the loops */
}

TEST(frame_offset_keeps_thresholds_in_range_and_uniform)
{
    /* The per-frame shift TAA uses: (0, 1] always, identity at frame 0, a uniform threshold stays
     * uniform (64-bin chi-square), and successive frames of one pixel are spread out. */
    CHECK(alpha_hashed_frame_offset(0.25f, 0) == 0.25f);
    CHECK(alpha_hashed_frame_offset(1.0f, 0) == 1.0f);
    long h[64] = {0};
    uint32_t st = 7;
    const int n = 1 << 20;
    for (int i = 0; i < n; i++) {
        st = st * 1664525u + 1013904223u;
        float t = 1.0f - (float)(st >> 8) / 16777216.0f; /* (0, 1] */
        float u = alpha_hashed_frame_offset(t, (uint32_t)i * 2654435761u);
        CHECK(u > 0.0f && u <= 1.0f);
        int b = (int)(u * 64.0f);
        h[b > 63 ? 63 : b]++;
    }
    double e = n / 64.0, chi2 = 0;
    for (int b = 0; b < 64; b++)
        chi2 += (h[b] - e) * (h[b] - e) / e;
    CHECK(chi2 < 103.4); /* 0.999 quantile, 63 degrees of freedom */
    /* 16 frames of one pixel cover (0, 1] with no gap wider than 0.2 (golden-ratio sequence). */
    float v[16];
    for (uint32_t f = 0; f < 16; f++)
        v[f] = alpha_hashed_frame_offset(0.5f, f);
    for (int i = 0; i < 16; i++)
        for (int j = i + 1; j < 16; j++)
            if (v[j] < v[i]) {
                float t = v[i];
                v[i] = v[j];
                v[j] = t;
            }
    float gap = v[0] + (1.0f - v[15]);
    for (int i = 1; i < 16; i++)
        gap = fmaxf(gap, v[i] - v[i - 1]);
    CHECK(gap < 0.2f);
}

/* >>layers */

TEST(layer_zero_is_the_unlayered_threshold)
{
    /* alpha_hashed_threshold_layer(..., 0) is alpha_hashed_threshold bit for bit (both hashes,
     * anisotropic on and off): the change that keys the lattice by layer moves nothing else. */
    rng_state = 4242;
    long long differ = 0;
    for (int i = 0; i < 100000; i++) {
        vec3 obj = rand_v3(-100, 100), dx, dy;
        rand_derivs(-2, 10, &dx, &dy);
        int kind = i & 1;
        bool aniso = (i >> 1) & 1;
        float a = alpha_hashed_threshold(obj, dx, dy, 1.0f, kind, aniso);
        float b = alpha_hashed_threshold_layer(obj, dx, dy, 1.0f, kind, aniso, 0u);
        differ += memcmp(&a, &b, sizeof a) != 0;
        float c = alpha_hash_kind(obj, kind), d = alpha_hash_kind_layer(obj, kind, 0u);
        differ += memcmp(&c, &d, sizeof c) != 0;
    }
    CHECK(differ == 0);
}

TEST(layer_keys_are_distinct_within_an_instance)
{
    /* pcg1 is a bijection, so the triangles of one instance never share a key; across instances
     * keys collide only by chance (2^-32 per pair). */
    enum { N = 1 << 16 };
    static float keys[N];
    for (uint32_t inst = 0; inst < 4; inst++) {
        for (uint32_t p = 0; p < N; p++) {
            uint32_t k = alpha_hash_layer(inst * 977u, p);
            keys[p] = (float)(k >> 8); /* distinct_values counts floats: keep 24 bits */
        }
        int d = distinct_values(keys, N);
        fprintf(stderr, "  instance %u: %d distinct 24-bit layer keys of %d triangles\n", inst * 977u, d, N);
        CHECK(d > N - 300); /* 24-bit truncation: ~128 birthday collisions expected */
    }
    for (uint32_t v = 0; v < 100000; v++) /* and the 32-bit keys of one instance are all different */
        CHECK(v == 0 || alpha_hash_pcg1(v) != alpha_hash_pcg1(0));
}

/* Coverage of k overlapping layers of opacity a whose fragments fall in one noise cell (same
 * object position and derivatives, as leaves of one far-away plant do), thresholds keyed by
 * `keyed` ? a distinct layer per surface : layer 0 for all (the old, shared threshold). */
static double layered_coverage(int kind, bool keyed, int k, float a, int trials)
{
    rng_state = 777;
    long long covered = 0;
    for (int i = 0; i < trials; i++) {
        vec3 obj = rand_v3(-100, 100), dx, dy;
        rand_derivs(-2, 10, &dx, &dy);
        bool pass = false;
        for (int j = 0; j < k; j++) {
            uint32_t layer = keyed ? alpha_hash_layer((uint32_t)(i % 7), (uint32_t)j) : 0u;
            pass |= a >= alpha_hashed_threshold_layer(obj, dx, dy, 1.0f, kind, false, layer);
        }
        covered += pass;
    }
    return (double)covered / trials;
}

TEST(layers_in_one_noise_cell_cover_as_independent_layers)
{
    /* The reference composites k layers of opacity a to 1 - (1 - a)^k; one shared threshold gives
     * only a (docs/hashed-alpha.md, "Layers"). With a key per layer the thresholds are independent:
     * within 0.01 of the closed form (binomial sigma at 200k trials ~ 0.001). */
    const int trials = 200000;
    const float as[] = {0.2f, 0.44f, 0.7f};
    for (int kind = 0; kind < 2; kind++)
        for (int ia = 0; ia < 3; ia++)
            for (int k = 2; k <= 8; k *= 2) {
                float a = as[ia];
                double want = 1.0 - pow(1.0 - a, k);
                double shared = layered_coverage(kind, false, k, a, trials);
                double keyed = layered_coverage(kind, true, k, a, trials);
                fprintf(stderr, "  %s, %d layers of alpha %.2f: independent %.4f, one shared threshold %.4f, keyed %.4f\n",
                        kind ? "sine" : "pcg", k, a, want, shared, keyed);
                CHECK(fabs(shared - a) < 0.01); /* the correlation this fixes */
                CHECK(fabs(keyed - want) < 0.01);
            }
}

TEST(layered_thresholds_are_uniform)
{
    /* Each layer's lattice is a bijection of the unlayered one: thresholds stay uniform, on random
     * volumes and on flat cards, with a different layer per input (pcg asserted; sine is not
     * uniform on flat cards anyway, docs/hashed-alpha.md, and is reported). */
    for (int kind = 0; kind < 2; kind++)
        for (int flat = 0; flat < 2; flat++) {
            hist h = {{0}, 0};
            rng_state = 99;
            for (int i = 0; i < (1 << 20); i++) {
                vec3 obj = rand_v3(-100, 100), dx, dy;
                if (flat)
                    obj.z = 0.37f;
                deriv_pair(4.0 * (double)i / (1 << 20), rng01(), &dx, &dy);
                uint32_t layer = alpha_hash_layer((uint32_t)(i >> 10), (uint32_t)(i & 1023));
                hist_add(&h, alpha_hashed_threshold_layer(obj, dx, dy, 1.0f, kind, false, layer));
            }
            double c2 = hist_chi2(&h);
            fprintf(stderr, "  %s, %s, a layer per input: chi2 %.1f (critical %.1f)\n", kind ? "sine" : "pcg",
                    flat ? "flat card z = 0.37" : "volume", c2, chi2_crit_0999());
            if (kind == ALPHA_HASH_PCG)
                CHECK(c2 < chi2_crit_0999());
        }
}

/* >>origin */

/* Listing 1's two hashes floor(2^lo obj) and floor(2^hi obj) are the same cell wherever
 * |obj| < 2^-hi on every axis: within a pixel of the object origin. Hashed with one function, the
 * two values there are equal, Eq. 1's CDF then skews the threshold (for alpha < 0.5 too many
 * fragments pass), and an asset 1-2 pixels wide lies entirely in that region (docs/hashed-alpha.md "Assets a pixel or two wide"). Each
 * level hashes its own lattice (alpha_hash_level_key), so the two are independent there too.
 *
 * Inputs: points uniform in |obj| < 2^-l on every axis (one pixel of footprint 2^-l around the
 * origin), l = L + f, f uniform in [0, 1), every level L in [-60, 60) in turn; `keyed`: a random
 * layer key per input (as instances and triangles have in the renderer), else key 0. */
enum { ORIGIN_LEVELS = 120, ORIGIN_ALPHAS = 3 };
static const float origin_alphas[ORIGIN_ALPHAS] = {0.119f, 0.25f, 0.4f}; /* 0.119: the issue's */

typedef struct origin_stats {
    double chi2;                 /* all 2^20 thresholds */
    double worst_level;          /* the largest chi2 of one level's 8,738 */
    double pass[ORIGIN_ALPHAS];  /* fraction of thresholds <= alpha: the coverage of alpha */
} origin_stats;

static origin_stats origin_thresholds(int kind, bool keyed, bool aniso)
{
    enum { N = 1 << 20 };
    static hist per_level[ORIGIN_LEVELS];
    hist all = {{0}, 0};
    long long pass[ORIGIN_ALPHAS] = {0};
    memset(per_level, 0, sizeof per_level);
    rng_state = 2027;
    for (int i = 0; i < N; i++) {
        int L = -60 + i % ORIGIN_LEVELS;
        double l = L + rng01();
        vec3 dx, dy;
        deriv_pair(l, rng01(), &dx, &dy);
        double d = exp2(-l);
        vec3 obj = rand_v3(-d, d);
        uint32_t key = keyed ? alpha_hash_layer((uint32_t)(i >> 10), (uint32_t)(i & 1023)) : 0u;
        float t = alpha_hashed_threshold_layer(obj, dx, dy, 1.0f, kind, aniso, key);
        hist_add(&all, t);
        hist_add(&per_level[i % ORIGIN_LEVELS], t);
        for (int a = 0; a < ORIGIN_ALPHAS; a++)
            pass[a] += origin_alphas[a] >= t;
    }
    origin_stats r = {hist_chi2(&all), 0, {0}};
    for (int k = 0; k < ORIGIN_LEVELS; k++)
        r.worst_level = fmax(r.worst_level, hist_chi2(&per_level[k]));
    for (int a = 0; a < ORIGIN_ALPHAS; a++)
        r.pass[a] = (double)pass[a] / N;
    return r;
}

TEST(hashed_thresholds_are_uniform_within_a_pixel_of_the_origin)
{
    /* Keyed: chi2 over all levels below the 0.999 quantile and, "at every level", each level's
     * chi2 below the quantile at p = 0.001 / 120 (z = 4.0, Bonferroni: ~118), pcg asserted (sine:
     * the overall chi2 only; its per-level values are reported). Key 0: one level's inputs reach
     * only 8 lo x 8 hi cell pairs, 7,680 over all levels, too few values for a chi2 of 2^20
     * thresholds, so what is asserted is what the issue measures: alpha's coverage within 10 %
     * (binomial sigma over 7,680 pairs: 3 % at alpha 0.119). Before the level keys: coverage
     * 1.49 x (pcg) and 1.19 x (sine) of alpha 0.119, chi2 ~73,000 keyed. */
    double crit = chi2_crit_0999(), crit_level = chi2_quantile(BINS - 1, 4.0);
    for (int kind = 0; kind < 2; kind++)
        for (int keyed = 1; keyed >= 0; keyed--)
            for (int aniso = 0; aniso < 2; aniso++) {
                origin_stats r = origin_thresholds(kind, keyed, aniso);
                fprintf(stderr,
                        "  within a pixel of the origin, %s, %s, %s: chi2 %8.1f, worst level %8.1f; coverage / alpha "
                        "%.3f %.3f %.3f (alpha %.3f %.2f %.2f)\n",
                        kind ? "sine" : "pcg ", keyed ? "a key per input" : "key 0          ",
                        aniso ? "anisotropic" : "isotropic  ", r.chi2, r.worst_level, r.pass[0] / origin_alphas[0],
                        r.pass[1] / origin_alphas[1], r.pass[2] / origin_alphas[2], origin_alphas[0], origin_alphas[1],
                        origin_alphas[2]);
                if (keyed) {
                    CHECK(r.chi2 < crit);
                    if (kind == ALPHA_HASH_PCG)
                        CHECK(r.worst_level < crit_level);
                }
                for (int a = 0; a < ORIGIN_ALPHAS; a++)
                    CHECK(fabs(r.pass[a] / origin_alphas[a] - 1.0) < (keyed ? 0.02 : 0.10));
            }
    fprintf(stderr, "  (critical chi2 %.1f over all levels, %.1f per level)\n", crit, crit_level);
    /* The key of every level is distinct and nonzero (none gives the old, unkeyed lattice). */
    for (int e = -60; e <= 60; e++) {
        CHECK(alpha_hash_level_key(e) != 0u);
        for (int g = -60; g < e; g++)
            CHECK(alpha_hash_level_key(e) != alpha_hash_level_key(g));
    }
}

int main(void)
{
    RUN(cdf_hard_cases_are_finite_and_monotonic);
    RUN(thresholds_are_in_range_for_every_hard_case);
    RUN(coordinates_outside_the_hashed_range_hash_as_zero);
    RUN(matches_listing_1_on_ordinary_inputs);
    RUN(alpha_zero_never_passes_alpha_one_always_does);
    RUN(hashed_thresholds_are_uniform);
    RUN(hashed_thresholds_are_uniform_on_flat_cards);
    RUN(hashes_are_uniform_on_integer_lattices);
    RUN(stable_under_sub_pixel_translation);
    RUN(continuous_under_z_translation);
    RUN(anisotropic_option_gives_pixel_scale_noise_along_the_minor_axis);
    RUN(stochastic_is_uniform_and_new_every_frame);
    RUN(hashed_a2c_thresholds_and_masks);
    RUN(fade_ramp_is_quadratic_in_lod);
    RUN(texture_lod_follows_the_long_axis);
    RUN(texture_fade_level_is_the_trilinear_level);
    RUN(report_cpu_cost_per_threshold);
    RUN(frame_offset_keeps_thresholds_in_range_and_uniform);
    RUN(layer_zero_is_the_unlayered_threshold);
    RUN(layer_keys_are_distinct_within_an_instance);
    RUN(layers_in_one_noise_cell_cover_as_independent_layers);
    RUN(layered_thresholds_are_uniform);
    RUN(hashed_thresholds_are_uniform_within_a_pixel_of_the_origin);
    RUN(alpha_lod_clamp_is_min_of_level_and_clamp);
    return test_summary();
}
