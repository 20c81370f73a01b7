/* renderer_draw.c: one frame (renderer_draw): each ring's culling and forward passes, the exact
 * reference's list pass and resolve, the TAA resolve, then the composite (renderer_composite.c);
 * the settings later frames use, and each stage's timing and statistics queries, covered pixels of
 * full-screen stages and footprint bytes (renderer_stats.c reads them back: renderer_last_stats). */
#include "passes/renderer_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "common/shared_defs.h"
#include "core/log.h"
#include "core/progress.h"
#include "passes/taa_math.h"

/* >>draw */
/* History is valid when there was a previous frame, it was the frame just before, and no camera
 * cut lies between (frame_record.cut). */
static bool taa_history_valid(const renderer *r, const frame_record *fr)
{
    return r->have_prev && !fr->cut && fr->index == r->prev_index + 1;
}

/* Per-card ring LOD: the ring's pixels per world unit at distance 1 (over sqrt(A / AREA_REF) for
 * "simplify:area=A"); 0 where the ring's law holds for every card (common/ring_lod.glsl). */
static float ring_lod_px(const renderer *r, const frame_record *fr, int ring)
{
    if (!r->pl.ring_lod || !ring_lod_ring_is_per_card(&r->pl.ring_lod_spec, &r->pl.layout, ring))
        return 0.0f;
    display_desc dd = frame_display(fr, r->width, r->height);
    /* "simplify:area=A": sides measured in units of sqrt(A / RING_LOD_AREA_REF) ring pixels */
    float area = ring_lod_area(&r->pl.ring_lod_spec) / (float)RING_LOD_AREA_REF;
    return fov_focal_px(&dd) / exp2f((float)r->pl.layout.rings[ring].scale_log2) / sqrtf(area);
}

/* How far (asset units) a per-card ring's enlarged cards may reach beyond an instance's box. A
 * card grows only while its side is below sqrt(RING_LOD_AREA_REF) units of px, and to at most that,
 * so a vertex ends at most (radius / side) * sqrt(RING_LOD_AREA_REF) ring pixels from the card's
 * centre (which lies in the box): at the box's farthest point from the eye, in world units, over
 * the instance's smallest axis scale. */
static float ring_lod_cull_pad(const gpu_asset *ga, const asset *as, const mat4 *model, vec3 eye, float px)
{
    float far = 0.0f;
    for (int c = 0; c < 8; c++) {
        vec3 q = v3(c & 1 ? as->bounds_max.x : as->bounds_min.x, c & 2 ? as->bounds_max.y : as->bounds_min.y,
                    c & 4 ? as->bounds_max.z : as->bounds_min.z);
        far = fmaxf(far, v3_len(v3_sub(m4_point(*model, q), eye)));
    }
    const float *m = model->m;
    float sx = v3_len(v3(m[0], m[1], m[2])), sy = v3_len(v3(m[4], m[5], m[6])), sz = v3_len(v3(m[8], m[9], m[10]));
    float smin = fmaxf(fminf(sx, fminf(sy, sz)), 1e-20f), smax = fmaxf(sx, fmaxf(sy, sz));
    /* Even the narrowest card spans sqrt(AREA_REF) units of px at the box's farthest point (the
     * shader's measure, the cube root of the volume change, is at least smin): nothing grows. */
    if (ga->lod_side_min * smin * px / fmaxf(far, 1e-20f) >= sqrtf((float)RING_LOD_AREA_REF))
        return 0.0f;
    /* The shader measures a card by the cube root of the instance's volume change: a non-uniform
     * scale can stretch it by up to smax / smin beyond what that predicts. */
    return ga->lod_aspect * sqrtf((float)RING_LOD_AREA_REF) * far / px * (smax / smin) / smin;
}

static void set_frame_uniforms(const renderer *r, const gpu_program *pg, const frame_record *fr, int ring)
{
    const light_desc *L = &r->sc->light;
    glProgramUniformMatrix4fv(pg->id, pg->u_view_proj, 1, GL_FALSE, r->draw_vp.m);
    glProgramUniform3f(pg->id, pg->u_eye, fr->camera.position.x, fr->camera.position.y, fr->camera.position.z);
    glProgramUniform3f(pg->id, pg->u_light_dir, L->direction.x, L->direction.y, L->direction.z);
    glProgramUniform3f(pg->id, pg->u_light_color, L->color.x, L->color.y, L->color.z);
    glProgramUniform3f(pg->id, pg->u_ambient, L->ambient.x, L->ambient.y, L->ambient.z);
    glProgramUniform1f(pg->id, pg->u_mip_bias, r->pl.layout.rings[ring].mip_bias);
    glProgramUniform1f(pg->id, pg->u_mip_scale, exp2f(r->pl.layout.rings[ring].mip_bias));
    const alpha_params *ap = &r->pl.alpha;
    glProgramUniform1f(pg->id, pg->u_hash_scale, ap->hash_scale);
    glProgramUniform1i(pg->id, pg->u_hash_kind, ap->hash_kind);
    glProgramUniform1i(pg->id, pg->u_hash_aniso, ap->anisotropic);
    glProgramUniform1ui(pg->id, pg->u_frame, (GLuint)fr->index);
    if (pg->u_ring_lod >= 0) { /* RING_LOD passes: this ring's law (identity where u = 1) */
        ring_lod_law law = ring_lod_ring_law(&r->pl.ring_lod_spec, &r->pl.layout, ring);
        glProgramUniform3f(pg->id, pg->u_ring_lod, law.a, law.k, law.gain);
        glProgramUniform1f(pg->id, pg->u_ring_lod_px, ring_lod_px(r, fr, ring));
    }
    if (r->pl.sway) {
        glProgramUniform1f(pg->id, pg->u_time, fr->time);
        /* Motion relative to the frame the history holds; none without history. */
        glProgramUniform1f(pg->id, pg->u_prev_time, taa_history_valid(r, fr) ? r->prev_time : fr->time);
    }
}

static void set_material(const renderer *r, const gpu_program *pg, const gpu_asset *ga, const asset *as, int mi)
{
    const material *m = &as->materials[mi];
    bool tex = m->base_color_image >= 0;
    glProgramUniform1i(pg->id, pg->u_has_base_tex, tex);
    glProgramUniform4fv(pg->id, pg->u_base_color, 1, m->base_color);
    glProgramUniform1f(pg->id, pg->u_alpha_cutoff, m->alpha_cutoff);
    glProgramUniform1i(pg->id, pg->u_double_sided, m->double_sided);
    glProgramUniform1f(pg->id, pg->u_fade_n, ga->fade_n[mi]);
    if (pg->u_alpha_lod_max >= 0) /* ALPHA_LOD_CLAMP passes: this material's clamp, or none */
        glProgramUniform1f(pg->id, pg->u_alpha_lod_max, plan_material_alpha_lod_max(&r->pl, m));
    GLuint t = !tex ? 0 : ga->castano[mi] ? ga->castano[mi] : ga->textures[m->base_color_image];
    glBindTextureUnit(TEX_UNIT_BASE_COLOR, t);
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
    /* MASK first, then BLEND: equal depths then order as the stochastic passes' depth test would. */
    case PLAN_PASS_FORWARD_SOLID: return m->alpha_kind == ALPHA_KIND_MASK;
    case PLAN_PASS_FORWARD_LIST: return m->alpha_kind == (r->list_phase == 0 ? ALPHA_KIND_MASK : ALPHA_KIND_BLEND);
    }
    return false;
}

/* Draws the primitives of asset `a` that belong to pass `ps`, for `count` instances starting at
 * instance slot `first`. */
static void draw_asset(renderer *r, const gpu_program *pg, const plan_pass *ps, int a, int first, int count)
{
    const gpu_asset *ga = &r->assets[a];
    const asset *as = &r->sc->assets[a];
    for (int p = 0; p < as->prim_count; p++) {
        const material *m = &as->materials[as->prims[p].material];
        if (!prim_in_pass(r, m, ps))
            continue;
        set_material(r, pg, ga, as, as->prims[p].material);
        if (pg->u_draw_order >= 0) { /* each draw's instances take the next orders (draw_order.glsl) */
            glProgramUniform1ui(pg->id, pg->u_draw_order, r->list_draw_order);
            r->list_draw_order += (uint32_t)count;
        }
        if (pg->u_hash_instance >= 0) /* the hashed modes' layer keys (draw_order.glsl) */
            glProgramUniform1ui(pg->id, pg->u_hash_instance, (GLuint)(ga->slot_base + first));
        if (pg->u_ring_lod_instance >= 0) /* the per-instance rank rotation's key (common/ring_lod.glsl) */
            glProgramUniform1ui(pg->id, pg->u_ring_lod_instance, (GLuint)(ga->slot_base + first));
        glBindVertexArray(ga->prims[p].vao);
        glDrawElementsInstancedBaseInstance(GL_TRIANGLES, ga->prims[p].index_count, GL_UNSIGNED_INT, NULL, count,
                                            (GLuint)first);
    }
}

/* Marks which instances ring `ring` draws: those that may be visible through its frustum (its
 * footprint's cropped projection: inner rings see a narrow cone and skip most instances' vertex
 * work), less, with plan.ring_cull, those whose whole image lies in the ring's hole (the region the
 * finer ring shows alone, fov_ring_cull_deg: it keeps a margin for the filters). Returns how many
 * instances it draws. TAA treats history from the hole as invalid (taa.frag, TAA_RING_CULL). */
static int cull_instances(renderer *r, const frame_record *fr, int ring)
{
    display_desc dd = frame_display(fr, r->width, r->height);
    float hole = r->pl.ring_cull ? fov_ring_cull_deg(&dd, &r->pl.layout, ring) : 0.0f;
    float px = ring_lod_px(r, fr, ring);
    int drawn = 0;
    for (int a = 0; a < r->sc->asset_count; a++) {
        gpu_asset *ga = &r->assets[a];
        const asset *as = &r->sc->assets[a];
        for (int k = 0; k < ga->instance_count; k++) {
            const mat4 *model = &r->sc->instances[ga->instance_ids[k]].transform;
            float d = ga->cull_pad ? ga->cull_pad[k] : 0.0f; /* a swaying instance's box grows */
            /* enlarged cards of a simplifying ring may reach beyond the asset's box (ring_lod.h) */
            bool per_card = px > 0.0f;
            vec3 bmin = r->pl.ring_lod && !per_card ? ga->lod_lo[ring] : as->bounds_min;
            vec3 bmax = r->pl.ring_lod && !per_card ? ga->lod_hi[ring] : as->bounds_max;
            if (per_card)
                d += ring_lod_cull_pad(ga, as, model, fr->camera.position, px);
            vec3 lo = v3_sub(bmin, v3(d, d, d)), hi = v3_add(bmax, v3(d, d, d));
            bool vis = !m4_box_outside_clip(m4_mul(fr->ring_view_proj[ring], *model), lo, hi);
            float rect[4];
            if (vis && hole > 0.0f &&
                m4_box_screen_rect(m4_mul(fr->view_proj, *model), lo, hi, (float)r->width, (float)r->height, rect))
                vis = !fov_rect_within_deg(&dd, fr->gaze_px[0], fr->gaze_px[1], rect, hole);
            ga->visible[k] = vis;
            drawn += vis;
        }
    }
    return drawn;
}

/* Every asset, instanced, in runs of consecutive visible instance slots. */
static void draw_instanced(renderer *r, const gpu_program *pg, const plan_pass *ps)
{
    for (int a = 0; a < r->sc->asset_count; a++) {
        const gpu_asset *ga = &r->assets[a];
        for (int k = 0; k < ga->instance_count;) {
            if (!ga->visible[k]) {
                k++;
                continue;
            }
            int first = k;
            while (k < ga->instance_count && ga->visible[k])
                k++;
            draw_asset(r, pg, ps, a, first, k - first);
        }
    }
}

static int cmp_far_first(const void *a, const void *b)
{
    float da = ((const sort_item *)a)->dist2, db = ((const sort_item *)b)->dist2;
    return (da < db) - (da > db);
}

/* BLEND: every instance separately, farthest first (sorted per instance by its bounds centre). */
static void draw_blend_sorted(renderer *r, const gpu_program *pg, const plan_pass *ps, const frame_record *fr)
{
    sort_item *items = r->blend_order;
    int n = 0;
    for (int a = 0; a < r->sc->asset_count; a++) {
        const asset *as = &r->sc->assets[a];
        bool has_blend = false;
        for (int p = 0; p < as->prim_count; p++)
            has_blend |= prim_in_pass(r, &as->materials[as->prims[p].material], ps);
        if (!has_blend)
            continue;
        vec3 c = v3_scale(v3_add(as->bounds_min, as->bounds_max), 0.5f);
        for (int s = 0; s < r->assets[a].instance_count; s++) {
            if (!r->assets[a].visible[s])
                continue;
            vec3 w = m4_point(r->sc->instances[r->assets[a].instance_ids[s]].transform, c);
            vec3 d = v3_sub(w, fr->camera.position);
            items[n++] = (sort_item){v3_dot(d, d), a, s};
        }
    }
    qsort(items, (size_t)n, sizeof *items, cmp_far_first);
    for (int i = 0; i < n; i++)
        draw_asset(r, pg, ps, items[i].asset, items[i].slot, 1);
}

/* What each stage counts (GL_ARB_pipeline_statistics_query), in renderer_stats order. Primitives:
 * GL_PRIMITIVES_SUBMITTED_ARB, what the draw calls send, rather than GL_CLIPPING_INPUT_PRIMITIVES_ARB:
 * it is fixed by the draw calls alone (index counts x instances the CPU culling lets through), so
 * any GPU reports the same number, while what reaches the clipper is implementation-defined.
 * Beside it, GL_CLIPPING_OUTPUT_PRIMITIVES_ARB: what is left after clipping (and, where the
 * implementation culls there, culling; docs/benchmarks.md "Work counts"). */
static const GLenum k_stat_targets[RENDERER_STAT_TARGETS] = {
    GL_VERTEX_SHADER_INVOCATIONS_ARB, GL_PRIMITIVES_SUBMITTED_ARB, GL_FRAGMENT_SHADER_INVOCATIONS_ARB,
    GL_CLIPPING_OUTPUT_PRIMITIVES_ARB};

/* Timed stage boundaries: GL timer and pipeline statistics queries (when timers are on; one query
 * per target may be active at a time, and stages never nest), wall clock with glFinish when
 * pass_sync is on. */
static void stage_begin(renderer *r, int k)
{
    if (r->timers)
        glBeginQuery(GL_TIME_ELAPSED, r->time_queries[k]);
    if (r->stat_queries_on)
        for (int q = 0; q < RENDERER_STAT_TARGETS; q++)
            glBeginQuery(k_stat_targets[q], r->stat_queries[k][q]);
}

static void stage_end(renderer *r, int k, double *t_prev)
{
    if (r->timers)
        glEndQuery(GL_TIME_ELAPSED);
    if (r->stat_queries_on)
        for (int q = 0; q < RENDERER_STAT_TARGETS; q++)
            glEndQuery(k_stat_targets[q]);
    r->stage_wall_ms[k] = -1.0;
    if (r->pass_sync) {
        glFinish();
        double t = time_now();
        r->stage_wall_ms[k] = (t - *t_prev) * 1e3;
        *t_prev = t;
    }
}

/* Once per frame, where the plan has TAA_COARSE_HISTORY and history is valid: every ring's
 * previous footprint, so that a pixel a saccade moved out of its own ring's footprint can take the
 * innermost coarser ring's history. */
static void taa_set_prev_footprints(renderer *r, const frame_record *fr)
{
    float rects[MAX_FOV_RINGS][4], blocks[MAX_FOV_RINGS];
    for (int k = 0; k < fr->ring_count; k++) {
        const fov_ring_rect *q = &r->prev_rect[k];
        rects[k][0] = (float)q->x0;
        rects[k][1] = (float)q->y0;
        rects[k][2] = (float)q->x1;
        rects[k][3] = (float)q->y1;
        blocks[k] = (float)q->block;
    }
    glProgramUniform4fv(r->taa.id, r->taa.u_ring_prev_rect, fr->ring_count, &rects[0][0]);
    glProgramUniform1fv(r->taa.id, r->taa.u_ring_block, fr->ring_count, blocks);
}

/* TAA of one ring: current (jittered) ring + last frame's resolved ring -> this frame's resolved
 * ring, in the `parity` pair of arrays. */
static void taa_resolve_ring(renderer *r, const frame_record *fr, int ring)
{
    const taa_program *p = &r->taa;
    const fov_ring_rect *rr = &fr->ring_rect[ring];
    bool valid = taa_history_valid(r, fr);
    mat4 inv;
    m4_invert(fr->ring_view_proj[ring], &inv);
    const fov_ring_rect *pr = valid ? &r->prev_rect[ring] : rr;
    glBindFramebuffer(GL_FRAMEBUFFER, r->taa_fbo[r->parity][ring]);
    glViewport(0, 0, rr->width, rr->height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glUseProgram(p->id);
    glProgramUniform1i(p->id, p->u_layer, ring);
    glProgramUniform2f(p->id, p->u_size, (float)rr->width, (float)rr->height);
    glProgramUniform2f(p->id, p->u_prev_size, (float)pr->width, (float)pr->height);
    glProgramUniform2f(p->id, p->u_array_px, (float)r->width, (float)r->height);
    glProgramUniformMatrix4fv(p->id, p->u_inv_view_proj, 1, GL_FALSE, inv.m);
    glProgramUniformMatrix4fv(p->id, p->u_prev_view_proj, 1, GL_FALSE,
                              (valid ? r->prev_vp[ring] : fr->ring_view_proj[ring]).m);
    if (r->pl.taa_disocclusion) {
        mat4 prev_inv;
        m4_invert(valid ? r->prev_vp[ring] : fr->ring_view_proj[ring], &prev_inv);
        glProgramUniformMatrix4fv(p->id, p->u_prev_inv_view_proj, 1, GL_FALSE, prev_inv.m);
        glProgramUniformMatrix4fv(p->id, p->u_view_proj, 1, GL_FALSE, fr->ring_view_proj[ring].m);
        glBindTextureUnit(6, r->taa_depth[1 - r->parity]); /* textureGather: no filtering */
    }
    glProgramUniform1i(p->id, p->u_history_valid, valid);
    glProgramUniform1f(p->id, p->u_blend, r->pl.taa_controls.blend);
    glProgramUniform1f(p->id, p->u_gamma, r->pl.taa_controls.gamma);
    glProgramUniform1f(p->id, p->u_sparse, fmaxf(r->pl.taa_controls.sparse, 0.0f));
    glProgramUniform4f(p->id, p->u_rect, (float)rr->x0, (float)rr->y0, (float)rr->x1, (float)rr->y1);
    glProgramUniform4f(p->id, p->u_prev_rect, (float)pr->x0, (float)pr->y0, (float)pr->x1, (float)pr->y1);
    glProgramUniform1f(p->id, p->u_block, (float)rr->block);
    if (r->pl.ring_cull) {
        glProgramUniform2f(p->id, p->u_cull_gaze_px, r->prev_gaze_px[0], r->prev_gaze_px[1]);
        glProgramUniform2f(p->id, p->u_cull_principal_px, r->prev_principal_px[0], r->prev_principal_px[1]);
        glProgramUniform1f(p->id, p->u_cull_focal_px, r->prev_focal_px);
        glProgramUniform1fv(p->id, p->u_ring_hole_deg, fr->ring_count, r->prev_hole_deg);
    }
    glBindTextureUnit(0, r->rt.color);
    glBindTextureUnit(1, r->rt.coverage);
    glBindTextureUnit(2, r->rt.depth);
    if (r->pl.velocity)
        glBindTextureUnit(5, r->rt.motion);
    glBindTextureUnit(3, r->taa_color[1 - r->parity]);
    glBindTextureUnit(4, r->taa_coverage[1 - r->parity]);
    glBindSampler(3, r->taa_sampler); /* bilinear: the 5-tap Catmull-Rom history fetch */
    glBindSampler(4, r->taa_sampler);
    glBindVertexArray(r->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindSampler(3, 0);
    glBindSampler(4, 0);
    glEnable(GL_DEPTH_TEST);
}

/* The exact reference's list pass: empty lists, then every MASK and then every BLEND fragment in
 * front of the opaque depth appended (early depth test, no depth or colour writes). */
static void draw_lists(renderer *r, const gpu_program *pg, const plan_pass *ps)
{
    const GLuint end = ABUFFER_END, zero = 0;
    glClearTexImage(r->list_head, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &end);
    glClearNamedBufferData(r->list_counter, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glBindImageTexture(ABUFFER_IMAGE_HEAD, r->list_head, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(ABUFFER_IMAGE_NODES, r->list_nodes_tex, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ABUFFER_COUNTER_BINDING, r->list_counter);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glProgramUniform1ui(pg->id, pg->u_list_capacity, (GLuint)r->list_capacity);
    glDepthMask(GL_FALSE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    r->list_draw_order = 0;
    for (r->list_phase = 0; r->list_phase < 2; r->list_phase++)
        draw_instanced(r, pg, ps);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
}

/* The exact reference's lists sorted and composited over the opaque pass (list_resolve.frag). */
static void list_resolve(renderer *r)
{
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glProgramUniform1ui(r->list_prog, r->list_u_capacity, (GLuint)r->list_capacity);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ABUFFER_COUNTER_BINDING, r->list_counter);
    glBindFramebuffer(GL_FRAMEBUFFER, r->list_fbo);
    glViewport(0, 0, r->width, r->height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glUseProgram(r->list_prog);
    /* No sampler objects (the forward passes leave a material's on unit 0): texelFetch only, and
     * an integer texture under a linear-filtering sampler is incomplete. */
    for (GLuint u = 0; u < 4; u++)
        glBindSampler(u, 0);
    glBindTextureUnit(0, r->list_head);
    glBindTextureUnit(1, r->list_nodes_tex);
    glBindTextureUnit(2, r->rt.color);
    glBindTextureUnit(3, r->rt.coverage);
    glBindVertexArray(r->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEnable(GL_DEPTH_TEST);
}

/* Forward pass `ps` with program `pg` (its uniforms set), over what the scissor lets through. */
static void draw_pass(renderer *r, const gpu_program *pg, const plan_pass *ps, const frame_record *fr)
{
    r->list_draw_order = 0;
    if (ps->kind == PLAN_PASS_FORWARD_BLEND) {
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); /* premultiplied "over" */
        glDepthMask(GL_FALSE);
        /* Blended surfaces are see-through: the motion stays that of what lies behind. */
        if (r->pl.velocity)
            glColorMaski(2, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        draw_blend_sorted(r, pg, ps, fr);
        if (r->pl.velocity)
            glColorMaski(2, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthMask(GL_TRUE);
        glDisable(GL_BLEND);
    } else if (ps->kind == PLAN_PASS_FORWARD_MASK && alpha_mode_has(ps->mode, ALPHA_TRAIT_GL_A2C)) {
        glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE);
        glEnable(GL_SAMPLE_ALPHA_TO_ONE);
        draw_instanced(r, pg, ps);
        glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
        glDisable(GL_SAMPLE_ALPHA_TO_ONE);
    } else if (ps->kind == PLAN_PASS_FORWARD_SOLID) {
        /* Pushed back, so that the list pass (GL_LESS) still stores these fragments and any
         * coplanar with them, in draw order: they order among themselves in the resolve. */
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(1.0f, 2.0f);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        draw_instanced(r, pg, ps);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDisable(GL_POLYGON_OFFSET_FILL);
    } else if (ps->kind == PLAN_PASS_FORWARD_LIST) {
        draw_lists(r, pg, ps);
    } else {
        draw_instanced(r, pg, ps);
    }
}

/* VRS foveation (plan.vrs): plan pass i's own program `pg` draws the 1x1 tiles, scissored to their
 * rectangles, exactly as without VRS; its twin (plan_pass_vrs) then draws the whole target and
 * shades the coarser tiles, discarding the 1x1 tiles' fragments. A pixel's fragments all come from
 * one of the two, in the same order as from one draw. */
static void draw_pass_vrs(renderer *r, const gpu_program *pg, int i, const frame_record *fr)
{
    const plan_pass *ps = &r->pl.passes[i];
    const gpu_program *twin = r->counting ? &r->count_vrs_programs[i] : &r->vrs_programs[i];
    if (!twin->id) { /* a pass without a twin (none shades colour under VRS) draws it all */
        draw_pass(r, pg, ps, fr);
        return;
    }
    for (int k = 0; k < r->vrs_rect_count; k++) {
        const int *q = &r->vrs_rects[4 * k];
        glScissor(q[0], q[1], q[2], q[3]);
        draw_pass(r, pg, ps, fr);
    }
    glScissor(0, 0, r->width, r->height);
    if (!r->vrs_coarse)
        return;
    glUseProgram(twin->id);
    set_frame_uniforms(r, twin, fr, 0);
    renderer_vrs_uniforms(r, twin);
    if (r->counting) /* VRS draws one ring: the pass's slot */
        glProgramUniform1ui(twin->id, twin->u_count_slot, (GLuint)i);
    draw_pass(r, twin, ps, fr);
}

/* The forward passes of one ring into its target. `stage` >= 0: time each pass as a stage from
 * there (rings off); < 0: the caller times the ring as a whole. */
static void draw_ring(renderer *r, const frame_record *fr, int ring, int stage, double *t_prev)
{
    const light_desc *L = &r->sc->light;
    GLuint fbo = r->pl.msaa ? r->rt.msaa_fbo : r->rt.fbo[ring];
    const fov_ring_rect *rr = &fr->ring_rect[ring];
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, rr->width, rr->height);
    glScissor(0, 0, rr->width, rr->height);
    glEnable(GL_SCISSOR_TEST);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    const float sky[4] = {L->sky.x, L->sky.y, L->sky.z, 0.0f}; /* A = 0: no geometry */
    const float zero[4] = {0, 0, 0, 0};
    const float one = 1.0f;
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, sky);
    glClearNamedFramebufferfv(fbo, GL_COLOR, 1, zero);
    if (r->pl.velocity)
        glClearNamedFramebufferfv(fbo, GL_COLOR, 2, zero);
    glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &one);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    r->ring_instances[ring] = cull_instances(r, fr, ring);
    if (r->pl.vrs) /* the rate map for this frame's gaze (VRS foveation: one ring) */
        renderer_vrs_frame(r, fr);
    r->draw_vp = fr->ring_view_proj[ring];
    if (r->pl.taa) {
        /* Sub-pixel jitter (Halton 2,3), in this ring's own pixels: an NDC offset of 2 j / size. */
        float j[2];
        taa_jitter((uint32_t)fr->index, r->pl.taa_controls.jitter_length, j);
        mat4 t = m4_translate(v3(2.0f * j[0] / (float)rr->width, 2.0f * j[1] / (float)rr->height, 0.0f));
        r->draw_vp = m4_mul(t, fr->ring_view_proj[ring]);
    }
    for (int i = 0; i < r->pl.pass_count; i++) {
        const plan_pass *ps = &r->pl.passes[i];
        const gpu_program *pg = r->counting ? &r->count_programs[i] : &r->programs[i];
        if (stage >= 0)
            stage_begin(r, stage + i);
        glUseProgram(pg->id);
        set_frame_uniforms(r, pg, fr, ring);
        if (r->counting) /* this ring's and pass's counter (COUNT_FRAGMENTS_BINDING) */
            glProgramUniform1ui(pg->id, pg->u_count_slot, (GLuint)(ring * r->pl.pass_count + i));
        if (r->pl.vrs)
            draw_pass_vrs(r, pg, i, fr);
        else
            draw_pass(r, pg, ps, fr);
        if (stage >= 0)
            stage_end(r, stage + i, t_prev);
    }
    glDisable(GL_SCISSOR_TEST);
    if (r->pl.msaa) {
        /* Resolve the footprint corner, colour, coverage (and motion) separately, into this ring's
         * layer. Motion resolves to the mean of the samples' motions. */
        static const GLenum att[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
        int outputs = r->pl.velocity ? 3 : 2;
        for (int k = 0; k < outputs; k++) {
            glNamedFramebufferReadBuffer(r->rt.msaa_fbo, att[k]);
            glNamedFramebufferDrawBuffer(r->rt.fbo[ring], att[k]);
            glBlitNamedFramebuffer(r->rt.msaa_fbo, r->rt.fbo[ring], 0, 0, rr->width, rr->height, 0, 0, rr->width,
                                   rr->height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        }
        glNamedFramebufferDrawBuffers(r->rt.fbo[ring], outputs, att);
        if (r->pl.taa) /* TAA reprojects through this ring's depth */
            glBlitNamedFramebuffer(r->rt.msaa_fbo, r->rt.fbo[ring], 0, 0, rr->width, rr->height, 0, 0, rr->width,
                                   rr->height, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    }
}

fs_status renderer_draw(renderer *r, const frame_record *fr)
{
    FS_ASSERT(fr->ring_count == r->pl.layout.count);
    if (r->pass_sync)
        glFinish();
    double t_prev = time_now();
    r->shaded_pixels = 0;
    r->counted = r->counting;
    if (r->counting) {
        const GLuint zero = 0;
        glClearNamedBufferData(r->count_buf, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, COUNT_FRAGMENTS_BINDING, r->count_buf);
        if (r->count_keys_buf) { /* no primitive has shaded a coarse pixel yet (keys start at 1) */
            glClearNamedBufferData(r->count_keys_buf, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, COUNT_COARSE_KEYS_BINDING, r->count_keys_buf);
        }
    }
    for (int k = 0; k < r->stage_count; k++) {
        r->fullscreen_px[k] = -1;
        r->stage_bytes[k] = (pass_bytes){0, 0};
    }
    long long display_px = (long long)r->width * r->height, ring_px[MAX_FOV_RINGS];
    for (int i = 0; i < fr->ring_count; i++)
        ring_px[i] = (long long)fr->ring_rect[i].width * fr->ring_rect[i].height;
    const target_bytes *tb = &r->target_bpp;
    bool history = taa_history_valid(r, fr);
    if (!r->pl.composite) {
        draw_ring(r, fr, 0, 0, &t_prev);
        r->stage_bytes[0] = pass_bytes_forward(tb, ring_px[0]); /* the targets, on the first pass */
        if (r->pl.reference_lists)
            for (int k = 0; k < r->stage_count; k++)
                r->stage_bytes[k] = (pass_bytes){-1, -1};
        if (r->pl.list_resolve) {
            stage_begin(r, r->pl.pass_count);
            list_resolve(r);
            stage_end(r, r->pl.pass_count, &t_prev);
            r->fullscreen_px[r->pl.pass_count] = display_px;
        }
        if (r->pl.taa) {
            int k = r->pl.pass_count + r->pl.list_resolve;
            stage_begin(r, k);
            taa_resolve_ring(r, fr, 0);
            stage_end(r, k, &t_prev);
            r->fullscreen_px[k] = ring_px[0];
            r->stage_bytes[k] = pass_bytes_taa(tb, ring_px[0], history ? ring_px[0] : 0);
        }
        r->shaded_pixels = (long long)fr->ring_rect[0].width * fr->ring_rect[0].height;
    } else {
        /* Stages: each ring's passes, then its TAA resolve (when on), then the composite. */
        if (r->pl.taa_coarse_history && taa_history_valid(r, fr))
            taa_set_prev_footprints(r, fr);
        int k = 0;
        for (int i = 0; i < r->pl.layout.count; i++) {
            stage_begin(r, k);
            draw_ring(r, fr, i, -1, &t_prev);
            r->stage_bytes[k] = pass_bytes_forward(tb, ring_px[i]);
            stage_end(r, k++, &t_prev);
            if (r->pl.taa) {
                stage_begin(r, k);
                taa_resolve_ring(r, fr, i);
                r->fullscreen_px[k] = ring_px[i];
                r->stage_bytes[k] = pass_bytes_taa(
                    tb, ring_px[i], history ? (long long)r->prev_rect[i].width * r->prev_rect[i].height : 0);
                stage_end(r, k++, &t_prev);
            }
            r->shaded_pixels += (long long)fr->ring_rect[i].width * fr->ring_rect[i].height;
        }
        stage_begin(r, k);
        renderer_draw_composite(r, fr);
        stage_end(r, k, &t_prev);
        r->fullscreen_px[k] = display_px; /* its rectangles tile the display */
        r->stage_bytes[k] = pass_bytes_composite(tb, ring_px, fr->ring_count, display_px);
    }
    if (r->pl.taa && !r->counting) { /* a counting frame leaves the history as it was */
        for (int i = 0; i < fr->ring_count; i++) {
            r->prev_vp[i] = fr->ring_view_proj[i];
            r->prev_rect[i] = fr->ring_rect[i];
        }
        r->prev_index = fr->index;
        r->prev_time = fr->time;
        display_desc dd = frame_display(fr, r->width, r->height);
        r->prev_gaze_px[0] = fr->gaze_px[0];
        r->prev_gaze_px[1] = fr->gaze_px[1];
        r->prev_focal_px = fov_focal_px(&dd);
        fov_principal_px(&dd, r->prev_principal_px);
        for (int i = 0; i < fr->ring_count; i++)
            r->prev_hole_deg[i] = r->pl.ring_cull && fov_ring_cull_deg(&dd, &r->pl.layout, i) > 0.0f
                                      ? fov_ring_hole_deg(&r->pl.layout, i)
                                      : 0.0f;
        r->have_prev = true;
        r->out_parity = r->parity; /* what renderer_read and the next frame's history use */
        r->parity = 1 - r->parity;
    }
    r->stats_pending = r->timers;
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return FS_OK;
}

void renderer_set_mip_bias(renderer *r, int ring, float bias)
{
    FS_ASSERT(ring >= 0 && ring < r->pl.layout.count);
    r->pl.layout.rings[ring].mip_bias = bias;
}

void renderer_set_pass_sync(renderer *r, bool on)
{
    r->pass_sync = on;
}

void renderer_set_counting(renderer *r, bool on)
{
    r->counting = on && r->count_buf != 0;
}

fs_status renderer_draw_counting(renderer *r, const frame_record *fr, renderer_stats *counted)
{
    renderer_set_counting(r, true);
    fs_status st = renderer_draw(r, fr);
    *counted = renderer_last_stats(r);
    renderer_set_counting(r, false);
    return st;
}

void renderer_finish(renderer *r)
{
    (void)r;
    glFinish();
}
