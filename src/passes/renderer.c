/* renderer.c: scene upload, program cache, forward passes, readback. */
#include "passes/renderer.h"

#include <epoxy/gl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/shared_defs.h"
#include "core/log.h"
#include "core/progress.h"
#include "gl/gl_device.h"
#include "gl/gl_program.h"
#include "scene/mip.h"

/* >>resources
 * What the forward pass reads and writes (STYLE.md: each pass declares its resources up front). */
typedef struct pass_resource {
    const char *name, *desc;
    GLenum format;
    bool output, optional;
} pass_resource;

static const pass_resource k_forward_resources[] = {
    {"color", "linear premultiplied radiance, A = opacity", GL_RGBA16F, true, false},
    {"coverage", "opacity contributed by alpha-mapped surfaces", GL_R16F, true, false},
    {"depth", "depth buffer", GL_DEPTH_COMPONENT24, true, false},
};
enum { RES_COLOR, RES_COVERAGE, RES_DEPTH, RES_COUNT };

/* >>types */
typedef struct gpu_program {
    GLuint id;
    GLint u_view_proj, u_has_base_tex, u_base_color, u_alpha_cutoff, u_double_sided, u_mip_bias, u_eye,
        u_light_dir, u_light_color, u_ambient;
} gpu_program;

typedef struct gpu_prim {
    GLuint vao, vbo[4], ibo;
    GLsizei index_count;
} gpu_prim;

typedef struct gpu_asset {
    gpu_prim *prims;
    GLuint *textures;       /* per image */
    GLuint *samplers;       /* per material */
    GLuint instance_vbo;    /* mat4 per instance of this asset, in instance_ids order */
    int *instance_ids;      /* scene instance index of each slot */
    int instance_count;
} gpu_asset;

struct renderer {
    const scene *sc;
    plan pl;
    gpu_asset *assets;
    gpu_program programs[PLAN_MAX_PASSES]; /* one per plan pass, same index */
    GLuint fbo, tex[RES_COUNT];
    int width, height;
    bool timers;
    GLuint time_queries[PLAN_MAX_PASSES];
    GLuint frag_query;
    bool stats_pending;
    bool pass_sync;
    double pass_wall_ms[PLAN_MAX_PASSES];
};

/* >>programs */
static fs_status program_create(const plan_pass *ps, gpu_program *out)
{
    const char *defs[PLAN_MAX_DEFINES];
    for (int i = 0; i < ps->define_count; i++)
        defs[i] = ps->defines[i];
    gpu_program_handle h;
    fs_status st = gl_program_build(&(gl_program_desc){.vs = ps->vs, .fs = ps->fs, .defines = defs,
                                                       .define_count = ps->define_count, .label = ps->name},
                                    &h);
    if (st != FS_OK)
        return st;
    GLuint p = h.id;
    out->id = p;
    out->u_view_proj = glGetUniformLocation(p, "u_view_proj");
    out->u_has_base_tex = glGetUniformLocation(p, "u_has_base_tex");
    out->u_base_color = glGetUniformLocation(p, "u_base_color");
    out->u_alpha_cutoff = glGetUniformLocation(p, "u_alpha_cutoff");
    out->u_double_sided = glGetUniformLocation(p, "u_double_sided");
    out->u_mip_bias = glGetUniformLocation(p, "u_mip_bias");
    out->u_eye = glGetUniformLocation(p, "u_eye");
    out->u_light_dir = glGetUniformLocation(p, "u_light_dir");
    out->u_light_color = glGetUniformLocation(p, "u_light_color");
    out->u_ambient = glGetUniformLocation(p, "u_ambient");
    return FS_OK;
}

/* >>upload */
/* Textures are stored as RGBA16 UNORM, linear premultiplied. 16-bit unorm holds every 8-bit
 * value k/255 exactly (k/255 = 257k/65535), so a level-0 alpha equal to a material's cutoff
 * compares exactly as glTF says (alpha >= cutoff); RGBA16F would round 51/255 below a 0.2 cutoff.
 * It also keeps 1/65535 precision for dark premultiplied colour in the averaged mips. */
static GLuint upload_image(const image_rgba8 *img, fs_status *st)
{
    mip_chain mc;
    *st = mip_chain_build(img, &mc);
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

static void upload_prim(const prim *p, gpu_prim *g, GLuint instance_vbo)
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
    glNamedBufferStorage(g->ibo, (GLsizeiptr)(sizeof(uint32_t) * p->index_count), p->indices, 0);
    glVertexArrayElementBuffer(g->vao, g->ibo);
    g->index_count = (GLsizei)p->index_count;
}

static fs_status upload_scene(renderer *r)
{
    const scene *sc = r->sc;
    r->assets = calloc((size_t)sc->asset_count + 1, sizeof *r->assets);
    if (!r->assets)
        return FS_ERR_NOMEM;
    for (int a = 0; a < sc->asset_count; a++) {
        const asset *as = &sc->assets[a];
        gpu_asset *ga = &r->assets[a];
        for (int i = 0; i < sc->instance_count; i++)
            ga->instance_count += sc->instances[i].asset == a;
        if (ga->instance_count == 0)
            continue; /* nothing places it: nothing to upload */
        ga->instance_ids = malloc(sizeof(int) * (size_t)ga->instance_count);
        mat4 *mats = malloc(sizeof(mat4) * (size_t)ga->instance_count);
        ga->prims = calloc((size_t)as->prim_count + 1, sizeof *ga->prims);
        ga->textures = calloc((size_t)as->image_count + 1, sizeof(GLuint));
        ga->samplers = calloc((size_t)as->material_count + 1, sizeof(GLuint));
        if (!ga->instance_ids || !mats || !ga->prims || !ga->textures || !ga->samplers) {
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
        for (int i = 0; i < as->image_count; i++) {
            fs_status st;
            ga->textures[i] = upload_image(&as->images[i], &st);
            if (st != FS_OK)
                return st;
        }
        for (int m = 0; m < as->material_count; m++)
            ga->samplers[m] = make_sampler(&as->materials[m]);
        for (int p = 0; p < as->prim_count; p++)
            upload_prim(&as->prims[p], &ga->prims[p], ga->instance_vbo);
    }
    return FS_OK;
}

/* >>targets */
static fs_status create_targets(renderer *r)
{
    glCreateFramebuffers(1, &r->fbo);
    for (int i = 0; i < RES_COUNT; i++) {
        glCreateTextures(GL_TEXTURE_2D, 1, &r->tex[i]);
        glTextureStorage2D(r->tex[i], 1, k_forward_resources[i].format, r->width, r->height);
    }
    glNamedFramebufferTexture(r->fbo, GL_COLOR_ATTACHMENT0, r->tex[RES_COLOR], 0);
    glNamedFramebufferTexture(r->fbo, GL_COLOR_ATTACHMENT1, r->tex[RES_COVERAGE], 0);
    glNamedFramebufferTexture(r->fbo, GL_DEPTH_ATTACHMENT, r->tex[RES_DEPTH], 0);
    static const GLenum bufs[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(r->fbo, 2, bufs);
    GLenum s = glCheckNamedFramebufferStatus(r->fbo, GL_FRAMEBUFFER);
    if (s != GL_FRAMEBUFFER_COMPLETE) {
        log_error("GL: forward targets %dx%d incomplete (0x%x)", r->width, r->height, s);
        return FS_ERR_GL;
    }
    return FS_OK;
}

/* >>lifetime */
renderer *renderer_create(const renderer_desc *desc, fs_status *status)
{
    FS_ASSERT(desc && desc->scene && desc->plan && gl_device_is_valid());
    renderer *r = calloc(1, sizeof *r);
    if (!r) {
        *status = FS_ERR_NOMEM;
        return NULL;
    }
    r->sc = desc->scene;
    r->pl = *desc->plan;
    r->width = r->pl.width;
    r->height = r->pl.height;
    r->timers = desc->timers;
    fs_status st = FS_OK;
    for (int i = 0; i < r->pl.pass_count && st == FS_OK; i++)
        st = program_create(&r->pl.passes[i], &r->programs[i]);
    if (st == FS_OK)
        st = upload_scene(r);
    if (st == FS_OK)
        st = create_targets(r);
    if (st == FS_OK && r->timers) {
        glGenQueries(PLAN_MAX_PASSES, r->time_queries);
        if (gl_device_has_pipeline_stats())
            glGenQueries(1, &r->frag_query);
    }
    if (st != FS_OK) {
        renderer_destroy(r);
        *status = st;
        return NULL;
    }
    *status = FS_OK;
    return r;
}

void renderer_destroy(renderer *r)
{
    if (!r)
        return;
    if (r->assets) {
        for (int a = 0; a < r->sc->asset_count; a++) {
            gpu_asset *ga = &r->assets[a];
            const asset *as = &r->sc->assets[a];
            if (ga->prims)
                for (int p = 0; p < as->prim_count; p++) {
                    glDeleteVertexArrays(1, &ga->prims[p].vao);
                    glDeleteBuffers(4, ga->prims[p].vbo);
                    glDeleteBuffers(1, &ga->prims[p].ibo);
                }
            if (ga->textures)
                glDeleteTextures(as->image_count, ga->textures);
            if (ga->samplers)
                glDeleteSamplers(as->material_count, ga->samplers);
            glDeleteBuffers(1, &ga->instance_vbo);
            free(ga->prims);
            free(ga->textures);
            free(ga->samplers);
            free(ga->instance_ids);
        }
        free(r->assets);
    }
    for (int i = 0; i < r->pl.pass_count; i++)
        glDeleteProgram(r->programs[i].id);
    glDeleteFramebuffers(1, &r->fbo);
    glDeleteTextures(RES_COUNT, r->tex);
    if (r->timers) {
        glDeleteQueries(PLAN_MAX_PASSES, r->time_queries);
        if (r->frag_query)
            glDeleteQueries(1, &r->frag_query);
    }
    free(r);
}

/* >>draw */
static void set_frame_uniforms(const renderer *r, const gpu_program *pg, const frame_record *fr)
{
    const light_desc *L = &r->sc->light;
    glProgramUniformMatrix4fv(pg->id, pg->u_view_proj, 1, GL_FALSE, fr->view_proj.m);
    glProgramUniform3f(pg->id, pg->u_eye, fr->camera.position.x, fr->camera.position.y, fr->camera.position.z);
    glProgramUniform3f(pg->id, pg->u_light_dir, L->direction.x, L->direction.y, L->direction.z);
    glProgramUniform3f(pg->id, pg->u_light_color, L->color.x, L->color.y, L->color.z);
    glProgramUniform3f(pg->id, pg->u_ambient, L->ambient.x, L->ambient.y, L->ambient.z);
    glProgramUniform1f(pg->id, pg->u_mip_bias, 0.0f);
}

static void set_material(const gpu_program *pg, const gpu_asset *ga, const asset *as, int mi)
{
    const material *m = &as->materials[mi];
    bool tex = m->base_color_image >= 0;
    glProgramUniform1i(pg->id, pg->u_has_base_tex, tex);
    glProgramUniform4fv(pg->id, pg->u_base_color, 1, m->base_color);
    glProgramUniform1f(pg->id, pg->u_alpha_cutoff, m->alpha_cutoff);
    glProgramUniform1i(pg->id, pg->u_double_sided, m->double_sided);
    glBindTextureUnit(TEX_UNIT_BASE_COLOR, tex ? ga->textures[m->base_color_image] : 0);
    glBindSampler(TEX_UNIT_BASE_COLOR, ga->samplers[mi]);
    if (m->double_sided)
        glDisable(GL_CULL_FACE);
    else
        glEnable(GL_CULL_FACE);
}

/* Which pass draws a primitive of material m. */
static bool prim_in_pass(const renderer *r, const material *m, const plan_pass *ps)
{
    switch (ps->kind) {
    case PLAN_PASS_FORWARD_OPAQUE: return m->alpha_kind == ALPHA_KIND_OPAQUE;
    case PLAN_PASS_FORWARD_MASK: return m->alpha_kind == ALPHA_KIND_MASK && plan_material_mode(&r->pl, m) == ps->mode;
    case PLAN_PASS_FORWARD_BLEND: return m->alpha_kind == ALPHA_KIND_BLEND;
    }
    return false;
}

/* Draws the primitives of asset `a` that belong to pass `ps`, for `count` instances starting at
 * instance slot `first`. */
static void draw_asset(const renderer *r, const gpu_program *pg, const plan_pass *ps, int a, int first, int count)
{
    const gpu_asset *ga = &r->assets[a];
    const asset *as = &r->sc->assets[a];
    for (int p = 0; p < as->prim_count; p++) {
        const material *m = &as->materials[as->prims[p].material];
        if (!prim_in_pass(r, m, ps))
            continue;
        set_material(pg, ga, as, as->prims[p].material);
        glBindVertexArray(ga->prims[p].vao);
        glDrawElementsInstancedBaseInstance(GL_TRIANGLES, ga->prims[p].index_count, GL_UNSIGNED_INT, NULL, count,
                                            (GLuint)first);
    }
}

static void draw_instanced(const renderer *r, const gpu_program *pg, const plan_pass *ps)
{
    for (int a = 0; a < r->sc->asset_count; a++)
        if (r->assets[a].instance_count > 0)
            draw_asset(r, pg, ps, a, 0, r->assets[a].instance_count);
}

typedef struct sort_item {
    float dist2;
    int asset, slot;
} sort_item;

static int cmp_far_first(const void *a, const void *b)
{
    float da = ((const sort_item *)a)->dist2, db = ((const sort_item *)b)->dist2;
    return (da < db) - (da > db);
}

/* BLEND: every instance separately, farthest first (sorted per instance by its bounds centre). */
static void draw_blend_sorted(const renderer *r, const gpu_program *pg, const plan_pass *ps, const frame_record *fr)
{
    int n = 0;
    for (int a = 0; a < r->sc->asset_count; a++)
        n += r->assets[a].instance_count;
    sort_item *items = malloc(sizeof *items * (size_t)(n + 1));
    if (!items)
        return;
    n = 0;
    for (int a = 0; a < r->sc->asset_count; a++) {
        const asset *as = &r->sc->assets[a];
        bool has_blend = false;
        for (int p = 0; p < as->prim_count; p++)
            has_blend |= prim_in_pass(r, &as->materials[as->prims[p].material], ps);
        if (!has_blend)
            continue;
        vec3 c = v3_scale(v3_add(as->bounds_min, as->bounds_max), 0.5f);
        for (int s = 0; s < r->assets[a].instance_count; s++) {
            vec3 w = m4_point(r->sc->instances[r->assets[a].instance_ids[s]].transform, c);
            vec3 d = v3_sub(w, fr->camera.position);
            items[n++] = (sort_item){v3_dot(d, d), a, s};
        }
    }
    qsort(items, (size_t)n, sizeof *items, cmp_far_first);
    for (int i = 0; i < n; i++)
        draw_asset(r, pg, ps, items[i].asset, items[i].slot, 1);
    free(items);
}

fs_status renderer_draw(renderer *r, const frame_record *fr)
{
    const light_desc *L = &r->sc->light;
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    glViewport(0, 0, r->width, r->height);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    const float sky[4] = {L->sky.x, L->sky.y, L->sky.z, 0.0f}; /* A = 0: no geometry */
    const float zero[4] = {0, 0, 0, 0};
    const float one = 1.0f;
    glClearNamedFramebufferfv(r->fbo, GL_COLOR, 0, sky);
    glClearNamedFramebufferfv(r->fbo, GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(r->fbo, GL_DEPTH, 0, &one);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    if (r->frag_query)
        glBeginQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB, r->frag_query);
    if (r->pass_sync)
        glFinish();
    double t_prev = time_now();
    for (int i = 0; i < r->pl.pass_count; i++) {
        const plan_pass *ps = &r->pl.passes[i];
        const gpu_program *pg = &r->programs[i];
        if (r->timers)
            glBeginQuery(GL_TIME_ELAPSED, r->time_queries[i]);
        glUseProgram(pg->id);
        set_frame_uniforms(r, pg, fr);
        if (ps->kind == PLAN_PASS_FORWARD_BLEND) {
            glEnable(GL_BLEND);
            glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); /* premultiplied "over" */
            glDepthMask(GL_FALSE);
            draw_blend_sorted(r, pg, ps, fr);
            glDepthMask(GL_TRUE);
            glDisable(GL_BLEND);
        } else {
            draw_instanced(r, pg, ps);
        }
        if (r->timers)
            glEndQuery(GL_TIME_ELAPSED);
        r->pass_wall_ms[i] = -1.0;
        if (r->pass_sync) {
            glFinish();
            double t = time_now();
            r->pass_wall_ms[i] = (t - t_prev) * 1e3;
            t_prev = t;
        }
    }
    if (r->frag_query)
        glEndQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB);
    r->stats_pending = r->timers;
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return FS_OK;
}

void renderer_set_pass_sync(renderer *r, bool on)
{
    r->pass_sync = on;
}

void renderer_finish(renderer *r)
{
    (void)r;
    glFinish();
}

renderer_stats renderer_last_stats(renderer *r)
{
    renderer_stats s = {0};
    s.pass_count = r->pl.pass_count;
    s.fragments = -1;
    for (int i = 0; i < r->pl.pass_count; i++) {
        snprintf(s.pass_names[i], sizeof s.pass_names[i], "%s", r->pl.passes[i].name);
        s.pass_ms[i] = -1.0;
        s.pass_wall_ms[i] = r->pass_wall_ms[i];
        if (r->stats_pending) {
            GLuint64 ns = 0;
            glGetQueryObjectui64v(r->time_queries[i], GL_QUERY_RESULT, &ns);
            s.pass_ms[i] = (double)ns * 1e-6;
        }
    }
    if (r->stats_pending && r->frag_query) {
        GLuint64 n = 0;
        glGetQueryObjectui64v(r->frag_query, GL_QUERY_RESULT, &n);
        s.fragments = (long long)n;
    }
    return s;
}

/* >>readback */
static void flip_rows(float *p, int w, int h, int comps)
{
    size_t row = (size_t)w * (size_t)comps;
    float *tmp = malloc(sizeof(float) * row);
    if (!tmp)
        return;
    for (int y = 0; y < h / 2; y++) {
        float *a = p + (size_t)y * row, *b = p + (size_t)(h - 1 - y) * row;
        memcpy(tmp, a, sizeof(float) * row);
        memcpy(a, b, sizeof(float) * row);
        memcpy(b, tmp, sizeof(float) * row);
    }
    free(tmp);
}

fs_status renderer_read(renderer *r, exr_image *img)
{
    size_t n = (size_t)r->width * (size_t)r->height;
    float *rgba = malloc(sizeof(float) * 4 * n);
    if (!rgba || !exr_image_init(img, r->width, r->height)) {
        free(rgba);
        return FS_ERR_NOMEM;
    }
    static const char *const names[] = {"R", "G", "B", "A", "coverage"};
    float *planes[5];
    for (int c = 0; c < 5; c++)
        if (!(planes[c] = exr_image_add_channel(img, names[c]))) {
            free(rgba);
            exr_image_free(img);
            return FS_ERR_NOMEM;
        }
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(r->tex[RES_COLOR], 0, GL_RGBA, GL_FLOAT, (GLsizei)(sizeof(float) * 4 * n), rgba);
    glGetTextureImage(r->tex[RES_COVERAGE], 0, GL_RED, GL_FLOAT, (GLsizei)(sizeof(float) * n), planes[4]);
    flip_rows(rgba, r->width, r->height, 4); /* GL rows are bottom first, EXR top first */
    flip_rows(planes[4], r->width, r->height, 1);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 4; c++)
            planes[c][i] = rgba[4 * i + (size_t)c];
    free(rgba);
    return FS_OK;
}
