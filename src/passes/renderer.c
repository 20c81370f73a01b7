/* renderer.c: the renderer's lifetime: its programs (one per plan pass, TAA, composite, list
 * resolve), renderer_create and renderer_destroy. The other files are listed in
 * renderer_internal.h. */
#include "passes/renderer_internal.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include "common/shared_defs.h"
#include "core/log.h"
#include "gl/gl_device.h"
#include "gl/gl_program.h"

/* >>programs */
/* Builds the program of a plan pass (its shaders and sorted defines). */
static fs_status build_pass_program(const plan_pass *ps, GLuint *id)
{
    const char *defs[PLAN_MAX_DEFINES];
    for (int i = 0; i < ps->define_count; i++)
        defs[i] = ps->defines[i];
    gpu_program_handle h = {0};
    fs_status st = gl_program_build(&(gl_program_desc){.vs = ps->vs, .gs = ps->gs, .fs = ps->fs, .defines = defs,
                                                       .define_count = ps->define_count, .label = ps->name},
                                    &h);
    *id = h.id;
    return st;
}

/* A program's uniforms, one table per program struct: each name is looked up into the GLint field
 * of the struct at `offset` (-1 where the shader does not use it). UNIFORM(type, field): the field
 * and the uniform share the name. */
typedef struct uniform_slot {
    const char *name;
    size_t offset;
} uniform_slot;
#define UNIFORM(type, field) {#field, offsetof(type, field)}

#define PASS(f) UNIFORM(gpu_program, f)
static const uniform_slot k_pass_uniforms[] = {
    PASS(u_view_proj), PASS(u_has_base_tex), PASS(u_base_color), PASS(u_alpha_cutoff), PASS(u_double_sided),
    PASS(u_mip_bias), PASS(u_mip_scale), PASS(u_eye), PASS(u_light_dir), PASS(u_light_color), PASS(u_ambient),
    PASS(u_hash_scale), PASS(u_hash_kind), PASS(u_hash_aniso), PASS(u_fade_n), PASS(u_frame), PASS(u_time),
    PASS(u_prev_time), PASS(u_draw_order), PASS(u_list_capacity), PASS(u_hash_instance),
    PASS(u_ring_lod), PASS(u_ring_lod_instance), PASS(u_ring_lod_px), PASS(u_alpha_lod_max), PASS(u_count_slot),
    PASS(u_vrs_tile), PASS(u_vrs_viewport),
};
#undef PASS

#define TAA(f) UNIFORM(taa_program, f)
static const uniform_slot k_taa_uniforms[] = {
    TAA(u_layer), TAA(u_size), TAA(u_prev_size), TAA(u_array_px), TAA(u_inv_view_proj), TAA(u_prev_view_proj),
    TAA(u_history_valid), TAA(u_blend), TAA(u_gamma), TAA(u_sparse), TAA(u_rect), TAA(u_prev_rect),
    TAA(u_ring_prev_rect), TAA(u_ring_block), TAA(u_block), TAA(u_cull_gaze_px), TAA(u_cull_principal_px),
    TAA(u_cull_focal_px), TAA(u_ring_hole_deg), TAA(u_prev_inv_view_proj), TAA(u_view_proj),
};
#undef TAA

#define COMP(f) UNIFORM(composite_program, f)
static const uniform_slot k_composite_uniforms[] = {
    COMP(u_display_px), COMP(u_focal_px), COMP(u_principal_px), COMP(u_gaze_px), COMP(u_ring_outer), COMP(u_ring_band), COMP(u_ring_rect),
    COMP(u_ring_block), COMP(u_array_px),
};
#undef COMP

#undef UNIFORM

/* Builds a plan pass's program into *id and looks up its uniforms (`slots`) into `program`, the
 * struct that holds *id. */
static fs_status build_with_uniforms(const plan_pass *ps, GLuint *id, const uniform_slot *slots, size_t count,
                                     void *program)
{
    fs_status st = build_pass_program(ps, id);
    if (st != FS_OK)
        return st;
    for (size_t i = 0; i < count; i++) {
        GLint *loc = (GLint *)((char *)program + slots[i].offset);
        *loc = glGetUniformLocation(*id, slots[i].name);
    }
    return FS_OK;
}

#define COUNT_OF(a) (sizeof(a) / sizeof(a)[0])

static fs_status program_create(const plan_pass *ps, gpu_program *out)
{
    return build_with_uniforms(ps, &out->id, k_pass_uniforms, COUNT_OF(k_pass_uniforms), out);
}

static fs_status taa_create(const plan_pass *ps, taa_program *out)
{
    return build_with_uniforms(ps, &out->id, k_taa_uniforms, COUNT_OF(k_taa_uniforms), out);
}

static fs_status composite_create(const plan_pass *ps, composite_program *out)
{
    return build_with_uniforms(ps, &out->id, k_composite_uniforms, COUNT_OF(k_composite_uniforms), out);
}

/* >>lifetime */
static void name_stages(renderer *r)
{
    r->stage_count = 0;
    if (!r->pl.composite) {
        for (int i = 0; i < r->pl.pass_count; i++)
            snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "%s", r->pl.passes[i].name);
        if (r->pl.list_resolve)
            snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "list resolve");
        if (r->pl.taa)
            snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "taa resolve");
        return;
    }
    for (int i = 0; i < r->pl.layout.count; i++) {
        snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "ring %d (1/%d, all passes)", i,
                 1 << r->pl.layout.rings[i].scale_log2);
        if (r->pl.taa)
            snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "ring %d taa resolve", i);
    }
    snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "composite");
}

/* Plan pass i's VRS twin (none for a pass without one) and, with `counting`, its counting variant. */
static fs_status vrs_programs_create(renderer *r, int i, bool counting)
{
    plan_pass twin, counted;
    if (!plan_pass_vrs(&r->pl.passes[i], &twin))
        return FS_OK;
    fs_status st = program_create(&twin, &r->vrs_programs[i]);
    if (st == FS_OK && counting)
        st = plan_pass_counting(&twin, &counted) ? program_create(&counted, &r->count_vrs_programs[i])
                                                 : FS_ERR_INTERNAL;
    return st;
}

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
    r->list_initial = desc->list_nodes ? desc->list_nodes : 4 * (uint64_t)r->width * (uint64_t)r->height;
    name_stages(r);
    fs_status st = FS_OK;
    for (int i = 0; i < r->pl.pass_count && st == FS_OK; i++)
        st = program_create(&r->pl.passes[i], &r->programs[i]);
    for (int i = 0; i < r->pl.pass_count && st == FS_OK && desc->count_fragments; i++) {
        plan_pass counting;
        st = plan_pass_counting(&r->pl.passes[i], &counting) ? program_create(&counting, &r->count_programs[i])
                                                              : FS_ERR_INTERNAL;
    }
    for (int i = 0; i < r->pl.pass_count && st == FS_OK && r->pl.vrs; i++)
        st = vrs_programs_create(r, i, desc->count_fragments);
    if (st == FS_OK && desc->count_fragments) {
        glCreateBuffers(1, &r->count_buf);
        glNamedBufferStorage(r->count_buf, sizeof(GLuint) * COUNT_WORDS, NULL, GL_DYNAMIC_STORAGE_BIT);
    }
    if (st == FS_OK && desc->count_fragments && r->pl.vrs && r->height % 4 != 0)
        log_warn("a display %d rows high (not a multiple of 4): VRS's coarse-shading invocations are an upper bound "
                 "(docs/benchmarks.md \"VRS: coarse-shading invocations\")", r->height);
    if (st == FS_OK && desc->count_fragments && r->pl.vrs) {
        glCreateBuffers(1, &r->count_keys_buf);
        glNamedBufferStorage(r->count_keys_buf, sizeof(GLuint) * (size_t)r->width * (size_t)r->height, NULL,
                             GL_DYNAMIC_STORAGE_BIT);
    }
    if (st == FS_OK && r->pl.composite)
        st = composite_create(&r->pl.composite_pass, &r->comp);
    if (st == FS_OK && r->pl.composite_tiles)
        st = composite_create(&r->pl.composite_tile_pass, &r->comp_tile);
    if (st == FS_OK && r->pl.taa)
        st = taa_create(&r->pl.taa_pass, &r->taa);
    if (st == FS_OK && r->pl.list_resolve) {
        st = build_pass_program(&r->pl.list_resolve_pass, &r->list_prog);
        r->list_u_capacity = glGetUniformLocation(r->list_prog, "u_capacity");
    }
    if (st == FS_OK)
        st = renderer_upload_scene(r);
    if (st == FS_OK)
        st = renderer_create_targets(r);
    if (st == FS_OK && r->pl.vrs)
        st = renderer_vrs_create(r);
    r->target_bpp = renderer_target_bytes(r);
    if (st == FS_OK && r->timers) {
        glGenQueries(r->stage_count, r->time_queries);
        r->stat_queries_on = gl_device_has_pipeline_stats();
        if (r->stat_queries_on)
            glGenQueries(r->stage_count * RENDERER_STAT_TARGETS, &r->stat_queries[0][0]);
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
                    glDeleteBuffers(2, ga->prims[p].card_vbo);
                    glDeleteBuffers(1, &ga->prims[p].tri_vbo);
                }
            if (ga->textures)
                glDeleteTextures(as->image_count, ga->textures);
            if (ga->samplers)
                glDeleteSamplers(as->material_count, ga->samplers);
            if (ga->castano)
                glDeleteTextures(as->material_count, ga->castano);
            free(ga->fade_n);
            glDeleteBuffers(1, &ga->instance_vbo);
            glDeleteBuffers(1, &ga->sway_vbo);
            free(ga->prims);
            free(ga->textures);
            free(ga->samplers);
            free(ga->castano);
            free(ga->instance_ids);
            free(ga->visible);
            free(ga->cull_pad);
        }
        free(r->assets);
    }
    free(r->blend_order);
    for (int i = 0; i < r->pl.pass_count; i++)
        glDeleteProgram(r->programs[i].id);
    glDeleteProgram(r->comp.id);
    glDeleteProgram(r->comp_tile.id);
    glDeleteVertexArrays(1, &r->tile_vao);
    glDeleteBuffers(1, &r->tile_vbo);
    free(r->tile_verts);
    free(r->squares);
    free(r->read_buf);
    free(r->read_row);
    glDeleteTextures(1, &r->list_head);
    glDeleteTextures(1, &r->list_color);
    glDeleteTextures(1, &r->list_coverage);
    glDeleteFramebuffers(1, &r->list_fbo);
    glDeleteProgram(r->list_prog);
    glDeleteTextures(1, &r->list_nodes_tex);
    glDeleteBuffers(1, &r->list_nodes);
    glDeleteBuffers(1, &r->list_counter);
    free(r->list_head_buf);
    free(r->list_node_buf);
    glDeleteFramebuffers(MAX_FOV_RINGS, r->rt.fbo);
    glDeleteTextures(1, &r->rt.color);
    glDeleteTextures(1, &r->rt.coverage);
    glDeleteTextures(1, &r->rt.depth);
    glDeleteTextures(1, &r->rt.motion);
    glDeleteTextures(1, &r->rt.msaa_motion);
    glDeleteFramebuffers(1, &r->rt.msaa_fbo);
    glDeleteTextures(1, &r->rt.msaa_color);
    glDeleteTextures(1, &r->rt.msaa_coverage);
    glDeleteTextures(1, &r->rt.msaa_depth);
    glDeleteProgram(r->taa.id);
    glDeleteSamplers(1, &r->taa_sampler);
    for (int k = 0; k < 2; k++) {
        glDeleteFramebuffers(MAX_FOV_RINGS, r->taa_fbo[k]);
        glDeleteTextures(1, &r->taa_color[k]);
        glDeleteTextures(1, &r->taa_coverage[k]);
        glDeleteTextures(1, &r->taa_depth[k]);
    }
    glDeleteFramebuffers(1, &r->out_fbo);
    glDeleteTextures(OUT_COUNT, r->out_tex);
    glDeleteVertexArrays(1, &r->empty_vao);
    glDeleteSamplers(1, &r->ring_sampler);
    if (r->timers) {
        glDeleteQueries(r->stage_count, r->time_queries);
        if (r->stat_queries_on)
            glDeleteQueries(r->stage_count * RENDERER_STAT_TARGETS, &r->stat_queries[0][0]);
    }
    for (int i = 0; i < r->pl.pass_count; i++)
        glDeleteProgram(r->count_programs[i].id);
    glDeleteBuffers(1, &r->count_buf);
    glDeleteTextures(1, &r->vrs_tex);
    free(r->vrs_rates);
    free(r->vrs_rects);
    for (int i = 0; i < r->pl.pass_count; i++) {
        glDeleteProgram(r->vrs_programs[i].id);
        glDeleteProgram(r->count_vrs_programs[i].id);
    }
    glDeleteBuffers(1, &r->count_keys_buf);
    free(r);
}
