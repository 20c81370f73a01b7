/* test_warp.c: the previous frame warped into the current one (src/metrics/warp.c) on a
 * synthetic static scene under pure camera motion, ray-cast here: a background plane whose colour
 * is linear in world x and y (so bilinear sampling reproduces it exactly: the plane faces the
 * camera) and a nearer square occluder. Where the point was visible in the previous frame the
 * warp reproduces the current frame; what the occluder hid, and what was outside the previous
 * view, is not warped. */
#include <stdlib.h>
#include <string.h>

#include "metrics/warp.h"
#include "test.h"

enum { W = 96, H = 64 };
#define ZNEAR 0.5f
#define ZFAR 50.0f
#define OCC_Z 3.0f  /* the occluder: |x| < 1, |y| < 1 at z = 3 */

typedef struct shot {
    mat4 vp;
    float r[W * H], g[W * H], b[W * H], cov[W * H], depth[W * H];
    unsigned char occ[W * H]; /* 1 where the occluder is seen */
} shot;

static mat4 camera(float cx)
{
    mat4 proj = m4_perspective_hfov(60.0f * 3.14159265f / 180.0f, (float)W / H, ZNEAR, ZFAR);
    return m4_mul(proj, m4_look_at(v3(cx, 0, 10), v3(cx, 0, 0), v3(0, 1, 0)));
}

/* World point where pixel (x, y)'s centre ray meets plane z = z0 (through the inverse view-proj). */
static vec3 hit(const mat4 *inv, int x, int y, float z0)
{
    float nx = 2.0f * ((float)x + 0.5f) / W - 1.0f, ny = 1.0f - 2.0f * ((float)y + 0.5f) / H;
    float a[4] = {nx, ny, -1.0f, 1.0f}, b[4] = {nx, ny, 1.0f, 1.0f}, pa[4] = {0}, pb[4] = {0};
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            pa[r] += inv->m[c * 4 + r] * a[c];
            pb[r] += inv->m[c * 4 + r] * b[c];
        }
    vec3 A = v3(pa[0] / pa[3], pa[1] / pa[3], pa[2] / pa[3]), B = v3(pb[0] / pb[3], pb[1] / pb[3], pb[2] / pb[3]);
    float t = (z0 - A.z) / (B.z - A.z);
    return v3_add(A, v3_scale(v3_sub(B, A), t));
}

static float window_depth(const mat4 *vp, vec3 p)
{
    float clip[4] = {0};
    float q[4] = {p.x, p.y, p.z, 1.0f};
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            clip[r] += vp->m[c * 4 + r] * q[c];
    return 0.5f * (clip[2] / clip[3] + 1.0f);
}

static void render(shot *s, float cx)
{
    s->vp = camera(cx);
    mat4 inv;
    m4_invert(s->vp, &inv);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int i = y * W + x;
            vec3 o = hit(&inv, x, y, OCC_Z);
            bool occ = fabsf(o.x) < 1.0f && fabsf(o.y) < 1.0f;
            vec3 p = occ ? o : hit(&inv, x, y, 0.0f);
            s->occ[i] = occ;
            s->r[i] = occ ? 0.9f : 0.5f + 0.02f * p.x;
            s->g[i] = occ ? 0.1f : 0.5f + 0.03f * p.y;
            s->b[i] = occ ? 0.1f : 0.2f;
            s->cov[i] = occ ? 1.0f : 0.4f;
            s->depth[i] = window_depth(&s->vp, p);
        }
}

TEST(warp_is_exact_for_a_static_scene_under_camera_motion)
{
    static shot prev, cur;
    render(&prev, 0.0f);
    render(&cur, 2.0f); /* the camera moves right: the scene moves left, the nearer occluder more */
    static float wr[W * H], wg[W * H], wb[W * H], wc[W * H];
    float *out[4] = {wr, wg, wb, wc};
    static unsigned char valid[W * H];
    metrics_view pv = {W, H, prev.r, prev.g, prev.b, prev.cov};
    warp_desc wd = {.width = W, .height = H, .depth = cur.depth, .view_proj = cur.vp, .prev_view_proj = prev.vp,
                    .prev_depth = prev.depth, .prev_znear = ZNEAR, .prev_zfar = ZFAR};
    long n = warp_previous(&wd, &pv, out, valid);
    CHECK(n > W * H / 2 && n < W * H);
    mat4 inv_cur, inv_prev;
    m4_invert(cur.vp, &inv_cur);
    m4_invert(prev.vp, &inv_prev);
    long exact = 0, checked = 0, hidden = 0, hidden_flagged = 0, outside = 0, outside_flagged = 0;
    double worst = 0;
    for (int y = 2; y < H - 2; y++)
        for (int x = 2; x < W - 2; x++) {
            int i = y * W + x;
            /* Ground truth: where this pixel's surface point lies in the previous frame. */
            vec3 p = cur.occ[i] ? hit(&inv_cur, x, y, OCC_Z) : hit(&inv_cur, x, y, 0.0f);
            float clip[4] = {0}, q[4] = {p.x, p.y, p.z, 1.0f};
            for (int r = 0; r < 4; r++)
                for (int c = 0; c < 4; c++)
                    clip[r] += prev.vp.m[c * 4 + r] * q[c];
            float px = (clip[0] / clip[3] + 1.0f) * 0.5f * W - 0.5f, py = (1.0f - clip[1] / clip[3]) * 0.5f * H - 0.5f;
            bool in_view = px >= 0.0f && px <= W - 1.0f && py >= 0.0f && py <= H - 1.0f;
            int pi = (int)lrintf(py) * W + (int)lrintf(px);
            /* Skip pixels next to an edge of the occluder (bilinear taps mix the two surfaces) or
             * of the previous view. */
            bool near_edge = !in_view || px < 1.0f || px > W - 2.0f || py < 1.0f || py > H - 2.0f;
            bool all_occ = in_view; /* the occluder covers the whole neighbourhood there */
            for (int dy = -2; dy <= 2 && in_view; dy++)
                for (int dx = -2; dx <= 2; dx++) {
                    int xx = (int)lrintf(px) + dx, yy = (int)lrintf(py) + dy;
                    bool inside = xx >= 0 && yy >= 0 && xx < W && yy < H;
                    if (inside && prev.occ[yy * W + xx] != cur.occ[i])
                        near_edge = true;
                    all_occ = all_occ && inside && prev.occ[yy * W + xx];
                }
            if (!in_view && (px < -2.0f || px > W + 1.0f)) {
                outside++;
                outside_flagged += !valid[i];
            }
            if (!cur.occ[i] && all_occ && prev.occ[pi]) {
                hidden++; /* the occluder covered this background point in the previous frame */
                hidden_flagged += !valid[i];
            }
            if (near_edge || !valid[i])
                continue;
            checked++;
            double d = fmax(fabs(wr[i] - cur.r[i]), fmax(fabs(wg[i] - cur.g[i]), fabs(wc[i] - cur.cov[i])));
            worst = fmax(worst, d);
            exact += d < 1e-4;
        }
    fprintf(stderr, "warp: %ld valid; %ld checked, worst %.2g; %ld hidden before (%ld flagged); %ld from outside "
                    "(%ld flagged)\n", n, checked, worst, hidden, hidden_flagged, outside, outside_flagged);
    CHECK(checked > W * H / 3 && exact == checked);
    CHECK(hidden > 20 && hidden_flagged == hidden);
    CHECK(outside > 20 && outside_flagged == outside);
}

TEST(a_still_camera_warps_to_the_previous_frame_itself)
{
    static shot s;
    render(&s, 0.3f);
    static float wr[W * H], wg[W * H], wb[W * H], wc[W * H];
    float *out[4] = {wr, wg, wb, wc};
    static unsigned char valid[W * H];
    metrics_view pv = {W, H, s.r, s.g, s.b, s.cov};
    warp_desc wd = {.width = W, .height = H, .depth = s.depth, .view_proj = s.vp, .prev_view_proj = s.vp,
                    .prev_depth = s.depth, .prev_znear = ZNEAR, .prev_zfar = ZFAR};
    CHECK(warp_previous(&wd, &pv, out, valid) == W * H);
    double worst = 0;
    for (int i = 0; i < W * H; i++)
        worst = fmax(worst, fabs(wr[i] - s.r[i]) + fabs(wc[i] - s.cov[i]));
    CHECK(worst < 1e-4);
    /* A singular view-projection is refused. */
    wd.view_proj = (mat4){{0}};
    CHECK(warp_previous(&wd, &pv, out, valid) == -1);
}

TEST(a_frozen_image_scores_worse_than_the_method_it_froze)
{
    /* The camera dollies sideways; the method that draws the reference exactly has temporal error
     * 0 (its change is the reference's change), the same method frozen at the previous frame has
     * the reference's whole change as error. The flicker ratio would have scored the frozen one 0,
     * the best. A still camera (the same frame twice) gives finite values. */
    static shot prev, cur;
    render(&prev, 0.0f);
    render(&cur, 0.5f);
    display_desc d = {W, H, 60.0f, 0.0f, 0.0f};
    fov_layout off = fov_layout_off();
    ring_mask m;
    CHECK(ring_mask_build(&d, &off, W / 2.0f, H / 2.0f, &m) == FS_OK);
    static float wr[W * H], wg[W * H], wb[W * H], wc[W * H], fr_[W * H], fg[W * H], fb[W * H], fc[W * H];
    float *wref[4] = {wr, wg, wb, wc}, *wfroz[4] = {fr_, fg, fb, fc};
    static unsigned char valid[W * H];
    metrics_view vprev = {W, H, prev.r, prev.g, prev.b, prev.cov}, vcur = {W, H, cur.r, cur.g, cur.b, cur.cov};
    warp_desc wd = {.width = W, .height = H, .depth = cur.depth, .view_proj = cur.vp, .prev_view_proj = prev.vp,
                    .prev_depth = prev.depth, .prev_znear = ZNEAR, .prev_zfar = ZFAR};
    CHECK(warp_previous(&wd, &vprev, wref, valid) > 0);
    metrics_view wrv = {W, H, wr, wg, wb, wc};
    ring_metrics exact[2], frozen[2];
    /* Exact: the method is the reference in both frames. */
    CHECK(metrics_temporal(&vcur, &wrv, &vcur, &wrv, valid, &m, exact) == FS_OK);
    /* Frozen: the method shows the previous frame again now; its warped previous is that warped. */
    CHECK(warp_previous(&wd, &vprev, wfroz, valid) > 0);
    metrics_view wfv = {W, H, fr_, fg, fb, fc};
    CHECK(metrics_temporal(&vprev, &wfv, &vcur, &wrv, valid, &m, frozen) == FS_OK);
    fprintf(stderr, "temporal error: exact %.5f, frozen %.5f, disoccluded %.3f\n", exact[1].temporal_error,
            frozen[1].temporal_error, exact[1].disoccluded);
    CHECK(exact[1].temporal_error == 0.0);
    CHECK(frozen[1].temporal_error > 0.01);
    CHECK(exact[1].disoccluded > 0.0 && exact[1].disoccluded < 0.5);
    /* Still camera, static scene: finite, and zero for a method that does not change. */
    wd.view_proj = wd.prev_view_proj = prev.vp;
    wd.depth = wd.prev_depth = prev.depth;
    CHECK(warp_previous(&wd, &vprev, wref, valid) == W * H);
    CHECK(metrics_temporal(&vprev, &wrv, &vprev, &wrv, valid, &m, exact) == FS_OK);
    CHECK(isfinite(exact[1].temporal_error) && exact[1].temporal_error < 1e-6 && exact[1].disoccluded == 0.0);
    ring_mask_free(&m);
}

/* A still camera's warp is the identity exactly (docs/metrics.md "Still camera"): a frame that did not change scores
 * temporal error 0, not the float rounding of reprojecting through inverse(VP) VP, which moves
 * pixels by ~1e-5 and read 8.3e-5 on a real run. A noisy image makes any resampling show. The
 * previous view-projection is the same matrix, then the same matrix one float ulp off in every
 * element (what a camera path rounding off its key gave). */
TEST(an_unchanged_frame_scores_exactly_0_under_a_still_camera)
{
    static shot s, f; /* the method (noise) and the reference (the smooth plane and square) */
    render(&s, 0.3f);
    render(&f, 0.3f);
    unsigned state = 12345u;
    for (int i = 0; i < W * H; i++) { /* noise: neighbours differ by up to 1 */
        state = state * 1664525u + 1013904223u;
        s.r[i] = (float)(state >> 8) / 16777216.0f;
        s.g[i] = 1.0f - s.r[i];
        s.cov[i] = (float)((state >> 4) & 1u);
    }
    display_desc d = {W, H, 60.0f, 0.0f, 0.0f};
    fov_layout off = fov_layout_off();
    ring_mask m;
    CHECK(ring_mask_build(&d, &off, W / 2.0f, H / 2.0f, &m) == FS_OK);
    static float wr[W * H], wg[W * H], wb[W * H], wc[W * H], fr[W * H], fg[W * H], fb[W * H], fc[W * H];
    float *out[4] = {wr, wg, wb, wc}, *fout[4] = {fr, fg, fb, fc};
    static unsigned char valid[W * H];
    metrics_view v = {W, H, s.r, s.g, s.b, s.cov}, wv = {W, H, wr, wg, wb, wc};
    metrics_view vf = {W, H, f.r, f.g, f.b, f.cov}, wvf = {W, H, fr, fg, fb, fc};
    for (int ulp = 0; ulp < 2; ulp++) {
        mat4 prev = s.vp;
        for (int k = 0; k < 16 && ulp; k++)
            prev.m[k] = nextafterf(prev.m[k], INFINITY);
        CHECK(warp_camera_still(&prev, &s.vp, W, H, warp_min_depth(s.depth, W, H)));
        warp_desc wd = {.width = W, .height = H, .depth = s.depth, .view_proj = s.vp, .prev_view_proj = prev,
                        .prev_depth = s.depth, .prev_znear = ZNEAR, .prev_zfar = ZFAR};
        CHECK(warp_previous(&wd, &v, out, valid) == W * H);
        CHECK(warp_previous(&wd, &vf, fout, valid) == W * H);
        long same = 0;
        for (int i = 0; i < W * H; i++)
            same += wr[i] == s.r[i] && wg[i] == s.g[i] && wb[i] == s.b[i] && wc[i] == s.cov[i];
        CHECK(same == W * H);
        ring_metrics te[2];
        CHECK(metrics_temporal(&v, &wv, &vf, &wvf, valid, &m, te) == FS_OK);
        fprintf(stderr, "still camera%s: %ld of %d pixels copied exactly, temporal error %.3g\n",
                ulp ? " (1 ulp off)" : "", same, W * H, te[1].temporal_error);
        CHECK(te[0].temporal_error == 0.0 && te[1].temporal_error == 0.0 && te[1].disoccluded == 0.0);
    }
    ring_mask_free(&m);
}

/* "The camera did not move" (WARP_STILL_TOLERANCE_PX = 1e-3 display pixels at the display's
 * corners, at the nearest surface's depth and at the far plane): ulps of rounding are still, a
 * shift of 1/100 pixel or a real camera step is not, and a sideways step that moves the plane 10 m
 * away by 1/1200 pixel is still only when nothing nearer is in view. */
TEST(still_means_within_a_thousandth_of_a_pixel)
{
    mat4 vp = camera(0.3f);
    CHECK(warp_camera_still(&vp, &vp, W, H, 0.0f));
    mat4 ulp = vp;
    for (int k = 0; k < 16; k++)
        ulp.m[k] = nextafterf(nextafterf(ulp.m[k], -INFINITY), -INFINITY);
    CHECK(warp_camera_still(&ulp, &vp, W, H, 0.0f));
    CHECK(warp_camera_still(&vp, &ulp, W, H, 0.0f));
    /* The whole image shifted by s pixels (a translation in NDC, as TAA's jitter is applied). */
    const float shifts[4] = {1e-4f, 5e-4f, 2e-3f, 1e-2f};
    for (int i = 0; i < 4; i++) {
        mat4 t = m4_mul(m4_translate(v3(2.0f * shifts[i] / W, 0.0f, 0.0f)), vp);
        CHECK(warp_camera_still(&vp, &t, W, H, 0.0f) == (shifts[i] < 1e-3f));
        mat4 u = m4_mul(m4_translate(v3(0.0f, 2.0f * shifts[i] / H, 0.0f)), vp);
        CHECK(warp_camera_still(&vp, &u, W, H, 0.0f) == (shifts[i] < 1e-3f));
    }
    /* 0.1 mm sideways: focal 83.1 px, so 8.3e-4 px at the plane 10 m away, 1.2e-3 px at the square
     * 7 m away, 1.7e-2 px at the near plane (0.5 m). */
    static shot s;
    render(&s, 0.3f);
    float plane = 1.0f; /* the plane's depth: the largest of the frame's (the square is nearer) */
    for (int i = 0; i < W * H; i++)
        plane = s.occ[i] ? plane : fminf(plane, s.depth[i]);
    mat4 step = camera(0.3001f);
    CHECK(warp_camera_still(&vp, &step, W, H, plane));
    CHECK(!warp_camera_still(&vp, &step, W, H, warp_min_depth(s.depth, W, H))); /* the square */
    CHECK(!warp_camera_still(&vp, &step, W, H, 0.0f));
    mat4 moved = camera(0.31f); /* 1 cm sideways */
    CHECK(!warp_camera_still(&vp, &moved, W, H, 1.0f));
    mat4 zero = {{0}};
    CHECK(!warp_camera_still(&vp, &zero, W, H, 0.0f));
    CHECK(warp_camera_still(&zero, &zero, W, H, 0.0f)); /* bit-identical */
    CHECK(warp_min_depth(s.depth, W, H) < plane && warp_min_depth(s.depth, W, H) > 0.0f);
}

/* warp_apply's bilinear sample (clamp and floor without libm calls) gives the values of the plain
 * formula it replaced, bit for bit, at positions inside, on and beyond the edges, and at NaN and
 * infinities. */
static float plain_bilinear(const float *p, int w, int h, float x, float y)
{
    x = fminf(fmaxf(x, 0.0f), (float)(w - 1));
    y = fminf(fmaxf(y, 0.0f), (float)(h - 1));
    int x0 = (int)floorf(x), y0 = (int)floorf(y);
    int x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
    float fx = x - (float)x0, fy = y - (float)y0;
    float a = p[y0 * w + x0];
    if (fx != 0.0f)
        a += fx * (p[y0 * w + x1] - a);
    if (fy == 0.0f)
        return a;
    float b = p[y1 * w + x0];
    if (fx != 0.0f)
        b += fx * (p[y1 * w + x1] - b);
    return a + fy * (b - a);
}

TEST(bilinear_matches_the_plain_formula)
{
    enum { PW = 7, PH = 5, N = PW * PH };
    static float img[4][N], out[4][N], coords[2 * N];
    static unsigned char valid[N];
    for (int c = 0; c < 4; c++)
        for (int i = 0; i < N; i++)
            img[c][i] = (float)((i * 37 + c * 11) % 17) * 0.173f - 0.5f;
    const float pos[] = {0.0f, -0.0f, 0.25f, 1.0f, 2.5f, 5.999f, 6.0f, 6.5f, 40.0f, -0.25f, -3.0f, NAN, INFINITY,
                         -INFINITY, 3.75f, 4.0f, 4.5f, 1e-7f, 3.0000002f};
    const int np = (int)(sizeof pos / sizeof pos[0]);
    metrics_view mv = {PW, PH, img[0], img[1], img[2], img[3]};
    float *const o[4] = {out[0], out[1], out[2], out[3]};
    int bad = 0, tried = 0;
    for (int a = 0; a < np; a++)
        for (int b0 = 0; b0 < np; b0 += N) {
            for (int i = 0; i < N; i++) {
                coords[2 * i] = pos[a];
                coords[2 * i + 1] = pos[(b0 + i) % np];
                valid[i] = 1;
            }
            warp_apply(coords, valid, &mv, o);
            for (int i = 0; i < N; i++)
                for (int c = 0; c < 4; c++) {
                    float want = plain_bilinear(img[c], PW, PH, coords[2 * i], coords[2 * i + 1]);
                    bad += memcmp(&want, &out[c][i], sizeof want) != 0;
                    tried++;
                }
        }
    CHECK(bad == 0);
    CHECK(tried == np * N * 4);
}

int main(void)
{
    RUN(bilinear_matches_the_plain_formula);
    RUN(an_unchanged_frame_scores_exactly_0_under_a_still_camera);
    RUN(still_means_within_a_thousandth_of_a_pixel);
    RUN(warp_is_exact_for_a_static_scene_under_camera_motion);
    RUN(a_still_camera_warps_to_the_previous_frame_itself);
    RUN(a_frozen_image_scores_worse_than_the_method_it_froze);
    return test_summary();
}
