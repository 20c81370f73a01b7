#include "passes/plan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "common/shared_defs.h"
#include "passes/alpha_test.h"
#include "scene/cards.h"

alpha_params alpha_params_defaults(const alpha_params *p)
{
    alpha_params r = p ? *p : (alpha_params){0};
    if (!(r.hash_scale > 0.0f))
        r.hash_scale = ALPHA_HASH_SCALE_DEFAULT;
    if (!(r.fade_n > 0.0f))
        r.fade_n = ALPHA_FADE_N_DEFAULT;
    return r;
}

taa_controls taa_controls_defaults(const taa_controls *c)
{
    taa_controls r = c ? *c : (taa_controls){0};
    if (!(r.blend > 0.0f && r.blend <= 1.0f))
        r.blend = TAA_BLEND_DEFAULT;
    if (!(r.gamma > 0.0f))
        r.gamma = TAA_GAMMA_DEFAULT;
    if (r.jitter_length <= 0)
        r.jitter_length = TAA_JITTER_LENGTH_DEFAULT;
    if (!(r.sparse < 0.0f) && !(r.sparse > 0.0f && r.sparse <= 1.0f))
        r.sparse = TAA_SPARSE_SLACK; /* negative (off) stays */
    if (r.neighbourhood != TAA_NEIGHBOURHOOD_3X3 && r.neighbourhood != TAA_NEIGHBOURHOOD_CROSS)
        r.neighbourhood = TAA_NEIGHBOURHOOD_CROSS;
    if (r.history != TAA_HISTORY_CATMULL && r.history != TAA_HISTORY_BILINEAR)
        r.history = TAA_HISTORY_CATMULL;
    if (r.nan_check != TAA_NAN_TAP && r.nan_check != TAA_NAN_SET)
        r.nan_check = TAA_NAN_TAP;
    return r;
}

alpha_mode plan_material_mode(const plan *p, const material *m)
{
    return m->alpha_mode != ALPHA_MODE_DEFAULT && !p->reference ? m->alpha_mode : p->global_mode;
}

float plan_material_alpha_lod_max(const plan *p, const material *m)
{
    if (p->reference || m->alpha_kind != ALPHA_KIND_MASK || p->alpha.lod_clamp < 0)
        return (float)ALPHA_LOD_OFF;
    if (m->has_alpha_lod_max)
        return m->alpha_lod_max;
    return p->alpha.lod_clamp > 0 ? p->alpha.lod_max : (float)ALPHA_LOD_OFF;
}

void plan_alpha_lod_format(const plan *p, const scene *sc, char *buf, size_t size)
{
    size_t o = 0;
    buf[0] = '\0';
    for (int a = 0; a < sc->asset_count; a++)
        for (int k = 0; k < sc->assets[a].material_count; k++) {
            const material *m = &sc->assets[a].materials[k];
            float l = plan_material_alpha_lod_max(p, m);
            if (l < 0.0f || strstr(buf, m->name)) /* a name shared by several assets is listed once */
                continue;
            int n = snprintf(buf + o, size - o, "%s%s %g", o ? ", " : "", m->name, (double)l);
            if (n < 0 || (size_t)n >= size - o)
                return;
            o += (size_t)n;
        }
}

const plan_pass *plan_find(const plan *p, plan_pass_kind kind, alpha_mode mode)
{
    for (int i = 0; i < p->pass_count; i++)
        if (p->passes[i].kind == kind && (kind != PLAN_PASS_FORWARD_MASK || p->passes[i].mode == mode))
            return &p->passes[i];
    return NULL;
}

static int cmp_str(const void *a, const void *b) { return strcmp((const char *)a, (const char *)b); }

/* Appends a define ("NAME VALUE") and keeps the list sorted. */
static void add_define(plan_pass *ps, const char *name, int value)
{
    if (ps->define_count >= PLAN_MAX_DEFINES) {
        log_error("plan: pass %s: more than %d defines (%s dropped)", ps->name, PLAN_MAX_DEFINES, name);
        return;
    }
    snprintf(ps->defines[ps->define_count++], sizeof ps->defines[0], "%s %d", name, value);
    qsort(ps->defines, (size_t)ps->define_count, sizeof ps->defines[0], cmp_str);
}

static bool plan_has_define(const plan_pass *ps, const char *define)
{
    for (int d = 0; d < ps->define_count; d++)
        if (!strcmp(ps->defines[d], define))
            return true;
    return false;
}

bool plan_pass_counting(const plan_pass *ps, plan_pass *out)
{
    *out = *ps;
    if (out->define_count >= PLAN_MAX_DEFINES) {
        log_error("plan: pass %s: no room for the counting variant's define", ps->name);
        return false;
    }
    add_define(out, "COUNT_FRAGMENTS", 1);
    return true;
}

static plan_pass *get_pass(plan *p, plan_pass_kind kind, alpha_mode mode)
{
    plan_pass *ps = (plan_pass *)plan_find(p, kind, mode);
    if (ps || p->pass_count == PLAN_MAX_PASSES)
        return ps;
    ps = &p->passes[p->pass_count++];
    memset(ps, 0, sizeof *ps);
    ps->kind = kind;
    ps->mode = kind == PLAN_PASS_FORWARD_MASK ? mode : ALPHA_MODE_DEFAULT;
    ps->vs = "shaders/forward.vert";
    ps->fs = "shaders/forward.frag";
    switch (kind) {
    case PLAN_PASS_FORWARD_OPAQUE:
        snprintf(ps->name, sizeof ps->name, "forward.opaque");
        snprintf(ps->defines[ps->define_count++], sizeof ps->defines[0], "PASS_OPAQUE 1");
        break;
    case PLAN_PASS_FORWARD_MASK:
        snprintf(ps->name, sizeof ps->name, "forward.mask[%s]", alpha_mode_name(mode));
        snprintf(ps->defines[ps->define_count++], sizeof ps->defines[0], "PASS_MASK 1");
        snprintf(ps->defines[ps->define_count++], sizeof ps->defines[0], "ALPHA_MODE %d", alpha_mode_shader_id(mode));
        /* What the mode's traits (FS_ALPHA_MODES, common/shared_defs.h) compile in. */
        if (alpha_mode_has(mode, ALPHA_TRAIT_MSAA))
            snprintf(ps->defines[ps->define_count++], sizeof ps->defines[0], "MSAA 1");
        if (alpha_mode_has(mode, ALPHA_TRAIT_GL_A2C) && p->alpha.a2c_sharpen)
            snprintf(ps->defines[ps->define_count++], sizeof ps->defines[0], "A2C_SHARPEN 1");
        if (alpha_mode_has(mode, ALPHA_TRAIT_HASH)) {
            snprintf(ps->defines[ps->define_count++], sizeof ps->defines[0], "ALPHA_HASH_KIND %d", p->alpha.hash_kind);
            snprintf(ps->defines[ps->define_count++], sizeof ps->defines[0], "ALPHA_HASH_ANISO %d", p->alpha.anisotropic);
        }
        break;
    case PLAN_PASS_FORWARD_BLEND:
        snprintf(ps->name, sizeof ps->name, "forward.blend");
        snprintf(ps->defines[ps->define_count++], sizeof ps->defines[0], "PASS_BLEND 1");
        break;
    case PLAN_PASS_FORWARD_SOLID:
        snprintf(ps->name, sizeof ps->name, "forward.solid");
        snprintf(ps->defines[ps->define_count++], sizeof ps->defines[0], "PASS_SOLID 1");
        break;
    case PLAN_PASS_FORWARD_LIST:
        snprintf(ps->name, sizeof ps->name, "forward.list");
        snprintf(ps->defines[ps->define_count++], sizeof ps->defines[0], "PASS_LIST 1");
        break;
    }
    qsort(ps->defines, (size_t)ps->define_count, sizeof ps->defines[0], cmp_str);
    return ps;
}

display_desc plan_display(const plan *p)
{
    return (display_desc){p->width, p->height, p->hfov_deg, p->ppx, p->ppy};
}

/* Whether any two camera keys differ (position, target or fov). */
static bool camera_moves(const camera_path *c)
{
    for (int i = 1; i < c->count; i++) {
        const camera_key *a = &c->keys[0], *b = &c->keys[i];
        if (v3_len(v3_sub(a->position, b->position)) > 0.0f || v3_len(v3_sub(a->target, b->target)) > 0.0f ||
            a->hfov_deg != b->hfov_deg)
            return true;
    }
    return false;
}

/* A pass drawn as one full-screen triangle (TAA resolve, composite), no defines yet. */
static void fullscreen_pass(plan_pass *ps, const char *name, const char *fs)
{
    memset(ps, 0, sizeof *ps);
    snprintf(ps->name, sizeof ps->name, "%s", name);
    ps->vs = "shaders/fullscreen.vert";
    ps->fs = fs;
}

/* Some surface is alpha-tested (a MASK pass) in a mode with all of `traits` (0: any mode; e.g.
 * ALPHA_TRAIT_NOISE: a stochastic or hashed test, whose samples are noise in time). */
static bool has_mask(const plan *p, unsigned traits)
{
    for (int i = 0; i < p->pass_count; i++)
        if (p->passes[i].kind == PLAN_PASS_FORWARD_MASK && alpha_mode_has(p->passes[i].mode, traits))
            return true;
    return false;
}

/* Phase 1: what the options and the scene decide before any pass: the output size, the global
 * alpha mode (--alpha, else the scene's, else traditional; the reference's is stochastic), the
 * hashed family's parameters. */
static void plan_settings(const scene *sc, const plan_options *o, plan *out)
{
    out->width = o->width > 0 ? o->width : sc->display.width;
    out->height = o->height > 0 ? o->height : sc->display.height;
    out->hfov_deg = sc->display.hfov_deg;
    display_desc at = display_resized(&sc->display, out->width, out->height);
    out->ppx = at.ppx;
    out->ppy = at.ppy;
    out->global_mode = o->alpha_mode != ALPHA_MODE_DEFAULT ? o->alpha_mode
                       : sc->alpha_mode != ALPHA_MODE_DEFAULT ? sc->alpha_mode
                                                              : ALPHA_MODE_TRADITIONAL;
    if (o->reference) {
        out->reference = true;
        out->reference_lists = o->reference_lists;
        out->global_mode = ALPHA_MODE_STOCHASTIC;
    }
    out->coverage = true;
    out->alpha = alpha_params_defaults(&o->alpha);
    out->msaa = o->force_msaa;
}

/* The forward pass kind a primitive of material `m` is drawn in while the passes of kind `now`
 * are planned (the exact reference's MASK materials go to the solid pass, then with BLEND to the
 * list pass). */
static plan_pass_kind forward_kind(const plan *p, const material *m, plan_pass_kind now)
{
    plan_pass_kind kind = m->alpha_kind == ALPHA_KIND_MASK    ? PLAN_PASS_FORWARD_MASK
                          : m->alpha_kind == ALPHA_KIND_BLEND ? PLAN_PASS_FORWARD_BLEND
                                                              : PLAN_PASS_FORWARD_OPAQUE;
    /* The exact reference: MASK materials draw their alpha-1 texels' depth first (the solid pass),
     * then MASK and BLEND go to the list pass. */
    if (p->reference_lists && kind != PLAN_PASS_FORWARD_OPAQUE)
        kind = kind == PLAN_PASS_FORWARD_MASK && now == PLAN_PASS_FORWARD_SOLID ? PLAN_PASS_FORWARD_SOLID
                                                                              : PLAN_PASS_FORWARD_LIST;
    return kind;
}

/* Phase 2: the forward passes, in draw order: opaque, then alpha-tested (one pass per alpha mode
 * in use), then blended (sorted back to front); the exact reference: opaque, solid, then the list
 * pass. Each placed primitive counts into its pass; its mode's traits switch on MSAA targets and
 * Castano mips, a material's alpha LOD clamp its pass's ALPHA_LOD_CLAMP. */
static fs_status plan_forward_passes(const scene *sc, plan *out)
{
    static const plan_pass_kind order[] = {PLAN_PASS_FORWARD_OPAQUE, PLAN_PASS_FORWARD_MASK, PLAN_PASS_FORWARD_BLEND,
                                           PLAN_PASS_FORWARD_SOLID, PLAN_PASS_FORWARD_LIST};
    for (int k = 0; k < (int)(sizeof order / sizeof order[0]); k++) {
        for (int a = 0; a < sc->asset_count; a++) {
            const asset *as = &sc->assets[a];
            long long inst = 0;
            for (int i = 0; i < sc->instance_count; i++)
                inst += sc->instances[i].asset == a;
            if (inst == 0)
                continue; /* an asset nobody places costs nothing */
            for (int pi = 0; pi < as->prim_count; pi++) {
                const prim *pr = &as->prims[pi];
                const material *m = &as->materials[pr->material];
                plan_pass_kind kind = forward_kind(out, m, order[k]);
                if (kind != order[k])
                    continue;
                alpha_mode mode = kind == PLAN_PASS_FORWARD_MASK ? plan_material_mode(out, m) : ALPHA_MODE_DEFAULT;
                plan_pass *ps = get_pass(out, kind, mode);
                if (!ps) {
                    log_error("plan: more than %d passes", PLAN_MAX_PASSES);
                    return FS_ERR_INTERNAL;
                }
                ps->prim_count++;
                ps->triangles += (long long)(pr->index_count / 3) * inst;
                out->msaa |= alpha_mode_has(mode, ALPHA_TRAIT_MSAA);
                out->castano |= alpha_mode_has(mode, ALPHA_TRAIT_COVERAGE_MIPS);
                /* The alpha LOD clamp: compiled only into the passes of materials that have one. */
                if (kind == PLAN_PASS_FORWARD_MASK && plan_material_alpha_lod_max(out, m) >= 0.0f) {
                    out->alpha_lod_prims++;
                    if (!plan_has_define(ps, "ALPHA_LOD_CLAMP 1"))
                        add_define(ps, "ALPHA_LOD_CLAMP", 1);
                }
            }
        }
    }
    for (int a = 0; a < sc->asset_count; a++)
        out->texture_count += sc->assets[a].image_count;
    return FS_OK;
}

/* Phase 3: time. TAA only when there is more than one frame to accumulate. With TAA the hashed
 * thresholds move every frame by a golden-ratio offset so the history averages them
 * (alpha_hashed_frame_offset; the paper's own suggestion, §5.4.1, is sub-pixel noise, a
 * --hash-scale of 0.3-0.5: docs/hashed-alpha.md measures both). Swaying instances move their
 * vertices in every forward pass (trunk and leaves together); with TAA the passes also write each
 * fragment's motion, so that history follows the leaves, not just the camera. A static scene
 * compiles neither. */
static void plan_time(const scene *sc, const plan_options *o, plan *out)
{
    out->taa = o->taa && o->frames > 1;
    for (int i = 0; i < out->pass_count && out->taa && !out->alpha.no_frame_offset; i++) {
        plan_pass *ps = &out->passes[i];
        if (ps->kind == PLAN_PASS_FORWARD_MASK && alpha_mode_has(ps->mode, ALPHA_TRAIT_HASH))
            add_define(ps, "TAA_HASH_OFFSET", 1);
    }
    out->sway_instances = scene_sway_count(sc);
    out->sway = out->sway_instances > 0;
    out->velocity = out->sway && out->taa && !o->taa_controls.no_object_motion;
    for (int i = 0; i < out->pass_count; i++) {
        if (out->sway)
            add_define(&out->passes[i], "SWAY", 1);
        if (out->velocity)
            add_define(&out->passes[i], "OBJECT_MOTION", 1);
    }
    out->taa_controls = taa_controls_defaults(&o->taa_controls);
    out->camera_motion = camera_moves(&sc->camera);
}

/* Phase 4: foveation: the rings, whether a composite pass runs (rings, overlay or debug channels)
 * and whether rings cull the instances in their hole. */
static void plan_rings(const plan_options *o, plan *out)
{
    out->layout = o->layout.count > 0 ? o->layout : fov_layout_off();
    out->rings = out->layout.count > 1 || out->layout.rings[0].scale_log2 > 0;
    out->overlay = o->overlay;
    out->debug_channels = o->debug_channels;
    out->composite = out->rings || o->overlay || o->debug_channels;
    out->ring_cull = out->layout.count > 1 && !o->no_ring_cull;
}

/* Phase 4b: VRS foveation (docs/foveation.md "Variable-rate shading: coarse shading"): one
 * full-resolution ring. Each forward pass that shades colour keeps its program for the tiles at
 * 1x1 and gets a coarse-shading twin (plan_pass_vrs) for the others; the exact reference's passes
 * never (the reference is never foveated). */
static void plan_vrs(const plan_options *o, plan *out)
{
    if (!o->vrs || out->reference)
        return;
    out->vrs = true;
    out->vrs_spec = o->vrs_spec;
    out->vrs_tile = o->vrs_tile > 0 ? o->vrs_tile : VRS_TILE_DEFAULT;
    out->vrs_rings = out->layout;
    out->layout = fov_layout_off();
    out->rings = false;
    out->composite = o->overlay || o->debug_channels;
    out->ring_cull = false;
}

bool plan_pass_vrs(const plan_pass *ps, plan_pass *out)
{
    *out = *ps;
    if (ps->kind == PLAN_PASS_FORWARD_SOLID || ps->kind == PLAN_PASS_FORWARD_LIST)
        return false;
    if (out->define_count >= PLAN_MAX_DEFINES) {
        log_error("plan: pass %s: no room for the VRS variant's define", ps->name);
        return false;
    }
    out->gs = "shaders/forward_vrs.geom";
    add_define(out, "VRS", 1);
    return true;
}

/* Phase 5: ring LOD (docs/ring-lod.md): only for scenes with foliage to thin, never for the
 * reference, and only when some ring keeps fewer than all cards (an explicit schedule of ones
 * compiles it too: that is how a test shows u = 1 changes nothing). The MASK passes then compile
 * RING_LOD; otherwise ring_lod_why says why not. */
static fs_status plan_ring_lod(const scene *sc, const plan_options *o, plan *out)
{
    if (o->ring_lod.kind != RING_LOD_OFF && !out->reference) {
        if (ring_lod_active(&o->ring_lod, &out->layout) || o->ring_lod.kind == RING_LOD_EXPLICIT) {
            fs_status st = scene_cards_count(sc, &out->ring_lod_prims, &out->ring_lod_cards);
            if (st != FS_OK)
                return st;
            out->ring_lod = out->ring_lod_prims > 0;
            if (!out->ring_lod)
                snprintf(out->ring_lod_why, sizeof out->ring_lod_why, "no MASK primitive has %d or more cards",
                         RING_LOD_MIN_CARDS);
        } else {
            snprintf(out->ring_lod_why, sizeof out->ring_lod_why, "every ring keeps all cards");
        }
    }
    out->ring_lod_spec = out->ring_lod ? o->ring_lod : (ring_lod_spec){0};
    for (int i = 0; i < out->pass_count && out->ring_lod; i++)
        if (out->passes[i].kind == PLAN_PASS_FORWARD_MASK)
            add_define(&out->passes[i], "RING_LOD", 1);
    return FS_OK;
}

/* Phase 6: the TAA resolve's pass and its defines (when TAA runs): which reprojections, which
 * history rules and which of the resolve's variants the scene and the options call for. */
static void plan_taa_pass(plan *out)
{
    if (!out->taa)
        return;
    plan_pass *t = &out->taa_pass;
    fullscreen_pass(t, "taa", "shaders/taa.frag");
    /* A still camera needs no reprojection through depth (simulate only what the scene needs). */
    if (out->camera_motion)
        snprintf(t->defines[t->define_count++], sizeof t->defines[0], "TAA_CAMERA_MOTION 1");
    /* Swaying instances: through depth and each fragment's own motion. */
    if (out->velocity)
        snprintf(t->defines[t->define_count++], sizeof t->defines[0], "TAA_OBJECT_MOTION 1");
    /* The rings a pixel that left its own ring's footprint may take history from: where the
     * alpha tests are stochastic, a coarser ring's history is closer to the converged image
     * than the noisy current sample; where they are not, it is not (docs/taa.md, "Saccades"). */
    snprintf(t->defines[t->define_count++], sizeof t->defines[0], "TAA_RING_COUNT %d", out->layout.count);
    /* The resolve's variants (docs/taa.md, "A leaner resolve"). */
    snprintf(t->defines[t->define_count++], sizeof t->defines[0], "TAA_NEIGHBOURS %d",
             out->taa_controls.neighbourhood == TAA_NEIGHBOURHOOD_CROSS ? 5 : 9);
    if (out->taa_controls.history == TAA_HISTORY_CATMULL)
        snprintf(t->defines[t->define_count++], sizeof t->defines[0], "TAA_HISTORY_CATMULL_ROM 1");
    if (out->taa_controls.nan_check == TAA_NAN_SET)
        snprintf(t->defines[t->define_count++], sizeof t->defines[0], "TAA_NAN_PER_SET 1");
    out->taa_coarse_history = out->layout.count > 1 && has_mask(out, ALPHA_TRAIT_NOISE);
    /* The sparse-coverage rule (docs/taa.md, "Sparse coverage"): wherever a surface is
     * alpha-tested, a pixel's coverage sample is a binary draw (a stochastic or hashed
     * threshold, or a jittered sub-pixel leaf under any test), which its neighbours cannot
     * refute. Scenes without MASK surfaces keep the plain clamp. */
    out->taa_sparse = out->taa_controls.sparse > 0.0f && has_mask(out, 0);
    if (out->taa_sparse)
        snprintf(t->defines[t->define_count++], sizeof t->defines[0], "TAA_SPARSE_COVERAGE 1");
    /* Disocclusion (docs/taa.md): only where pixels move, i.e. where TAA reprojects through
     * depth; a still camera without sway keeps every surface on its pixel. */
    out->taa_disocclusion = (out->camera_motion || out->velocity) && !out->taa_controls.no_disocclusion;
    if (out->taa_disocclusion)
        snprintf(t->defines[t->define_count++], sizeof t->defines[0], "TAA_DISOCCLUSION 1");
    /* Rings that skip instances in their hole: history from there is not whole. */
    if (out->ring_cull)
        snprintf(t->defines[t->define_count++], sizeof t->defines[0], "TAA_RING_CULL 1");
    if (out->taa_coarse_history)
        snprintf(t->defines[t->define_count++], sizeof t->defines[0], "TAA_COARSE_HISTORY 1");
    qsort(t->defines, (size_t)t->define_count, sizeof t->defines[0], cmp_str);
}

/* Phase 7: the full-screen passes after the rings: the exact reference's list resolve, and the
 * composite (with its tile variant, for pixels whose ring is known from their tile). */
static void plan_display_passes(const plan_options *o, plan *out)
{
    out->list_resolve = plan_find(out, PLAN_PASS_FORWARD_LIST, ALPHA_MODE_DEFAULT) != NULL;
    if (out->list_resolve)
        fullscreen_pass(&out->list_resolve_pass, "list resolve", "shaders/list_resolve.frag");
    if (!out->composite)
        return;
    plan_pass *c = &out->composite_pass;
    fullscreen_pass(c, "composite", "shaders/composite.frag");
    snprintf(c->defines[c->define_count++], sizeof c->defines[0], "FOV_RING_COUNT %d", out->layout.count);
    if (o->overlay)
        snprintf(c->defines[c->define_count++], sizeof c->defines[0], "OVERLAY 1");
    if (o->debug_channels)
        snprintf(c->defines[c->define_count++], sizeof c->defines[0], "DEBUG_CHANNELS 1");
    c->vs = "shaders/composite.vert";
    qsort(c->defines, (size_t)c->define_count, sizeof c->defines[0], cmp_str);
    /* Pixels whose ring is known from their tile skip the search (the overlay draws ring borders
     * per pixel, so it keeps the search everywhere). */
    out->composite_tiles = out->rings && !o->overlay && !o->composite_per_pixel;
    if (out->composite_tiles) {
        plan_pass *t = &out->composite_tile_pass;
        *t = *c;
        snprintf(t->name, sizeof t->name, "composite (tiles of one ring)");
        snprintf(t->defines[t->define_count++], sizeof t->defines[0], "COMPOSITE_TILE 1");
        qsort(t->defines, (size_t)t->define_count, sizeof t->defines[0], cmp_str);
    }
}

fs_status plan_build(const scene *sc, const plan_options *opt, plan *out)
{
    plan_options o = opt ? *opt : (plan_options){0};
    memset(out, 0, sizeof *out);
    plan_settings(sc, &o, out);
    fs_status st = plan_forward_passes(sc, out);
    if (st != FS_OK)
        return st;
    plan_time(sc, &o, out);
    plan_rings(&o, out);
    plan_vrs(&o, out);
    st = plan_ring_lod(sc, &o, out);
    if (st != FS_OK)
        return st;
    plan_taa_pass(out);
    plan_display_passes(&o, out);
    return FS_OK;
}

/* The layout's guaranteed acuity margin (fov_layout_acuity_margin, default acuity model): how
 * coarse its blocks may get against the MAR at their ring's inner edge, for any gaze on the
 * display. Explicit layouts may fall short; that is reported, not refused. */
static void plan_print_acuity(const display_desc *dd, const fov_layout *l, FILE *f)
{
    int worst = -1;
    double margin = fov_layout_acuity_margin(dd, l, 0.0f, 0.0f, &worst);
    if (worst < 0) {
        fprintf(f, "  acuity     no ring coarser than full resolution is shown\n");
        return;
    }
    double ratio = 1.0 / margin;
    if (margin >= 1.0)
        fprintf(f, "  acuity     margin %.3fx: blocks span at most %.3fx the MAR at their ring's inner edge, for any gaze "
                   "on the display (tightest: ring %d)\n", margin, ratio, worst);
    else
        fprintf(f, "  acuity     margin %.3fx: ring %d's blocks span up to %.3fx the MAR at its inner edge for some gazes, "
                   "coarser than the acuity model by %.0f %%\n", margin, worst, ratio, 100.0 * (ratio - 1.0));
}

void plan_foveation_format(const plan *p, char *buf, size_t size)
{
    if (!p->vrs) {
        fov_layout_format(&p->layout, buf, (int)size);
        return;
    }
    char spec[128];
    vrs_spec_format(&p->vrs_spec, spec, sizeof spec);
    snprintf(buf, size, "vrs %s, %d px tiles", spec, p->vrs_tile);
}

void plan_print(const plan *p, const scene *sc, FILE *f)
{
    long long tris = 0;
    for (int i = 0; i < p->pass_count; i++)
        tris += p->passes[i].triangles;
    fprintf(f, "scene      %s\n", sc->path);
    fprintf(f, "display    %d x %d, hfov %.1f deg\n", p->width, p->height, p->hfov_deg);
    fprintf(f, "assets     %d, instances %d, triangles/frame %lld, textures %d (premultiplied mips, RGBA16)\n",
            sc->asset_count, sc->instance_count, tris, p->texture_count);
    fprintf(f, "alpha mode %s (global; per-material overrides shown per pass)\n", alpha_mode_name(p->global_mode));
    bool hashed = false;
    for (int i = 0; i < p->pass_count; i++)
        hashed |= p->passes[i].kind == PLAN_PASS_FORWARD_MASK && alpha_mode_has(p->passes[i].mode, ALPHA_TRAIT_HASH);
    if (hashed)
    {
        char fade[64];
        if (p->alpha.no_fade)
            snprintf(fade, sizeof fade, "off");
        else
            snprintf(fade, sizeof fade, "over %.1f mip levels", p->alpha.fade_n);
        fprintf(f, "hash       %s, scale %.2f px%s, fade-in %s%s\n", p->alpha.hash_kind == ALPHA_HASH_SINE ? "sine" : "pcg3d",
                p->alpha.hash_scale, p->alpha.anisotropic ? ", anisotropic" : "", fade,
                !p->taa                    ? ""
                : p->alpha.no_frame_offset ? "; with TAA no per-frame offset (--no-hash-offset)"
                                           : "; with TAA a golden-ratio offset per frame");
    }
    fprintf(f, "passes (in draw order):\n");
    if (p->pass_count == 0)
        fprintf(f, "  (none: the scene draws nothing; output is the sky colour)\n");
    for (int i = 0; i < p->pass_count; i++) {
        const plan_pass *ps = &p->passes[i];
        fprintf(f, "  %-26s %3d prims %9lld tris  %s + %s [", ps->name, ps->prim_count, ps->triangles, ps->vs, ps->fs);
        for (int d = 0; d < ps->define_count; d++)
            fprintf(f, "%s%s", d ? ", " : "", ps->defines[d]);
        fprintf(f, "]\n");
    }
    plan_pass v;
    if (p->vrs && p->pass_count > 0 && plan_pass_vrs(&p->passes[0], &v))
        fprintf(f, "  (VRS: each pass above draws the 1x1 tiles; its twin + %s [VRS 1] shades the coarser ones once per "
                   "coarse pixel and triangle)\n", v.gs);
    display_desc dd = plan_display(p);
    if (p->rings) {
        char spec[256];
        fov_layout_format(&p->layout, spec, sizeof spec);
        long long per[MAX_FOV_RINGS];
        long long total = fov_shaded_pixels(&dd, &p->layout, 0.5f * (float)p->width, 0.5f * (float)p->height,
                                            FOV_MARGIN_BLOCKS, per);
        double px = (double)p->width * (double)p->height;
        fprintf(f, "rings      %s (%s), %.1f px/deg at the centre; gaze at the centre:\n",
                fov_layout_kind_name(p->layout.kind), spec, fov_pixels_per_degree(&dd));
        float inner = 0.0f;
        for (int i = 0; i < p->layout.count; i++) {
            const fov_ring *r = &p->layout.rings[i];
            fov_ring_rect rr = fov_ring_footprint(&dd, &p->layout, i, 0.5f * (float)p->width,
                                                  0.5f * (float)p->height, FOV_MARGIN_BLOCKS);
            char outer[32];
            if (isinf(r->outer_deg))
                snprintf(outer, sizeof outer, "display edge");
            else
                snprintf(outer, sizeof outer, "%.2f deg (%.0f px)", r->outer_deg, r->outer_deg * fov_pixels_per_degree(&dd));
            /* The worst block against the MAR at the ring's inner edge, any gaze (fov_ring_block_mar_ratio). */
            double ratio = fov_ring_block_mar_ratio(&dd, &p->layout, i, 0.0f, 0.0f);
            char acuity[32] = "";
            if (ratio > 0.0)
                snprintf(acuity, sizeof acuity, "  block/MAR %.3f", ratio);
            fprintf(f, "  ring %d   %5.2f deg .. %-24s scale 1/%-2d mip bias %+.2f  target %4d x %-4d  shades %5.1f %%%s\n",
                    i, inner, outer, 1 << r->scale_log2, r->mip_bias, rr.width, rr.height, 100.0 * (double)per[i] / px,
                    acuity);
            inner = r->outer_deg;
        }
        fprintf(f, "  total      %.1f %% of display pixels shaded (ideal speedup %.2fx)\n", 100.0 * (double)total / px,
                px / (double)total);
        plan_print_acuity(&dd, &p->layout, f);
    } else {
        fprintf(f, "rings      off (full resolution)\n");
    }
    if (p->composite) {
        fprintf(f, "composite  %s + %s [", p->composite_pass.vs, p->composite_pass.fs);
        for (int d = 0; d < p->composite_pass.define_count; d++)
            fprintf(f, "%s%s", d ? ", " : "", p->composite_pass.defines[d]);
        fprintf(f, "]%s\n", p->debug_channels ? ", writes ring.id and eccentricity" : "");
        fprintf(f, "           %s\n", p->composite_tiles
                                         ? "display drawn in 16-pixel tiles: those inside one ring fetch it directly "
                                           "(+ COMPOSITE_TILE), the others search per pixel"
                                         : "every pixel searches its ring");
    }
    if (p->layout.count > 1)
        fprintf(f, "culling    per ring: instances outside its frustum%s\n",
                p->ring_cull ? ", and those wholly inside its hole (where the finer ring is shown alone)"
                             : " (--ring-cull off: not those in its hole)");
    if (p->ring_lod) {
        char u[160], card[160] = "";
        ring_lod_format_u(&p->ring_lod_spec, &p->layout, u, sizeof u);
        if (p->ring_lod_spec.kind == RING_LOD_SCHEDULE)
            snprintf(card, sizeof card, "; card: each card's own u = its area in ring pixels / %g, at least 1/16 "
                     "(cards of %g ring pixels or more are drawn as they are)",
                     (double)ring_lod_area(&p->ring_lod_spec), (double)ring_lod_area(&p->ring_lod_spec));
        fprintf(f, "ring LOD   keep fraction u per ring = %s of the cards of %d MASK primitives (%llu cards in the "
                   "scene), kept cards scaled by sqrt(1/u) about their centres (RING_LOD)%s\n",
                u, p->ring_lod_prims, (unsigned long long)p->ring_lod_cards, card);
    }
    if (p->alpha_lod_prims > 0) {
        char lods[256];
        plan_alpha_lod_format(p, sc, lods, sizeof lods);
        fprintf(f, "alpha LOD  the alpha test of %d MASK primitives reads alpha at most at mip level: %s; colour keeps "
                   "the whole chain (ALPHA_LOD_CLAMP)\n", p->alpha_lod_prims, lods);
    }
    if (p->sway)
        fprintf(f, "animation  %d of %d instances sway in the wind (vertex displacement in every forward pass)\n",
                p->sway_instances, sc->instance_count);
    fprintf(f, "targets    per ring: colour RGBA16F + coverage R16F + depth 24%s%s; display: %s\n",
            p->velocity ? " + motion RGBA16F (world-space motion of swaying fragments)" : "",
            p->msaa ? ", drawn through a shared MSAA target and resolved" : "", p->composite ? "colour + coverage + debug (composite)" : "the ring itself");
    char sparse[96];
    if (p->taa_sparse)
        snprintf(sparse, sizeof sparse, "sparse coverage kept within %.2f of each pixel's sample", p->taa_controls.sparse);
    else
        snprintf(sparse, sizeof sparse, "no sparse-coverage rule (%s)",
                 p->taa_controls.sparse > 0.0f ? "no alpha-tested surface" : "off");
    const char *disocc = p->taa_disocclusion ? "; history whose nearest surface moved off the pixel dropped (depth)"
                         : (p->camera_motion || p->velocity) ? "; no disocclusion test (off)"
                                                              : "";
    if (p->taa)
        fprintf(f, "taa        per ring after its passes: %s + %s; history RGBA16F + R16F%s x 2 per ring; "
                   "blend %.2f, gamma %.2f, %s, Halton(2,3) jitter of %d frames; %s%s; %s%s; "
                   "clip box from the %s, %s history, NaN checked per %s\n",
                p->taa_pass.vs, p->taa_pass.fs, p->taa_disocclusion ? " + depth R32F" : "", p->taa_controls.blend,
                p->taa_controls.gamma, sparse, p->taa_controls.jitter_length,
                p->velocity        ? (p->camera_motion ? "reprojection through depth and per-object motion (the camera moves, instances sway)"
                                                       : "reprojection through depth and per-object motion (instances sway)")
                : p->camera_motion ? "reprojection through depth (the camera moves)"
                                   : "no reprojection (still camera: only the rings move with the gaze)",
                disocc,
                p->taa_coarse_history ? "history that leaves its ring's footprint from a coarser ring"
                                      : "history that leaves its ring's footprint dropped",
                p->ring_cull ? "; history from where a ring culled (its hole) dropped" : "",
                p->taa_controls.neighbourhood == TAA_NEIGHBOURHOOD_CROSS ? "5-tap cross" : "3x3",
                p->taa_controls.history == TAA_HISTORY_BILINEAR ? "bilinear" : "Catmull-Rom",
                p->taa_controls.nan_check == TAA_NAN_SET ? "set of fetches" : "tap");
    char off[256] = "";
    if (!p->msaa)
        snprintf(off + strlen(off), sizeof off - strlen(off), "%sMSAA (no alpha-to-coverage mode)", off[0] ? ", " : "");
    if (!p->taa)
        snprintf(off + strlen(off), sizeof off - strlen(off), "%sTAA (--taa off, or a single frame)", off[0] ? ", " : "");
    if (!p->sway)
        snprintf(off + strlen(off), sizeof off - strlen(off), "%ssway and per-object motion (no instance sways)",
                 off[0] ? ", " : "");
    else if (!p->velocity)
        snprintf(off + strlen(off), sizeof off - strlen(off), "%sper-object motion (no TAA, or --object-motion off)",
                 off[0] ? ", " : "");
    if (!p->ring_lod && p->ring_lod_why[0])
        snprintf(off + strlen(off), sizeof off - strlen(off), "%sring LOD (%s)", off[0] ? ", " : "", p->ring_lod_why);
    fprintf(f, "off        %s\n", off[0] ? off : "nothing");
}
