/* GPU twin of the TAA math: shaders/test/taa_twin.comp runs every function of
 * shaders/common/taa.glsl, and of shaders/common/sway.glsl (the per-object motion TAA follows), on
 * a buffer of inputs and the results are compared with the C twins (src/passes/taa_math.c,
 * src/scene/sway.c), input by input.
 *
 * Input groups: ordinary (HDR colours in [0, 16], sigma in [0, 1], neighbourhoods of 5 or 9 taps
 * and histories of 5 or 1 taps, NaN per tap or per set, random cameras moving a little
 * between frames with a sub-pixel jitter, NDC inside the frustum) and hard cases (NaN, +-Inf,
 * -0, denormals, 1e30, FLT_MAX anywhere, matrices with NaN / Inf entries or all zero, huge Halton
 * indices and bases).
 *
 * Tolerances, and why:
 *   - taa_halton and taa_jitter: bit-identical, every input. They are integer operations, one
 *     conversion of a value below 2^24, a multiplication by 2^-24 and a subtraction of 0.5: exact.
 *   - everything else: |gpu - cpu| <= 1e-5 * max(1, |cpu|, s), s the largest magnitude among the
 *     (sanitized) operands of that function. Both sides do the same IEEE additions and
 *     multiplications in the same order (C11 does not contract, the GLSL results are `precise`), so
 *     they differ only where GLSL is not correctly rounded: the division of the clip (extent / |d|)
 *     and of the reprojection (2.5 ULP allowed), and denormals a GPU may flush to 0. A few ULP of the
 *     operands is ~1e-6 relative; 1e-5 leaves margin, and the largest difference is printed. The
 *     absolute floor (max(1, ...)) covers results that cancel to ~0 and flushed denormals.
 *   - sway (wave, displacement, motion): |gpu - cpu| <= 5e-4 * max(1, |offset|). Everything but the
 *     sine is the same correctly rounded float operations on both sides (the argument is reduced
 *     with fract first, identically), and GLSL leaves sin's precision to the implementation; 5e-4
 *     is about 2^-11, the absolute error Vulkan allows sin in [-pi, pi], which GL drivers share.
 *   - reprojection validity: identical for the ordinary group (the flag depends only on the
 *     matrix products, which are exact twins); reported for the hard group.
 *   - the neighbourhood's sigma is the square root of a variance that cancels (sum(Y^2) / n -
 *     mean^2), so it is compared as that variance: |gpu^2 - cpu^2| <= 1e-5 * (mean^2 + sigma^2),
 *     a few ULP of the sum of squares it came from. Everything else of the neighbourhood, the
 *     Catmull-Rom taps and the history sum: 1e-5 as above (on llvmpipe all of it is
 *     bit-identical).
 *   - contract, every group: sanitize, clip, resolve, the weights, the reprojected NDC, the
 *     neighbourhood, the Catmull-Rom taps and the history are finite on the GPU; resolve (RGB,
 *     RGBA, one channel), sanitize4 and the history sum are in [0, TAA_MAX_VALUE].
 */
#include <epoxy/gl.h>
#include <float.h>
#include <stdint.h>

#include "common/shared_defs.h"
#include "gl/gl_device.h"
#include "gl/gl_program.h"
#include "passes/taa_math.h"
#include "scene/sway.h"
#include "test.h"
#include "twin_util.h"

typedef struct twin_in {
    float a[4], b[4], c[4], d[4];
    uint32_t u[4], v[4];
    float inv[16], prev[16];
    float e[4], f[4], g[4];
    float nb[TAA_MAX_TAPS][4], nbcov[12], hw[8], h[4];
    uint32_t w[4];
} twin_in;

typedef struct twin_out {
    float o[23][4];
} twin_out;

enum { GROUP = 1 << 15, GROUPS = 2, COUNT = GROUP * GROUPS };
enum { G_ORDINARY, G_HARD };
static const char *group_name[GROUPS] = {"ordinary", "hard cases"};

static twin_in *inputs;
static twin_out *gpu, *cpu;
static bool have_gpu_results;

/* >>inputs */

static const float hard_values[] = {NAN, -NAN, INFINITY, -INFINITY, 0.0f, -0.0f, 1e-40f, -1e-40f, 1e30f, -1e30f,
                                    FLT_MAX, 65504.0f, 65505.0f, 1.0f, 0.5f, -1.0f};
#define HARD_COUNT ((int)(sizeof hard_values / sizeof hard_values[0]))

/* In the hard group, one value in three is a hard value. */
static float maybe_hard(int g, float x)
{
    return g == G_HARD && rng_u64() % 3 == 0 ? hard_values[rng_u64() % HARD_COUNT] : x;
}

static mat4 random_view_proj(vec3 eye, vec3 target, float jx, float jy)
{
    float hfov = rngf(0.5, 2.0), aspect = rngf(0.5, 2.0), znear = rngf(0.01, 1.0);
    mat4 p = m4_perspective_hfov(hfov, aspect, znear, znear * rngf(50, 10000));
    p = m4_mul(m4_translate(v3(jx, jy, 0)), p);
    return m4_mul(p, m4_look_at(eye, target, v3(0, 1, 0)));
}

static void make_input(int i, twin_in *in)
{
    int g = i / GROUP;
    memset(in, 0, sizeof *in);
    for (int k = 0; k < 3; k++) {
        in->a[k] = maybe_hard(g, rngf(0, 16) * (float)rng01());
        in->b[k] = maybe_hard(g, rngf(-1, 8));
        in->c[k] = maybe_hard(g, rngf(0, 1) * (float)rng01());
    }
    in->a[3] = maybe_hard(g, rngf(-70000, 70000));
    in->b[3] = maybe_hard(g, rng01() < 0.5 ? (float)TAA_BLEND_DEFAULT : rngf(-0.2, 1.2));
    in->c[3] = maybe_hard(g, rng01() < 0.5 ? (float)TAA_GAMMA_DEFAULT : rngf(0, 2));
    in->d[0] = maybe_hard(g, rngf(-1, 1));
    in->d[1] = maybe_hard(g, rngf(-1, 1));
    in->d[2] = maybe_hard(g, rngf(-1, 0.999));
    in->d[3] = maybe_hard(g, rngf(-0.1, 1.1));
    in->u[0] = rng01() < 0.5 ? (uint32_t)(rng_u64() % 5000) : (uint32_t)rng_u64();
    const uint32_t bases[] = {2, 3, 5, 7};
    in->u[1] = g == G_HARD ? (uint32_t)(rng01() < 0.5 ? rng_u64() % 4 : rng_u64()) : bases[rng_u64() % 4];
    in->u[2] = (uint32_t)rng_u64();
    const uint32_t lengths[] = {TAA_JITTER_LENGTH_DEFAULT, 8, 0, 1000};
    in->u[3] = g == G_HARD ? (uint32_t)rng_u64() : lengths[rng_u64() % 4];
    in->v[0] = (uint32_t)(rng_u64() % 2);

    vec3 eye = v3(rngf(-10, 10), rngf(-10, 10), rngf(-10, 10));
    vec3 target = v3_add(eye, v3(rngf(-1, 1), rngf(-0.5, 0.5), rngf(-1, 1)));
    float jitter[2];
    taa_jitter(in->u[2], TAA_JITTER_LENGTH_DEFAULT, jitter);
    mat4 cur = random_view_proj(eye, target, jitter[0] * 2 / 1024, jitter[1] * 2 / 768), inv;
    vec3 move = v3(rngf(-0.3, 0.3), rngf(-0.3, 0.3), rngf(-0.3, 0.3));
    mat4 prev = random_view_proj(v3_add(eye, move), v3_add(target, v3_scale(move, rngf(0, 2))), 0, 0);
    if (!m4_invert(cur, &inv))
        inv = m4_identity();
    if (g == G_HARD) {
        uint64_t r = rng_u64() % 6;
        if (r == 0)
            inv.m[rng_u64() % 16] = hard_values[rng_u64() % HARD_COUNT];
        else if (r == 1)
            prev.m[rng_u64() % 16] = hard_values[rng_u64() % HARD_COUNT];
        else if (r == 2)
            memset(&prev, 0, sizeof prev);
    }
    memcpy(in->inv, inv.m, sizeof in->inv);
    memcpy(in->prev, prev.m, sizeof in->prev);
    /* Per-object motion (a swaying leaf moves centimetres per frame) and sway parameters, with
     * scene times up to an hour. */
    for (int k = 0; k < 3; k++) {
        in->e[k] = maybe_hard(g, rngf(-0.2, 0.2));
        in->g[k] = maybe_hard(g, rngf(-1, 1));
    }
    in->f[0] = maybe_hard(g, rngf(0.05, 5));
    in->f[1] = maybe_hard(g, (float)rng01());
    in->f[2] = maybe_hard(g, rngf(-2, 25));
    in->f[3] = maybe_hard(g, rng01() < 0.5 ? rngf(0, 10) : rngf(0, 3600));
    in->e[3] = maybe_hard(g, in->f[3] - 1.0f / 24.0f);
    in->g[3] = maybe_hard(g, rngf(0.1, 20));
    /* The resolve's neighbourhood (HDR colour, alpha and coverage mostly 0 or 1, 3x3 or cross, NaN
     * per tap or per set) and history: a Catmull-Rom fetch at a position in or near a footprint,
     * its taps' weights, and 5 or 1 (bilinear) taps. */
    in->w[0] = rng01() < 0.5 ? 5u : 9u;
    in->w[1] = (uint32_t)(rng_u64() % 2);
    in->w[2] = rng01() < 0.5 ? 5u : 1u;
    if (g == G_HARD && rng_u64() % 4 == 0)
        in->w[0] = (uint32_t)(rng_u64() % 12), in->w[2] = (uint32_t)(rng_u64() % 7);
    for (int k = 0; k < TAA_MAX_TAPS; k++) {
        for (int c = 0; c < 3; c++)
            in->nb[k][c] = maybe_hard(g, rngf(0, 16) * (float)rng01());
        in->nb[k][3] = maybe_hard(g, rng01() < 0.7 ? (float)(rng_u64() % 2) : (float)rng01());
        in->nbcov[k] = maybe_hard(g, rng01() < 0.7 ? (float)(rng_u64() % 2) : (float)rng01());
    }
    float size[2] = {rngf(1, 400), rngf(1, 300)};
    in->h[0] = maybe_hard(g, rngf(-2, size[0] + 2));
    in->h[1] = maybe_hard(g, rngf(-2, size[1] + 2));
    in->h[2] = maybe_hard(g, size[0]);
    in->h[3] = maybe_hard(g, size[1]);
    float taps[5][3];
    taa_catmull_rom_taps(rngf(0, 64), rngf(0, 64), 64, 64, taps);
    for (int k = 0; k < 5; k++)
        in->hw[k] = g == G_HARD && rng_u64() % 6 == 0 ? hard_values[rng_u64() % HARD_COUNT] : taps[k][2];
}

static void set3(float o[4], vec3 v, float w)
{
    o[0] = v.x;
    o[1] = v.y;
    o[2] = v.z;
    o[3] = w;
}

static void run_cpu(const twin_in *p, twin_out *r)
{
    vec3 a = v3(p->a[0], p->a[1], p->a[2]), b = v3(p->b[0], p->b[1], p->b[2]), c = v3(p->c[0], p->c[1], p->c[2]);
    memset(r, 0, sizeof *r);
    float j[2];
    taa_jitter(p->u[2], p->u[3], j);
    r->o[0][0] = taa_halton(p->u[0], p->u[1]);
    r->o[0][1] = j[0];
    r->o[0][2] = j[1];
    r->o[0][3] = taa_sanitize(p->a[3]);
    set3(r->o[1], taa_rgb_to_ycocg(a), taa_sanitize_color(a).x);
    set3(r->o[2], taa_ycocg_to_rgb(a), 0.0f);
    set3(r->o[3], taa_clip_to_box(a, b, c, p->c[3], p->d[3]), 0.0f);
    taa_catmull_rom_weights(p->d[3], r->o[4]);
    set3(r->o[5], taa_resolve(a, b, p->v[0] != 0, p->b[3]), 0.0f);
    mat4 inv, prev;
    memcpy(inv.m, p->inv, sizeof inv.m);
    memcpy(prev.m, p->prev, sizeof prev.m);
    vec3 o;
    bool valid;
    taa_reproject(v3(p->d[0], p->d[1], p->d[2]), &inv, &prev, &o, &valid);
    set3(r->o[6], o, valid ? 1.0f : 0.0f);
    float hist4[4] = {p->b[0], p->b[1], p->b[2], p->c[3]};
    taa_resolve4(p->a, hist4, p->v[0] != 0, p->b[3], r->o[7]);
    taa_sanitize4(p->a, r->o[8]);
    r->o[9][0] = taa_resolve1(p->a[3], p->c[3], p->v[0] != 0, p->b[3]);
    float unused;
    r->o[9][1] = taa_sparse_coverage(p->d[3], p->a[3], p->c[0], p->c[1], p->c[2], &r->o[9][2]);
    r->o[9][3] = taa_sparse_coverage(p->d[3], p->c[0], p->c[0], p->c[0], (float)TAA_SPARSE_SLACK, &unused);
    taa_reproject_moving(v3(p->d[0], p->d[1], p->d[2]), v3(p->e[0], p->e[1], p->e[2]), &inv, &prev, &o, &valid);
    set3(r->o[10], o, valid ? 1.0f : 0.0f);
    const instance_sway sw = {.offset = {p->g[0], p->g[1], p->g[2]}, .height = p->g[3], .frequency = p->f[0],
                              .phase = p->f[1]};
    set3(r->o[11], sway_motion(&sw, p->f[2], p->f[3], p->e[3]), sway_wave(p->f[0], p->f[1], p->f[3]));
    set3(r->o[12], sway_displacement(&sw, p->f[2], p->f[3]), sway_weight(p->f[2], p->g[3]));
    taa_box nbox = taa_neighbourhood(p->nb, p->nbcov, (int)p->w[0], p->w[1] != 0);
    set3(r->o[13], nbox.mean, nbox.alpha[0]);
    set3(r->o[14], nbox.sigma, nbox.alpha[1]);
    r->o[15][0] = nbox.coverage[0];
    r->o[15][1] = nbox.coverage[1];
    float ct[5][3];
    taa_catmull_rom_taps(p->h[0], p->h[1], p->h[2], p->h[3], ct);
    const float cto[4][4] = {{ct[0][0], ct[0][1], ct[1][0], ct[1][1]},
                             {ct[2][0], ct[2][1], ct[3][0], ct[3][1]},
                             {ct[4][0], ct[4][1], ct[0][2], ct[1][2]},
                             {ct[2][2], ct[3][2], ct[4][2], 0.0f}};
    memcpy(r->o[16], cto, sizeof cto);
    taa_history_sum(p->nb, p->hw, (int)p->w[2], p->w[1] != 0, r->o[20]);
    bool here = taa_history_surface_here(v3(p->d[0], p->d[1], p->d[2]), v3(p->e[0], p->e[1], p->e[2]), &inv, &prev,
                                         p->a[0], p->a[1], p->h[2], p->h[3], p->b[3], p->c[3], &r->o[21][0], r->o[21] + 2);
    r->o[22][0] = here ? 1.0f : 0.0f;
}

/* >>gpu */

TEST(glsl_compiles_and_runs)
{
    bool ok = twin_run("shaders/test/taa_twin.comp", inputs, sizeof(twin_in) * COUNT, gpu, sizeof(twin_out) * COUNT, COUNT);
    CHECK(ok);
    have_gpu_results = ok;
}

/* >>compare */

TEST(halton_and_jitter_are_bit_identical)
{
    if (!have_gpu_results) {
        CHECK(have_gpu_results);
        return;
    }
    long long bad_halton = 0, bad_jitter = 0;
    for (int i = 0; i < COUNT; i++) {
        const twin_out *g = &gpu[i], *c = &cpu[i];
        bool hb = !twin_same_bits(g->o[0][0], c->o[0][0]);
        bad_halton += hb;
        bad_jitter += !twin_same_bits(g->o[0][1], c->o[0][1]) || !twin_same_bits(g->o[0][2], c->o[0][2]);
        if (hb && bad_halton <= 3)
            fprintf(stderr, "  halton(%u, %u): gpu %.9g cpu %.9g\n", inputs[i].u[0], inputs[i].u[1], g->o[0][0], c->o[0][0]);
    }
    fprintf(stderr, "  %d inputs; mismatches: halton %lld, jitter %lld\n", COUNT, bad_halton, bad_jitter);
    CHECK(bad_halton == 0);
    CHECK(bad_jitter == 0);
}

static bool finite4(const float *v, int n)
{
    for (int k = 0; k < n; k++)
        if (!isfinite(v[k]))
            return false;
    return true;
}

TEST(gpu_results_are_finite)
{
    if (!have_gpu_results) {
        CHECK(have_gpu_results);
        return;
    }
    long long bad = 0;
    for (int i = 0; i < COUNT; i++) {
        const twin_out *g = &gpu[i];
        bool ok = isfinite(g->o[0][3]) && isfinite(g->o[1][3]) && finite4(g->o[3], 3) && finite4(g->o[4], 4) &&
                  finite4(g->o[5], 3) && finite4(g->o[6], 3) && finite4(g->o[7], 4) && finite4(g->o[8], 4) &&
                  isfinite(g->o[9][0]) && finite4(g->o[10], 3) && finite4(g->o[11], 4) && finite4(g->o[12], 4) &&
                  finite4(g->o[13], 4) && finite4(g->o[14], 4) && finite4(g->o[15], 2) && finite4(g->o[16], 4) &&
                  finite4(g->o[17], 4) && finite4(g->o[18], 4) && finite4(g->o[19], 3) && finite4(g->o[20], 4) &&
                  finite4(g->o[9], 4) && finite4(g->o[21], 4);
        for (int k = 0; k < 4; k++) /* the history fetch is in [0, TAA_MAX_VALUE] */
            ok = ok && g->o[20][k] >= 0.0f && g->o[20][k] <= (float)TAA_MAX_VALUE;
        for (int k = 0; k < 4; k++)
            ok = ok && (k == 3 || (g->o[5][k] >= 0.0f && g->o[5][k] <= (float)TAA_MAX_VALUE)) && g->o[7][k] >= 0.0f &&
                 g->o[7][k] <= (float)TAA_MAX_VALUE && g->o[8][k] >= 0.0f && g->o[8][k] <= (float)TAA_MAX_VALUE;
        ok = ok && g->o[9][0] >= 0.0f && g->o[9][0] <= (float)TAA_MAX_VALUE;
        if (!ok && bad < 5)
            fprintf(stderr, "  not finite at %d (%s): clip %g %g %g resolve %g %g %g reproject %g %g %g\n", i,
                    group_name[i / GROUP], g->o[3][0], g->o[3][1], g->o[3][2], g->o[5][0], g->o[5][1], g->o[5][2], g->o[6][0],
                    g->o[6][1], g->o[6][2]);
        bad += !ok;
    }
    CHECK(bad == 0);
}

static float sanitized_abs(float x)
{
    return fabsf(taa_sanitize(x));
}

/* Largest magnitude among the operands of output slot k of input p (the tolerance's scale). */
static double operand_scale(const twin_in *p, int k)
{
    double s = 0;
    for (int c = 0; c < 3; c++) {
        if (k == 1 || k == 2) /* ycocg: raw inputs */
            s = fmax(s, fabs(p->a[c]));
        if (k == 3) /* clip: history, mean, gamma * sigma, margin */
            s = fmax(s, fmax(fmax(sanitized_abs(p->a[c]), sanitized_abs(p->b[c])),
                             fmax(sanitized_abs(p->c[c]) * fmin(fmax(sanitized_abs(p->c[3]), 1.0), (double)TAA_MAX_VALUE),
                                  sanitized_abs(p->d[3]))));
        if (k == 5 || k == 7) /* resolve: both colours */
            s = fmax(s, fmax(sanitized_abs(p->a[c]), sanitized_abs(p->b[c])));
    }
    if (k == 7 || k == 9) /* the alpha / single channel: a.w and c.w */
        s = fmax(s, fmax(sanitized_abs(p->a[3]), sanitized_abs(p->c[3])));
    if (k == 11 || k == 12) /* sway: the offset, when finite (else the twins return 0) */
        for (int c = 0; c < 3; c++)
            s = fmax(s, isfinite(p->g[c]) ? fabs(p->g[c]) : 0.0);
    if (k >= 13 && k <= 15) /* neighbourhood: its taps and coverages */
        for (int t = 0; t < TAA_MAX_TAPS; t++) {
            for (int c = 0; c < 4; c++)
                s = fmax(s, sanitized_abs(p->nb[t][c]));
            s = fmax(s, sanitized_abs(p->nbcov[t]));
        }
    if (k == 16 || k == 17) /* catmull-rom tap positions: the position and the footprint (slots 18
                             * and 19, mostly the weights, are at most ~1 and need no scale) */
        for (int c = 0; c < 4; c++)
            s = fmax(s, sanitized_abs(p->h[c]));
    if (k == 20) { /* history: the taps, times sum |w| / |sum w| */
        double sw = 0, saw = 0, st = 0;
        for (int t = 0; t < 5; t++) {
            sw += p->hw[t];
            saw += fabs(p->hw[t]);
            for (int c = 0; c < 4; c++)
                st = fmax(st, sanitized_abs(p->nb[t][c]));
        }
        s = fmax(s, isfinite(saw / fabs(sw)) ? fmin(st * saw / fabs(sw), (double)TAA_MAX_VALUE) : (double)TAA_MAX_VALUE);
    }
    return s;
}

enum { SLOTS = 23 };
static const char *slot_name[SLOTS] = {"sanitize",  "rgb_to_ycocg", "ycocg_to_rgb", "clip_to_box", "catmull_rom",
                                       "resolve",   "reproject",    "resolve4",     "sanitize4",   "resolve1+sparse",
                                       "reproject_moving", "sway_motion+wave", "sway_displacement+weight",
                                       "neighbourhood mean+alpha", "neighbourhood sigma+alpha", "neighbourhood coverage",
                                       "catmull_rom_taps 0-1", "catmull_rom_taps 2-3", "catmull_rom_taps 4+w",
                                       "catmull_rom_taps w", "history_sum", "history_surface_here keep+offset",
                                       "history_surface_here"};
/* Elements compared in a slot: [first, last). */
static const int slot_first[SLOTS] = {3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
static const int slot_last[SLOTS] = {4, 3, 3, 3, 4, 3, 3, 4, 4, 4, 3, 4, 4, 4, 4, 2, 4, 4, 4, 3, 4, 4, 1};
/* Relative tolerance of a slot: sway goes through GLSL's sin (see the header). */
static double slot_tolerance(int k)
{
    return k == 11 || k == 12 ? 5e-4 : 1e-5;
}

TEST(float_functions_agree)
{
    if (!have_gpu_results) {
        CHECK(have_gpu_results);
        return;
    }
    for (int grp = 0; grp < GROUPS; grp++) {
        long long bad[SLOTS] = {0}, n[SLOTS] = {0}, valid_mismatch = 0;
        double worst_rel[SLOTS] = {0};
        for (int i = grp * GROUP; i < (grp + 1) * GROUP; i++) {
            const twin_out *g = &gpu[i], *c = &cpu[i];
            bool gv = g->o[6][3] != 0.0f, cv = c->o[6][3] != 0.0f;
            bool gmv = g->o[10][3] != 0.0f, cmv = c->o[10][3] != 0.0f;
            /* history_surface_here: its result */
            bool ghv = g->o[22][0] != 0.0f, chv = c->o[22][0] != 0.0f;
            valid_mismatch += (gv != cv) + (gmv != cmv) + (ghv != chv);
            for (int k = 0; k < SLOTS; k++) {
                int first = slot_first[k], last = slot_last[k];
                if ((k == 6 && gv != cv) || (k == 10 && gmv != cmv) || ((k == 21 || k == 22) && ghv != chv))
                    continue; /* different branches: counted above */
                for (int e = first; e < last; e++) {
                    double a = g->o[k][e], b = c->o[k][e];
                    double d = (isnan(a) && isnan(b)) || a == b ? 0.0 : fabs(a - b);
                    if (isnan(d))
                        d = INFINITY;
                    double scale = fmax(1.0, fmax(fabs(b), operand_scale(&inputs[i], k)));
                    if (k == 14 && e < 3) {
                        /* sigma: compared as the variance, relative to sum(Y^2) / n = mean^2 + sigma^2 */
                        double mu = c->o[13][e];
                        d = (isnan(a) && isnan(b)) || a == b ? 0.0 : fabs(a * a - b * b);
                        if (isnan(d))
                            d = INFINITY;
                        scale = fmax(1e-12, mu * mu + b * b);
                    }
                    n[k]++;
                    bad[k] += !(d <= slot_tolerance(k) * scale);
                    worst_rel[k] = fmax(worst_rel[k], d / scale);
                    if (!(d <= slot_tolerance(k) * scale) && bad[k] <= 2)
                        fprintf(stderr, "  %s [%d] at %d (%s): gpu %.9g cpu %.9g\n", slot_name[k], e, i, group_name[grp], a, b);
                }
            }
        }
        fprintf(stderr, "  %s: largest difference / scale:", group_name[grp]);
        for (int k = 0; k < SLOTS; k++)
            fprintf(stderr, " %s %.3g%s", slot_name[k], worst_rel[k], bad[k] ? " (FAILS)" : "");
        fprintf(stderr, "; reprojection validity mismatches %lld\n", valid_mismatch);
        for (int k = 0; k < SLOTS; k++)
            CHECK(bad[k] == 0);
        if (grp == G_ORDINARY)
            CHECK(valid_mismatch == 0);
    }
}

int main(void)
{
    if (gl_device_create(&(gl_device_desc){.gpu_index = -1}) != FS_OK) {
        fprintf(stderr, "no OpenGL 4.5 context: GPU tests need Mesa's EGL (libegl-mesa0, libgl1-mesa-dri)\n");
        return 1;
    }
    fprintf(stderr, "renderer: %s\n", gl_device_renderer());
    rng_state = 0x853c49e6748fea9bull; /* this test's own input sequence */
    inputs = calloc(COUNT, sizeof *inputs);
    gpu = calloc(COUNT, sizeof *gpu);
    cpu = calloc(COUNT, sizeof *cpu);
    if (!inputs || !gpu || !cpu)
        return 1;
    long long valid_cpu = 0;
    for (int i = 0; i < COUNT; i++) {
        make_input(i, &inputs[i]);
        run_cpu(&inputs[i], &cpu[i]);
        valid_cpu += i < GROUP && cpu[i].o[6][3] != 0.0f;
    }
    fprintf(stderr, "  ordinary group: %lld of %d reprojections valid on the CPU\n", valid_cpu, GROUP);
    RUN(glsl_compiles_and_runs);
    RUN(halton_and_jitter_are_bit_identical);
    RUN(gpu_results_are_finite);
    RUN(float_functions_agree);
    free(inputs);
    free(gpu);
    free(cpu);
    gl_device_destroy();
    return test_summary();
}
