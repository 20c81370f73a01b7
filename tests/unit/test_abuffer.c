/* test_abuffer.c: the exact reference's resolve (src/passes/abuffer.c) against the closed form of
 * front-to-back "over" compositing, on lists built by hand in the order a GPU might append them:
 * back-to-front input must not change the answer, equal depths follow draw order, alpha 0 and 1 do
 * what the stochastic test would, overflow marks the pixel, a corrupt list stops. */
#include "passes/abuffer.h"
#include "test.h"

// >>helpers

static abuffer_node frag(float depth, uint32_t order, float r, float g, float b, float alpha)
{
    return (abuffer_node){ABUFFER_END, depth, order, 0, {r * alpha, g * alpha, b * alpha}, alpha};
}

/* The closed form for layers given front to back: colour, A and coverage over a base. */
static void closed_form(const abuffer_node *front_to_back, int n, const float base[5], double out[5])
{
    double t = 1.0, c[3] = {0, 0, 0}, a = 0.0;
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++)
            c[k] += t * front_to_back[i].rgb[k];
        a += t * front_to_back[i].alpha;
        t *= 1.0 - front_to_back[i].alpha;
    }
    for (int k = 0; k < 3; k++)
        out[k] = c[k] + t * base[k];
    out[3] = a + t * base[3];
    out[4] = a + t * base[4];
}

static const float k_sky[5] = {0.4f, 0.6f, 0.9f, 0.0f, 0.0f};   /* background: A = 0, no coverage */
static const float k_trunk[5] = {0.3f, 0.2f, 0.1f, 1.0f, 0.0f}; /* opaque: A = 1, no coverage */

// >>tests

TEST(three_cards_any_input_order_match_the_closed_form)
{
    abuffer_node ftb[3] = {frag(0.2f, 0, 1, 0, 0, 0.4f), frag(0.5f, 1, 0, 1, 0, 0.5f), frag(0.7f, 2, 0, 0, 1, 0.3f)};
    double want[5];
    closed_form(ftb, 3, k_sky, want);
    /* all six input orders */
    static const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int p = 0; p < 6; p++) {
        abuffer_node f[3] = {ftb[perm[p][0]], ftb[perm[p][1]], ftb[perm[p][2]]};
        float out[5];
        abuffer_composite(f, 3, k_sky, out);
        for (int k = 0; k < 5; k++)
            CHECK_NEAR(out[k], want[k], 1e-6);
    }
    /* Coverage 1 - prod(1 - a): 1 - 0.6 * 0.5 * 0.7 = 0.79. */
    CHECK_NEAR(want[4], 0.79, 1e-6);
    /* Back-to-front compositing would give a different colour: the test can tell. */
    abuffer_node btf[3] = {ftb[2], ftb[1], ftb[0]};
    double wrong[5];
    closed_form(btf, 3, k_sky, wrong);
    CHECK(fabs(wrong[0] - want[0]) > 0.05 && fabs(wrong[2] - want[2]) > 0.05);
}

TEST(alpha_one_hides_what_lies_behind_and_alpha_zero_nothing)
{
    abuffer_node f[4] = {frag(0.9f, 3, 0, 0, 1, 0.5f), frag(0.6f, 2, 0, 1, 0, 1.0f), frag(0.3f, 1, 1, 1, 1, 0.0f),
                         frag(0.1f, 0, 1, 0, 0, 0.25f)};
    float out[5];
    abuffer_composite(f, 4, k_trunk, out);
    /* 0.25 red in front, then the opaque green card: the blue card and the trunk are hidden. */
    CHECK_NEAR(out[0], 0.25, 1e-6);
    CHECK_NEAR(out[1], 0.75, 1e-6);
    CHECK_NEAR(out[2], 0.0, 1e-6);
    CHECK_NEAR(out[3], 1.0, 1e-6);
    CHECK_NEAR(out[4], 1.0, 1e-6);
}

TEST(no_fragments_give_the_base)
{
    float out[5];
    abuffer_composite(NULL, 0, k_trunk, out);
    for (int k = 0; k < 5; k++)
        CHECK_NEAR(out[k], k_trunk[k], 0.0);
}

TEST(equal_depths_follow_draw_order_then_primitive)
{
    /* Two cards at one depth: the one drawn first is in front (GL_LESS keeps the first). */
    abuffer_node a = frag(0.5f, 7, 1, 0, 0, 0.3f), b = frag(0.5f, 9, 0, 1, 0, 0.6f);
    abuffer_node f1[2] = {a, b}, f2[2] = {b, a};
    static const float black[5] = {0, 0, 0, 0, 0};
    float o1[5], o2[5];
    abuffer_composite(f1, 2, black, o1);
    abuffer_composite(f2, 2, black, o2);
    CHECK_NEAR(o1[0], 0.3, 1e-6);       /* red in front: 0.3 */
    CHECK_NEAR(o1[1], 0.7 * 0.6, 1e-6); /* green behind it */
    for (int k = 0; k < 5; k++)
        CHECK(o1[k] == o2[k]);
    /* Same draw (instance): the primitive decides. */
    a.order = b.order = 3;
    a.prim = 5;
    b.prim = 2;
    abuffer_node f3[2] = {a, b};
    abuffer_composite(f3, 2, black, o1);
    CHECK_NEAR(o1[1], 0.6, 1e-6); /* green (primitive 2) now in front */
}

TEST(nan_and_out_of_range_alpha_are_clamped)
{
    abuffer_node f[2] = {frag(0.2f, 0, 1, 1, 1, 0.5f), frag(0.4f, 1, 1, 1, 1, 2.0f)};
    f[0].alpha = NAN;
    float out[5];
    abuffer_composite(f, 2, k_sky, out);
    CHECK(isfinite(out[0]) && isfinite(out[3]));
    CHECK_NEAR(out[3], 1.0, 1e-6); /* the alpha-2 card counts as alpha 1 */
}

/* A 3x1 image: pixel 0 empty, pixel 1 a three-node list appended back to front, pixel 2 a list
 * whose store overflowed (its head carries the overflow bit). */
TEST(resolve_walks_lists_and_flags_overflow)
{
    abuffer_node nodes[4] = {frag(0.7f, 2, 0, 0, 1, 0.3f), frag(0.5f, 1, 0, 1, 0, 0.5f), frag(0.2f, 0, 1, 0, 0, 0.4f),
                             frag(0.3f, 0, 1, 1, 1, 0.5f)};
    nodes[1].next = 0; /* appended 0, 1, 2: the head points at the last */
    nodes[2].next = 1;
    uint32_t head[3] = {ABUFFER_END, 2, 3 | ABUFFER_OVERFLOW_BIT};
    float base[5][3], out[5][3];
    for (int k = 0; k < 5; k++)
        for (int i = 0; i < 3; i++)
            base[k][i] = k_sky[k];
    const float *b[5] = {base[0], base[1], base[2], base[3], base[4]};
    float *o[5] = {out[0], out[1], out[2], out[3], out[4]};
    abuffer_lists l = {3, 1, head, nodes, 5, 4}; /* asked for 5, held 4 */
    unsigned char over[3];
    abuffer_scratch s = {0};
    CHECK(abuffer_resolve(&l, b, o, over, &s) == 1);
    CHECK(over[0] == 0 && over[1] == 0 && over[2] == 1);
    for (int k = 0; k < 5; k++)
        CHECK_NEAR(out[k][0], k_sky[k], 0.0);
    abuffer_node ftb[3] = {nodes[2], nodes[1], nodes[0]};
    double want[5];
    closed_form(ftb, 3, k_sky, want);
    for (int k = 0; k < 5; k++)
        CHECK_NEAR(out[k][1], want[k], 1e-6);
    CHECK_NEAR(out[3][2], 0.5, 1e-6); /* what was stored is still composited */
    abuffer_scratch_free(&s);
}

TEST(corrupt_lists_stop)
{
    /* A cycle, and a pointer past what was stored: both end the walk, the second flags the pixel. */
    abuffer_node nodes[2] = {frag(0.2f, 0, 1, 0, 0, 0.5f), frag(0.4f, 1, 0, 1, 0, 0.5f)};
    nodes[0].next = 1;
    nodes[1].next = 0;
    uint32_t head[2] = {0, 1000};
    float base[5][2] = {{0}}, out[5][2];
    const float *b[5] = {base[0], base[1], base[2], base[3], base[4]};
    float *o[5] = {out[0], out[1], out[2], out[3], out[4]};
    abuffer_lists l = {2, 1, head, nodes, 2, 2};
    unsigned char over[2];
    abuffer_scratch s = {0};
    CHECK(abuffer_resolve(&l, b, o, over, &s) == 1);
    CHECK(over[0] == 0 && over[1] == 1);
    CHECK(isfinite(out[0][0]) && out[3][0] <= 1.0f + 1e-6f);
    abuffer_scratch_free(&s);
}

TEST(long_lists_sort_like_short_ones)
{
    /* 200 layers in reverse order (qsort path) against the closed form in order. */
    enum { N = 200 };
    abuffer_node f[N], ftb[N];
    for (int i = 0; i < N; i++) {
        ftb[i] = frag(0.001f * (float)(i + 1), (uint32_t)i, (float)(i % 3 == 0), (float)(i % 3 == 1),
                      (float)(i % 3 == 2), 0.02f);
        f[N - 1 - i] = ftb[i];
    }
    double want[5];
    closed_form(ftb, N, k_trunk, want);
    float out[5];
    abuffer_composite(f, N, k_trunk, out);
    for (int k = 0; k < 5; k++)
        CHECK_NEAR(out[k], want[k], 1e-5);
}

int main(void)
{
    RUN(three_cards_any_input_order_match_the_closed_form);
    RUN(alpha_one_hides_what_lies_behind_and_alpha_zero_nothing);
    RUN(no_fragments_give_the_base);
    RUN(equal_depths_follow_draw_order_then_primitive);
    RUN(nan_and_out_of_range_alpha_are_clamped);
    RUN(resolve_walks_lists_and_flags_overflow);
    RUN(corrupt_lists_stop);
    RUN(long_lists_sort_like_short_ones);
    return test_summary();
}
