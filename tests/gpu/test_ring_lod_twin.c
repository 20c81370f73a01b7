/* GPU twin of the per-ring simplification law: shaders/test/ring_lod_twin.comp runs every function
 * of shaders/common/ring_lod.glsl on a buffer of inputs and the results are compared with the C
 * twin (src/fov/ring_lod.c), input by input.
 *
 * Inputs: laws of ring_lod_law_for for u in (0, 1] (a third of them the schedule's values, 1, the
 * two branches' boundary u*, 0.9, 0.01), ranks that are real ranks (multiples of 2^-24), exactly
 * RING_LOD_RANK_KEEP, or on and next to the ramp's ends; random instance keys; card centres in
 * [-10, 10]^3 and vertices up to 2 units from them.
 *
 * Tolerances, and why:
 *   - ring_lod_instance_offset, ring_lod_rank (its bits) and ring_lod_weight (of the card's rank and
 *     of the rotated rank): bit-identical, every input. The offset and the rotation are integer
 *     operations and exact conversions (ranks are below 1, so rank * 2^24 < 2^24 fits a float's
 *     mantissa; the product by 2^-24 is exact); the weight is one subtraction, one multiplication,
 *     one subtraction and a clamp, correctly rounded on both sides (`precise` on the GPU, no
 *     contraction in C11).
 *   - ring_lod_scale: within 8 ULP (relative 2^-20) of the C value. GLSL leaves sqrt's precision to
 *     the implementation (inherited from 1 / inversesqrt: a few ULP); sqrt(0) = 0 on both sides, so a
 *     dropped card has scale 0 on both.
 *   - ring_lod_apply: per component within 2^-20 (|centre| + |p - centre| s) (the scale's
 *     tolerance carried through one multiplication and one addition); bit for bit the input
 *     position where the scale is exactly 1 on both sides (the identity law, RING_LOD_RANK_KEEP),
 *     and bit for bit the centre where the weight is 0: u = 1 draws exactly what no simplification
 *     draws, and dropped cards have zero area, on the GPU too.
 */
#include <epoxy/gl.h>
#include <stdint.h>

#include "common/shared_defs.h"
#include "gl/gl_device.h"
#include "gl/gl_program.h"
#include "fov/ring_lod.h"
#include "test.h"
#include "twin_util.h"

typedef struct twin_in {
    float card[4], p[4], law[4];
    uint32_t key[4];
} twin_in;

typedef struct twin_out {
    float o0[4], o1[4], o2[4];
    uint32_t o3[4];
    float o4[4];
} twin_out;

enum { COUNT = 1 << 16 };

static twin_in *inputs;
static twin_out *gpu, *cpu;
static bool have_gpu_results;

/* >>inputs */

static float pick_u(void)
{
    const float list[] = {1.0f, 0.5f, 0.25f, 0.125f, 0.0625f, 0.9f, 0.01f, (float)(1.0 / (1.0 + 0.5 * RING_LOD_BAND))};
    if (rng01() < 0.35)
        return list[rng_u64() % (sizeof list / sizeof list[0])];
    return rngf(0.01, 1.0);
}

static float pick_rank(const ring_lod_law *l)
{
    double x = rng01();
    if (x < 0.6) /* a real rank */
        return (float)(rng_u64() & RING_LOD_RANK_MASK) * (float)(1.0 / RING_LOD_RANK_ONE);
    if (x < 0.7)
        return (float)RING_LOD_RANK_KEEP;
    /* On and next to the ends of the ramp, where the clamp decides. */
    float e = l->k > 0.0f ? l->a + 1.0f / l->k : 1.0f;
    float r = rng01() < 0.5 ? l->a : e;
    int steps = (int)(rng_u64() % 5) - 2;
    for (; steps > 0; steps--)
        r = nextafterf(r, 2.0f);
    for (; steps < 0; steps++)
        r = nextafterf(r, -2.0f);
    return r < 0.0f ? 0.0f : (r >= 1.0f ? 1.0f - 0x1p-24f : r);
}

static void make_input(twin_in *in)
{
    memset(in, 0, sizeof *in);
    ring_lod_law l = ring_lod_law_for(pick_u());
    in->law[0] = l.a, in->law[1] = l.k, in->law[2] = l.gain;
    for (int k = 0; k < 3; k++) {
        in->card[k] = rngf(-10, 10);
        in->p[k] = in->card[k] + rngf(-2, 2);
    }
    in->card[3] = pick_rank(&l);
    in->key[0] = (uint32_t)rng_u64();
    in->law[3] = rng01() < 0.1 ? rngf(-0.5, 1.5) : pick_u(); /* ring_lod_law_for's u, also outside (0, 1] */
    in->p[3] = rng01() < 0.1 ? 0.0f : rngf(0.0, 2.0);         /* ring_lod_card_u's side in ring pixels */
}

static void run_cpu(const twin_in *in, twin_out *out)
{
    memset(out, 0, sizeof *out);
    ring_lod_law l = {in->law[0], in->law[1], in->law[2]};
    float rr = ring_lod_rank(in->card[3], in->key[0]);
    out->o0[0] = ring_lod_weight(&l, in->card[3]);
    out->o0[1] = ring_lod_scale(&l, in->card[3]);
    out->o0[2] = rr;
    out->o0[3] = ring_lod_weight(&l, rr);
    vec3 p = v3(in->p[0], in->p[1], in->p[2]);
    vec3 q = ring_lod_apply(&l, p, in->card);
    out->o1[0] = q.x, out->o1[1] = q.y, out->o1[2] = q.z;
    const float rot[4] = {in->card[0], in->card[1], in->card[2], rr};
    q = ring_lod_apply(&l, p, rot);
    out->o2[0] = q.x, out->o2[1] = q.y, out->o2[2] = q.z;
    out->o3[0] = ring_lod_instance_offset(in->key[0]);
    memcpy(&out->o3[1], &rr, sizeof rr);
    ring_lod_law f = ring_lod_law_for(in->law[3]);
    out->o4[0] = f.a, out->o4[1] = f.k, out->o4[2] = f.gain;
    out->o4[3] = ring_lod_card_u(in->p[3]);
}

/* >>run */

TEST(glsl_compiles_and_runs)
{
    bool ok = twin_run("shaders/test/ring_lod_twin.comp", inputs, sizeof(twin_in) * COUNT, gpu,
                       sizeof(twin_out) * COUNT, COUNT);
    CHECK(ok);
    have_gpu_results = ok;
}

/* >>compare */

TEST(integer_paths_and_weights_are_bit_identical)
{
    if (!have_gpu_results) {
        CHECK(have_gpu_results);
        return;
    }
    long long bad_offset = 0, bad_rank = 0, bad_weight = 0, dropped = 0, partial = 0;
    for (int i = 0; i < COUNT; i++) {
        const twin_out *g = &gpu[i], *c = &cpu[i];
        bad_offset += g->o3[0] != c->o3[0];
        bad_rank += g->o3[1] != c->o3[1] || !twin_same_bits(g->o0[2], c->o0[2]);
        bool w = twin_same_bits(g->o0[0], c->o0[0]) && twin_same_bits(g->o0[3], c->o0[3]);
        bad_weight += !w;
        if (!w && bad_weight <= 3)
            fprintf(stderr, "  weight at %d: gpu %.9g %.9g cpu %.9g %.9g (rank %.9g, a %.9g, k %.9g)\n", i, g->o0[0],
                    g->o0[3], c->o0[0], c->o0[3], inputs[i].card[3], inputs[i].law[0], inputs[i].law[1]);
        dropped += c->o0[0] == 0.0f;
        partial += c->o0[0] > 0.0f && c->o0[0] < 1.0f;
    }
    fprintf(stderr, "  %d inputs: %lld dropped, %lld fading; mismatches: offset %lld, rank %lld, weight %lld\n", COUNT,
            dropped, partial, bad_offset, bad_rank, bad_weight);
    CHECK(bad_offset == 0 && bad_rank == 0 && bad_weight == 0);
    CHECK(dropped > COUNT / 20 && partial > COUNT / 20); /* the inputs reach every part of the law */
}

TEST(scale_and_apply_agree)
{
    if (!have_gpu_results) {
        CHECK(have_gpu_results);
        return;
    }
    const double tol = 0x1p-20;
    long long bad_scale = 0, bad_apply = 0, bad_identity = 0, bad_dropped = 0, identities = 0, same_scale = 0;
    double worst_scale = 0.0, worst_apply = 0.0;
    for (int i = 0; i < COUNT; i++) {
        const twin_in *in = &inputs[i];
        const twin_out *g = &gpu[i], *c = &cpu[i];
        double s = c->o0[1], ds = fabs((double)g->o0[1] - s);
        if (isnan(ds))
            ds = INFINITY;
        bad_scale += !(ds <= tol * s);
        same_scale += twin_same_bits(g->o0[1], c->o0[1]);
        if (s > 0.0)
            worst_scale = fmax(worst_scale, ds / s);
        for (int set = 0; set < 2; set++) {
            const float *go = set ? g->o2 : g->o1, *co = set ? c->o2 : c->o1;
            ring_lod_law l = {in->law[0], in->law[1], in->law[2]};
            float rank = set ? c->o0[2] : in->card[3];
            float cs = ring_lod_scale(&l, rank), cw = ring_lod_weight(&l, rank);
            for (int k = 0; k < 3; k++) {
                double scale = fabs((double)in->card[k]) + fabs((double)in->p[k] - in->card[k]) * cs + 1e-30;
                double d = fabs((double)go[k] - co[k]);
                if (isnan(d))
                    d = INFINITY;
                bad_apply += !(d <= tol * scale);
                worst_apply = fmax(worst_apply, d / scale);
                if (ring_lod_law_is_identity(&l) || rank < 0.0f) { /* u = 1 or KEEP: the position, bit for bit */
                    identities += k == 0;
                    bad_identity += !twin_same_bits(go[k], in->p[k]) || !twin_same_bits(co[k], in->p[k]);
                }
                if (cw == 0.0f) /* dropped: exactly on the centre */
                    bad_dropped += !twin_same_bits(go[k], in->card[k]) || !twin_same_bits(co[k], in->card[k]);
            }
        }
    }
    fprintf(stderr,
            "  scale: largest relative difference %.3g (%lld of %d bit-identical); apply: largest %.3g; "
            "%lld identity vertices\n",
            worst_scale, same_scale, COUNT, worst_apply, identities);
    CHECK(bad_scale == 0 && bad_apply == 0);
    CHECK(bad_identity == 0 && identities > COUNT / 10);
    CHECK(bad_dropped == 0);
}

/* The per-card schedule's twins: the GPU computes each card's u and law. u is bit-identical (a
 * product, a division by 1 and a clamp); the law within 8 ULP (relative 2^-20): GLSL allows 2.5 ULP
 * for a division, and k and gain are quotients. */
TEST(per_card_u_and_law_agree)
{
    if (!have_gpu_results)
        return;
    int bad_u = 0, bad_law = 0, identity = 0;
    for (int i = 0; i < COUNT; i++) {
        const twin_out *g = &gpu[i], *c = &cpu[i];
        bad_u += !twin_same_bits(g->o4[3], c->o4[3]);
        bool same = true;
        for (int k = 0; k < 3; k++) {
            double d = fabs((double)g->o4[k] - (double)c->o4[k]);
            same &= d <= fabs((double)c->o4[k]) * 0x1p-20 || twin_same_bits(g->o4[k], c->o4[k]);
        }
        if (!same && bad_law++ < 5)
            fprintf(stderr, "  law at u %.9g: gpu %.9g %.9g %.9g cpu %.9g %.9g %.9g\n", inputs[i].law[3], g->o4[0],
                    g->o4[1], g->o4[2], c->o4[0], c->o4[1], c->o4[2]);
        identity += c->o4[1] == 0.0f && twin_same_bits(g->o4[1], 0.0f) && g->o4[2] == 1.0f;
    }
    fprintf(stderr, "per card: %d u and %d laws differ of %d; %d identity laws on both sides\n", bad_u, bad_law, COUNT,
            identity);
    CHECK(bad_u == 0 && bad_law == 0);
    CHECK(identity > COUNT / 20); /* u >= 1 and u <= 0 reach the identity on both sides */
}

int main(void)
{
    if (gl_device_create(&(gl_device_desc){.gpu_index = -1}) != FS_OK) {
        fprintf(stderr, "no OpenGL 4.5 context: GPU tests need Mesa's EGL (libegl-mesa0, libgl1-mesa-dri)\n");
        return 1;
    }
    fprintf(stderr, "renderer: %s\n", gl_device_renderer());
    rng_state = 0x1f83d9abfb41bd6bull; /* this test's own input sequence */
    inputs = calloc(COUNT, sizeof *inputs);
    gpu = calloc(COUNT, sizeof *gpu);
    cpu = calloc(COUNT, sizeof *cpu);
    if (!inputs || !gpu || !cpu)
        return 1;
    for (int i = 0; i < COUNT; i++) {
        make_input(&inputs[i]);
        run_cpu(&inputs[i], &cpu[i]);
    }
    RUN(glsl_compiles_and_runs);
    RUN(integer_paths_and_weights_are_bit_identical);
    RUN(scale_and_apply_agree);
    RUN(per_card_u_and_law_agree);
    free(inputs);
    free(gpu);
    free(cpu);
    gl_device_destroy();
    return test_summary();
}
