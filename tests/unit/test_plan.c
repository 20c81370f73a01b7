/* The plan: only the passes and variants a scene's content calls for (docs/design.md "Simulate only what the scene calls for"). */
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "passes/plan.h"
#include "test.h"

/* A one-triangle asset with one material of the given kind. */
static asset tri_asset(alpha_kind kind, alpha_mode override)
{
    asset a = {0};
    snprintf(a.name, sizeof a.name, "tri");
    a.prims = calloc(1, sizeof(prim));
    a.prim_count = 1;
    a.materials = calloc(1, sizeof(material));
    a.material_count = 1;
    material *m = &a.materials[0];
    snprintf(m->name, sizeof m->name, "m");
    m->base_color[0] = m->base_color[1] = m->base_color[2] = m->base_color[3] = 1.0f;
    m->base_color_image = -1;
    m->alpha_kind = kind;
    m->alpha_cutoff = 0.5f;
    m->alpha_mode = override;
    prim *p = &a.prims[0];
    p->vertex_count = 3;
    p->index_count = 3;
    p->positions = calloc(9, sizeof(float));
    p->normals = calloc(9, sizeof(float));
    p->uvs = calloc(6, sizeof(float));
    p->colors = calloc(12, sizeof(float));
    p->indices = calloc(3, sizeof(uint32_t));
    p->positions[3] = 1.0f;
    p->positions[7] = 1.0f;
    p->indices[1] = 1;
    p->indices[2] = 2;
    asset_compute_bounds(&a);
    return a;
}

static void add(scene *sc, alpha_kind kind, int instances)
{
    asset a = tri_asset(kind, ALPHA_MODE_DEFAULT);
    int idx = scene_add_asset(sc, &a);
    CHECK(idx >= 0);
    for (int i = 0; i < instances; i++)
        CHECK(scene_add_instance(sc, idx, m4_translate(v3((float)i, 0, 0))));
}

TEST(opaque_scene_has_no_alpha_variant_whatever_the_mode)
{
    scene sc;
    scene_init_defaults(&sc);
    add(&sc, ALPHA_KIND_OPAQUE, 5);
    for (int m = ALPHA_MODE_DEFAULT; m < ALPHA_MODE_COUNT; m++) {
        plan p;
        CHECK(plan_build(&sc, &(plan_options){.alpha_mode = (alpha_mode)m}, &p) == FS_OK);
        CHECK(p.pass_count == 1);
        CHECK(p.passes[0].kind == PLAN_PASS_FORWARD_OPAQUE);
        CHECK(p.passes[0].triangles == 5);
        CHECK(!p.msaa && !p.taa && !p.rings && !p.velocity);
        CHECK(plan_find(&p, PLAN_PASS_FORWARD_MASK, ALPHA_MODE_TRADITIONAL) == NULL);
    }
    scene_free(&sc);
}

TEST(mask_and_blend_get_their_passes_in_draw_order)
{
    scene sc;
    scene_init_defaults(&sc);
    add(&sc, ALPHA_KIND_BLEND, 2);
    add(&sc, ALPHA_KIND_MASK, 3);
    add(&sc, ALPHA_KIND_OPAQUE, 1);
    plan p;
    CHECK(plan_build(&sc, NULL, &p) == FS_OK);
    CHECK(p.pass_count == 3);
    CHECK(p.passes[0].kind == PLAN_PASS_FORWARD_OPAQUE);
    CHECK(p.passes[1].kind == PLAN_PASS_FORWARD_MASK && p.passes[1].mode == ALPHA_MODE_TRADITIONAL);
    CHECK(p.passes[2].kind == PLAN_PASS_FORWARD_BLEND);
    CHECK(p.passes[1].triangles == 3 && p.passes[2].triangles == 2);
    /* Defines are sorted (the program cache key) and name the variant. */
    CHECK(strcmp(p.passes[1].defines[0], "ALPHA_MODE 1") == 0);
    CHECK(strcmp(p.passes[1].defines[1], "PASS_MASK 1") == 0);
    scene_free(&sc);
}

TEST(exact_reference_passes_follow_the_content)
{
    /* The exact reference: opaque, the solid depth of MASK materials, then one list pass for MASK
     * and BLEND, and the list resolve. Without MASK no solid pass; with only opaque materials no
     * list pass and no resolve (the opaque pass is the whole answer). */
    plan_options ref = {.frames = 1, .reference = true, .reference_lists = true};
    scene sc;
    scene_init_defaults(&sc);
    add(&sc, ALPHA_KIND_BLEND, 2);
    add(&sc, ALPHA_KIND_MASK, 3);
    add(&sc, ALPHA_KIND_OPAQUE, 1);
    plan p;
    CHECK(plan_build(&sc, &ref, &p) == FS_OK);
    CHECK(p.pass_count == 3 && p.list_resolve);
    CHECK(p.passes[0].kind == PLAN_PASS_FORWARD_OPAQUE);
    CHECK(p.passes[1].kind == PLAN_PASS_FORWARD_SOLID && p.passes[1].triangles == 3);
    CHECK(p.passes[2].kind == PLAN_PASS_FORWARD_LIST && p.passes[2].triangles == 5);
    CHECK(plan_find(&p, PLAN_PASS_FORWARD_MASK, ALPHA_MODE_STOCHASTIC) == NULL);
    scene_free(&sc);

    scene_init_defaults(&sc);
    add(&sc, ALPHA_KIND_BLEND, 2);
    CHECK(plan_build(&sc, &ref, &p) == FS_OK);
    CHECK(p.pass_count == 1 && p.passes[0].kind == PLAN_PASS_FORWARD_LIST && p.list_resolve);
    scene_free(&sc);

    scene_init_defaults(&sc);
    add(&sc, ALPHA_KIND_OPAQUE, 2);
    CHECK(plan_build(&sc, &ref, &p) == FS_OK);
    CHECK(p.pass_count == 1 && p.passes[0].kind == PLAN_PASS_FORWARD_OPAQUE && !p.list_resolve);
    scene_free(&sc);
}

TEST(unplaced_assets_cost_nothing)
{
    scene sc;
    scene_init_defaults(&sc);
    add(&sc, ALPHA_KIND_MASK, 0);
    add(&sc, ALPHA_KIND_OPAQUE, 1);
    plan p;
    CHECK(plan_build(&sc, NULL, &p) == FS_OK);
    CHECK(p.pass_count == 1 && p.passes[0].kind == PLAN_PASS_FORWARD_OPAQUE);
    scene_free(&sc);
}

static bool pass_has_define(const plan_pass *ps, const char *define)
{
    for (int d = 0; d < ps->define_count; d++)
        if (!strcmp(ps->defines[d], define))
            return true;
    return false;
}

/* How many passes compile the alpha LOD clamp. */
static int clamp_passes(const plan *p)
{
    int n = 0;
    for (int i = 0; i < p->pass_count; i++)
        n += pass_has_define(&p->passes[i], "ALPHA_LOD_CLAMP 1");
    return n;
}

/* The alpha LOD clamp (docs/hashed-alpha.md "Alpha LOD clamp"): ALPHA_LOD_CLAMP only in the MASK
 * passes of materials that have a clamp (their own "alpha_lod_max", else --alpha-lod-max), none
 * for --alpha-lod-max off, none for the reference. */
TEST(alpha_lod_clamp_only_where_a_material_has_one)
{
    scene sc;
    scene_init_defaults(&sc);
    add(&sc, ALPHA_KIND_MASK, 2);
    add(&sc, ALPHA_KIND_MASK, 3);
    add(&sc, ALPHA_KIND_OPAQUE, 1);
    add(&sc, ALPHA_KIND_BLEND, 1);
    snprintf(sc.assets[0].materials[0].name, sizeof sc.assets[0].materials[0].name, "leaves");
    snprintf(sc.assets[1].materials[0].name, sizeof sc.assets[1].materials[0].name, "flowers");
    sc.assets[1].materials[0].alpha_mode = ALPHA_MODE_HASHED; /* a pass of its own */
    material *leaves = &sc.assets[0].materials[0], *flowers = &sc.assets[1].materials[0];
    char buf[128];
    plan p;

    /* Nothing asked: no variant, bit-identical passes to before the option existed. */
    CHECK(plan_build(&sc, NULL, &p) == FS_OK);
    CHECK(p.pass_count == 4 && clamp_passes(&p) == 0 && p.alpha_lod_prims == 0);
    CHECK(plan_material_alpha_lod_max(&p, leaves) < 0.0f);
    plan_alpha_lod_format(&p, &sc, buf, sizeof buf);
    CHECK(buf[0] == '\0');

    /* --alpha-lod-max 5: both MASK passes, not the opaque or blend ones. */
    plan_options o = {.alpha = {.lod_clamp = 1, .lod_max = 5.0f}};
    CHECK(plan_build(&sc, &o, &p) == FS_OK);
    CHECK(clamp_passes(&p) == 2 && p.alpha_lod_prims == 2);
    CHECK(pass_has_define(plan_find(&p, PLAN_PASS_FORWARD_MASK, ALPHA_MODE_TRADITIONAL), "ALPHA_LOD_CLAMP 1"));
    CHECK(pass_has_define(plan_find(&p, PLAN_PASS_FORWARD_MASK, ALPHA_MODE_HASHED), "ALPHA_LOD_CLAMP 1"));
    CHECK(plan_material_alpha_lod_max(&p, leaves) == 5.0f);
    CHECK(plan_material_alpha_lod_max(&p, &sc.assets[3].materials[0]) < 0.0f); /* BLEND */
    plan_alpha_lod_format(&p, &sc, buf, sizeof buf);
    CHECK(strcmp(buf, "leaves 5, flowers 5") == 0);

    /* A material's own clamp: only its pass; with --alpha-lod-max it wins over the option. */
    flowers->has_alpha_lod_max = true;
    flowers->alpha_lod_max = 3.0f;
    CHECK(plan_build(&sc, NULL, &p) == FS_OK);
    CHECK(clamp_passes(&p) == 1 && p.alpha_lod_prims == 1);
    CHECK(pass_has_define(plan_find(&p, PLAN_PASS_FORWARD_MASK, ALPHA_MODE_HASHED), "ALPHA_LOD_CLAMP 1"));
    CHECK(!pass_has_define(plan_find(&p, PLAN_PASS_FORWARD_MASK, ALPHA_MODE_TRADITIONAL), "ALPHA_LOD_CLAMP 1"));
    CHECK(plan_build(&sc, &o, &p) == FS_OK);
    CHECK(plan_material_alpha_lod_max(&p, flowers) == 3.0f && plan_material_alpha_lod_max(&p, leaves) == 5.0f);
    plan_alpha_lod_format(&p, &sc, buf, sizeof buf);
    CHECK(strcmp(buf, "leaves 5, flowers 3") == 0);

    /* --alpha-lod-max off: none, the scene's neither. */
    o.alpha.lod_clamp = -1;
    CHECK(plan_build(&sc, &o, &p) == FS_OK);
    CHECK(clamp_passes(&p) == 0 && p.alpha_lod_prims == 0 && plan_material_alpha_lod_max(&p, flowers) < 0.0f);

    /* The reference draws the materials as they are (both kinds), whatever is asked. */
    o.alpha.lod_clamp = 1;
    for (int lists = 0; lists < 2; lists++) {
        plan_options r = o;
        r.reference = true;
        r.reference_lists = lists;
        CHECK(plan_build(&sc, &r, &p) == FS_OK);
        CHECK(clamp_passes(&p) == 0 && p.alpha_lod_prims == 0);
        CHECK(plan_material_alpha_lod_max(&p, flowers) < 0.0f && plan_material_alpha_lod_max(&p, leaves) < 0.0f);
    }
    scene_free(&sc);

    /* No MASK material, no variant, whatever is asked. */
    scene_init_defaults(&sc);
    add(&sc, ALPHA_KIND_OPAQUE, 1);
    add(&sc, ALPHA_KIND_BLEND, 1);
    o.alpha.lod_clamp = 1;
    CHECK(plan_build(&sc, &o, &p) == FS_OK);
    CHECK(clamp_passes(&p) == 0 && p.alpha_lod_prims == 0);
    scene_free(&sc);
}

TEST(modes_choose_variants_and_targets)
{
    scene sc;
    scene_init_defaults(&sc);
    add(&sc, ALPHA_KIND_MASK, 1);
    plan p;
    /* Every mode compiles its own MASK variant; only the A2C modes ask for MSAA targets. */
    for (int m = ALPHA_MODE_TRADITIONAL; m < ALPHA_MODE_COUNT; m++) {
        CHECK(plan_build(&sc, &(plan_options){.alpha_mode = (alpha_mode)m}, &p) == FS_OK);
        const plan_pass *ps = plan_find(&p, PLAN_PASS_FORWARD_MASK, (alpha_mode)m);
        CHECK(ps != NULL);
        bool a2c = m == ALPHA_MODE_A2C || m == ALPHA_MODE_HASHED_A2C;
        CHECK(p.msaa == a2c);
        CHECK(p.castano == (m == ALPHA_MODE_CASTANO));
        bool msaa_define = false;
        for (int d = 0; ps && d < ps->define_count; d++)
            msaa_define |= strcmp(ps->defines[d], "MSAA 1") == 0;
        CHECK(msaa_define == a2c);
    }
    /* The scene's own mode applies when the CLI gives none; a material override beats both. */
    sc.alpha_mode = ALPHA_MODE_HASHED;
    CHECK(plan_build(&sc, NULL, &p) == FS_OK && p.global_mode == ALPHA_MODE_HASHED);
    sc.assets[0].materials[0].alpha_mode = ALPHA_MODE_STOCHASTIC;
    CHECK(plan_build(&sc, NULL, &p) == FS_OK);
    CHECK(plan_find(&p, PLAN_PASS_FORWARD_MASK, ALPHA_MODE_STOCHASTIC) != NULL);
    CHECK(plan_find(&p, PLAN_PASS_FORWARD_MASK, ALPHA_MODE_HASHED) == NULL);
    /* Defaults of the hashed parameters. */
    CHECK(p.alpha.hash_scale == 1.0f && p.alpha.fade_n == 6.0f && !p.alpha.no_fade);
    scene_free(&sc);
}

TEST(shipped_scenes)
{
    /* Built-in scenes: foliage is MASK over opaque trunks, posts and ground; nothing blends. */
    const char *names[] = {"forest", "fence", "tree", "grass", "wind"};
    for (int i = 0; i < 5; i++) {
        scene sc;
        CHECK(scene_load_builtin(names[i], &sc) == FS_OK);
        plan p;
        CHECK(plan_build(&sc, NULL, &p) == FS_OK);
        CHECK(plan_find(&p, PLAN_PASS_FORWARD_MASK, ALPHA_MODE_TRADITIONAL) != NULL);
        CHECK(plan_find(&p, PLAN_PASS_FORWARD_OPAQUE, ALPHA_MODE_DEFAULT) != NULL);
        CHECK(plan_find(&p, PLAN_PASS_FORWARD_BLEND, ALPHA_MODE_DEFAULT) == NULL);
        CHECK(!p.msaa);
        CHECK(p.width == 1280 && p.height == 720);
        scene_free(&sc);
    }
    /* The opaque control asset from the MegaKit: one opaque pass, even when --alpha asks for hashed. */
    scene sc;
    CHECK(scene_load_file(test_shared_path("assets/quaternius_megakit_set_a/Grass_Wispy_Tall.gltf"), &sc) == FS_OK);
    plan p;
    CHECK(plan_build(&sc, &(plan_options){.alpha_mode = ALPHA_MODE_HASHED}, &p) == FS_OK);
    CHECK(p.pass_count == 1 && p.passes[0].kind == PLAN_PASS_FORWARD_OPAQUE);
    scene_free(&sc);
    /* The BLEND control asset gets a blend pass and nothing else. */
    CHECK(scene_load_file(test_shared_path("assets/polypizza_flower_bushes_glb/flower_bushes.glb"), &sc) == FS_OK);
    CHECK(plan_build(&sc, NULL, &p) == FS_OK);
    CHECK(p.pass_count == 1 && p.passes[0].kind == PLAN_PASS_FORWARD_BLEND);
    scene_free(&sc);
}

static bool has_define(const plan_pass *ps, const char *d)
{
    for (int i = 0; ps && i < ps->define_count; i++)
        if (strcmp(ps->defines[i], d) == 0)
            return true;
    return false;
}

TEST(rings_and_composite_only_when_asked)
{
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    plan p;
    /* Rings off, no overlay, no debug channels: no composite pass at all. */
    CHECK(plan_build(&sc, NULL, &p) == FS_OK);
    CHECK(!p.rings && !p.composite && p.layout.count == 1 && p.layout.rings[0].scale_log2 == 0);
    /* Overlay alone needs the composite (it draws into it), with one full-resolution ring. */
    CHECK(plan_build(&sc, &(plan_options){.overlay = true}, &p) == FS_OK);
    CHECK(!p.rings && p.composite);
    CHECK(strcmp(p.composite_pass.defines[0], "FOV_RING_COUNT 1") == 0);
    CHECK(strcmp(p.composite_pass.defines[1], "OVERLAY 1") == 0);
    /* The auto layout: several rings, the composite, and debug channels only when asked. */
    display_desc d = sc.display;
    plan_options po = {.layout = fov_layout_auto(&d, 0, 0)};
    CHECK(plan_build(&sc, &po, &p) == FS_OK);
    CHECK(p.rings && p.composite && p.layout.count >= 3);
    for (int i = 0; i < p.composite_pass.define_count; i++)
        CHECK(strncmp(p.composite_pass.defines[i], "DEBUG_CHANNELS", 14) != 0);
    po.debug_channels = true;
    CHECK(plan_build(&sc, &po, &p) == FS_OK);
    bool debug = false;
    for (int i = 0; i < p.composite_pass.define_count; i++)
        debug |= strcmp(p.composite_pass.defines[i], "DEBUG_CHANNELS 1") == 0;
    CHECK(debug);
    /* Rings: the composite draws tiles of one ring with its COMPOSITE_TILE variant, and rings skip
     * what only their hole would see; neither without rings, the tiles not with the overlay (it
     * draws ring borders per pixel), and each can be turned off to measure it. */
    CHECK(p.composite_tiles && p.ring_cull && has_define(&p.composite_tile_pass, "COMPOSITE_TILE 1") &&
          !has_define(&p.composite_pass, "COMPOSITE_TILE 1"));
    po.composite_per_pixel = po.no_ring_cull = true;
    CHECK(plan_build(&sc, &po, &p) == FS_OK);
    CHECK(p.rings && !p.composite_tiles && !p.ring_cull);
    po.composite_per_pixel = po.no_ring_cull = false;
    po.overlay = true;
    CHECK(plan_build(&sc, &po, &p) == FS_OK);
    CHECK(!p.composite_tiles && p.ring_cull);
    CHECK(plan_build(&sc, &(plan_options){.overlay = true}, &p) == FS_OK);
    CHECK(!p.composite_tiles && !p.ring_cull);
    /* The forward passes are the same with or without rings: rings multiply draws, not variants. */
    plan off;
    CHECK(plan_build(&sc, NULL, &off) == FS_OK);
    CHECK(off.pass_count == p.pass_count);
    scene_free(&sc);
}

TEST(taa_only_for_sequences_and_reprojection_only_for_a_moving_camera)
{
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    plan p;
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 1}, &p) == FS_OK);
    CHECK(!p.taa); /* one frame: no history */
    CHECK(plan_build(&sc, &(plan_options){.taa = false, .frames = 48}, &p) == FS_OK);
    CHECK(!p.taa);
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48}, &p) == FS_OK);
    CHECK(p.taa && p.camera_motion);
    /* the default resolve (docs/taa.md, "A leaner resolve"): cross, Catmull-Rom, NaN per tap; the
     * forest is alpha-tested (the sparse-coverage rule) and its camera moves (disocclusion) */
    CHECK(p.taa_pass.define_count == 6 && has_define(&p.taa_pass, "TAA_CAMERA_MOTION 1") &&
          has_define(&p.taa_pass, "TAA_RING_COUNT 1") && has_define(&p.taa_pass, "TAA_NEIGHBOURS 5") &&
          has_define(&p.taa_pass, "TAA_HISTORY_CATMULL_ROM 1") && has_define(&p.taa_pass, "TAA_SPARSE_COVERAGE 1") &&
          has_define(&p.taa_pass, "TAA_DISOCCLUSION 1") && p.taa_sparse && p.taa_disocclusion);
    CHECK(!p.taa_coarse_history);
    CHECK(p.taa_controls.blend == 0.1f && p.taa_controls.gamma == 1.0f && p.taa_controls.jitter_length == 16);
    CHECK(p.taa_controls.neighbourhood == TAA_NEIGHBOURHOOD_CROSS && p.taa_controls.history == TAA_HISTORY_CATMULL &&
          p.taa_controls.nan_check == TAA_NAN_TAP);
    /* the other variants, each to its define */
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48, .taa_controls = {.neighbourhood = TAA_NEIGHBOURHOOD_3X3,
                                          .history = TAA_HISTORY_BILINEAR, .nan_check = TAA_NAN_SET}}, &p) == FS_OK);
    CHECK(p.taa_pass.define_count == 6 && has_define(&p.taa_pass, "TAA_NEIGHBOURS 9") &&
          !has_define(&p.taa_pass, "TAA_HISTORY_CATMULL_ROM 1") && has_define(&p.taa_pass, "TAA_NAN_PER_SET 1"));
    /* --taa-disocclusion off */
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48, .taa_controls = {.no_disocclusion = true}}, &p) ==
          FS_OK);
    CHECK(!p.taa_disocclusion && !has_define(&p.taa_pass, "TAA_DISOCCLUSION 1"));
    /* out-of-range values fall back to the defaults */
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48, .taa_controls = {.neighbourhood = (taa_neighbourhood_kind)7,
                                          .history = (taa_history_kind)-1, .nan_check = (taa_nan_kind)9}}, &p) == FS_OK);
    CHECK(has_define(&p.taa_pass, "TAA_NEIGHBOURS 5") && has_define(&p.taa_pass, "TAA_HISTORY_CATMULL_ROM 1") &&
          !has_define(&p.taa_pass, "TAA_NAN_PER_SET 1"));
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48}, &p) == FS_OK);
    /* Hashed thresholds get their per-frame offset only with TAA. */
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48, .alpha_mode = ALPHA_MODE_HASHED}, &p) == FS_OK);
    CHECK(has_define(plan_find(&p, PLAN_PASS_FORWARD_MASK, ALPHA_MODE_HASHED), "TAA_HASH_OFFSET 1"));
    CHECK(!p.taa_coarse_history); /* one ring: no coarser history to take */
    /* With rings, stochastic tests take a coarser ring's history after a saccade; traditional not. */
    fov_layout l;
    char err[128];
    CHECK(fov_layout_parse("10:1:0,*:1/2:0", &sc.display, &l, err, sizeof err) == FS_OK);
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48, .alpha_mode = ALPHA_MODE_HASHED, .layout = l}, &p) == FS_OK);
    CHECK(p.taa_coarse_history && has_define(&p.taa_pass, "TAA_COARSE_HISTORY 1") && has_define(&p.taa_pass, "TAA_RING_COUNT 2"));
    /* Rings that cull: history from a hole is invalid (TAA_RING_CULL); not when culling is off. */
    CHECK(p.ring_cull && has_define(&p.taa_pass, "TAA_RING_CULL 1"));
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48, .layout = l, .no_ring_cull = true}, &p) == FS_OK);
    CHECK(!p.ring_cull && !has_define(&p.taa_pass, "TAA_RING_CULL 1"));
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48, .alpha_mode = ALPHA_MODE_STOCHASTIC, .layout = l}, &p) == FS_OK);
    CHECK(p.taa_coarse_history);
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48, .alpha_mode = ALPHA_MODE_TRADITIONAL, .layout = l}, &p) == FS_OK);
    CHECK(!p.taa_coarse_history && !has_define(&p.taa_pass, "TAA_COARSE_HISTORY 1"));
    /* The sparse-coverage rule wherever a surface is alpha-tested (docs/taa.md "Sparse coverage and disocclusion": a jittered sub-pixel
     * leaf is a binary draw under any test), with or without hashed's per-frame offset. */
    const struct {
        alpha_mode mode;
        bool no_offset, sparse;
    } sparse_cases[] = {{ALPHA_MODE_STOCHASTIC, false, true}, {ALPHA_MODE_HASHED, false, true},
                        {ALPHA_MODE_HASHED_A2C, false, true}, {ALPHA_MODE_HASHED, true, true},
                        {ALPHA_MODE_TRADITIONAL, false, true}, {ALPHA_MODE_A2C, false, true},
                        {ALPHA_MODE_CASTANO, false, true}, {ALPHA_MODE_MIPSCALE, false, true}};
    for (size_t i = 0; i < sizeof sparse_cases / sizeof sparse_cases[0]; i++) {
        plan_options po = {.taa = true, .frames = 48, .alpha_mode = sparse_cases[i].mode,
                           .alpha = {.no_frame_offset = sparse_cases[i].no_offset}};
        CHECK(plan_build(&sc, &po, &p) == FS_OK);
        CHECK(p.taa_sparse == sparse_cases[i].sparse);
        CHECK(has_define(&p.taa_pass, "TAA_SPARSE_COVERAGE 1") == sparse_cases[i].sparse);
        CHECK(has_define(plan_find(&p, PLAN_PASS_FORWARD_MASK, sparse_cases[i].mode), "TAA_HASH_OFFSET 1") ==
              ((sparse_cases[i].mode == ALPHA_MODE_HASHED || sparse_cases[i].mode == ALPHA_MODE_HASHED_A2C) &&
               !sparse_cases[i].no_offset));
    }
    /* ... and not when it is off. */
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48, .alpha_mode = ALPHA_MODE_STOCHASTIC,
                                          .taa_controls = {.sparse = -1.0f}}, &p) == FS_OK);
    CHECK(!p.taa_sparse && !has_define(&p.taa_pass, "TAA_SPARSE_COVERAGE 1"));
    /* A still camera: TAA without reprojection through depth. */
    sc.camera.count = 1;
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48}, &p) == FS_OK);
    CHECK(p.taa && !p.camera_motion && !has_define(&p.taa_pass, "TAA_CAMERA_MOTION 1"));
    CHECK(!p.taa_disocclusion && !has_define(&p.taa_pass, "TAA_DISOCCLUSION 1")); /* nothing moves */
    scene_free(&sc);
}

TEST(sway_and_per_object_motion_only_where_instances_sway)
{
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    plan p;
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48}, &p) == FS_OK);
    CHECK(!p.sway && !p.velocity && p.sway_instances == 0); /* a static scene compiles neither */
    for (int i = 0; i < p.pass_count; i++)
        CHECK(!has_define(&p.passes[i], "SWAY 1") && !has_define(&p.passes[i], "OBJECT_MOTION 1"));
    CHECK(!has_define(&p.taa_pass, "TAA_OBJECT_MOTION 1"));
    scene_free(&sc);

    CHECK(scene_load_builtin("wind", &sc) == FS_OK);
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48}, &p) == FS_OK);
    CHECK(p.sway && p.velocity && p.sway_instances == sc.instance_count);
    CHECK(!p.camera_motion); /* the camera stands still: the leaves are what moves */
    for (int i = 0; i < p.pass_count; i++) /* trunks and leaves bend together */
        CHECK(has_define(&p.passes[i], "SWAY 1") && has_define(&p.passes[i], "OBJECT_MOTION 1"));
    CHECK(has_define(&p.taa_pass, "TAA_OBJECT_MOTION 1") && !has_define(&p.taa_pass, "TAA_CAMERA_MOTION 1"));
    /* Without TAA nothing reads motion: sway only. */
    CHECK(plan_build(&sc, &(plan_options){.taa = false, .frames = 48}, &p) == FS_OK);
    CHECK(p.sway && !p.velocity);
    for (int i = 0; i < p.pass_count; i++)
        CHECK(has_define(&p.passes[i], "SWAY 1") && !has_define(&p.passes[i], "OBJECT_MOTION 1"));
    /* --object-motion off: TAA as for a still scene. */
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48, .taa_controls = {.no_object_motion = true}}, &p) ==
          FS_OK);
    CHECK(p.sway && !p.velocity && !has_define(&p.taa_pass, "TAA_OBJECT_MOTION 1"));
    /* Every alpha mode's pass fits its defines (hashed A2C with TAA has the most). */
    CHECK(plan_build(&sc, &(plan_options){.taa = true, .frames = 48, .alpha_mode = ALPHA_MODE_HASHED_A2C}, &p) == FS_OK);
    const plan_pass *m = plan_find(&p, PLAN_PASS_FORWARD_MASK, ALPHA_MODE_HASHED_A2C);
    CHECK(m && has_define(m, "OBJECT_MOTION 1") && has_define(m, "TAA_HASH_OFFSET 1") && has_define(m, "MSAA 1"));
    scene_free(&sc);
}

int main(void)
{
    RUN(opaque_scene_has_no_alpha_variant_whatever_the_mode);
    RUN(mask_and_blend_get_their_passes_in_draw_order);
    RUN(exact_reference_passes_follow_the_content);
    RUN(unplaced_assets_cost_nothing);
    RUN(modes_choose_variants_and_targets);
    RUN(alpha_lod_clamp_only_where_a_material_has_one);
    RUN(shipped_scenes);
    RUN(rings_and_composite_only_when_asked);
    RUN(taa_only_for_sequences_and_reprojection_only_for_a_moving_camera);
    RUN(sway_and_per_object_motion_only_where_instances_sway);
    return test_summary();
}
