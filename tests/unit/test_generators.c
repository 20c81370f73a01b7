/* test_generators.c: procedural foliage assets (src/scene/generators.c): geometry sanity,
 * determinism, alpha-mapped texture statistics (transparent share, thin features, soft edges,
 * padding, dilated colour), desc validation and bounds. */
#include <stdint.h>

#include "core/log.h"
#include "scene/generators.h"
#include "test.h"

/* >>helpers */

typedef struct tex_stats {
    double transparent; /* share of texels with alpha byte 0 */
    double partial;     /* share with 0 < alpha < 255 */
    double mean_alpha;
    long black_hidden;  /* transparent texels whose colour is pure black */
    int max_run;        /* longest horizontal run of texels with alpha >= 128 */
    double short_runs;  /* share of those runs no longer than 5 texels */
} tex_stats;

static tex_stats image_stats(const image_rgba8 *im)
{
    tex_stats s = {0};
    size_t n = (size_t)im->width * im->height, zero = 0, part = 0;
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        const uint8_t *p = &im->rgba[4 * i];
        zero += p[3] == 0;
        part += p[3] > 0 && p[3] < 255;
        sum += p[3] / 255.0;
        if (p[3] == 0 && p[0] == 0 && p[1] == 0 && p[2] == 0)
            s.black_hidden++;
    }
    long runs = 0, short_runs = 0;
    for (int y = 0; y < im->height; y++) {
        int run = 0;
        for (int x = 0; x <= im->width; x++) {
            bool on = x < im->width && im->rgba[4 * ((size_t)y * im->width + x) + 3] >= 128;
            if (on) {
                run++;
            } else if (run > 0) {
                runs++;
                short_runs += run <= 5;
                if (run > s.max_run)
                    s.max_run = run;
                run = 0;
            }
        }
    }
    s.transparent = (double)zero / (double)n;
    s.partial = (double)part / (double)n;
    s.mean_alpha = sum / (double)n;
    s.short_runs = runs ? (double)short_runs / (double)runs : 0.0;
    return s;
}

/* Alpha of every texel on the border rows/columns named by the mask (1 top, 2 bottom, 4 left,
 * 8 right) is 0. */
static bool border_transparent(const image_rgba8 *im, int mask)
{
    for (int y = 0; y < im->height; y++)
        for (int x = 0; x < im->width; x++) {
            bool edge = ((mask & 1) && y == 0) || ((mask & 2) && y == im->height - 1) ||
                        ((mask & 4) && x == 0) || ((mask & 8) && x == im->width - 1);
            if (edge && im->rgba[4 * ((size_t)y * im->width + x) + 3] != 0)
                return false;
        }
    return true;
}

/* Everything every generated asset must satisfy. */
static void check_asset(const asset *a, const char *name)
{
    CHECK(strcmp(a->name, name) == 0);
    CHECK(a->source == ASSET_SOURCE_GENERATOR);
    CHECK(a->prim_count >= 1);
    for (int i = 0; i < a->prim_count; i++) {
        const prim *p = &a->prims[i];
        CHECK(p->vertex_count > 0);
        CHECK(p->index_count > 0 && p->index_count % 3 == 0);
        CHECK(p->positions && p->normals && p->uvs && p->colors && p->indices);
        CHECK(p->material >= 0 && p->material < a->material_count);
        bool idx_ok = true, pos_ok = true, nrm_ok = true, uv_ok = true, col_ok = true;
        for (uint32_t k = 0; k < p->index_count; k++)
            idx_ok = idx_ok && p->indices[k] < p->vertex_count;
        for (uint32_t v = 0; v < p->vertex_count; v++) {
            const float *q = &p->positions[3 * v], *n = &p->normals[3 * v];
            pos_ok = pos_ok && isfinite(q[0]) && isfinite(q[1]) && isfinite(q[2]);
            float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            nrm_ok = nrm_ok && fabsf(len - 1.0f) < 1e-4f;
            uv_ok = uv_ok && isfinite(p->uvs[2 * v]) && isfinite(p->uvs[2 * v + 1]);
            for (int c = 0; c < 4; c++)
                col_ok = col_ok && p->colors[4 * v + c] == 1.0f;
        }
        CHECK(idx_ok);
        CHECK(pos_ok);
        CHECK(nrm_ok);
        CHECK(uv_ok);
        CHECK(col_ok);
        /* No degenerate triangles. */
        bool area_ok = true;
        for (uint32_t t = 0; t + 2 < p->index_count && idx_ok; t += 3) {
            const float *A = &p->positions[3 * p->indices[t]], *B = &p->positions[3 * p->indices[t + 1]],
                        *C = &p->positions[3 * p->indices[t + 2]];
            float ux = B[0] - A[0], uy = B[1] - A[1], uz = B[2] - A[2];
            float vx = C[0] - A[0], vy = C[1] - A[1], vz = C[2] - A[2];
            float cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
            area_ok = area_ok && cx * cx + cy * cy + cz * cz > 0.0f;
        }
        CHECK(area_ok);
    }
    for (int m = 0; m < a->material_count; m++) {
        const material *mt = &a->materials[m];
        CHECK(mt->name[0] != '\0');
        CHECK(mt->base_color_image >= -1 && mt->base_color_image < a->image_count);
        if (mt->alpha_kind == ALPHA_KIND_MASK) {
            CHECK(mt->double_sided);
            CHECK(mt->base_color_image >= 0);
            CHECK(mt->alpha_cutoff > 0.0f && mt->alpha_cutoff <= 1.0f);
        }
    }
    for (int i = 0; i < a->image_count; i++) {
        CHECK(a->images[i].rgba != NULL);
        CHECK(a->images[i].width >= 1 && a->images[i].height >= 1);
        CHECK(a->images[i].name[0] != '\0');
    }
    CHECK(a->bounds_min.x <= a->bounds_max.x && a->bounds_min.y <= a->bounds_max.y &&
          a->bounds_min.z <= a->bounds_max.z);
}

static const material *find_material(const asset *a, const char *name)
{
    for (int m = 0; m < a->material_count; m++)
        if (strcmp(a->materials[m].name, name) == 0)
            return &a->materials[m];
    return NULL;
}

/* The image of the one MASK material (the foliage texture). */
static const image_rgba8 *foliage_image(const asset *a)
{
    for (int m = 0; m < a->material_count; m++)
        if (a->materials[m].alpha_kind == ALPHA_KIND_MASK && a->materials[m].base_color_image >= 0)
            return &a->images[a->materials[m].base_color_image];
    return NULL;
}

static bool same_asset(const asset *a, const asset *b)
{
    if (a->prim_count != b->prim_count || a->image_count != b->image_count)
        return false;
    for (int i = 0; i < a->prim_count; i++) {
        const prim *p = &a->prims[i], *q = &b->prims[i];
        if (p->vertex_count != q->vertex_count || p->index_count != q->index_count ||
            memcmp(p->positions, q->positions, sizeof(float) * 3 * p->vertex_count) != 0 ||
            memcmp(p->uvs, q->uvs, sizeof(float) * 2 * p->vertex_count) != 0 ||
            memcmp(p->indices, q->indices, sizeof(uint32_t) * p->index_count) != 0)
            return false;
    }
    for (int i = 0; i < a->image_count; i++) {
        const image_rgba8 *x = &a->images[i], *y = &b->images[i];
        if (x->width != y->width || x->height != y->height ||
            memcmp(x->rgba, y->rgba, (size_t)x->width * x->height * 4) != 0)
            return false;
    }
    return true;
}

static bool same_image(const image_rgba8 *x, const image_rgba8 *y)
{
    return x->width == y->width && x->height == y->height &&
           memcmp(x->rgba, y->rgba, (size_t)x->width * x->height * 4) == 0;
}

static void print_stats(const char *what, const tex_stats *s)
{
    printf("%-22s transparent %.4f  partial %.4f  mean alpha %.4f  max run %d  short runs %.2f\n", what,
           s->transparent, s->partial, s->mean_alpha, s->max_run, s->short_runs);
}

/* >>tree */

TEST(tree_defaults)
{
    asset a;
    CHECK(gen_tree(NULL, &a) == FS_OK);
    check_asset(&a, "tree");
    gen_tree_desc d = gen_tree_defaults(NULL);
    CHECK(d.seed == 1 && d.height == 6.0f && d.crown_radius == 2.0f && d.card_count == 60 &&
          d.card_size == 1.2f && d.texture_size == 256 && d.alpha_cutoff == 0.5f);
    const material *leaves = find_material(&a, "leaves"), *bark = find_material(&a, "bark");
    CHECK(leaves && bark);
    if (leaves && bark) {
        CHECK(leaves->alpha_kind == ALPHA_KIND_MASK && leaves->alpha_cutoff == 0.5f);
        CHECK(bark->alpha_kind == ALPHA_KIND_OPAQUE);
    }
    const image_rgba8 *im = foliage_image(&a);
    CHECK(im && im->width == 256 && im->height == 256);
    /* Crown of 60 clusters of 2-3 crossed cards. */
    CHECK(a.prims[0].vertex_count >= 60 * 2 * 4 && a.prims[0].vertex_count <= 60 * 3 * 4);
    /* Height within 20 % of the desc, standing on the ground, crown about 2 m around the trunk. */
    float h = a.bounds_max.y - a.bounds_min.y;
    CHECK(fabsf(h - 6.0f) <= 0.2f * 6.0f);
    CHECK(fabsf(a.bounds_min.y) < 1e-6f);
    CHECK(a.bounds_max.x <= 2.0f + 1.2f && a.bounds_min.x >= -2.0f - 1.2f);
    CHECK(a.bounds_max.x > 1.0f && a.bounds_min.x < -1.0f);
    if (im) {
        tex_stats s = image_stats(im);
        print_stats("tree leaves 256", &s);
        CHECK(s.transparent >= 0.55 && s.transparent <= 0.70);
        CHECK(s.partial > 0.005);        /* soft edges */
        CHECK(s.black_hidden == 0);      /* transparent texels carry a dilated colour */
        CHECK(border_transparent(im, 15)); /* padding all around */
        CHECK(s.short_runs > 0.1);         /* 1-3 texel stems and twigs between the leaves */
    }
    asset_free(&a);
    CHECK(a.prims == NULL && a.prim_count == 0);
}

TEST(tree_custom_desc)
{
    asset a;
    gen_tree_desc d = {.seed = 7, .height = 12.0f, .crown_radius = 3.0f, .card_count = 200,
                       .card_size = 0.8f, .texture_size = 128, .alpha_cutoff = 0.3f};
    CHECK(gen_tree(&d, &a) == FS_OK);
    check_asset(&a, "tree");
    float h = a.bounds_max.y - a.bounds_min.y;
    CHECK(fabsf(h - 12.0f) <= 0.2f * 12.0f);
    CHECK(a.prims[0].vertex_count >= 200 * 8 && a.prims[0].vertex_count <= 200 * 12);
    CHECK(find_material(&a, "leaves") && find_material(&a, "leaves")->alpha_cutoff == 0.3f);
    CHECK(foliage_image(&a) && foliage_image(&a)->width == 128);
    asset_free(&a);
    /* A wide crown on a short tree still stands on the ground. */
    CHECK(gen_tree(&(gen_tree_desc){.height = 2.0f, .crown_radius = 5.0f}, &a) == FS_OK);
    CHECK(a.bounds_min.y >= -1e-6f);
    CHECK(a.bounds_max.y - a.bounds_min.y <= 1.2f * 2.0f + 1.2f);
    asset_free(&a);
}

/* >>grass */

TEST(grass_defaults)
{
    asset a;
    CHECK(gen_grass(&(gen_grass_desc){0}, &a) == FS_OK);
    check_asset(&a, "grass");
    const material *blades = find_material(&a, "blades"), *ground = find_material(&a, "ground");
    CHECK(blades && ground);
    if (blades && ground) {
        CHECK(blades->alpha_kind == ALPHA_KIND_MASK);
        CHECK(ground->alpha_kind == ALPHA_KIND_OPAQUE);
    }
    /* 400 tufts of 2 crossed quads, plus a ground quad facing up at y = 0. */
    CHECK(a.prim_count == 2);
    CHECK(a.prims[0].vertex_count == 400 * 2 * 4);
    const prim *g = &a.prims[1];
    CHECK(g->vertex_count == 4);
    for (uint32_t v = 0; v < g->vertex_count; v++) {
        CHECK(g->positions[3 * v + 1] == 0.0f);
        CHECK(g->normals[3 * v + 1] > 0.99f);
    }
    CHECK_NEAR(a.bounds_min.x, -5.0, 1e-5);
    CHECK_NEAR(a.bounds_max.x, 5.0, 1e-5);
    CHECK_NEAR(a.bounds_min.z, -5.0, 1e-5);
    CHECK_NEAR(a.bounds_max.z, 5.0, 1e-5);
    CHECK(a.bounds_min.y == 0.0f);
    CHECK(a.bounds_max.y > 0.5f && a.bounds_max.y <= 0.5f * 1.3f + 1e-5f);
    const image_rgba8 *im = foliage_image(&a);
    CHECK(im && im->width == 128);
    if (im) {
        tex_stats s = image_stats(im);
        print_stats("grass blades 128", &s);
        CHECK(s.transparent >= 0.60 && s.transparent <= 0.75);
        CHECK(s.partial > 0.01);
        CHECK(s.black_hidden == 0);
        CHECK(border_transparent(im, 1 | 4 | 8)); /* blades rise from the bottom edge */
        /* Blades are thin: in the upper half (above the dense base) nearly all opaque runs
         * are 1-5 texels. */
        image_rgba8 top = *im;
        top.height = im->height / 2;
        tex_stats t = image_stats(&top);
        CHECK(t.short_runs > 0.9);
    }
    asset_free(&a);
}

/* >>fence */

TEST(fence_defaults)
{
    asset a;
    CHECK(gen_fence(NULL, &a) == FS_OK);
    check_asset(&a, "fence");
    const material *wire = find_material(&a, "wire"), *posts = find_material(&a, "posts");
    CHECK(wire && posts);
    if (wire && posts) {
        CHECK(wire->alpha_kind == ALPHA_KIND_MASK);
        CHECK(wire->wrap_s == TEX_WRAP_REPEAT && wire->wrap_t == TEX_WRAP_REPEAT);
        CHECK(posts->alpha_kind == ALPHA_KIND_OPAQUE);
    }
    /* The wire mesh is one quad in z = 0 whose UVs repeat the cell 100 x 20 times. */
    const prim *w = &a.prims[0];
    CHECK(w->vertex_count == 4 && w->index_count == 6);
    float umax = 0.0f, vmax = 0.0f;
    for (uint32_t v = 0; v < w->vertex_count; v++) {
        CHECK(w->positions[3 * v + 2] == 0.0f);
        umax = fmaxf(umax, w->uvs[2 * v]);
        vmax = fmaxf(vmax, w->uvs[2 * v + 1]);
    }
    CHECK_NEAR(umax, 10.0 / 0.1, 1e-3);
    CHECK_NEAR(vmax, 2.0 / 0.1, 1e-3);
    /* Posts every 2.5 m (5 for 10 m) plus the top rail, 24 vertices per box. */
    CHECK(a.prims[1].vertex_count == (5 + 1) * 24);
    CHECK_NEAR(a.bounds_min.x, 0.0, 1e-6);
    CHECK_NEAR(a.bounds_max.x, 10.0, 1e-5);
    CHECK(a.bounds_min.y == 0.0f && a.bounds_max.y >= 2.0f && a.bounds_max.y <= 2.1f);
    CHECK(a.bounds_min.z >= -0.05f && a.bounds_max.z <= 0.05f);

    const image_rgba8 *im = foliage_image(&a);
    CHECK(im && im->width == 64 && im->height == 64);
    if (im) {
        tex_stats s = image_stats(im);
        print_stats("fence wire 64 w3", &s);
        CHECK(s.transparent >= 0.50 && s.transparent <= 0.85);
        CHECK(s.mean_alpha < 0.25); /* well below the cutoff: erodes at distance */
        CHECK(s.partial > 0.01);
        CHECK(s.black_hidden == 0);
        /* Two 3-texel wires: a horizontal run is at most one wire's width (3 sqrt 2) plus the
         * rounding, or two merged wires near a crossing. */
        CHECK(s.max_run <= (int)(2.0 * 3.0 * sqrt(2.0) + 2.0));
        int n = im->width, bad = 0;
        for (int y = 0; y < n; y++) {
            /* Rows away from the crossings (y = 0 and y = n/2) see single wires only. */
            float yc = (float)y + 0.5f;
            float dy = fminf(fabsf(yc - 0.5f * (float)n), fminf(yc, (float)n - yc));
            if (dy < 6.0f)
                continue;
            image_rgba8 row = {.width = n, .height = 1, .rgba = im->rgba + (size_t)y * n * 4};
            tex_stats rs = image_stats(&row);
            bad += rs.max_run > (int)(5.0 * sqrt(2.0) + 2.0) || rs.max_run < 3;
        }
        CHECK(bad == 0);
        /* The tile wraps seamlessly: opposite edges match texel for texel (the pattern is
         * symmetric about the tile's centre lines). */
        bool seam = true;
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++) {
                uint8_t a0 = im->rgba[4 * ((size_t)y * n + x) + 3];
                uint8_t a1 = im->rgba[4 * ((size_t)y * n + (n - 1 - x)) + 3];
                uint8_t a2 = im->rgba[4 * ((size_t)(n - 1 - y) * n + x) + 3];
                seam = seam && a0 == a1 && a0 == a2;
            }
        CHECK(seam);
        /* Across the tile border the wire continues: texel (n-1, n-1) and (0, 0) both lie on the
         * diagonal wire. */
        CHECK(im->rgba[3] == 255 && im->rgba[4 * ((size_t)n * n - 1) + 3] == 255);
    }
    asset_free(&a);
}

TEST(fence_wire_thickness)
{
    double prev = 0.0;
    for (int wt = 1; wt <= 5; wt++) {
        asset a;
        CHECK(gen_fence(&(gen_fence_desc){.wire_texels = wt}, &a) == FS_OK);
        tex_stats s = image_stats(&a.images[0]);
        char what[64];
        snprintf(what, sizeof what, "fence wire 64 w%d", wt);
        print_stats(what, &s);
        /* Mean alpha grows with the wire, about 2 w sqrt(2) / 64 (two wires, minus the
         * crossing). */
        CHECK(s.mean_alpha > prev);
        CHECK(fabs(s.mean_alpha - 2.0 * wt * sqrt(2.0) / 64.0) < 0.02);
        prev = s.mean_alpha;
        if (wt >= 2)
            CHECK(s.transparent >= 0.50 && s.transparent <= 0.85);
        asset_free(&a);
    }
    /* A short, low fence keeps its posts inside [0, length]. */
    asset a;
    CHECK(gen_fence(&(gen_fence_desc){.length = 0.3f, .height = 0.2f, .cell_size = 0.05f}, &a) == FS_OK);
    check_asset(&a, "fence");
    CHECK_NEAR(a.bounds_min.x, 0.0, 1e-6);
    CHECK_NEAR(a.bounds_max.x, 0.3, 1e-6);
    asset_free(&a);
}

/* >>fern */

TEST(fern_defaults)
{
    asset a;
    CHECK(gen_fern(NULL, &a) == FS_OK);
    check_asset(&a, "fern");
    const material *fr = find_material(&a, "fronds");
    CHECK(fr && fr->alpha_kind == ALPHA_KIND_MASK);
    /* 8 fronds, each a strip of 4-6 quads: 10-14 vertices. */
    CHECK(a.prims[0].vertex_count >= 8 * 10 && a.prims[0].vertex_count <= 8 * 14);
    CHECK(a.bounds_min.y >= 0.0f);
    CHECK(a.bounds_max.y > 0.2f && a.bounds_max.y < 1.0f);
    float reach = fmaxf(fmaxf(a.bounds_max.x, -a.bounds_min.x), fmaxf(a.bounds_max.z, -a.bounds_min.z));
    CHECK(reach > 0.5f && reach < 1.3f);
    const image_rgba8 *im = foliage_image(&a);
    CHECK(im && im->width == 128);
    if (im) {
        tex_stats s = image_stats(im);
        print_stats("fern fronds 128", &s);
        CHECK(s.transparent >= 0.55 && s.transparent <= 0.75);
        CHECK(s.partial > 0.01);
        CHECK(s.black_hidden == 0);
        CHECK(border_transparent(im, 15));
        /* Pinnae are 1-2 texels wide: most horizontal opaque runs are short. */
        CHECK(s.short_runs > 0.8);
        /* The 2-texel rachis: the two centre columns are opaque along most of the height. */
        int n = im->width, on = 0;
        for (int y = 0; y < n; y++)
            on += im->rgba[4 * ((size_t)y * n + n / 2 - 1) + 3] == 255 && im->rgba[4 * ((size_t)y * n + n / 2) + 3] == 255;
        CHECK(on > n * 8 / 10);
    }
    asset_free(&a);
}

/* >>all generators */

TEST(transparent_share_over_seeds_and_sizes)
{
    const int sizes[] = {64, 128, 256, 512};
    for (uint32_t seed = 1; seed <= 6; seed++)
        for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
            int ts = sizes[k];
            asset a;
            CHECK(gen_tree(&(gen_tree_desc){.seed = seed, .texture_size = ts, .card_count = 1}, &a) == FS_OK);
            tex_stats s = image_stats(foliage_image(&a));
            CHECK(s.transparent >= 0.55 && s.transparent <= 0.70);
            CHECK(s.black_hidden == 0);
            asset_free(&a);
            CHECK(gen_grass(&(gen_grass_desc){.seed = seed, .texture_size = ts, .card_count = 1}, &a) == FS_OK);
            s = image_stats(foliage_image(&a));
            CHECK(s.transparent >= 0.60 && s.transparent <= 0.75);
            CHECK(s.black_hidden == 0);
            asset_free(&a);
            CHECK(gen_fern(&(gen_fern_desc){.seed = seed, .texture_size = ts, .frond_count = 1}, &a) == FS_OK);
            s = image_stats(foliage_image(&a));
            CHECK(s.transparent >= 0.55 && s.transparent <= 0.75);
            CHECK(s.black_hidden == 0);
            asset_free(&a);
        }
}

TEST(deterministic_in_seed)
{
    asset a, b;
    CHECK(gen_tree(&(gen_tree_desc){.seed = 42}, &a) == FS_OK);
    CHECK(gen_tree(&(gen_tree_desc){.seed = 42}, &b) == FS_OK);
    CHECK(same_asset(&a, &b));
    asset_free(&b);
    CHECK(gen_tree(&(gen_tree_desc){.seed = 43}, &b) == FS_OK);
    CHECK(!same_asset(&a, &b));
    CHECK(!same_image(&a.images[0], &b.images[0]));
    asset_free(&b);
    /* The texture does not depend on the card count (separate random streams). */
    CHECK(gen_tree(&(gen_tree_desc){.seed = 42, .card_count = 7}, &b) == FS_OK);
    CHECK(same_image(&a.images[0], &b.images[0]));
    asset_free(&a);
    asset_free(&b);

    CHECK(gen_grass(&(gen_grass_desc){.seed = 5}, &a) == FS_OK);
    CHECK(gen_grass(&(gen_grass_desc){.seed = 5}, &b) == FS_OK);
    CHECK(same_asset(&a, &b));
    asset_free(&b);
    CHECK(gen_grass(&(gen_grass_desc){.seed = 6}, &b) == FS_OK);
    CHECK(!same_asset(&a, &b));
    CHECK(!same_image(&a.images[0], &b.images[0]));
    asset_free(&a);
    asset_free(&b);

    CHECK(gen_fern(&(gen_fern_desc){.seed = 9}, &a) == FS_OK);
    CHECK(gen_fern(&(gen_fern_desc){.seed = 9}, &b) == FS_OK);
    CHECK(same_asset(&a, &b));
    asset_free(&b);
    CHECK(gen_fern(&(gen_fern_desc){.seed = 10}, &b) == FS_OK);
    CHECK(!same_asset(&a, &b));
    CHECK(!same_image(&a.images[0], &b.images[0]));
    asset_free(&a);
    asset_free(&b);

    /* The fence is fully regular: the seed changes nothing (documented in generators.h). */
    CHECK(gen_fence(&(gen_fence_desc){.seed = 1}, &a) == FS_OK);
    CHECK(gen_fence(&(gen_fence_desc){.seed = 2}, &b) == FS_OK);
    CHECK(same_asset(&a, &b));
    asset_free(&a);
    asset_free(&b);

    /* Seed 0 means the default seed 1. */
    CHECK(gen_fern(&(gen_fern_desc){.seed = 0}, &a) == FS_OK);
    CHECK(gen_fern(&(gen_fern_desc){.seed = 1}, &b) == FS_OK);
    CHECK(same_asset(&a, &b));
    asset_free(&a);
    asset_free(&b);
}

TEST(bad_descs_rejected)
{
    log_set_quiet_errors(true);
    asset a;
    const gen_tree_desc bad_tree[] = {
        {.texture_size = 100},  {.texture_size = 4},        {.texture_size = 8192},
        {.texture_size = -256}, {.card_count = -1},         {.card_count = 100001},
        {.height = -1.0f},      {.height = NAN},            {.crown_radius = INFINITY},
        {.card_size = -0.5f},   {.alpha_cutoff = 1.5f},     {.alpha_cutoff = -0.1f},
    };
    for (size_t i = 0; i < sizeof bad_tree / sizeof bad_tree[0]; i++) {
        memset(&a, 0xab, sizeof a);
        CHECK(gen_tree(&bad_tree[i], &a) == FS_ERR_SCENE);
        CHECK(a.prim_count == 0 && a.prims == NULL && a.images == NULL);
    }
    const gen_grass_desc bad_grass[] = {
        {.extent = -10.0f}, {.card_count = -5}, {.blade_height = NAN}, {.texture_size = 96}, {.alpha_cutoff = 2.0f},
    };
    for (size_t i = 0; i < sizeof bad_grass / sizeof bad_grass[0]; i++)
        CHECK(gen_grass(&bad_grass[i], &a) == FS_ERR_SCENE);
    const gen_fence_desc bad_fence[] = {
        {.wire_texels = 6},  {.wire_texels = -1},       {.length = -1.0f},   {.height = INFINITY},
        {.cell_size = -0.1f}, {.texture_size = 48},     {.texture_size = 16384},
    };
    for (size_t i = 0; i < sizeof bad_fence / sizeof bad_fence[0]; i++)
        CHECK(gen_fence(&bad_fence[i], &a) == FS_ERR_SCENE);
    const gen_fern_desc bad_fern[] = {
        {.size = -1.0f}, {.frond_count = -3}, {.frond_count = 100001}, {.texture_size = 3}, {.alpha_cutoff = NAN},
    };
    for (size_t i = 0; i < sizeof bad_fern / sizeof bad_fern[0]; i++)
        CHECK(gen_fern(&bad_fern[i], &a) == FS_ERR_SCENE);
    log_set_quiet_errors(false);
    /* The edges of the valid ranges are accepted. */
    CHECK(gen_tree(&(gen_tree_desc){.texture_size = 8, .card_count = 1, .alpha_cutoff = 1.0f}, &a) == FS_OK);
    asset_free(&a);
    CHECK(gen_fence(&(gen_fence_desc){.texture_size = 4096, .wire_texels = 5}, &a) == FS_OK);
    asset_free(&a);
    CHECK(gen_fence(&(gen_fence_desc){.wire_texels = 1}, &a) == FS_OK);
    asset_free(&a);
}

int main(void)
{
    RUN(tree_defaults);
    RUN(tree_custom_desc);
    RUN(grass_defaults);
    RUN(fence_defaults);
    RUN(fence_wire_thickness);
    RUN(fern_defaults);
    RUN(transparent_share_over_seeds_and_sizes);
    RUN(deterministic_in_seed);
    RUN(bad_descs_rejected);
    return test_summary();
}
