/* generators.c: procedural foliage assets (tree, grass, fence, fern), see generators.h: geometry,
 * materials and the checks of each desc; the textures are painted in gen_textures.c.
 *
 * Every generator draws from its own PCG32 streams (one for the texture, one for the geometry),
 * so the same desc gives byte-identical output, and changing card_count leaves the texture alone.
 */
#include "scene/generators.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"
#include "core/log.h"
#include "scene/generators_internal.h"

/* >>mesh builder */

typedef struct mesh_b {
    float *pos, *nrm, *uv;
    uint32_t *idx;
    uint32_t nv, ni;
    size_t cap_v, cap_i; /* pos, nrm and uv share cap_v */
    bool oom;
} mesh_b;

static bool mb_reserve(mesh_b *m, uint32_t add_v, uint32_t add_i)
{
    if (m->oom)
        return false;
    size_t need_v = (size_t)m->nv + add_v, cap_n = m->cap_v, cap_u = m->cap_v;
    if (!fs_grow((void **)&m->nrm, &cap_n, need_v, 3 * sizeof(float)) ||
        !fs_grow((void **)&m->uv, &cap_u, need_v, 2 * sizeof(float)) ||
        !fs_grow((void **)&m->pos, &m->cap_v, need_v, 3 * sizeof(float)) || !FS_GROW(m->idx, m->cap_i, (size_t)m->ni + add_i))
        return !(m->oom = true);
    return true;
}

static uint32_t mb_vertex(mesh_b *m, vec3 p, vec3 n, float u, float v)
{
    uint32_t i = m->nv++;
    m->pos[3 * i] = p.x, m->pos[3 * i + 1] = p.y, m->pos[3 * i + 2] = p.z;
    m->nrm[3 * i] = n.x, m->nrm[3 * i + 1] = n.y, m->nrm[3 * i + 2] = n.z;
    m->uv[2 * i] = u, m->uv[2 * i + 1] = v;
    return i;
}

static void mb_tri(mesh_b *m, uint32_t a, uint32_t b, uint32_t c)
{
    m->idx[m->ni++] = a;
    m->idx[m->ni++] = b;
    m->idx[m->ni++] = c;
}

/* A quad p0 p1 p2 p3 (around its edge) with UVs uv[0..3], wound so its geometric normal agrees
 * with `n` (stored on all four vertices). */
static void mb_quad(mesh_b *m, const vec3 p[4], const float uv[4][2], vec3 n)
{
    if (!mb_reserve(m, 4, 6))
        return;
    uint32_t b = m->nv;
    for (int k = 0; k < 4; k++)
        mb_vertex(m, p[k], n, uv[k][0], uv[k][1]);
    vec3 g = v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]));
    if (v3_dot(g, n) >= 0.0f) {
        mb_tri(m, b, b + 1, b + 2);
        mb_tri(m, b, b + 2, b + 3);
    } else {
        mb_tri(m, b, b + 2, b + 1);
        mb_tri(m, b, b + 3, b + 2);
    }
}

/* A card centred at c spanning `up` (texture top at +up) and `side` (texture left at -side),
 * each a full-edge vector. Normal = side x up. */
static void mb_card(mesh_b *m, vec3 c, vec3 side, vec3 up)
{
    vec3 hs = v3_scale(side, 0.5f), hu = v3_scale(up, 0.5f);
    vec3 p[4] = {v3_sub(v3_sub(c, hs), hu), v3_sub(v3_add(c, hs), hu), v3_add(v3_add(c, hs), hu),
                 v3_add(v3_sub(c, hs), hu)};
    const float uv[4][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    mb_quad(m, p, uv, v3_norm_or(v3_cross(side, up), v3(0, 0, 1)));
}

/* An axis-aligned box [lo, hi] with outward face normals; UVs span each face. */
static void mb_box(mesh_b *m, vec3 lo, vec3 hi)
{
    const float uv[4][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    for (int axis = 0; axis < 3; axis++)
        for (int sgn = 0; sgn < 2; sgn++) {
            float f = sgn ? (&hi.x)[axis] : (&lo.x)[axis];
            int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            vec3 p[4], n = v3(0, 0, 0);
            (&n.x)[axis] = sgn ? 1.0f : -1.0f;
            for (int k = 0; k < 4; k++) {
                float *q = &p[k].x;
                q[axis] = f;
                q[a1] = (k == 1 || k == 2) ? (&hi.x)[a1] : (&lo.x)[a1];
                q[a2] = (k >= 2) ? (&hi.x)[a2] : (&lo.x)[a2];
            }
            mb_quad(m, p, uv, n);
        }
}

/* Moves the builder into a prim (colours 1). */
static bool mb_finish(mesh_b *m, int material_index, prim *out)
{
    memset(out, 0, sizeof *out);
    if (m->oom || m->nv == 0)
        return false;
    out->colors = malloc(sizeof(float) * 4 * m->nv);
    if (!out->colors)
        return false;
    for (uint32_t i = 0; i < 4 * m->nv; i++)
        out->colors[i] = 1.0f;
    out->vertex_count = m->nv;
    out->index_count = m->ni;
    out->positions = m->pos;
    out->normals = m->nrm;
    out->uvs = m->uv;
    out->indices = m->idx;
    out->material = material_index;
    memset(m, 0, sizeof *m);
    return true;
}

static void mb_free(mesh_b *m)
{
    free(m->pos);
    free(m->nrm);
    free(m->uv);
    free(m->idx);
    memset(m, 0, sizeof *m);
}

/* >>asset assembly */

static bool asset_alloc(asset *a, const char *name, int prims, int materials, int images)
{
    memset(a, 0, sizeof *a);
    snprintf(a->name, sizeof a->name, "%s", name);
    a->source = ASSET_SOURCE_GENERATOR;
    a->prims = calloc((size_t)prims, sizeof *a->prims);
    a->materials = calloc((size_t)materials, sizeof *a->materials);
    a->images = images ? calloc((size_t)images, sizeof *a->images) : NULL;
    if (!a->prims || !a->materials || (images && !a->images)) {
        asset_free(a);
        return false;
    }
    a->prim_count = prims;
    a->material_count = materials;
    a->image_count = images;
    return true;
}

static material mat_foliage(const char *name, int image, float cutoff, tex_wrap wrap)
{
    material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    for (int k = 0; k < 4; k++)
        m.base_color[k] = 1.0f;
    m.base_color_image = image;
    m.wrap_s = m.wrap_t = wrap;
    m.mag_filter = TEX_FILTER_LINEAR;
    m.alpha_kind = ALPHA_KIND_MASK;
    m.alpha_cutoff = cutoff;
    m.double_sided = true;
    m.alpha_mode = ALPHA_MODE_DEFAULT;
    return m;
}

static material mat_opaque(const char *name, int image, float r, float g, float b)
{
    material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    m.base_color[0] = r, m.base_color[1] = g, m.base_color[2] = b, m.base_color[3] = 1.0f;
    m.base_color_image = image;
    m.wrap_s = m.wrap_t = TEX_WRAP_REPEAT;
    m.mag_filter = TEX_FILTER_LINEAR;
    m.alpha_kind = ALPHA_KIND_OPAQUE;
    m.alpha_cutoff = 0.5f;
    m.double_sided = false;
    return m;
}

static fs_status gen_fail_nomem(const char *gen, asset *out, mesh_b *m1, mesh_b *m2)
{
    if (m1)
        mb_free(m1);
    if (m2)
        mb_free(m2);
    asset_free(out);
    log_error("generator %s: out of memory", gen);
    return FS_ERR_NOMEM;
}

/* >>validation */

static bool check_pow2(const char *gen, const char *field, int v)
{
    if (v >= 8 && v <= 4096 && (v & (v - 1)) == 0)
        return true;
    log_error("generator %s: %s: expected a power of two in [8, 4096], got %d", gen, field, v);
    return false;
}

static bool check_int(const char *gen, const char *field, int v, int lo, int hi)
{
    if (v >= lo && v <= hi)
        return true;
    log_error("generator %s: %s: expected an integer in [%d, %d], got %d", gen, field, lo, hi, v);
    return false;
}

/* World sizes: finite, > 0 and at most 100 km (beyond that float positions lose the texel). */
static bool check_size(const char *gen, const char *field, float v)
{
    if (isfinite(v) && v > 0.0f && v <= 1e5f)
        return true;
    log_error("generator %s: %s: expected a finite size in (0, 100000] metres, got %g", gen, field, (double)v);
    return false;
}

static bool check_cutoff(const char *gen, float v)
{
    if (isfinite(v) && v > 0.0f && v <= 1.0f)
        return true;
    log_error("generator %s: alpha_cutoff: expected a number in (0, 1], got %g", gen, (double)v);
    return false;
}

/* >>defaults */

gen_tree_desc gen_tree_defaults(const gen_tree_desc *d)
{
    gen_tree_desc r = d ? *d : (gen_tree_desc){0};
    if (r.seed == 0) r.seed = 1;
    if (r.height == 0.0f) r.height = 6.0f;
    if (r.crown_radius == 0.0f) r.crown_radius = 2.0f;
    if (r.card_count == 0) r.card_count = 60;
    if (r.card_size == 0.0f) r.card_size = 1.2f;
    if (r.texture_size == 0) r.texture_size = 256;
    if (r.alpha_cutoff == 0.0f) r.alpha_cutoff = 0.5f;
    return r;
}

gen_grass_desc gen_grass_defaults(const gen_grass_desc *d)
{
    gen_grass_desc r = d ? *d : (gen_grass_desc){0};
    if (r.seed == 0) r.seed = 1;
    if (r.extent == 0.0f) r.extent = 10.0f;
    if (r.card_count == 0) r.card_count = 400;
    if (r.blade_height == 0.0f) r.blade_height = 0.5f;
    if (r.texture_size == 0) r.texture_size = 128;
    if (r.alpha_cutoff == 0.0f) r.alpha_cutoff = 0.5f;
    return r;
}

gen_fence_desc gen_fence_defaults(const gen_fence_desc *d)
{
    gen_fence_desc r = d ? *d : (gen_fence_desc){0};
    if (r.seed == 0) r.seed = 1;
    if (r.length == 0.0f) r.length = 10.0f;
    if (r.height == 0.0f) r.height = 2.0f;
    if (r.cell_size == 0.0f) r.cell_size = 0.1f;
    if (r.texture_size == 0) r.texture_size = 64;
    if (r.wire_texels == 0) r.wire_texels = 3;
    if (r.alpha_cutoff == 0.0f) r.alpha_cutoff = 0.5f;
    return r;
}

gen_fern_desc gen_fern_defaults(const gen_fern_desc *d)
{
    gen_fern_desc r = d ? *d : (gen_fern_desc){0};
    if (r.seed == 0) r.seed = 1;
    if (r.size == 0.0f) r.size = 1.0f;
    if (r.frond_count == 0) r.frond_count = 8;
    if (r.texture_size == 0) r.texture_size = 128;
    if (r.alpha_cutoff == 0.0f) r.alpha_cutoff = 0.5f;
    return r;
}

/* >>tree */

/* A random unit vector (uniform on the sphere). */
static vec3 rng_dir(gen_rng *r)
{
    float z = rng_range(r, -1.0f, 1.0f), phi = rng_range(r, 0.0f, 2.0f * (float)FS_PI);
    float s = sqrtf(fmaxf(0.0f, 1.0f - z * z));
    return v3(s * cosf(phi), z, s * sinf(phi));
}

/* Any unit vector perpendicular to unit vector a. */
static vec3 perp(vec3 a)
{
    vec3 t = fabsf(a.y) < 0.9f ? v3(0, 1, 0) : v3(1, 0, 0);
    return v3_norm_or(v3_cross(a, t), v3(1, 0, 0));
}

fs_status gen_tree(const gen_tree_desc *desc, asset *out)
{
    memset(out, 0, sizeof *out);
    gen_tree_desc d = gen_tree_defaults(desc);
    const char *g = "tree";
    if (!check_size(g, "height", d.height) || !check_size(g, "crown_radius", d.crown_radius) ||
        !check_int(g, "card_count", d.card_count, 1, 100000) || !check_size(g, "card_size", d.card_size) ||
        !check_pow2(g, "texture_size", d.texture_size) || !check_cutoff(g, d.alpha_cutoff))
        return FS_ERR_SCENE;

    if (!asset_alloc(out, "tree", 2, 2, 2))
        return gen_fail_nomem(g, out, NULL, NULL);
    if (!gen_tex_leaves(d.seed, d.texture_size, &out->images[0]) || !gen_tex_bark(d.seed, &out->images[1]))
        return gen_fail_nomem(g, out, NULL, NULL);
    out->materials[0] = mat_foliage("leaves", 0, d.alpha_cutoff, TEX_WRAP_CLAMP);
    out->materials[1] = mat_opaque("bark", 1, 1.0f, 1.0f, 1.0f);

    /* Crown: an ellipsoid (R, Rv, R) whose top touches `height`; leaf clusters inside it, shrunk
     * by half a card so cards stay near the crown's surface. */
    float H = d.height, R = d.crown_radius, s = d.card_size;
    float Rv = fminf(1.2f * R, 0.45f * H), cy = H - Rv;
    float ir = fmaxf(R - 0.5f * s, 0.3f * R), irv = fmaxf(Rv - 0.5f * s, 0.3f * Rv);
    gen_rng r = rng_make(d.seed, STREAM_GEOMETRY);

    mesh_b leaves = {0}, trunk = {0};
    for (int i = 0; i < d.card_count; i++) {
        /* Radius u^(1/4): clusters favour the outer shell, as foliage on a real crown does. */
        vec3 dir = rng_dir(&r);
        float rad = powf(rng_float(&r), 0.25f);
        vec3 c = v3(dir.x * ir * rad, cy + dir.y * irv * rad, dir.z * ir * rad);
        /* Card "up" points away from the crown centre, jittered: twig base inwards. */
        vec3 up = v3_norm_or(v3_add(dir, v3_scale(rng_dir(&r), 0.6f)), v3(0, 1, 0));
        vec3 b0 = perp(up), b1 = v3_cross(up, b0);
        float roll = rng_range(&r, 0.0f, (float)FS_PI);
        int quads = rng_int(&r, 2, 3);
        float sc = s * rng_range(&r, 0.85f, 1.15f);
        for (int q = 0; q < quads; q++) {
            float a = roll + (float)FS_PI * (float)q / (float)quads;
            vec3 side = v3_add(v3_scale(b0, cosf(a)), v3_scale(b1, sinf(a)));
            mb_card(&leaves, c, v3_scale(side, sc), v3_scale(up, sc));
        }
    }

    /* Trunk: 8-sided tapered cylinder from the ground into the crown centre, radial normals
     * (tilted by the taper), bark UVs wrapping twice around. */
    const int sides = 8, rings = 4;
    float top = cy + 0.3f * Rv, r0 = fmaxf(0.04f * H, 0.02f), r1 = 0.45f * r0;
    float slope = (r0 - r1) / fmaxf(top, 1e-6f);
    if (mb_reserve(&trunk, (uint32_t)((sides + 1) * (rings + 1)), (uint32_t)(sides * rings * 6))) {
        for (int j = 0; j <= rings; j++) {
            float t = (float)j / (float)rings, y = top * t, rr = r0 + (r1 - r0) * t;
            for (int k = 0; k <= sides; k++) {
                float a = 2.0f * (float)FS_PI * (float)k / (float)sides;
                vec3 n = v3_norm_or(v3(cosf(a), slope, sinf(a)), v3(1, 0, 0));
                mb_vertex(&trunk, v3(rr * cosf(a), y, rr * sinf(a)), n, 2.0f * (float)k / (float)sides,
                          (1.0f - t) * top / (2.0f * (float)FS_PI * r0 / 2.0f));
            }
        }
        for (int j = 0; j < rings; j++)
            for (int k = 0; k < sides; k++) {
                uint32_t a = (uint32_t)(j * (sides + 1) + k), b = a + 1, c = a + (uint32_t)(sides + 1), e = c + 1;
                /* Outward-facing (counter-clockwise seen from outside). */
                mb_tri(&trunk, a, c, b);
                mb_tri(&trunk, b, c, e);
            }
    }
    if (!mb_finish(&leaves, 0, &out->prims[0]) || !mb_finish(&trunk, 1, &out->prims[1]))
        return gen_fail_nomem(g, out, &leaves, &trunk);
    asset_compute_bounds(out);
    return FS_OK;
}

/* >>grass */

fs_status gen_grass(const gen_grass_desc *desc, asset *out)
{
    memset(out, 0, sizeof *out);
    gen_grass_desc d = gen_grass_defaults(desc);
    const char *g = "grass";
    if (!check_size(g, "extent", d.extent) || !check_int(g, "card_count", d.card_count, 1, 100000) ||
        !check_size(g, "blade_height", d.blade_height) || !check_pow2(g, "texture_size", d.texture_size) ||
        !check_cutoff(g, d.alpha_cutoff))
        return FS_ERR_SCENE;

    if (!asset_alloc(out, "grass", 2, 2, 1))
        return gen_fail_nomem(g, out, NULL, NULL);
    if (!gen_tex_blades(d.seed, d.texture_size, &out->images[0]))
        return gen_fail_nomem(g, out, NULL, NULL);
    out->materials[0] = mat_foliage("blades", 0, d.alpha_cutoff, TEX_WRAP_CLAMP);
    out->materials[1] = mat_opaque("ground", -1, 0.11f, 0.14f, 0.05f);

    gen_rng r = rng_make(d.seed, STREAM_GEOMETRY);
    mesh_b blades = {0}, ground = {0};
    float half = 0.5f * d.extent;
    for (int i = 0; i < d.card_count; i++) {
        float h = d.blade_height * rng_range(&r, 0.7f, 1.3f), w = h * rng_range(&r, 1.0f, 1.4f);
        float m = fminf(0.5f * w, half);
        float x = rng_range(&r, -half + m, half - m), z = rng_range(&r, -half + m, half - m);
        float yaw = rng_range(&r, 0.0f, (float)FS_PI);
        for (int q = 0; q < 2; q++) {
            float a = yaw + 0.5f * (float)FS_PI * (float)q;
            mb_card(&blades, v3(x, 0.5f * h, z), v3(w * cosf(a), 0, w * sinf(a)), v3(0, h, 0));
        }
    }
    {
        vec3 p[4] = {v3(-half, 0, -half), v3(half, 0, -half), v3(half, 0, half), v3(-half, 0, half)};
        float k = d.extent; /* UVs in metres, for whoever textures the ground later */
        const float uv[4][2] = {{0, 0}, {k, 0}, {k, k}, {0, k}};
        mb_quad(&ground, p, uv, v3(0, 1, 0));
    }
    if (!mb_finish(&blades, 0, &out->prims[0]) || !mb_finish(&ground, 1, &out->prims[1]))
        return gen_fail_nomem(g, out, &blades, &ground);
    asset_compute_bounds(out);
    return FS_OK;
}

/* >>fence */

fs_status gen_fence(const gen_fence_desc *desc, asset *out)
{
    memset(out, 0, sizeof *out);
    gen_fence_desc d = gen_fence_defaults(desc);
    const char *g = "fence";
    if (!check_size(g, "length", d.length) || !check_size(g, "height", d.height) ||
        !check_size(g, "cell_size", d.cell_size) || !check_pow2(g, "texture_size", d.texture_size) ||
        !check_int(g, "wire_texels", d.wire_texels, 1, 5) || !check_cutoff(g, d.alpha_cutoff))
        return FS_ERR_SCENE;

    if (!asset_alloc(out, "fence", 2, 2, 1))
        return gen_fail_nomem(g, out, NULL, NULL);
    if (!gen_tex_wire(d.texture_size, d.wire_texels, &out->images[0]))
        return gen_fail_nomem(g, out, NULL, NULL);
    out->materials[0] = mat_foliage("wire", 0, d.alpha_cutoff, TEX_WRAP_REPEAT);
    out->materials[1] = mat_opaque("posts", -1, 0.33f, 0.34f, 0.36f);

    mesh_b wire = {0}, posts = {0};
    float L = d.length, H = d.height;
    {
        /* One quad; the sampler repeats the cell tile L/cell x H/cell times. */
        vec3 p[4] = {v3(0, 0, 0), v3(L, 0, 0), v3(L, H, 0), v3(0, H, 0)};
        float u = L / d.cell_size, v = H / d.cell_size;
        const float uv[4][2] = {{0, v}, {u, v}, {u, 0}, {0, 0}};
        mb_quad(&wire, p, uv, v3(0, 0, 1));
    }
    /* Posts every ~2.5 m, the end posts flush with x = 0 and x = length; a top rail above the
     * mesh. Thin parts shrink with a short fence so they never exceed it. */
    float pw = fminf(0.06f, 0.1f * L), rail = fminf(0.05f, 0.1f * H);
    int count = (int)ceilf(L / 2.5f) + 1;
    if (count < 2)
        count = 2;
    for (int i = 0; i < count; i++) {
        float x = 0.5f * pw + (L - pw) * (float)i / (float)(count - 1);
        mb_box(&posts, v3(x - 0.5f * pw, 0, -0.5f * pw), v3(x + 0.5f * pw, H + rail, 0.5f * pw));
    }
    mb_box(&posts, v3(0, H, -0.4f * rail), v3(L, H + rail, 0.4f * rail));
    if (!mb_finish(&wire, 0, &out->prims[0]) || !mb_finish(&posts, 1, &out->prims[1]))
        return gen_fail_nomem(g, out, &wire, &posts);
    asset_compute_bounds(out);
    return FS_OK;
}

/* >>fern */

fs_status gen_fern(const gen_fern_desc *desc, asset *out)
{
    memset(out, 0, sizeof *out);
    gen_fern_desc d = gen_fern_defaults(desc);
    const char *g = "fern";
    if (!check_size(g, "size", d.size) || !check_int(g, "frond_count", d.frond_count, 1, 100000) ||
        !check_pow2(g, "texture_size", d.texture_size) || !check_cutoff(g, d.alpha_cutoff))
        return FS_ERR_SCENE;

    if (!asset_alloc(out, "fern", 1, 1, 1))
        return gen_fail_nomem(g, out, NULL, NULL);
    if (!gen_tex_fern(d.seed, d.texture_size, &out->images[0]))
        return gen_fail_nomem(g, out, NULL, NULL);
    out->materials[0] = mat_foliage("fronds", 0, d.alpha_cutoff, TEX_WRAP_CLAMP);

    gen_rng r = rng_make(d.seed, STREAM_GEOMETRY);
    mesh_b fr = {0};
    const int segs_max = 6;
    for (int i = 0; i < d.frond_count; i++) {
        float az = 2.0f * (float)FS_PI * ((float)i + rng_range(&r, -0.3f, 0.3f)) / (float)d.frond_count;
        float len = d.size * rng_range(&r, 0.8f, 1.1f), width = 0.5f * len;
        float elev = rng_range(&r, 0.9f, 1.3f), bend = rng_range(&r, 1.0f, 1.7f); /* radians */
        float roll = rng_range(&r, -0.25f, 0.25f);
        int segs = rng_int(&r, 4, segs_max);
        vec3 fwd = v3(cosf(az), 0, sinf(az));
        vec3 lat = v3(-sinf(az) * cosf(roll), sinf(roll), cosf(az) * cosf(roll)); /* across the frond */
        if (!mb_reserve(&fr, (uint32_t)(2 * (segs + 1)), (uint32_t)(6 * segs)))
            break;
        uint32_t base = fr.nv;
        vec3 p = v3_scale(fwd, 0.03f * d.size);
        for (int k = 0; k <= segs; k++) {
            float t = (float)k / (float)segs;
            /* Frond base (texture bottom, v = 1) at the clump centre, tip at v = 0. */
            vec3 hl = v3_scale(lat, 0.5f * width);
            vec3 a = v3_sub(p, hl), b = v3_add(p, hl);
            a.y = fmaxf(a.y, 0.0f);
            b.y = fmaxf(b.y, 0.0f);
            mb_vertex(&fr, a, v3(0, 1, 0), 0.0f, 1.0f - t);
            mb_vertex(&fr, b, v3(0, 1, 0), 1.0f, 1.0f - t);
            /* Arch: elevation falls linearly along the frond, so it rises, then droops. */
            float e = elev - bend * (t + 0.5f / (float)segs);
            p = v3_add(p, v3_add(v3_scale(fwd, cosf(e) * len / (float)segs), v3(0, sinf(e) * len / (float)segs, 0)));
        }
        for (int k = 0; k < segs; k++) {
            uint32_t a = base + 2u * (uint32_t)k;
            mb_tri(&fr, a, a + 1, a + 3);
            mb_tri(&fr, a, a + 3, a + 2);
        }
    }
    if (!mb_finish(&fr, 0, &out->prims[0]))
        return gen_fail_nomem(g, out, &fr, NULL);
    prim_compute_normals(&out->prims[0]); /* smooth along each arched strip */
    asset_compute_bounds(out);
    return FS_OK;
}
