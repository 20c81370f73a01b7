/* Unit tests of the VRS shading-rate map (src/fov/vrs_map.c): the auto map is conservative against
 * the acuity model measured here on its own (every pixel of every tile, random gazes, several
 * displays) and not needlessly fine; rates coarsen outwards; the gaze's tile is full rate; the
 * lowest eccentricity of a rectangle against dense sampling; the explicit map's text form and its
 * refusals; the statistics. */
#include <stdint.h>
#include <string.h>

#include "fov/fov_ring.h"
#include "fov/vrs_map.h"
#include "test.h"

/* >>the test's own model: a pinhole display, angles between view rays, MAR(e) = m e + w0 */

typedef struct tdisp {
    display_desc d;
    double f;
} tdisp;

static tdisp tdisp_make(int w, int h, float hfov)
{
    tdisp t = {{w, h, hfov, 0.0f, 0.0f}, 0.5 * w / tan(0.5 * hfov * FS_PI / 180.0)};
    return t;
}

static double ray_angle(const tdisp *t, double ax, double ay, double bx, double by)
{
    double a[3] = {ax - 0.5 * t->d.width, 0.5 * t->d.height - ay, -t->f};
    double b[3] = {bx - 0.5 * t->d.width, 0.5 * t->d.height - by, -t->f};
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

static double mar_rad(double ecc_rad)
{
    double e_deg = ecc_rad * 180.0 / FS_PI;
    return (FOV_ACUITY_SLOPE_DEFAULT * e_deg + FOV_ACUITY_OMEGA0_DEFAULT) * FS_PI / 180.0;
}

/* Deterministic uniform numbers in [0, 1). */
static double rnd(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* Angular width (height) of the coarse pixel of log2 width k holding pixel (x, y), along the row
 * (column) through the pixel's centre: coarse pixels align to the tile grid, so to multiples of 2^k. */
static double span_x(const tdisp *t, int x, int y, int k)
{
    int x0 = x - x % (1 << k);
    return ray_angle(t, x0, y + 0.5, x0 + (1 << k), y + 0.5);
}

static double span_y(const tdisp *t, int x, int y, int k)
{
    int y0 = y - y % (1 << k);
    return ray_angle(t, x + 0.5, y0, x + 0.5, y0 + (1 << k));
}

/* Pixels of map `rates` whose coarse pixel spans more than the MAR at the pixel's centre along an
 * axis where it is wider than one pixel (the rates made `coarser` steps coarser per axis, capped at
 * 4). sx, sy: span_x, span_y per
 * pixel and log2 width. */
static long violations(const tdisp *t, int tile, const vrs_rate *rates, float gx, float gy, const double *sx,
                       const double *sy, int coarser)
{
    int nx, ny;
    vrs_tile_grid(&t->d, tile, &nx, &ny);
    int W = t->d.width, H = t->d.height;
    long bad = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            vrs_rate r = rates[(y / tile) * nx + x / tile];
            int wl = (r >> 2) + coarser, hl = (r & 3) + coarser;
            wl = wl > 2 ? 2 : wl, hl = hl > 2 ? 2 : hl;
            double mar = mar_rad(ray_angle(t, gx, gy, x + 0.5, y + 0.5)) * (1.0 + 1e-9);
            size_t i = (size_t)y * W + x;
            /* One pixel along an axis is the display's own pitch, not the map's choice. */
            bad += (wl > 0 && sx[i * 3 + wl] > mar) || (hl > 0 && sy[i * 3 + hl] > mar);
        }
    return bad;
}

TEST(auto_map_is_conservative_for_random_gazes)
{
    const struct { int w, h, tile; float hfov; } cases[] = {
        {160, 90, 16, 90.0f}, {97, 61, 8, 60.0f}, {128, 128, 32, 110.0f}, {120, 72, 16, 30.0f}};
    uint64_t seed = 33;
    int coarse_tiles = 0;
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        tdisp t = tdisp_make(cases[c].w, cases[c].h, cases[c].hfov);
        int W = cases[c].w, H = cases[c].h, nx, ny;
        vrs_tile_grid(&t.d, cases[c].tile, &nx, &ny);
        double *sx = malloc(sizeof(double) * 3 * W * H), *sy = malloc(sizeof(double) * 3 * W * H);
        vrs_rate *rates = malloc((size_t)nx * ny);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                for (int k = 0; k < 3; k++)
                    sx[((size_t)y * W + x) * 3 + k] = span_x(&t, x, y, k), sy[((size_t)y * W + x) * 3 + k] = span_y(&t, x, y, k);
        long bad = 0, coarser_bad_gazes = 0;
        const vrs_spec autos = {.is_auto = true};
        for (int g = 0; g < 1000; g++) {
            float gx = (float)(rnd(&seed) * W), gy = (float)(rnd(&seed) * H);
            if (g < 4) /* the corners: the farthest any tile gets from the gaze */
                gx = (float)(g & 1 ? W : 0), gy = (float)(g & 2 ? H : 0);
            vrs_map_fill(&t.d, &autos, cases[c].tile, gx, gy, rates);
            long v = violations(&t, cases[c].tile, rates, gx, gy, sx, sy, 0);
            if (v && !bad)
                fprintf(stderr, "  %dx%d@%g gaze (%g, %g): %ld pixels beyond acuity\n", W, H, (double)cases[c].hfov,
                        (double)gx, (double)gy, v);
            bad += v;
            /* The check itself can fail: one step coarser everywhere exceeds acuity somewhere. */
            coarser_bad_gazes += violations(&t, cases[c].tile, rates, gx, gy, sx, sy, 1) > 0;
            for (int i = 0; i < nx * ny; i++)
                coarse_tiles += rates[i] != VRS_1X1;
        }
        CHECK(bad == 0);
        CHECK(coarser_bad_gazes == 1000);
        free(sx), free(sy), free(rates);
    }
    CHECK(coarse_tiles > 0); /* not the trivially conservative all-1x1 map */
}

/* Not needlessly fine: where a tile's rate could double along an axis, doubling exceeds the MAR at
 * the tile's lowest eccentricity by the test's own measure, but for the bound's slack (the largest
 * pixel angle of the tile against the one at its nearest point: at most a few percent here). */
TEST(auto_map_is_tight)
{
    tdisp t = tdisp_make(1280, 720, 90.0f);
    const int tile = 16;
    int nx, ny, loose = 0, candidates = 0;
    vrs_tile_grid(&t.d, tile, &nx, &ny);
    uint64_t seed = 7;
    for (int g = 0; g < 20; g++) {
        float gx = (float)(rnd(&seed) * 1280), gy = (float)(rnd(&seed) * 720);
        for (int ty = 0; ty < ny; ty++)
            for (int tx = 0; tx < nx; tx++) {
                int x0 = tx * tile, y0 = ty * tile;
                vrs_rate r = vrs_tile_rate_auto(&t.d, tile, gx, gy, x0, y0, 0.0f, 0.0f);
                int wl = r >> 2, hl = r & 3;
                double mar = mar_rad(vrs_rect_min_ecc_deg(&t.d, gx, gy, x0, y0, x0 + tile, y0 + tile) * FS_PI / 180.0);
                /* The widest span of twice the width in the tile: at its row nearest the principal point. */
                double wide = 0.0, tall = 0.0;
                for (int y = y0; y < y0 + tile; y++)
                    for (int x = x0; x + (2 << wl) <= x0 + tile; x += 2 << wl)
                        wide = fmax(wide, ray_angle(&t, x, y + 0.5, x + (2 << wl), y + 0.5));
                for (int x = x0; x < x0 + tile; x++)
                    for (int y = y0; y + (2 << hl) <= y0 + tile; y += 2 << hl)
                        tall = fmax(tall, ray_angle(&t, x + 0.5, y, x + 0.5, y + (2 << hl)));
                /* Only where doubling one axis keeps a rate that exists (no 1x4, 4x1). */
                if (wl < 2 && wl + 1 <= hl + 1)
                    candidates++, loose += wide <= mar * 0.97;
                if (hl < 2 && hl + 1 <= wl + 1)
                    candidates++, loose += tall <= mar * 0.97;
            }
    }
    fprintf(stderr, "  %d of %d tile axes could double within 97 %% of the MAR\n", loose, candidates);
    CHECK(candidates > 0);
    CHECK(loose == 0);
}

TEST(gaze_tile_is_full_rate)
{
    const float fovs[] = {60.0f, 90.0f, 110.0f};
    const vrs_spec autos = {.is_auto = true};
    uint64_t seed = 1;
    for (int i = 0; i < 3; i++) {
        display_desc d = {1280, 720, fovs[i], 0.0f, 0.0f};
        int nx, ny;
        vrs_tile_grid(&d, 16, &nx, &ny);
        vrs_rate *rates = malloc((size_t)nx * ny);
        for (int g = 0; g < 200; g++) {
            float gx = (float)(rnd(&seed) * 1279.0), gy = (float)(rnd(&seed) * 719.0);
            vrs_map_fill(&d, &autos, 16, gx, gy, rates);
            CHECK(rates[(int)(gy / 16) * nx + (int)(gx / 16)] == VRS_1X1);
        }
        free(rates);
    }
}

/* Rates coarsen outwards: stepping one tile along a row or column to a tile whose lowest
 * eccentricity is higher and which lies no nearer the principal point (where pixels subtend most),
 * the rate never gets finer along either axis; for the centred gaze that is every step away from
 * the gaze's tile. (Elsewhere a step may get one rate finer: towards the display centre pixels
 * subtend more, faster than the MAR grows; counted, documented in docs/foveation.md.) */
static bool no_nearer_centre(int a, int b, int tile, double half)
{
    double da = fabs(a * tile + 0.5 * tile - half), db = fabs(b * tile + 0.5 * tile - half);
    return db >= da;
}

TEST(rates_coarsen_outwards)
{
    const vrs_spec autos = {.is_auto = true};
    display_desc d = {1280, 720, 90.0f, 0.0f, 0.0f};
    int nx, ny;
    vrs_tile_grid(&d, 16, &nx, &ny);
    vrs_rate *rates = malloc((size_t)nx * ny);
    uint64_t seed = 5;
    int finer = 0, steps = 0, other_finer = 0, other = 0;
    for (int g = 0; g < 200; g++) {
        float gx = g ? (float)(rnd(&seed) * 1280) : 640.0f, gy = g ? (float)(rnd(&seed) * 720) : 360.0f;
        vrs_map_fill(&d, &autos, 16, gx, gy, rates);
        for (int ty = 0; ty < ny; ty++)
            for (int tx = 0; tx < nx; tx++)
                for (int k = 0; k < 4; k++) {
                    int ox = tx + (k == 0) - (k == 1), oy = ty + (k == 2) - (k == 3);
                    if (ox < 0 || ox >= nx || oy < 0 || oy >= ny)
                        continue;
                    double e = vrs_rect_min_ecc_deg(&d, gx, gy, tx * 16, ty * 16, tx * 16 + 16, ty * 16 + 16);
                    double eo = vrs_rect_min_ecc_deg(&d, gx, gy, ox * 16, oy * 16, ox * 16 + 16, oy * 16 + 16);
                    vrs_rate r = rates[ty * nx + tx], o = rates[oy * nx + ox];
                    bool f = vrs_rate_width(o) < vrs_rate_width(r) || vrs_rate_height(o) < vrs_rate_height(r);
                    if (!(eo > e))
                        continue;
                    if (no_nearer_centre(tx, ox, 16, 640.0) && no_nearer_centre(ty, oy, 16, 360.0))
                        steps++, finer += f;
                    else
                        other++, other_finer += f;
                }
    }
    fprintf(stderr, "  %d of %d outward steps away from the centre finer; %d of %d other outward steps\n", finer,
            steps, other_finer, other);
    CHECK(steps > 0);
    CHECK(finer == 0);
    free(rates);
}

/* Gaze at the centre of 1280x720 at 90 degrees: 1x1 at the centre, 4x4 in the corners, and the
 * anisotropic rates where one axis allows twice the other (pixels span less along the direction
 * away from the principal point). */
TEST(centre_map_has_every_kind_of_rate)
{
    const vrs_spec autos = {.is_auto = true};
    display_desc d = {1280, 720, 90.0f, 0.0f, 0.0f};
    int nx, ny;
    vrs_tile_grid(&d, 16, &nx, &ny);
    CHECK(nx == 80 && ny == 45);
    vrs_rate rates[80 * 45];
    vrs_map_fill(&d, &autos, 16, 640.0f, 360.0f, rates);
    CHECK(rates[22 * 80 + 40] == VRS_1X1);
    CHECK(rates[0] == VRS_4X4 && rates[80 * 45 - 1] == VRS_4X4);
    int seen[VRS_RATE_COUNT] = {0};
    for (int i = 0; i < 80 * 45; i++) {
        CHECK(vrs_rate_index(rates[i]) >= 0);
        seen[vrs_rate_index(rates[i]) >= 0 ? vrs_rate_index(rates[i]) : 0]++;
    }
    for (int i = 0; i < VRS_RATE_COUNT; i++)
        fprintf(stderr, "  %s: %d tiles\n", vrs_rate_name(k_vrs_rates[i]), seen[i]);
    CHECK(seen[vrs_rate_index(VRS_2X1)] + seen[vrs_rate_index(VRS_4X2)] > 0); /* left and right */
    /* Left-right symmetric about the centre column (the gaze is on it). */
    for (int ty = 0; ty < 45; ty++)
        for (int tx = 0; tx < 40; tx++)
            CHECK(rates[ty * 80 + tx] == rates[ty * 80 + 79 - tx]);
}

TEST(rect_min_eccentricity_matches_sampling)
{
    tdisp t = tdisp_make(640, 360, 100.0f);
    uint64_t seed = 9;
    for (int k = 0; k < 300; k++) {
        float gx = (float)(rnd(&seed) * 640), gy = (float)(rnd(&seed) * 360);
        double x0 = floor(rnd(&seed) * 600), y0 = floor(rnd(&seed) * 330);
        double x1 = x0 + 1 + floor(rnd(&seed) * 40), y1 = y0 + 1 + floor(rnd(&seed) * 30);
        double e = vrs_rect_min_ecc_deg(&t.d, gx, gy, x0, y0, x1, y1);
        double best = INFINITY;
        const int n = 200;
        for (int i = 0; i <= n; i++)
            for (int j = 0; j <= n; j++)
                best = fmin(best, ray_angle(&t, gx, gy, x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / n));
        best *= 180.0 / FS_PI;
        CHECK(e <= best + 1e-9);  /* never above a point of the rectangle */
        CHECK(e >= best - 0.01);  /* and as low as the sampling finds (step <= 0.2 px) */
    }
    CHECK(vrs_rect_min_ecc_deg(&t.d, 100.0f, 100.0f, 96, 96, 112, 112) == 0.0);
}

/* >>the explicit map */

TEST(explicit_map_parses_and_formats)
{
    vrs_spec s;
    char err[256], buf[256];
    CHECK(vrs_spec_parse("10:1x1,25:2x2,*:4x4", &s, err, sizeof err) == FS_OK);
    CHECK(!s.is_auto && s.count == 3 && s.rate[0] == VRS_1X1 && s.rate[1] == VRS_2X2 && s.rate[2] == VRS_4X4);
    CHECK(s.outer_deg[0] == 10.0f && s.outer_deg[1] == 25.0f && isinf(s.outer_deg[2]));
    vrs_spec_format(&s, buf, sizeof buf);
    CHECK(!strcmp(buf, "10:1x1,25:2x2,*:4x4"));
    CHECK(vrs_spec_parse(" 7.5 : 1x1 , 12:2x1, 20:4x2 ,* : 4x4 ", &s, err, sizeof err) == FS_OK);
    vrs_spec_format(&s, buf, sizeof buf);
    CHECK(!strcmp(buf, "7.5:1x1,12:2x1,20:4x2,*:4x4"));
    CHECK(vrs_spec_parse("*:2x2", &s, err, sizeof err) == FS_OK && s.count == 1);
    CHECK(vrs_spec_parse("auto", &s, err, sizeof err) == FS_OK && s.is_auto);
    vrs_spec_format(&s, buf, sizeof buf);
    CHECK(!strcmp(buf, "auto"));
}

static void check_refused(const char *text, const char *want1, const char *want2)
{
    vrs_spec s = {.is_auto = true, .count = 42};
    char err[256] = "";
    fs_status st = vrs_spec_parse(text, &s, err, sizeof err);
    if (st == FS_OK || !strstr(err, want1) || !strstr(err, want2) || strchr(err, '\n'))
        fprintf(stderr, "  '%s' -> status %d, '%s'\n", text, (int)st, err);
    CHECK(st == FS_ERR_USAGE);
    CHECK(strstr(err, want1) && strstr(err, want2));
    CHECK(!strchr(err, '\n'));
    CHECK(s.is_auto && s.count == 42); /* untouched */
}

TEST(explicit_map_refusals_name_the_band)
{
    check_refused("10:3x3,*:4x4", "band 1", "'3x3'");
    check_refused("10:1x1,*:1x4", "band 2", "'1x4'");
    check_refused("25:1x1,10:2x2,*:4x4", "band 2", "not beyond");
    check_refused("10:1x1,10:2x2,*:4x4", "band 2", "not beyond");
    check_refused("10:1x1,25:2x2", "band 2", "'*'");
    check_refused("*:1x1,10:2x2", "band 1", "last");
    check_refused("10:2x2,*:1x1", "band 2", "finer");
    check_refused("10:2x1,*:1x2", "band 2", "finer");
    check_refused("10:1x1,,*:2x2", "band 2", "OUTER:RATE");
    check_refused("-5:1x1,*:2x2", "band 1", "'-5'");
    check_refused("10:1x1:0,*:2x2", "band 1", "OUTER:RATE");
    check_refused("", "expected auto", "''");
    check_refused("automatic", "expected auto", "'automatic'");
    check_refused("1:1x1,2:1x1,3:1x1,4:1x1,5:1x1,6:1x1,7:1x1,8:1x1,*:1x1", "more than", "8");
}

TEST(explicit_map_follows_the_bands)
{
    tdisp t = tdisp_make(640, 360, 90.0f);
    vrs_spec s;
    CHECK(vrs_spec_parse("8:1x1,20:2x1,*:4x4", &s, NULL, 0) == FS_OK);
    int nx, ny;
    vrs_tile_grid(&t.d, 16, &nx, &ny);
    vrs_rate rates[40 * 23];
    CHECK(nx * ny <= 40 * 23);
    vrs_map_fill(&t.d, &s, 16, 200.0f, 150.0f, rates);
    int seen[3] = {0};
    for (int ty = 0; ty < ny; ty++)
        for (int tx = 0; tx < nx; tx++) {
            /* The tile's lowest eccentricity by sampling its pixels' corners. */
            double e = INFINITY;
            for (int y = ty * 16; y <= ty * 16 + 16 && y <= 360; y++)
                for (int x = tx * 16; x <= tx * 16 + 16 && x <= 640; x++)
                    e = fmin(e, ray_angle(&t, 200.0, 150.0, x, y) * 180.0 / FS_PI);
            if (fabs(e - 8.0) < 0.05 || fabs(e - 20.0) < 0.05)
                continue; /* too close to a border for the sampling to decide */
            vrs_rate want = e < 8.0 ? VRS_1X1 : e < 20.0 ? VRS_2X1 : VRS_4X4;
            CHECK(rates[ty * nx + tx] == want);
            seen[e < 8.0 ? 0 : e < 20.0 ? 1 : 2]++;
        }
    CHECK(seen[0] > 0 && seen[1] > 0 && seen[2] > 0);
}

/* >>statistics */

TEST(statistics)
{
    display_desc d = {97, 61, 90.0f, 0.0f, 0.0f}; /* partial tiles at the right and bottom */
    int nx, ny;
    vrs_tile_grid(&d, 16, &nx, &ny);
    CHECK(nx == 7 && ny == 4);
    vrs_rate rates[28];
    memset(rates, VRS_1X1, sizeof rates);
    vrs_stats st = vrs_map_stats(&d, 16, rates);
    CHECK(st.pixels[0] == 97 * 61 && st.share[0] == 1.0 && st.saving == 0.0);
    memset(rates, VRS_4X4, sizeof rates);
    st = vrs_map_stats(&d, 16, rates);
    CHECK_NEAR(st.saving, 15.0 / 16.0, 1e-12);
    CHECK(st.pixels[vrs_rate_index(VRS_4X4)] == 97 * 61);

    /* A 32x16 display of two tiles, 1x1 and 2x4: 256 + 256 / 8 of 512 pixels shaded. */
    display_desc two = {32, 16, 90.0f, 0.0f, 0.0f};
    vrs_rate r2[2] = {VRS_1X1, VRS_2X4};
    st = vrs_map_stats(&two, 16, r2);
    CHECK_NEAR(st.shaded, 288.0, 1e-12);
    CHECK_NEAR(st.saving, 1.0 - 288.0 / 512.0, 1e-12);
    CHECK(st.share[0] == 0.5 && st.share[vrs_rate_index(VRS_2X4)] == 0.5);

    /* An auto map's shares sum to 1 and its pixels to the display's. */
    display_desc big = {1280, 720, 90.0f, 0.0f, 0.0f};
    vrs_rate *m = malloc(80 * 45);
    const vrs_spec autos = {.is_auto = true};
    vrs_map_fill(&big, &autos, 16, 300.0f, 500.0f, m);
    st = vrs_map_stats(&big, 16, m);
    double sum = 0.0;
    long long px = 0;
    for (int i = 0; i < VRS_RATE_COUNT; i++)
        sum += st.share[i], px += st.pixels[i];
    CHECK_NEAR(sum, 1.0, 1e-12);
    CHECK(px == 1280 * 720);
    CHECK(st.saving > 0.0 && st.saving < 15.0 / 16.0);
    free(m);
}

TEST(rates_and_names)
{
    for (int i = 0; i < VRS_RATE_COUNT; i++) {
        vrs_rate r = k_vrs_rates[i], back = 0xff;
        CHECK(vrs_rate_parse(vrs_rate_name(r), &back) && back == r);
        char want[8];
        snprintf(want, sizeof want, "%dx%d", vrs_rate_width(r), vrs_rate_height(r));
        CHECK(!strcmp(vrs_rate_name(r), want));
        CHECK(i == 0 || vrs_rate_width(r) * vrs_rate_height(r) >= vrs_rate_width(k_vrs_rates[i - 1]) *
                                                                   vrs_rate_height(k_vrs_rates[i - 1]));
    }
    vrs_rate r;
    CHECK(!vrs_rate_parse("3x3", &r) && !vrs_rate_parse("1x4", &r) && !vrs_rate_parse("", &r));
    CHECK(VRS_2X4 == 6 && VRS_4X2 == 9 && VRS_4X4 == 10); /* D3D12's codes */
    foveation_kind k;
    CHECK(foveation_kind_parse("vrs", &k) && k == FOVEATION_VRS);
    CHECK(foveation_kind_parse("off", &k) && k == FOVEATION_OFF);
    CHECK(!foveation_kind_parse("VRS", &k) && !foveation_kind_parse("ring", &k));
    CHECK(vrs_tile_valid(8) && vrs_tile_valid(16) && vrs_tile_valid(32) && !vrs_tile_valid(4) && !vrs_tile_valid(64));
}

int main(void)
{
    RUN(auto_map_is_conservative_for_random_gazes);
    RUN(auto_map_is_tight);
    RUN(gaze_tile_is_full_rate);
    RUN(rates_coarsen_outwards);
    RUN(centre_map_has_every_kind_of_rate);
    RUN(rect_min_eccentricity_matches_sampling);
    RUN(explicit_map_parses_and_formats);
    RUN(explicit_map_refusals_name_the_band);
    RUN(explicit_map_follows_the_bands);
    RUN(statistics);
    RUN(rates_and_names);
    return test_summary();
}
