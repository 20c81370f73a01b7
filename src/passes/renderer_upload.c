/* renderer_upload.c: what renderer_create puts on the GPU once the programs are built: the scene
 * (textures with their mip chains, samplers, primitives, instances and their sway attributes),
 * the render targets with the resources their passes declare, and the exact reference's
 * fragment-list store. */
#include "passes/renderer_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/shared_defs.h"
#include "core/log.h"
#include "scene/cards.h"
#include "scene/mip.h"

/* >>resources
 * What the forward pass reads and writes, declared up front in one table per pass so that the
 * targets made below and the passes that bind them cannot disagree; pass_resource and the tables'
 * indices (RES_*, OUT_*) are in renderer_internal.h. */

/* Each ring's forward passes write these, at the ring's resolution. */
const pass_resource k_forward_resources[] = {
    {"color", "linear premultiplied radiance, A = opacity", GL_RGBA16F, true, false},
    {"coverage", "opacity contributed by alpha-mapped surfaces", GL_R16F, true, false},
    {"depth", "depth buffer", GL_DEPTH_COMPONENT24, true, false},
    {"motion", "world position last frame - now, of swaying fragments (plan.velocity)", GL_RGBA16F, true, true},
};

/* The composite reads every ring's color and coverage and writes these at display resolution. */
const pass_resource k_composite_resources[] = {
    {"color", "display colour, rings upsampled and blended", GL_RGBA16F, true, false},
    {"coverage", "display coverage", GL_R16F, true, false},
    {"debug", "ring.id (ring + blend weight) and eccentricity (degrees)", GL_RG32F, true, true},
};

/* >>upload */
/* Textures are stored as RGBA16 UNORM, linear premultiplied. 16-bit unorm holds every 8-bit
 * value k/255 exactly (k/255 = 257k/65535), so a level-0 alpha equal to a material's cutoff
 * compares exactly as glTF says (alpha >= cutoff); RGBA16F would round 51/255 below a 0.2 cutoff.
 * It also keeps 1/65535 precision for dark premultiplied colour in the averaged mips. */
static GLuint upload_chain(const image_rgba8 *img, float cutoff, bool castano, fs_status *st)
{
    mip_chain mc;
    *st = castano ? mip_chain_build_castano(img, cutoff, &mc) : mip_chain_build(img, &mc);
    if (*st != FS_OK)
        return 0;
    size_t n0 = (size_t)mc.width[0] * (size_t)mc.height[0] * 4;
    uint16_t *buf = malloc(sizeof(uint16_t) * n0);
    if (!buf) {
        mip_chain_free(&mc);
        *st = FS_ERR_NOMEM;
        return 0;
    }
    GLuint t;
    glCreateTextures(GL_TEXTURE_2D, 1, &t);
    glTextureStorage2D(t, mc.level_count, GL_RGBA16, mc.width[0], mc.height[0]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    for (int l = 0; l < mc.level_count; l++) {
        size_t n = (size_t)mc.width[l] * (size_t)mc.height[l] * 4;
        for (size_t i = 0; i < n; i++) {
            float v = mc.rgba[l][i];
            v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; /* also maps NaN to 0 */
            buf[i] = (uint16_t)lrintf(v * 65535.0f);
        }
        glTextureSubImage2D(t, l, 0, 0, mc.width[l], mc.height[l], GL_RGBA, GL_UNSIGNED_SHORT, buf);
    }
    free(buf);
    mip_chain_free(&mc);
    return t;
}

static GLuint make_sampler(const material *m)
{
    static const GLenum wraps[] = {[TEX_WRAP_REPEAT] = GL_REPEAT, [TEX_WRAP_CLAMP] = GL_CLAMP_TO_EDGE,
                                   [TEX_WRAP_MIRROR] = GL_MIRRORED_REPEAT};
    GLuint s;
    glCreateSamplers(1, &s);
    glSamplerParameteri(s, GL_TEXTURE_WRAP_S, (GLint)wraps[m->wrap_s]);
    glSamplerParameteri(s, GL_TEXTURE_WRAP_T, (GLint)wraps[m->wrap_t]);
    glSamplerParameteri(s, GL_TEXTURE_MAG_FILTER, m->mag_filter == TEX_FILTER_NEAREST ? GL_NEAREST : GL_LINEAR);
    glSamplerParameteri(s, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    return s;
}

/* Per-instance sway attributes (binding 5): (offset.xyz, height) at ATTR_SWAY, (frequency, phase)
 * at ATTR_SWAY_WAVE, 8 floats per instance. */
enum { SWAY_FLOATS = 8 };

/* The primitives of passes that key fragments by their triangle (prim_needs_triangles,
 * common/draw_order.glsl): every triangle's provoking (last) vertex carries the asset's triangle
 * index, t0 + its index t in the primitive, and t itself (what gl_PrimitiveID counts), two uints
 * per vertex. A vertex that two triangles end on is duplicated for the second, with the same
 * attributes (so the same image), and that triangle's last index points at the copy. Writes *out
 * (its own arrays; prim_free_copy), out_src (each vertex's source vertex in p) and out_tri. */
static fs_status prim_triangle_ids(const prim *p, uint32_t t0, prim *out, uint32_t **out_src, uint32_t **out_tri)
{
    uint32_t tris = p->index_count / 3u, max = p->vertex_count + tris;
    uint32_t *src = malloc(sizeof(uint32_t) * ((size_t)max + 1)), *tri = malloc(sizeof(uint32_t) * 2 * ((size_t)max + 1));
    unsigned char *taken = calloc((size_t)p->vertex_count + 1, 1);
    *out = (prim){.material = p->material, .index_count = p->index_count,
                  .indices = malloc(sizeof(uint32_t) * ((size_t)p->index_count + 1))};
    if (!src || !tri || !taken || !out->indices) {
        free(src);
        free(tri);
        free(taken);
        free(out->indices);
        out->indices = NULL;
        return FS_ERR_NOMEM;
    }
    uint32_t n = p->vertex_count;
    for (uint32_t v = 0; v < n; v++) {
        src[v] = v;
        tri[2 * v] = tri[2 * v + 1] = 0; /* provokes no triangle: never read */
    }
    memcpy(out->indices, p->indices, sizeof(uint32_t) * p->index_count);
    for (uint32_t t = 0; t < tris; t++) {
        uint32_t v = p->indices[3 * t + 2];
        if (taken[v]) {
            src[n] = v;
            out->indices[3 * t + 2] = v = n++;
        }
        taken[src[v]] = 1;
        tri[2 * v] = t0 + t;
        tri[2 * v + 1] = t;
    }
    free(taken);
    out->vertex_count = n;
    const float *in[4] = {p->positions, p->normals, p->uvs, p->colors};
    float **dst[4] = {&out->positions, &out->normals, &out->uvs, &out->colors};
    const size_t comps[4] = {3, 3, 2, 4};
    fs_status st = FS_OK;
    for (int a = 0; a < 4; a++) {
        *dst[a] = malloc(sizeof(float) * comps[a] * ((size_t)n + 1));
        if (!*dst[a]) {
            st = FS_ERR_NOMEM;
            continue;
        }
        for (uint32_t v = 0; v < n; v++)
            memcpy(*dst[a] + comps[a] * v, in[a] + comps[a] * src[v], sizeof(float) * comps[a]);
    }
    *out_src = src;
    *out_tri = tri;
    return st;
}

static void prim_free_copy(prim *p)
{
    free(p->positions);
    free(p->normals);
    free(p->uvs);
    free(p->colors);
    free(p->indices);
}

/* A primitive's buffers and vertex array; tri: ATTR_TRIANGLE, two uints per vertex
 * (prim_triangle_ids), or NULL. */
static void upload_prim(const prim *p, gpu_prim *g, GLuint instance_vbo, GLuint sway_vbo, const uint32_t *tri)
{
    glCreateVertexArrays(1, &g->vao);
    glCreateBuffers(4, g->vbo);
    glCreateBuffers(1, &g->ibo);
    const float *data[4] = {p->positions, p->normals, p->uvs, p->colors};
    const int comps[4] = {3, 3, 2, 4};
    const GLuint locs[4] = {ATTR_POSITION, ATTR_NORMAL, ATTR_UV, ATTR_COLOR};
    for (int i = 0; i < 4; i++) {
        glNamedBufferStorage(g->vbo[i], (GLsizeiptr)(sizeof(float) * (size_t)comps[i] * p->vertex_count), data[i], 0);
        glVertexArrayVertexBuffer(g->vao, (GLuint)i, g->vbo[i], 0, (GLsizei)(sizeof(float) * (size_t)comps[i]));
        glVertexArrayAttribFormat(g->vao, locs[i], comps[i], GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(g->vao, locs[i], (GLuint)i);
        glEnableVertexArrayAttrib(g->vao, locs[i]);
    }
    glVertexArrayVertexBuffer(g->vao, 4, instance_vbo, 0, sizeof(mat4));
    glVertexArrayBindingDivisor(g->vao, 4, 1);
    for (GLuint c = 0; c < 4; c++) {
        glVertexArrayAttribFormat(g->vao, ATTR_INSTANCE + c, 4, GL_FLOAT, GL_FALSE, c * 4 * sizeof(float));
        glVertexArrayAttribBinding(g->vao, ATTR_INSTANCE + c, 4);
        glEnableVertexArrayAttrib(g->vao, ATTR_INSTANCE + c);
    }
    if (sway_vbo) {
        glVertexArrayVertexBuffer(g->vao, 5, sway_vbo, 0, SWAY_FLOATS * sizeof(float));
        glVertexArrayBindingDivisor(g->vao, 5, 1);
        glVertexArrayAttribFormat(g->vao, ATTR_SWAY, 4, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribFormat(g->vao, ATTR_SWAY_WAVE, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float));
        glVertexArrayAttribBinding(g->vao, ATTR_SWAY, 5);
        glVertexArrayAttribBinding(g->vao, ATTR_SWAY_WAVE, 5);
        glEnableVertexArrayAttrib(g->vao, ATTR_SWAY);
        glEnableVertexArrayAttrib(g->vao, ATTR_SWAY_WAVE);
    }
    if (tri) {
        glCreateBuffers(1, &g->tri_vbo);
        glNamedBufferStorage(g->tri_vbo, (GLsizeiptr)(sizeof(uint32_t) * 2 * p->vertex_count), tri, 0);
        glVertexArrayVertexBuffer(g->vao, 8, g->tri_vbo, 0, 2 * sizeof(uint32_t));
        glVertexArrayAttribIFormat(g->vao, ATTR_TRIANGLE, 2, GL_UNSIGNED_INT, 0);
        glVertexArrayAttribBinding(g->vao, ATTR_TRIANGLE, 8);
        glEnableVertexArrayAttrib(g->vao, ATTR_TRIANGLE);
    }
    glNamedBufferStorage(g->ibo, (GLsizeiptr)(sizeof(uint32_t) * p->index_count), p->indices, 0);
    glVertexArrayElementBuffer(g->vao, g->ibo);
    g->index_count = (GLsizei)p->index_count;
}

/* Card attributes (4 floats, then 1 per vertex, of `n` source vertices) for a primitive whose
 * vertices were duplicated (prim_triangle_ids): vertex v takes source vertex src[v]'s; `count`
 * vertices out. */
static float *gather_cards(const float *attr, const float *side, const uint32_t *src, uint32_t count)
{
    float *out = malloc(sizeof(float) * 5 * ((size_t)count + 1));
    if (!out)
        return NULL;
    for (uint32_t v = 0; v < count; v++) {
        memcpy(out + 4 * (size_t)v, attr + 4 * (size_t)src[v], 4 * sizeof(float));
        out[4 * (size_t)count + v] = side[src[v]];
    }
    return out;
}

/* Ring LOD (plan.ring_lod; docs/ring-lod.md): each MASK primitive's (card centre, rank) per vertex
 * at ATTR_CARD, and per ring the box its enlarged cards may reach. A primitive that is not
 * simplified gets rank RING_LOD_RANK_KEEP, which the shader never moves. */
static fs_status upload_cards(renderer *r, const asset *as, gpu_asset *ga)
{
    asset_cards cards;
    fs_status st = asset_cards_build(as, &cards);
    if (st != FS_OK)
        return st;
    ga->lod_side_min = INFINITY;
    for (int p = 0; p < as->prim_count && st == FS_OK; p++) {
        if (!cards_prim_is_candidate(as, p))
            continue;
        const prim *pr = &as->prims[p];
        float *attr = malloc(sizeof(float) * 5 * ((size_t)pr->vertex_count + 1));
        if (!attr) {
            st = FS_ERR_NOMEM;
            break;
        }
        float *side = attr + 4 * (size_t)pr->vertex_count;
        const prim_cards *pc = &cards.prims[p];
        for (uint32_t c = 0; pc->simplified && c < pc->card_count; c++) {
            float side = sqrtf(pc->area[c]);
            if (side > 0.0f) { /* a card without area draws nothing, enlarged or not */
                ga->lod_side_min = fminf(ga->lod_side_min, side);
                ga->lod_aspect = fmaxf(ga->lod_aspect, pc->radius[c] / side);
            }
        }
        prim_cards_vertex_attrib(&cards.prims[p], pr, attr);
        prim_cards_vertex_side(&cards.prims[p], pr, side);
        gpu_prim *g = &ga->prims[p];
        float *gathered = g->vsrc ? gather_cards(attr, side, g->vsrc, g->vertex_count) : attr;
        if (!gathered) {
            free(attr);
            st = FS_ERR_NOMEM;
            break;
        }
        glCreateBuffers(2, g->card_vbo);
        glNamedBufferStorage(g->card_vbo[0], (GLsizeiptr)(sizeof(float) * 4 * g->vertex_count), gathered, 0);
        glNamedBufferStorage(g->card_vbo[1], (GLsizeiptr)(sizeof(float) * g->vertex_count),
                             gathered + 4 * (size_t)g->vertex_count, 0);
        if (gathered != attr)
            free(gathered);
        free(attr);
        const GLuint locs[2] = {ATTR_CARD, ATTR_CARD_SIDE};
        const GLint comps[2] = {4, 1};
        for (int i = 0; i < 2; i++) {
            glVertexArrayVertexBuffer(g->vao, 6 + (GLuint)i, g->card_vbo[i], 0, (GLsizei)(sizeof(float) * (size_t)comps[i]));
            glVertexArrayAttribFormat(g->vao, locs[i], comps[i], GL_FLOAT, GL_FALSE, 0);
            glVertexArrayAttribBinding(g->vao, locs[i], 6 + (GLuint)i);
            glEnableVertexArrayAttrib(g->vao, locs[i]);
        }
    }
    for (int k = 0; k < r->pl.layout.count && st == FS_OK; k++) {
        ring_lod_law law = ring_lod_ring_law(&r->pl.ring_lod_spec, &r->pl.layout, k);
        asset_cards_bounds(as, &cards, ring_lod_max_scale(&law), &ga->lod_lo[k], &ga->lod_hi[k]);
    }
    asset_cards_free(&cards);
    return st;
}

/* Fade-in length of the hashed noise for one material (seed 000 §5.5.1, docs/hashed-alpha.md):
 * fade_n mip levels (default 6), but never later than the level where the traditional test's
 * coverage of this texture at this cutoff has drifted by a quarter — a thin wire erodes by mip 3,
 * and noise that arrives at mip 6 would leave it invisible in between. No texture: no mip levels
 * to fade over, so no fade (the noise is the only way to show a constant partial alpha). */
static fs_status material_fade(const plan *pl, const material *m, const asset *as, float *out)
{
    alpha_mode mode = plan_material_mode(pl, m);
    *out = 0.0f;
    if (m->alpha_kind != ALPHA_KIND_MASK || m->base_color_image < 0 || pl->alpha.no_fade ||
        !alpha_mode_has(mode, ALPHA_TRAIT_HASH))
        return FS_OK;
    mip_chain mc;
    fs_status st = mip_chain_build(&as->images[m->base_color_image], &mc);
    if (st != FS_OK)
        return st;
    int drift = mip_coverage_drift_level(&mc, m->alpha_cutoff, 0.25);
    mip_chain_free(&mc);
    *out = fmaxf(1.0f, fminf(pl->alpha.fade_n, (float)drift));
    log_info("ALPHA: [%s] material \"%s\": hashed noise fades in over %.1f mip levels", as->name, m->name, *out);
    return FS_OK;
}

/* Whether the passes that draw primitives of material m read ATTR_TRIANGLE (FORWARD_TRIANGLE in
 * common/draw_order.glsl): hashed and stochastic MASK passes, and the exact reference's list pass
 * (MASK and BLEND). Every such primitive must have it: a missing attribute reads as 0. */
static bool prim_needs_triangles(const plan *pl, const material *m)
{
    if (pl->reference_lists && m->alpha_kind != ALPHA_KIND_OPAQUE)
        return true;
    alpha_mode mode = plan_material_mode(pl, m);
    return m->alpha_kind == ALPHA_KIND_MASK &&
           (alpha_mode_has(mode, ALPHA_TRAIT_HASH) || mode == ALPHA_MODE_STOCHASTIC);
}

/* Primitive p of asset `as` (its triangles start at the asset's triangle t0): with their triangle
 * ids where its passes read them (prim_triangle_ids), else as it is. */
static fs_status upload_prim_of(const renderer *r, const asset *as, int p, uint32_t t0, gpu_asset *ga)
{
    const prim *pr = &as->prims[p];
    const material *m = &as->materials[pr->material];
    gpu_prim *g = &ga->prims[p];
    g->vertex_count = pr->vertex_count;
    if (!prim_needs_triangles(&r->pl, m)) {
        upload_prim(pr, g, ga->instance_vbo, ga->sway_vbo, NULL);
        return FS_OK;
    }
    prim q;
    uint32_t *tri = NULL;
    fs_status st = prim_triangle_ids(pr, t0, &q, &g->vsrc, &tri);
    if (st == FS_OK) {
        upload_prim(&q, g, ga->instance_vbo, ga->sway_vbo, tri);
        g->vertex_count = q.vertex_count;
    }
    prim_free_copy(&q);
    free(tri);
    return st;
}

fs_status renderer_upload_scene(renderer *r)
{
    const scene *sc = r->sc;
    r->assets = calloc((size_t)sc->asset_count + 1, sizeof *r->assets);
    r->blend_order = calloc((size_t)sc->instance_count + 1, sizeof *r->blend_order);
    if (!r->assets || !r->blend_order)
        return FS_ERR_NOMEM;
    for (int a = 0, slots = 0; a < sc->asset_count; a++) {
        const asset *as = &sc->assets[a];
        gpu_asset *ga = &r->assets[a];
        for (int i = 0; i < sc->instance_count; i++)
            ga->instance_count += sc->instances[i].asset == a;
        ga->slot_base = slots;
        slots += ga->instance_count;
        if (ga->instance_count == 0)
            continue; /* nothing places it: nothing to upload */
        ga->instance_ids = malloc(sizeof(int) * (size_t)ga->instance_count);
        ga->visible = malloc((size_t)ga->instance_count);
        mat4 *mats = malloc(sizeof(mat4) * (size_t)ga->instance_count);
        ga->prims = calloc((size_t)as->prim_count + 1, sizeof *ga->prims);
        ga->textures = calloc((size_t)as->image_count + 1, sizeof(GLuint));
        ga->samplers = calloc((size_t)as->material_count + 1, sizeof(GLuint));
        ga->castano = calloc((size_t)as->material_count + 1, sizeof(GLuint));
        ga->fade_n = calloc((size_t)as->material_count + 1, sizeof(float));
        if (!ga->instance_ids || !ga->visible || !mats || !ga->prims || !ga->textures || !ga->samplers ||
            !ga->castano || !ga->fade_n) {
            free(mats);
            return FS_ERR_NOMEM;
        }
        for (int i = 0, k = 0; i < sc->instance_count; i++)
            if (sc->instances[i].asset == a) {
                ga->instance_ids[k] = i;
                mats[k++] = sc->instances[i].transform;
            }
        glCreateBuffers(1, &ga->instance_vbo);
        glNamedBufferStorage(ga->instance_vbo, (GLsizeiptr)(sizeof(mat4) * (size_t)ga->instance_count), mats, 0);
        free(mats);
        if (r->pl.sway) {
            float *sw = malloc(sizeof(float) * SWAY_FLOATS * (size_t)ga->instance_count);
            if (!sw)
                return FS_ERR_NOMEM;
            ga->cull_pad = calloc((size_t)ga->instance_count, sizeof(float));
            if (!ga->cull_pad) {
                free(sw);
                return FS_ERR_NOMEM;
            }
            for (int k = 0; k < ga->instance_count; k++) {
                const instance *in = &sc->instances[ga->instance_ids[k]];
                const instance_sway *w = &in->sway;
                /* Sway moves a vertex up to |offset| (world) from the box: in asset units, that
                 * divided by the transform's smallest axis scale. */
                const float *m = in->transform.m;
                float smin = fminf(v3_len(v3(m[0], m[1], m[2])),
                                   fminf(v3_len(v3(m[4], m[5], m[6])), v3_len(v3(m[8], m[9], m[10]))));
                ga->cull_pad[k] = instance_sways(in) ? v3_len(w->offset) / fmaxf(smin, 1e-20f) : 0.0f;
                const float v[SWAY_FLOATS] = {w->offset.x, w->offset.y, w->offset.z, w->height, w->frequency, w->phase, 0, 0};
                memcpy(sw + SWAY_FLOATS * k, v, sizeof v);
            }
            glCreateBuffers(1, &ga->sway_vbo);
            glNamedBufferStorage(ga->sway_vbo, (GLsizeiptr)(sizeof(float) * SWAY_FLOATS * (size_t)ga->instance_count),
                                 sw, 0);
            free(sw);
        }
        for (int i = 0; i < as->image_count; i++) {
            fs_status st;
            ga->textures[i] = upload_chain(&as->images[i], 0.0f, false, &st);
            if (st != FS_OK)
                return st;
        }
        for (int m = 0; m < as->material_count; m++) {
            const material *mt = &as->materials[m];
            ga->samplers[m] = make_sampler(mt);
            /* Castano: the traditional test on a chain whose alpha is rescaled per level so each
             * level keeps level 0's coverage at this material's cutoff (seed 001). */
            fs_status fst = material_fade(&r->pl, mt, as, &ga->fade_n[m]);
            if (fst != FS_OK)
                return fst;
            if (mt->alpha_kind == ALPHA_KIND_MASK && mt->base_color_image >= 0 &&
                alpha_mode_has(plan_material_mode(&r->pl, mt), ALPHA_TRAIT_COVERAGE_MIPS)) {
                fs_status st;
                ga->castano[m] = upload_chain(&as->images[mt->base_color_image], mt->alpha_cutoff, true, &st);
                if (st != FS_OK)
                    return st;
            }
        }
        for (int p = 0, t0 = 0; p < as->prim_count; t0 += (int)(as->prims[p].index_count / 3u), p++) {
            fs_status st = upload_prim_of(r, as, p, (uint32_t)t0, ga);
            if (st != FS_OK)
                return st;
        }
        fs_status st = r->pl.ring_lod ? upload_cards(r, as, ga) : FS_OK;
        for (int p = 0; p < as->prim_count; p++) { /* the duplicated vertices' sources: cards only */
            free(ga->prims[p].vsrc);
            ga->prims[p].vsrc = NULL;
        }
        if (st != FS_OK)
            return st;
    }
    return FS_OK;
}

/* >>targets */
/* Bytes per pixel of the formats the targets use (0 for any other). */
static int format_bytes(GLenum f)
{
    switch (f) {
    case GL_RGBA16F: return 8;
    case GL_R16F: return 2;
    case GL_R32F: return 4;
    case GL_RG32F: return 8;
    case GL_RGBA32F: return 16;
    case GL_R32UI: return 4;
    case GL_DEPTH_COMPONENT24: return 4; /* stored in 32 bits */
    default: return 0;
    }
}

/* History formats (renderer_create_targets). */
#define TAA_HISTORY_COLOR GL_RGBA16F
#define TAA_HISTORY_COVERAGE GL_R16F
#define TAA_HISTORY_DEPTH GL_R32F

target_bytes renderer_target_bytes(const renderer *r)
{
    const plan *p = &r->pl;
    return (target_bytes){
        .color = format_bytes(k_forward_resources[RES_COLOR].format),
        .coverage = format_bytes(k_forward_resources[RES_COVERAGE].format),
        .depth = format_bytes(k_forward_resources[RES_DEPTH].format),
        .motion = p->velocity ? format_bytes(k_forward_resources[RES_MOTION].format) : 0,
        .history_color = p->taa ? format_bytes(TAA_HISTORY_COLOR) : 0,
        .history_coverage = p->taa ? format_bytes(TAA_HISTORY_COVERAGE) : 0,
        .history_depth = p->taa && p->taa_disocclusion ? format_bytes(TAA_HISTORY_DEPTH) : 0,
        .out_color = p->composite ? format_bytes(k_composite_resources[OUT_COLOR].format) : 0,
        .out_coverage = p->composite ? format_bytes(k_composite_resources[OUT_COVERAGE].format) : 0,
        .out_debug = p->composite && p->debug_channels ? format_bytes(k_composite_resources[OUT_DEBUG].format) : 0,
        .msaa_samples = p->msaa ? MSAA_SAMPLES : 0,
        .taa = p->taa,
    };
}

static fs_status check_fbo(GLuint fbo, const char *what, int w, int h)
{
    GLenum s = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
    if (s != GL_FRAMEBUFFER_COMPLETE) {
        log_error("GL: %s targets %dx%d incomplete (0x%x)", what, w, h, s);
        return FS_ERR_GL;
    }
    return FS_OK;
}

fs_status renderer_create_targets(renderer *r)
{
    static const GLenum bufs[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    int n = r->pl.layout.count;
    ring_targets *t = &r->rt;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t->color);
    glTextureStorage3D(t->color, 1, k_forward_resources[RES_COLOR].format, r->width, r->height, n);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t->coverage);
    glTextureStorage3D(t->coverage, 1, k_forward_resources[RES_COVERAGE].format, r->width, r->height, n);
    glCreateTextures(GL_TEXTURE_2D, 1, &t->depth);
    glTextureStorage2D(t->depth, 1, k_forward_resources[RES_DEPTH].format, r->width, r->height);
    int outputs = r->pl.velocity ? 3 : 2;
    if (r->pl.velocity) {
        glCreateTextures(GL_TEXTURE_2D, 1, &t->motion);
        glTextureStorage2D(t->motion, 1, k_forward_resources[RES_MOTION].format, r->width, r->height);
    }
    for (int i = 0; i < n; i++) {
        glCreateFramebuffers(1, &t->fbo[i]);
        glNamedFramebufferTextureLayer(t->fbo[i], GL_COLOR_ATTACHMENT0, t->color, 0, i);
        glNamedFramebufferTextureLayer(t->fbo[i], GL_COLOR_ATTACHMENT1, t->coverage, 0, i);
        glNamedFramebufferTexture(t->fbo[i], GL_DEPTH_ATTACHMENT, t->depth, 0);
        if (r->pl.velocity)
            glNamedFramebufferTexture(t->fbo[i], GL_COLOR_ATTACHMENT2, t->motion, 0);
        glNamedFramebufferDrawBuffers(t->fbo[i], outputs, bufs);
        fs_status st = check_fbo(t->fbo[i], "ring", r->width, r->height);
        if (st != FS_OK)
            return st;
    }
    if (r->pl.msaa) {
        glCreateFramebuffers(1, &t->msaa_fbo);
        GLuint *ms[RES_COUNT] = {&t->msaa_color, &t->msaa_coverage, &t->msaa_depth, &t->msaa_motion};
        static const GLenum att[RES_COUNT] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_DEPTH_ATTACHMENT,
                                              GL_COLOR_ATTACHMENT2};
        for (int k = 0; k < (r->pl.velocity ? RES_COUNT : RES_MOTION); k++) {
            glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, ms[k]);
            glTextureStorage2DMultisample(*ms[k], MSAA_SAMPLES, k_forward_resources[k].format, r->width, r->height,
                                          GL_TRUE);
            glNamedFramebufferTexture(t->msaa_fbo, att[k], *ms[k], 0);
        }
        glNamedFramebufferDrawBuffers(t->msaa_fbo, outputs, bufs);
        fs_status st = check_fbo(t->msaa_fbo, "MSAA ring", r->width, r->height);
        if (st != FS_OK)
            return st;
    }
    if (r->pl.taa) {
        static const GLenum bufs3[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
        int outputs = r->pl.taa_disocclusion ? 3 : 2;
        for (int k = 0; k < 2; k++) {
            glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &r->taa_color[k]);
            glTextureStorage3D(r->taa_color[k], 1, TAA_HISTORY_COLOR, r->width, r->height, n);
            glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &r->taa_coverage[k]);
            glTextureStorage3D(r->taa_coverage[k], 1, TAA_HISTORY_COVERAGE, r->width, r->height, n);
            if (r->pl.taa_disocclusion) { /* each history pixel's nearest depth (taa.frag) */
                glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &r->taa_depth[k]);
                glTextureStorage3D(r->taa_depth[k], 1, TAA_HISTORY_DEPTH, r->width, r->height, n);
                glTextureParameteri(r->taa_depth[k], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
                glTextureParameteri(r->taa_depth[k], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
                glTextureParameteri(r->taa_depth[k], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
                glTextureParameteri(r->taa_depth[k], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            }
            for (int i = 0; i < n; i++) {
                glCreateFramebuffers(1, &r->taa_fbo[k][i]);
                glNamedFramebufferTextureLayer(r->taa_fbo[k][i], GL_COLOR_ATTACHMENT0, r->taa_color[k], 0, i);
                glNamedFramebufferTextureLayer(r->taa_fbo[k][i], GL_COLOR_ATTACHMENT1, r->taa_coverage[k], 0, i);
                if (r->pl.taa_disocclusion)
                    glNamedFramebufferTextureLayer(r->taa_fbo[k][i], GL_COLOR_ATTACHMENT2, r->taa_depth[k], 0, i);
                glNamedFramebufferDrawBuffers(r->taa_fbo[k][i], outputs, bufs3);
                fs_status st = check_fbo(r->taa_fbo[k][i], "TAA history", r->width, r->height);
                if (st != FS_OK)
                    return st;
            }
        }
        glCreateVertexArrays(1, &r->empty_vao);
        glCreateSamplers(1, &r->taa_sampler);
        glSamplerParameteri(r->taa_sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glSamplerParameteri(r->taa_sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glSamplerParameteri(r->taa_sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(r->taa_sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    if (plan_find(&r->pl, PLAN_PASS_FORWARD_LIST, ALPHA_MODE_DEFAULT)) {
        glCreateTextures(GL_TEXTURE_2D, 1, &r->list_head);
        glTextureStorage2D(r->list_head, 1, GL_R32UI, r->width, r->height);
        /* An integer texture with (the default) linear filtering is incomplete: reads return 0. */
        glTextureParameteri(r->list_head, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(r->list_head, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glCreateTextures(GL_TEXTURE_2D, 1, &r->list_color);
        glTextureStorage2D(r->list_color, 1, GL_RGBA32F, r->width, r->height);
        glCreateTextures(GL_TEXTURE_2D, 1, &r->list_coverage);
        glTextureStorage2D(r->list_coverage, 1, GL_RG32F, r->width, r->height);
        glCreateFramebuffers(1, &r->list_fbo);
        glNamedFramebufferTexture(r->list_fbo, GL_COLOR_ATTACHMENT0, r->list_color, 0);
        glNamedFramebufferTexture(r->list_fbo, GL_COLOR_ATTACHMENT1, r->list_coverage, 0);
        glNamedFramebufferDrawBuffers(r->list_fbo, 2, bufs);
        fs_status cst = check_fbo(r->list_fbo, "list resolve", r->width, r->height);
        if (cst != FS_OK)
            return cst;
        if (!r->empty_vao)
            glCreateVertexArrays(1, &r->empty_vao);
        glCreateBuffers(1, &r->list_counter);
        glNamedBufferStorage(r->list_counter, sizeof(GLuint), NULL, GL_DYNAMIC_STORAGE_BIT);
        if (renderer_reserve_list_nodes(r, r->list_initial) != FS_OK) {
            log_error("GL: no room for %llu fragment-list nodes (%.0f MB)", (unsigned long long)r->list_initial,
                      (double)(r->list_initial * sizeof(abuffer_node)) / 1048576.0);
            return FS_ERR_NOMEM;
        }
    }
    if (!r->pl.composite)
        return FS_OK;
    int outs = r->pl.debug_channels ? OUT_COUNT : OUT_DEBUG; /* the debug target only when asked */
    glCreateFramebuffers(1, &r->out_fbo);
    for (int k = 0; k < outs; k++) {
        glCreateTextures(GL_TEXTURE_2D, 1, &r->out_tex[k]);
        glTextureStorage2D(r->out_tex[k], 1, k_composite_resources[k].format, r->width, r->height);
        glNamedFramebufferTexture(r->out_fbo, bufs[k], r->out_tex[k], 0);
    }
    glNamedFramebufferDrawBuffers(r->out_fbo, outs, bufs);
    fs_status st = renderer_composite_create(r);
    if (st != FS_OK)
        return st;
    glCreateSamplers(1, &r->ring_sampler);
    glSamplerParameteri(r->ring_sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(r->ring_sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(r->ring_sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(r->ring_sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return check_fbo(r->out_fbo, "composite", r->width, r->height);
}

/* >>lists */
uint64_t renderer_list_nodes_max(void)
{
    GLint64 texels = 0;
    glGetInteger64v(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
    uint64_t n = (uint64_t)(texels > 0 ? texels : 0) / ABUFFER_NODE_TEXELS;
    return n < ABUFFER_END ? n : ABUFFER_END; /* indices must stay below the end marker */
}

fs_status renderer_reserve_list_nodes(renderer *r, uint64_t nodes)
{
    FS_ASSERT(r->list_head);
    uint64_t max = renderer_list_nodes_max();
    nodes = nodes < max ? nodes : max;
    if (nodes <= r->list_capacity)
        return FS_OK;
    while (glGetError() != GL_NO_ERROR) {
    }
    /* The new store first: when the GL has no room for it, the old one stays. */
    GLuint buf, tex;
    glCreateBuffers(1, &buf);
    glNamedBufferStorage(buf, (GLsizeiptr)(nodes * sizeof(abuffer_node)), NULL, 0);
    glCreateTextures(GL_TEXTURE_BUFFER, 1, &tex);
    glTextureBuffer(tex, GL_RGBA32UI, buf);
    if (glGetError() != GL_NO_ERROR) {
        glDeleteTextures(1, &tex);
        glDeleteBuffers(1, &buf);
        return FS_ERR_NOMEM;
    }
    glDeleteTextures(1, &r->list_nodes_tex);
    glDeleteBuffers(1, &r->list_nodes);
    r->list_nodes = buf;
    r->list_nodes_tex = tex;
    r->list_capacity = nodes;
    free(r->list_node_buf); /* the read-back scratch follows the store's size on next use */
    r->list_node_buf = NULL;
    r->list_node_buf_cap = 0;
    return FS_OK;
}
