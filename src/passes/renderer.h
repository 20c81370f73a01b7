/* renderer.h: the GL back end: uploads a scene, runs the plan's passes for a frame_record, reads
 * the result back as an exr_image (R, G, B, A, coverage; linear, premultiplied).
 *
 * Usage (a GL context must be current: gl_device_create):
 *   renderer *r = renderer_create(&(renderer_desc){ .scene = &sc, .plan = &pl }, &status);
 *   renderer_draw(r, &frame);  renderer_read(r, &img);  ...  renderer_destroy(r);
 *
 * Passes declare their resources (docs/design.md "Conventions"): see k_forward_resources in renderer_upload.c.
 * With foveation the forward passes run once per ring into the ring's own target (cropped frustum,
 * ring mip bias), and a composite pass upsamples and blends the rings at display resolution.
 * A2C modes draw each ring through a shared 4x MSAA target and resolve it into the ring's layer.
 * Each ring draws only the instances its frustum sees, less those wholly inside its hole (where the
 * finer ring is shown alone; plan.ring_cull); the composite draws the display in tiles, those of
 * one ring without the per-pixel ring search (plan.composite_tiles). TAA resolves each ring after
 * its passes (plan.taa) and follows swaying instances' own motion (plan.velocity).
 */
#ifndef FOVSIM_RENDERER_H
#define FOVSIM_RENDERER_H

#include "core/status.h"
#include "output/exr_write.h"
#include "passes/abuffer.h"
#include "passes/plan.h"
#include "frame/frame.h"
#include "scene/scene.h"

typedef struct renderer renderer;

typedef struct renderer_desc {
    const scene *scene; /* borrowed: must outlive the renderer */
    const plan *plan;   /* copied */
    bool timers;        /* GL timer queries around each stage (for bench), and pipeline statistics
                         * queries where GL_ARB_pipeline_statistics_query is supported */
    bool count_fragments; /* also build the counting variant of the forward passes
                           * (renderer_set_counting; docs/benchmarks.md "Work counts") */
    uint64_t list_nodes; /* plan.reference_lists: nodes the list store starts with (0 = 4 per pixel;
                          * at most renderer_list_nodes_max) */
} renderer_desc;

#define RENDERER_STATS_MAX (2 * MAX_FOV_RINGS + PLAN_MAX_PASSES + 1)

/* Timed stages of the last frame: the forward passes (and the TAA resolve) when foveation is off;
 * each ring's passes, its TAA resolve and the composite when it is on. */
typedef struct renderer_stats {
    int pass_count;
    char pass_names[RENDERER_STATS_MAX][48];
    long long shaded_pixels;                 /* ring target pixels drawn (display pixels when off) */
    double pass_ms[RENDERER_STATS_MAX];      /* GL timer query of each stage of the last frame, -1 = none */
    double pass_wall_ms[RENDERER_STATS_MAX]; /* wall clock of each pass with glFinish around it, -1 = not
                                             measured (renderer_set_pass_sync off). Software
                                             rasterisers (llvmpipe) defer work to the flush, so only
                                             this measure is meaningful there. */
    /* GL_ARB_pipeline_statistics_query counts of each stage of the last frame, -1 = unknown (no
     * extension, or no timers): vertex-shader invocations, primitives submitted (what the draw
     * calls sent, before clipping and culling) and fragment-shader invocations. */
    long long pass_vs_invocations[RENDERER_STATS_MAX];
    long long pass_primitives[RENDERER_STATS_MAX];
    long long pass_fs_invocations[RENDERER_STATS_MAX];
    long long pass_clipped[RENDERER_STATS_MAX]; /* primitives after clipping (GL_CLIPPING_OUTPUT_PRIMITIVES_ARB) */
    /* Covered fragments (docs/benchmarks.md "Work counts"), -1 = not counted (the last frame was
     * not drawn with renderer_set_counting on): the forward passes' from the counting variant's
     * counter; full-screen stages (TAA resolve, list resolve, composite) cover the pixels they
     * draw. ring_pass_covered: each ring's (stage's, rings off) forward passes, in plan order. */
    long long pass_covered[RENDERER_STATS_MAX];
    bool pass_geometry[RENDERER_STATS_MAX]; /* the stage draws the scene (forward passes), not a full-screen pass */
    long long ring_pass_covered[MAX_FOV_RINGS][PLAN_MAX_PASSES];
    /* Fragment-shader invocations a GPU would run, from the same counting frame, -1 = not counted:
     * covered fragments, but under VRS (`vrs`) one per primitive and coarse pixel with a covered
     * pixel (docs/benchmarks.md "VRS: coarse-shading invocations"). `shaded`: their sum. */
    long long pass_shaded[RENDERER_STATS_MAX], shaded;
    bool vrs;
    /* Bytes each stage read and wrote, from its targets' footprints (passes/pass_bytes.h), -1 = not
     * modelled (the exact reference's list passes). Rings off: the forward passes' on the first. */
    long long pass_bytes_read[RENDERER_STATS_MAX], pass_bytes_written[RENDERER_STATS_MAX];
    int ring_count;                          /* rings of the plan (1 when foveation is off) */
    int ring_instances[MAX_FOV_RINGS];       /* instances each ring drew (frustum and hole culling) */
    /* The frame's: sums of the stages above, -1 = unknown. `fragments` = fragment-shader invocations. */
    long long vs_invocations, primitives, fragments, clipped, covered, bytes_read, bytes_written;
} renderer_stats;

renderer *renderer_create(const renderer_desc *desc, fs_status *status);
void renderer_destroy(renderer *r);
/* Draws one frame into the renderer's targets. */
fs_status renderer_draw(renderer *r, const frame_record *fr);
/* Reads colour and coverage into *img (initialised here; rows top first): channels R, G, B, A,
 * coverage, and ring.id + eccentricity when the plan asks for debug channels. The exact
 * reference's plan (plan.list_resolve): its resolved lists, and RENDERER_LIST_FLAG_CHANNEL with
 * each pixel's ABUFFER_FLAG_* (long lists and overflowed ones are not resolved there). */
fs_status renderer_read(renderer *r, exr_image *img);
#define RENDERER_LIST_FLAG_CHANNEL "list.flag"
/* The last frame's window depth in [0, 1] (width * height floats, rows top first), for a plan
 * without rings or MSAA (one display-sized target). */
fs_status renderer_read_depth(renderer *r, float *depth);
/* plan.list_resolve: the opaque pass alone (what the lists are composited over), R, G, B, A, coverage. */
fs_status renderer_read_opaque(renderer *r, exr_image *img);
/* With `on`, every later renderer_draw finishes the GPU after each pass and records its wall time
 * (renderer_stats.pass_wall_ms). Adds sync overhead: bench measures frame time without it. */
void renderer_set_pass_sync(renderer *r, bool on);
/* With `on` (and renderer_desc.count_fragments), later frames draw the forward passes' counting
 * variant and renderer_last_stats reports covered fragments; the timed frames of bench keep it
 * off, so the frame they measure is the one without the counter. A counting frame leaves TAA's
 * state (history, previous frame) as it was, so it may be drawn between two frames of a sequence
 * (after reading the first back: it overwrites the targets). */
void renderer_set_counting(renderer *r, bool on);
/* A counting frame of fr in one call: drawn with the counting variant on, its statistics into
 * *counted, the variant off again. The draw's status. */
fs_status renderer_draw_counting(renderer *r, const frame_record *fr, renderer_stats *counted);
/* A VRS frame's (counted->vrs) fragment-shader invocations are what a GPU would shade: each scene
 * stage's pipeline statistic in *timed (on llvmpipe: every pixel of the blocks the emulation
 * shades, twice drawn) becomes the counting frame's pass_shaded, and `fragments` their sum with
 * the other stages'. Other frames: unchanged. docs/benchmarks.md "VRS: coarse-shading invocations"
 * says why the two units differ and which count compares rings with VRS. */
void renderer_stats_take_shaded(renderer_stats *timed, const renderer_stats *counted);
/* Blocks until the GPU has finished all submitted work (glFinish), for wall-clock timing. */
void renderer_finish(renderer *r);
/* The exact reference's fragment lists (plan.reference_lists, abuffer.h). The store holds a fixed
 * number of nodes; a frame that asks for more loses fragments and says so (abuffer_lists.count >
 * capacity, and the pixels' overflow marks). */
/* The most nodes one store can hold here (the GL buffer-texture limit). */
uint64_t renderer_list_nodes_max(void);
/* Grows the store to at least `nodes` (at most renderer_list_nodes_max); the next frame uses it. */
fs_status renderer_reserve_list_nodes(renderer *r, uint64_t nodes);
/* The last frame's lists (borrowed: valid until the next call or renderer_destroy); rows top first.
 * `with_nodes` false reads only the counts (count, capacity), for deciding whether to grow. */
fs_status renderer_read_lists(renderer *r, abuffer_lists *out, bool with_nodes);

/* Sets a ring's mip bias for later frames (the reference draws grids of several sizes). */
void renderer_set_mip_bias(renderer *r, int ring, float bias);

/* Pass timings of the last frame (valid after renderer_draw with timers; waits for results). */
renderer_stats renderer_last_stats(renderer *r);
/* The GL framebuffer whose colour attachment 0 (its read buffer) holds the last frame's
 * display-resolution colour (linear, premultiplied, GL rows: bottom first), for presenting it in
 * a window: the viewer blits from it (src/gl/gl_window.c). Borrowed; TAA alternates between two
 * framebuffers, so ask again after every renderer_draw. */
unsigned renderer_output_framebuffer(const renderer *r);

#endif
