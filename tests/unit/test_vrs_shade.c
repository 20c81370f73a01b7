/* Unit tests of VRS foveation's coarse-shading math (src/passes/vrs_shade.c, the C twin of
 * shaders/common/vrs_shade.glsl): every pixel of a coarse pixel finds the same aligned block and
 * centre, which lies inside no other block; the barycentric weights at a point reproject onto it
 * and their steps match finite differences (perspective triangles, computed here in double); the
 * LOD rule reads one level coarser per doubling of the rate. */
#include <math.h>

#include "passes/alpha_hash.h"
#include "passes/vrs_shade.h"
#include "test.h"

TEST(coarse_pixel_is_the_aligned_block)
{
    const int W = 37, H = 23; /* odd on purpose: blocks hang over the bottom and right edges */
    for (int k = 0; k < VRS_RATE_COUNT; k++) {
        vrs_rate r = k_vrs_rates[k];
        int w = vrs_rate_width(r), h = vrs_rate_height(r);
        for (int py = 0; py < H; py++)
            for (int px = 0; px < W; px++) {
                int o[2];
                float c[2];
                vrs_coarse_pixel(px, py, r, H, o, c);
                int top = H - 1 - py;
                CHECK(o[0] % w == 0 && o[1] % h == 0);
                CHECK(px >= o[0] && px < o[0] + w && top >= o[1] && top < o[1] + h);
                /* the centre, back in display coordinates, is the block's centre */
                CHECK(c[0] == (float)o[0] + 0.5f * (float)w && (float)H - c[1] == (float)o[1] + 0.5f * (float)h);
                if (r == VRS_1X1) /* full rate: the pixel's own centre (gl_FragCoord) */
                    CHECK(c[0] == (float)px + 0.5f && c[1] == (float)py + 0.5f);
            }
    }
    /* every pixel of one 4x2 block, and none outside, shares its origin */
    int ref[2], o[2];
    float c[2];
    vrs_coarse_pixel(8, H - 1 - 6, VRS_4X2, H, ref, c);
    for (int y = 4; y < 10; y++)
        for (int x = 6; x < 14; x++) {
            vrs_coarse_pixel(x, H - 1 - y, VRS_4X2, H, o, c);
            bool inside = x >= 8 && x < 12 && y >= 6 && y < 8;
            CHECK(inside == (o[0] == ref[0] && o[1] == ref[1]));
        }
}

static double urand(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (double)(*s >> 8) / 16777216.0;
}

/* The window point of clip position p (x, y, z, w) in a vw x vh viewport, in double. */
static void to_window(const double p[4], double vw, double vh, double out[2])
{
    out[0] = (p[0] / p[3] + 1.0) * 0.5 * vw;
    out[1] = (p[1] / p[3] + 1.0) * 0.5 * vh;
}

/* The weights at window point (x, y) in double: the clip point sum b_i c_i projects onto it. */
static void bary_double(const double c[3][4], double x, double y, double vw, double vh, double b[3])
{
    double nx = 2.0 * x / vw - 1.0, ny = 2.0 * y / vh - 1.0, e[3];
    for (int i = 0; i < 3; i++) {
        const double *a = c[(i + 1) % 3], *d = c[(i + 2) % 3];
        double E[3] = {a[1] * d[3] - a[3] * d[1], a[3] * d[0] - a[0] * d[3], a[0] * d[1] - a[1] * d[0]};
        e[i] = nx * E[0] + ny * E[1] + E[2];
    }
    double s = e[0] + e[1] + e[2];
    for (int i = 0; i < 3; i++)
        b[i] = e[i] / s;
}

TEST(barycentrics_reproject_and_step)
{
    unsigned seed = 7;
    const float vw = 320.0f, vh = 180.0f;
    int tested = 0;
    for (int t = 0; t < 2000; t++) {
        double cd[3][4];
        float cf[3][4];
        for (int i = 0; i < 3; i++) {
            double w = 0.5 + 4.0 * urand(&seed); /* in front of the eye, at depths 1:9 apart */
            cd[i][0] = (2.0 * urand(&seed) - 1.0) * w;
            cd[i][1] = (2.0 * urand(&seed) - 1.0) * w;
            cd[i][2] = 0.5 * w;
            cd[i][3] = w;
            for (int k = 0; k < 4; k++)
                cf[i][k] = (float)cd[i][k];
        }
        double x = vw * urand(&seed), y = vh * urand(&seed);
        float edge[3][3], b[3], bx[3], by[3];
        vrs_triangle_edges(cf, edge);
        vrs_bary(edge, (float)x, (float)y, 2.0f, 4.0f, vw, vh, b, bx, by);
        double bd[3], P[4] = {0, 0, 0, 0}, win[2];
        bary_double(cd, x, y, vw, vh, bd);
        if (!(fabs(bd[0]) + fabs(bd[1]) + fabs(bd[2]) < 20.0))
            continue; /* the point's ray nearly parallel to the triangle: ill-conditioned in float */
        tested++;
        CHECK_NEAR(b[0] + b[1] + b[2], 1.0, 1e-5);
        for (int i = 0; i < 3; i++) {
            CHECK_NEAR(b[i], bd[i], 2e-4 * (1.0 + fabs(bd[i])));
            for (int k = 0; k < 4; k++)
                P[k] += bd[i] * cd[i][k];
        }
        to_window(P, vw, vh, win);
        CHECK_NEAR(win[0], x, 1e-6 * vw);
        CHECK_NEAR(win[1], y, 1e-6 * vh);
        /* steps: central differences over +-0.001 of a step of 2 pixels in x, 4 in y */
        double bp[3], bm[3], h = 1e-3;
        bary_double(cd, x + 2.0 * h, y, vw, vh, bp);
        bary_double(cd, x - 2.0 * h, y, vw, vh, bm);
        for (int i = 0; i < 3; i++)
            CHECK_NEAR(bx[i], (bp[i] - bm[i]) / (2.0 * h), 2e-3 * (1.0 + fabs(bx[i])));
        bary_double(cd, x, y + 4.0 * h, vw, vh, bp);
        bary_double(cd, x, y - 4.0 * h, vw, vh, bm);
        for (int i = 0; i < 3; i++)
            CHECK_NEAR(by[i], (bp[i] - bm[i]) / (2.0 * h), 2e-3 * (1.0 + fabs(by[i])));
    }
    CHECK(tested > 1500);
}

TEST(lod_rises_with_the_rate)
{
    const float size[2] = {64.0f, 64.0f};
    const float dx[2] = {1.0f / 16.0f, 0.0f}, dy[2] = {0.0f, 1.0f / 16.0f}; /* 4 texels per pixel: level 2 */
    float full = alpha_texture_fade_level(dx, dy, size, 1.0f);
    CHECK_NEAR(full, 2.0, 1e-6);
    CHECK(vrs_coarse_lod(dx, dy, VRS_1X1, size, 1.0f) == full);
    CHECK_NEAR(vrs_coarse_lod(dx, dy, VRS_2X2, size, 1.0f), 3.0, 1e-6); /* the checkerboard at 2x2: one above */
    CHECK_NEAR(vrs_coarse_lod(dx, dy, VRS_4X4, size, 1.0f), 4.0, 1e-6);
    /* isotropic rule: the longer axis decides */
    CHECK_NEAR(vrs_coarse_lod(dx, dy, VRS_2X1, size, 1.0f), 3.0, 1e-6);
    CHECK_NEAR(vrs_coarse_lod(dx, dy, VRS_1X2, size, 1.0f), 3.0, 1e-6);
    CHECK_NEAR(vrs_coarse_lod(dx, dy, VRS_4X2, size, 1.0f), 4.0, 1e-6);
    /* a mip bias of -1 (mip_scale 1/2) cancels one doubling */
    CHECK_NEAR(vrs_coarse_lod(dx, dy, VRS_2X2, size, 0.5f), 2.0, 1e-6);
    /* magnified (half a texel per pixel): level 0 at 1x1 and 2x2, 1 at 4x4 */
    const float mx[2] = {1.0f / 128.0f, 0.0f}, my[2] = {0.0f, 1.0f / 128.0f};
    CHECK(vrs_coarse_lod(mx, my, VRS_1X1, size, 1.0f) == 0.0f);
    CHECK(vrs_coarse_lod(mx, my, VRS_2X2, size, 1.0f) == 0.0f);
    CHECK_NEAR(vrs_coarse_lod(mx, my, VRS_4X4, size, 1.0f), 1.0, 1e-6);
}

int main(void)
{
    RUN(coarse_pixel_is_the_aligned_block);
    RUN(barycentrics_reproject_and_step);
    RUN(lod_rises_with_the_rate);
    return test_summary();
}
