/* renderer_internal.h: what the renderer's files share (internal to src/passes/; the public
 * contract is renderer.h): `struct renderer` and its GL objects, the resources the passes declare,
 * and the steps of renderer_create that live in renderer_upload.c.
 *
 *   renderer.c         the programs, renderer_create and _destroy
 *   renderer_upload.c  the resources the passes declare, the scene on the GPU (textures, samplers,
 *                      primitives, instances), the render targets, the exact reference's list store
 *   renderer_draw.c    one frame: each ring's culling and forward passes, the list pass and its
 *                      resolve, the TAA resolve; stage timing and statistics
 *   renderer_composite.c  the composite: the display classified into cells, drawn as points
 *   renderer_vrs.c     VRS foveation's rate image, filled per frame (plan.vrs)
 *   renderer_stats.c   renderer_last_stats: the stages' queries, covered fragments, footprint bytes
 *   renderer_read.c    read-back (images, depth, fragment lists) and the framebuffer the viewer blits
 *
 * What it does NOT do: anything a caller outside src/passes/ may use.
 */
#ifndef FOVSIM_RENDERER_INTERNAL_H
#define FOVSIM_RENDERER_INTERNAL_H

#include "passes/renderer.h"

#include <epoxy/gl.h>

#include "passes/pass_bytes.h"

/* >>resources: what the passes read and write (the tables are in renderer_upload.c) */
typedef struct pass_resource {
    const char *name, *desc;
    GLenum format;
    bool output, optional;
} pass_resource;

/* k_forward_resources: each ring's forward passes write these, at the ring's resolution. */
enum { RES_COLOR, RES_COVERAGE, RES_DEPTH, RES_MOTION, RES_COUNT };
extern const pass_resource k_forward_resources[RES_COUNT];

/* k_composite_resources: the composite reads every ring's color and coverage and writes these at
 * display resolution. */
enum { OUT_COLOR, OUT_COVERAGE, OUT_DEBUG, OUT_COUNT };
extern const pass_resource k_composite_resources[OUT_COUNT];

/* >>types */
typedef struct gpu_program {
    GLuint id;
    GLint u_view_proj, u_has_base_tex, u_base_color, u_alpha_cutoff, u_double_sided, u_mip_bias, u_mip_scale, u_eye,
        u_light_dir, u_light_color, u_ambient, u_hash_scale, u_hash_kind, u_hash_aniso, u_fade_n, u_frame, u_time,
        u_prev_time, u_draw_order, u_list_capacity, u_hash_instance, u_ring_lod,
        u_ring_lod_instance, u_ring_lod_px, u_alpha_lod_max, u_count_slot, u_vrs_tile, u_vrs_viewport;
} gpu_program;

typedef struct composite_program {
    GLuint id;
    GLint u_display_px, u_focal_px, u_principal_px, u_gaze_px, u_ring_outer, u_ring_band, u_ring_rect, u_ring_block, u_array_px;
} composite_program;

/* A square of the composite (renderer_composite.c): window pixels [x0, x1) x [y0, y1) (row 0 at
 * the bottom) of a square of `side` at (x0, y0), cut by the display's edge unless `whole`; the ring
 * all its pixels take, or -1 (searched per pixel). */
typedef struct comp_square {
    int x0, y0, x1, y1, side, ring;
    bool whole;
} comp_square;

typedef struct taa_program {
    GLuint id;
    GLint u_layer, u_size, u_prev_size, u_array_px, u_inv_view_proj, u_prev_view_proj, u_history_valid, u_blend,
        u_gamma, u_sparse, u_rect, u_prev_rect, u_block, u_ring_prev_rect, u_ring_block, u_cull_gaze_px,
        u_cull_principal_px, u_cull_focal_px, u_ring_hole_deg, u_prev_inv_view_proj, u_view_proj;
} taa_program;

typedef struct gpu_prim {
    GLuint vao, vbo[4], ibo;
    GLuint card_vbo[2];      /* plan.ring_lod, MASK primitives: (card centre, rank) and the card's
                              * side per vertex */
    GLuint tri_vbo;          /* where the passes read it: ATTR_TRIANGLE per vertex (renderer_upload.c) */
    GLsizei index_count;
    uint32_t vertex_count;   /* on the GPU: duplicated provoking vertices included */
    uint32_t *vsrc;          /* during the upload, where vertices were duplicated: each one's source */
} gpu_prim;

typedef struct gpu_asset {
    gpu_prim *prims;
    GLuint *textures;       /* per image */
    GLuint *castano;        /* per material: coverage-preserving chain of its image at its cutoff, or 0 */
    float *fade_n;          /* per material: hashed fade-in length in mip levels, 0 = no fade */
    GLuint *samplers;       /* per material */
    GLuint instance_vbo;    /* mat4 per instance of this asset, in instance_ids order */
    GLuint sway_vbo;        /* plan.sway: (offset, height), (frequency, phase, 0, 0) per instance */
    int *instance_ids;      /* scene instance index of each slot */
    unsigned char *visible; /* per slot: may be visible in the ring being drawn (frustum culling) */
    float *cull_pad;        /* plan.sway, per slot: how far (asset units) sway may leave the box */
    int instance_count;
    int slot_base;          /* instances of the earlier assets: slot k is the scene's slot_base + k */
    /* plan.ring_lod: per ring, the asset-space box its enlarged cards may reach (culling) under a
     * per-ring law; for per-card rings, the largest card radius / side (ring_lod_cull_pad) */
    vec3 lod_lo[MAX_FOV_RINGS], lod_hi[MAX_FOV_RINGS];
    float lod_aspect, lod_side_min; /* and the narrowest card's side, asset units */
} gpu_asset;

/* Ring targets: colour and coverage are texture arrays with one layer per ring, each layer the
 * size of the display (the innermost ring may need all of it); a ring renders into the
 * footprint's (width x height) corner of its layer. Rings draw one after another, so they share
 * one depth buffer. */
typedef struct ring_targets {
    GLuint fbo[MAX_FOV_RINGS];
    GLuint color, coverage, depth;
    GLuint motion; /* plan.velocity: one display-sized 2D target shared by the rings, as depth is */
    /* A2C modes: every ring draws into one shared multisampled target (display-sized), then
     * resolves its footprint corner into its layer. */
    GLuint msaa_fbo, msaa_color, msaa_coverage, msaa_depth, msaa_motion;
} ring_targets;

#define RENDERER_MAX_STAGES (2 * MAX_FOV_RINGS + PLAN_MAX_PASSES + 1)
/* Pipeline statistics queried per stage (k_stat_targets in renderer_draw.c). */
#define RENDERER_STAT_TARGETS 4

/* One blended instance to draw, farthest first. */
typedef struct sort_item {
    float dist2;
    int asset, slot;
} sort_item;

struct renderer {
    const scene *sc;
    plan pl;
    gpu_asset *assets;
    sort_item *blend_order;                /* scratch for the BLEND sort: one per instance */
    gpu_program programs[PLAN_MAX_PASSES]; /* one per plan pass, same index */
    composite_program comp;
    composite_program comp_tile;           /* plan.composite_tiles: the cells of one ring */
    GLuint tile_vao, tile_vbo;             /* the composite's cells, rebuilt every frame */
    float *tile_verts;                     /* scratch: up to 6 vertices (x, y, ring) per cell */
    comp_square *squares;                  /* scratch: the frame's squares, at most one per tile */
    int square_count;
    float point_max;                       /* the largest point size the GL draws */
    ring_targets rt;
    GLuint out_fbo, out_tex[OUT_COUNT];    /* display targets of the composite */
    GLuint empty_vao;                      /* TAA's full-screen triangle needs a bound VAO */
    GLuint ring_sampler;                   /* bilinear, clamp to edge */
    int width, height;
    bool timers;
    int stage_count;                       /* timed stages: passes (rings off) or rings + composite */
    char stage_names[RENDERER_MAX_STAGES][48];
    GLuint time_queries[RENDERER_MAX_STAGES];
    double stage_wall_ms[RENDERER_MAX_STAGES];
    /* Pipeline statistics queries of each stage (GL_ARB_pipeline_statistics_query), one per
     * k_stat_targets entry; 0 when the extension is missing or timers are off. */
    GLuint stat_queries[RENDERER_MAX_STAGES][RENDERER_STAT_TARGETS];
    bool stat_queries_on;
    bool stats_pending;
    /* >>counting: renderer_desc.count_fragments builds count_programs (COUNT_FRAGMENTS, one per
     * plan pass) and count_buf (one counter per ring and pass); renderer_set_counting picks them. */
    gpu_program count_programs[PLAN_MAX_PASSES];
    GLuint count_buf;                      /* COUNT_WORDS words (common/shared_defs.h) */
    /* VRS: the twins' counting variants (id 0: none) and the coarse pixels' keys, one word per
     * display pixel (COUNT_COARSE_KEYS_BINDING) */
    gpu_program count_vrs_programs[PLAN_MAX_PASSES];
    GLuint count_keys_buf;
    bool counting, counted;                /* draw with them / the last frame was drawn with them */
    long long fullscreen_px[RENDERER_MAX_STAGES]; /* pixels each full-screen stage drew, last frame */
    pass_bytes stage_bytes[RENDERER_MAX_STAGES];  /* each stage's footprint bytes, last frame (-1: not modelled) */
    target_bytes target_bpp;                      /* bytes per pixel of the targets (renderer_target_bytes) */
    /* >>taa state: resolved rings ping-pong between two pairs of arrays (no read/write of one
     * texture in a pass); the previous frame's unjittered ring matrices and footprints. */
    taa_program taa;
    GLuint taa_color[2], taa_coverage[2], taa_fbo[2][MAX_FOV_RINGS];
    GLuint taa_depth[2];     /* plan.taa_disocclusion: each history pixel's nearest depth, R32F */
    GLuint taa_sampler;
    int parity;                             /* the pair this frame writes */
    int out_parity;                         /* the pair the last frame wrote */
    bool have_prev;
    int prev_index;
    float prev_time;                        /* the previous frame's time (per-object motion) */
    mat4 prev_vp[MAX_FOV_RINGS];
    fov_ring_rect prev_rect[MAX_FOV_RINGS];
    float prev_gaze_px[2], prev_focal_px;   /* plan.ring_cull: where the previous frame's holes were */
    float prev_principal_px[2];             /* ... and its principal point (fov_principal_px) */
    float prev_hole_deg[MAX_FOV_RINGS];     /* fov_ring_hole_deg of the rings that culled, else 0 */
    mat4 draw_vp;                           /* the view-projection the ring being drawn uses */
    bool pass_sync;
    long long shaded_pixels;               /* ring target pixels drawn by the last frame */
    int ring_instances[MAX_FOV_RINGS];     /* instances each ring drew in the last frame */
    float *read_buf, *read_row;            /* renderer_read's scratch, made on first use */
    /* >>lists: the exact reference's list pass (plan.reference_lists; abuffer.h) */
    GLuint list_head;                      /* R32UI, display-sized: each pixel's first node */
    GLuint list_nodes, list_nodes_tex;     /* the node store and its RGBA32UI buffer texture */
    GLuint list_counter;                   /* shader storage: nodes asked for (atomicAdd) */
    uint64_t list_capacity;                /* nodes the store holds */
    uint32_t list_draw_order;              /* instances drawn so far in this pass (draw_order.glsl) */
    int list_phase;                        /* the list pass draws MASK (0), then BLEND (1) materials */
    uint64_t list_initial;                 /* renderer_desc.list_nodes, or 4 per pixel */
    GLuint list_prog;                      /* the resolve (plan.list_resolve) */
    GLint list_u_capacity;
    GLuint list_fbo, list_color, list_coverage; /* its output: RGBA32F, RG32F (coverage, flag) */
    uint32_t *list_head_buf;               /* renderer_read_lists' scratch */
    void *list_node_buf;
    uint64_t list_node_buf_cap;
    /* >>vrs: plan.vrs: the rate image (R8UI, one texel per tile, row 0 the top row of tiles) and
     * the map vrs_map_fill writes into it every frame for the rendered gaze */
    GLuint vrs_tex;
    vrs_rate *vrs_rates;
    int vrs_tiles_x, vrs_tiles_y;
    gpu_program vrs_programs[PLAN_MAX_PASSES]; /* each plan pass's VRS twin (plan_pass_vrs), id 0: none */
    int *vrs_rects;        /* this frame's 1x1 tiles as window rectangles (x, y, width, height) */
    int vrs_rect_count;
    bool vrs_coarse;       /* this frame's map has a tile coarser than 1x1 */
};

/* >>create: renderer_create's steps after the programs (renderer_upload.c) */
fs_status renderer_upload_scene(renderer *r);
fs_status renderer_create_targets(renderer *r);
/* >>vrs (renderer_vrs.c, plan.vrs): the rate image's texture, map and rectangles; each frame, the
 * map for the frame's rendered gaze uploaded and bound, and its 1x1 tiles as rectangles (where
 * the passes' own programs draw); the uniforms of a VRS twin. */
fs_status renderer_vrs_create(renderer *r);
void renderer_vrs_frame(renderer *r, const frame_record *fr);
void renderer_vrs_uniforms(const renderer *r, const gpu_program *pg);
/* >>composite (renderer_composite.c) */
/* The composite's vertex buffer and scratch (its targets and sampler are renderer_upload.c's). */
fs_status renderer_composite_create(renderer *r);
/* The composite pass of frame fr into the display targets. */
void renderer_draw_composite(renderer *r, const frame_record *fr);
/* Bytes per pixel of the targets the plan creates, from the resource tables (pass_bytes.h). */
target_bytes renderer_target_bytes(const renderer *r);

#endif
