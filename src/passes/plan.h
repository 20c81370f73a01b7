/* plan.h: which passes and shader variants a scene needs, decided before anything is drawn.
 *
 * docs/design.md "Simulate only what the scene calls for": the plan is computed once from the scene's
 * content and the run options. A scene with no MASK material gets no alpha-test variant whatever
 * --alpha says; no BLEND material, no blend pass; no MSAA target unless an A2C mode is in use; no
 * TAA history for a single frame; no rings when foveation is off; no sway without swaying instances
 * and no per-object motion (velocity) without sway and TAA.
 * `fovsim plan` prints it; tests assert it for the shipped scenes.
 *
 * Pure C (no GL): the renderer consumes a plan, it does not make one.
 */
#ifndef FOVSIM_PLAN_H
#define FOVSIM_PLAN_H

#include <stdbool.h>
#include <stdio.h>

#include "fov/fov_ring.h"
#include "fov/ring_lod.h"
#include "fov/vrs_map.h"
#include "scene/scene.h"

#ifndef PLAN_MAX_PASSES
#define PLAN_MAX_PASSES 16
#endif
#define PLAN_MAX_DEFINES 12

typedef enum plan_pass_kind {
    PLAN_PASS_FORWARD_OPAQUE = 0,
    PLAN_PASS_FORWARD_MASK,
    PLAN_PASS_FORWARD_BLEND,
    PLAN_PASS_FORWARD_SOLID, /* the exact reference: depth of MASK fragments of alpha 1, pushed back */
    PLAN_PASS_FORWARD_LIST, /* the exact reference: MASK and BLEND fragments into per-pixel lists */
} plan_pass_kind;

typedef struct plan_pass {
    plan_pass_kind kind;
    char name[48];          /* "forward.opaque", "forward.mask[traditional]", "forward.blend", "forward.list" */
    alpha_mode mode;        /* MASK passes: the strategy; others: DEFAULT */
    const char *vs, *fs;    /* embedded shader paths */
    const char *gs;         /* geometry shader between them, or NULL (VRS twins: forward_vrs.geom) */
    char defines[PLAN_MAX_DEFINES][48]; /* sorted "NAME VALUE" strings */
    int define_count;
    int prim_count;         /* primitives (per asset, drawn instanced) this pass draws */
    long long triangles;    /* triangles per frame, instances included */
} plan_pass;

/* Parameters of the hashed-family alpha tests (seed 000 §5), the same for every material. */
typedef struct alpha_params {
    float hash_scale;   /* noise scale in pixels, default 1 (seed 000 §5.4.1 suggests 0.3-0.5 with TAA) */
    int hash_kind;      /* ALPHA_HASH_* (common/shared_defs.h), default the project's choice */
    bool anisotropic;   /* per-axis derivative scaling of the hash (option) */
    bool no_fade;       /* disable the fade-in of hashed noise with LOD (seed 000 §5.5.1) */
    bool no_frame_offset; /* with TAA: no per-frame golden-ratio offset of hashed thresholds */
    float fade_n;       /* mip levels over which the noise fades in, default 6 */
    bool a2c_sharpen;   /* a2c: Golus's mip-level alpha scaling and fwidth sharpening (seed 002) */
    int lod_clamp;      /* --alpha-lod-max: 0 = only materials with their own "alpha_lod_max";
                         * 1 = lod_max for every MASK material without one; -1 (off) = no clamp */
    float lod_max;      /* with lod_clamp 1: mip level in [0, ALPHA_LOD_MAX_LIMIT] */
} alpha_params;

/* Fills zero fields with defaults. */
alpha_params alpha_params_defaults(const alpha_params *p);

/* The resolve's variants (docs/taa.md, "A leaner resolve"); 0 = the default. */
typedef enum taa_neighbourhood_kind { TAA_NEIGHBOURHOOD_DEFAULT, TAA_NEIGHBOURHOOD_3X3, TAA_NEIGHBOURHOOD_CROSS } taa_neighbourhood_kind;
typedef enum taa_history_kind { TAA_HISTORY_DEFAULT, TAA_HISTORY_CATMULL, TAA_HISTORY_BILINEAR } taa_history_kind;
typedef enum taa_nan_kind { TAA_NAN_DEFAULT, TAA_NAN_TAP, TAA_NAN_SET } taa_nan_kind;

/* Temporal antialiasing controls (docs/design.md "Temporal antialiasing", docs/taa.md); zero = default. */
typedef struct taa_controls {
    float blend;        /* weight of the current frame, default TAA_BLEND_DEFAULT (0.1) */
    float gamma;        /* variance-box half-width in sigmas, default TAA_GAMMA_DEFAULT (1) */
    int jitter_length;  /* Halton (2,3) period in frames, default TAA_JITTER_LENGTH_DEFAULT (16) */
    float sparse;       /* sparse-coverage slack 1 - alpha in (0, 1] (taa_sparse_coverage),
                         * default TAA_SPARSE_SLACK; negative = off */
    bool no_disocclusion; /* keep history whose nearest surface moved away (no depth test):
                           * for measuring what the test buys */
    bool no_object_motion; /* ignore swaying instances' motion (reproject them as if still):
                            * for measuring what per-object motion buys */
    taa_neighbourhood_kind neighbourhood; /* clip box from the 3x3 or the 5-tap cross (docs/taa.md) */
    taa_history_kind history;           /* history fetch: 5-tap Catmull-Rom or one bilinear tap */
    taa_nan_kind nan_check;       /* NaN / Inf checked per tap or once per set of fetches */
} taa_controls;

taa_controls taa_controls_defaults(const taa_controls *c);

typedef struct plan_options {
    alpha_mode alpha_mode; /* --alpha; DEFAULT = the scene's mode, else traditional */
    int width, height;     /* 0 = the scene's display */
    int frames;            /* frames to draw (TAA would need history only when > 1) */
    fov_layout layout;     /* foveation rings; zeroed = off (one full-resolution ring) */
    alpha_params alpha;    /* hashed-family parameters (zero = defaults) */
    bool overlay;          /* draw ring borders and the gaze marker into the colour */
    bool debug_channels;   /* write ring.id and eccentricity channels */
    bool force_msaa;       /* draw through MSAA targets even without an A2C mode (bench: cost split) */
    bool taa;              /* temporal antialiasing per ring (only when frames > 1) */
    taa_controls taa_controls;
    bool reference;        /* the ground truth's passes (reference.h): every MASK material is drawn
                              stochastic, whatever the scene's or material's mode */
    bool reference_lists;  /* with reference: the exact reference's passes instead, opaque then one
                              list pass that stores every MASK and BLEND fragment (abuffer.h) */
    bool no_ring_cull;     /* rings draw every instance in their frustum, also those only their hole
                              (where the finer ring is shown alone) would see: to measure culling */
    bool composite_per_pixel; /* every composite pixel searches its ring (no tile classification):
                                 for measuring what the classification saves */
    ring_lod_spec ring_lod; /* --ring-lod: per-ring stochastic simplification of MASK foliage
                               (ring_lod.h); zeroed = off. Checked against the layout by the caller */
    bool vrs;              /* VRS foveation (vrs_map.h): one full-resolution pass shaded at the rate
                              map's rates; `layout` is then only what `fovsim plan` compares with */
    vrs_spec vrs_spec;     /* with vrs: the rate map's rule */
    int vrs_tile;          /* with vrs: the tile (8, 16 or 32) */
} plan_options;

typedef struct plan {
    int width, height;
    float hfov_deg;
    float ppx, ppy;             /* the scene display's principal point at width x height (core/display.h) */
    alpha_mode global_mode;     /* effective mode for MASK materials without an override */
    bool reference;             /* plan_options.reference: overrides ignored, global_mode stochastic */
    bool reference_lists;       /* plan_options.reference_lists: MASK and BLEND go to the list pass */
    plan_pass passes[PLAN_MAX_PASSES];
    int pass_count;
    int texture_count;          /* images uploaded (with premultiplied mips) */
    bool msaa;                  /* MSAA_SAMPLES x MSAA targets: only for A2C modes */
    alpha_params alpha;         /* with defaults filled */
    bool castano;               /* some material uses coverage-preserving mips */
    bool taa;                   /* TAA per ring: asked for and more than one frame */
    taa_controls taa_controls;  /* with defaults filled */
    plan_pass taa_pass;         /* shaders of the TAA resolve (valid when taa) */
    int sway_instances;         /* instances that sway in the wind (scene_sway_count) */
    bool sway;                  /* some instance sways: forward passes displace vertices (SWAY) */
    bool velocity;              /* per-object motion: swaying instances and TAA; forward passes
                                 * write a motion target (OBJECT_MOTION), TAA reads it */
    bool camera_motion;         /* the camera path moves: TAA reprojects through depth */
    bool taa_coarse_history;    /* stochastic alpha tests and rings: a pixel that left its ring's
                                 * footprint takes a coarser ring's history */
    bool taa_sparse;            /* the sparse-coverage rule (TAA_SPARSE_COVERAGE): some surface is
                                 * alpha-tested, so a pixel's coverage sample is one binary draw */
    bool taa_disocclusion;      /* history carries its nearest depth and is dropped where that
                                 * surface moved off the pixel (TAA_DISOCCLUSION): TAA reprojects
                                 * through depth (the camera moves or instances sway) */
    bool coverage;              /* coverage channel written (always: opaque scenes write zeros) */
    fov_layout layout;          /* count >= 1; kind OFF = one full-resolution ring */
    bool rings;                 /* foveation on: more than one ring or a reduced scale */
    bool composite;             /* a composite pass runs (rings, overlay or debug channels) */
    bool overlay, debug_channels;
    plan_pass composite_pass;   /* shaders and defines of the composite (valid when composite):
                                 * the rectangles whose pixels search their ring */
    bool ring_cull;             /* rings skip instances whose image lies inside their hole (the
                                 * finer ring shown alone there), fov_ring_cull_deg */
    bool composite_tiles;       /* rings without overlay: rectangles whose every pixel takes one ring
                                 * unblended are drawn by composite_tile_pass, without the search */
    plan_pass composite_tile_pass; /* composite_pass + COMPOSITE_TILE (valid when composite_tiles) */
    ring_lod_spec ring_lod_spec; /* plan_options.ring_lod (kind OFF when ring_lod is false) */
    bool ring_lod;              /* the MASK passes compile RING_LOD (fewer, larger cards in rings whose
                                 * law is not the identity): asked for, not the reference, some placed
                                 * MASK primitive has RING_LOD_MIN_CARDS cards, and some ring's u < 1
                                 * (or the keep fractions were given explicitly) */
    int ring_lod_prims;         /* MASK primitives that are simplified (scene_cards_count) */
    uint64_t ring_lod_cards;    /* their cards, instances included */
    char ring_lod_why[64];      /* asked for but not compiled: why (for `fovsim plan`), else "" */
    int alpha_lod_prims;        /* MASK primitives whose alpha lookup is clamped (plan_material_alpha_lod_max
                                 * >= 0): their passes compile ALPHA_LOD_CLAMP; 0 = no pass does */
    bool list_resolve;          /* the exact reference's list pass runs: its lists are sorted and
                                 * composited by list_resolve_pass (shaders/list_resolve.frag) */
    plan_pass list_resolve_pass;
    bool vrs;                   /* VRS foveation: rings off; each forward pass draws the 1x1 tiles and
                                 * its VRS twin (plan_pass_vrs) the coarser ones, from a rate image
                                 * filled per frame for the rendered gaze */
    vrs_spec vrs_spec;          /* with vrs: the map's rule */
    int vrs_tile;               /* with vrs: its tile */
    fov_layout vrs_rings;       /* with vrs: the rings the run would have drawn (for `fovsim plan`) */
} plan;

/* Builds the plan (FS_ERR_INTERNAL only if the scene needs more than PLAN_MAX_PASSES passes). */
fs_status plan_build(const scene *sc, const plan_options *opt, plan *out);
/* The pass of a kind (and mode for MASK), or NULL when the scene does not need it. */
/* The display the plan draws: width x height, the scene's hfov and principal point. */
display_desc plan_display(const plan *p);
const plan_pass *plan_find(const plan *p, plan_pass_kind kind, alpha_mode mode);
/* The counting variant of forward pass `ps` (docs/benchmarks.md "Work counts"): the same pass with
 * COUNT_FRAGMENTS defined, so its fragment shader counts covered fragments. False (and a logged
 * error) when the pass has no room for another define. */
bool plan_pass_counting(const plan_pass *ps, plan_pass *out);
/* The VRS twin of forward pass `ps` (plan.vrs; docs/foveation.md "Variable-rate shading: coarse
 * shading"): the same pass with the geometry shader forward_vrs.geom and VRS defined, which shades
 * the tiles coarser than 1x1 (the pass itself draws the 1x1 tiles). False for the exact reference's
 * passes, and (with a logged error) when the pass has no room for another define. */
bool plan_pass_vrs(const plan_pass *ps, plan_pass *out);
/* The effective alpha mode of a material under this plan. */
alpha_mode plan_material_mode(const plan *p, const material *m);
/* The mip level at most at which a MASK material's alpha test reads alpha under this plan (its
 * own "alpha_lod_max", else --alpha-lod-max), or ALPHA_LOD_OFF: no clamp, also for the reference
 * (the ground truth of the material as it is) and for materials that are not MASK. */
float plan_material_alpha_lod_max(const plan *p, const material *m);
/* The clamps in use, for `fovsim plan` and the EXR header: "Leaves 6, Flowers 6" (material and
 * level, each name once); "" when none. */
void plan_alpha_lod_format(const plan *p, const scene *sc, char *buf, size_t size);
/* How the plan foveates, for summaries: the ring layout ("auto", "*:1:0"), or under VRS
 * "vrs auto, 16 px tiles" (the rate map's rule and tile). */
void plan_foveation_format(const plan *p, char *buf, size_t size);
/* Human-readable description (for `fovsim plan`). */
void plan_print(const plan *p, const scene *sc, FILE *f);

#endif
