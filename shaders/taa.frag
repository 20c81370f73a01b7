// taa.frag: temporal antialiasing of one foveation ring (docs/design.md "Temporal antialiasing").
// Runs over the ring's footprint in ring pixels, right after the ring was drawn with sub-pixel
// jitter. Each pixel reprojects through its depth (and, with TAA_OBJECT_MOTION, its swaying
// instance's own motion) into the PREVIOUS frame's ring (the ring frustum moves with the gaze),
// fetches that history (Catmull-Rom or bilinear), clips it to the variance box of the current
// neighbourhood (3x3 or cross) in YCoCg (widened by the coverage the history keeps beyond the
// neighbourhood's), and blends. History that falls outside the
// previous ring's footprint (a saccade) comes, with TAA_COARSE_HISTORY (stochastic alpha tests),
// from the innermost coarser ring whose previous footprint holds it; where none does, without it,
// or where the point was behind the previous camera, the pixel takes the current sample. With
// TAA_DISOCCLUSION the history also records its nearest surface's depth, and history whose nearest
// surface has moved off the pixel is dropped; the history's coverage is kept unless the pixel's own
// sample refutes it (TAA_SPARSE_COVERAGE). NaN and Inf never enter history. The math is in
// common/taa.glsl (C twin: src/passes/taa_math.c).
#include "common/taa.glsl"

layout(binding = 0) uniform sampler2DArray u_cur_color;     // this frame's rings (jittered)
layout(binding = 1) uniform sampler2DArray u_cur_coverage;
layout(binding = 2) uniform sampler2D u_depth;              // this ring's depth
layout(binding = 3) uniform sampler2DArray u_hist_color;    // last frame's resolved rings
layout(binding = 4) uniform sampler2DArray u_hist_coverage;
#ifdef TAA_OBJECT_MOTION
layout(binding = 5) uniform sampler2D u_motion;             // this ring's per-object motion (world)
#endif
#if defined(TAA_DISOCCLUSION) && !(defined(TAA_CAMERA_MOTION) || defined(TAA_OBJECT_MOTION))
#error "TAA_DISOCCLUSION needs the reprojection through depth (TAA_CAMERA_MOTION or TAA_OBJECT_MOTION)"
#endif
#ifdef TAA_DISOCCLUSION
layout(binding = 6) uniform sampler2DArray u_hist_depth;    // last frame's history: its nearest surface's depth
uniform mat4 u_prev_inv_view_proj; // this ring, last frame, unjittered: NDC -> world
uniform mat4 u_view_proj;          // this ring, this frame, unjittered: world -> clip
#endif
uniform int u_layer;             // this ring's layer in both arrays
uniform vec2 u_size;             // this frame's footprint, ring pixels
uniform vec2 u_prev_size;        // last frame's footprint of this ring, ring pixels
uniform vec2 u_array_px;         // size of the array layers, texels
uniform mat4 u_inv_view_proj;    // this ring, this frame, unjittered: NDC -> world
uniform mat4 u_prev_view_proj;   // this ring, last frame, unjittered: world -> clip
uniform vec4 u_rect;             // this frame's footprint, display pixels (x0, y0, x1, y1)
uniform vec4 u_prev_rect;        // last frame's footprint
uniform float u_block;           // display pixels per ring pixel
uniform vec4 u_ring_prev_rect[TAA_RING_COUNT]; // every ring's footprint last frame, display pixels
uniform float u_ring_block[TAA_RING_COUNT];    // every ring's display pixels per ring pixel
uniform bool u_history_valid;    // false on the first frame and after a camera cut
uniform float u_blend;           // weight of the current sample, default 0.1
uniform float u_gamma;           // variance box half-width in sigmas, default 1
uniform float u_sparse;          // sparse-coverage slack (taa_sparse_margin), default 0.28; 0 = off
#ifdef TAA_RING_CULL
#include "common/eccentricity.glsl"
uniform vec2 u_cull_gaze_px;     // last frame's gaze, display pixels (top-left origin)
uniform vec2 u_cull_principal_px; // last frame's principal point, display pixels
uniform float u_cull_focal_px;   // last frame's focal length, display pixels
uniform float u_ring_hole_deg[TAA_RING_COUNT]; // fov_ring_hole_deg of each ring (0: no hole)

// Last frame, ring `layer` skipped the instances that lay wholly in its hole around the gaze of
// then (plan.ring_cull): its history at display point `at` is valid only outside that hole. The
// hole is the culled region grown by FOV_CULL_MARGIN_BLOCKS ring pixels, which covers the
// Catmull-Rom taps around `at` (2 ring pixels) and the jitter.
bool culled_history(vec2 at, int layer)
{
    return fov_angle_deg(at, u_cull_gaze_px, u_cull_principal_px, u_cull_focal_px) < u_ring_hole_deg[layer];
}
#endif

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_coverage;
#ifdef TAA_DISOCCLUSION
layout(location = 2) out vec4 o_depth; // the window depth of the nearest surface this pixel's history holds
#endif

// Compile-time variants (`fovsim plan` shows which; docs/taa.md "A leaner resolve" has their
// measured accuracy and cost): TAA_NEIGHBOURS 9 (3x3) or 5 (the cross) taps for the clip box;
// TAA_HISTORY_CATMULL_ROM: 5-tap Catmull-Rom history, else one bilinear tap; TAA_NAN_PER_SET: NaN
// and Inf checked once per set of fetches, else per tap.
#ifndef TAA_NEIGHBOURS
#define TAA_NEIGHBOURS 9
#endif
#ifdef TAA_NAN_PER_SET
const bool TAA_PER_TAP = false;
#else
const bool TAA_PER_TAP = true;
#endif
// The centre, the cross, then the corners: the first TAA_NEIGHBOURS of these.
const ivec2 TAA_OFFSET[TAA_MAX_TAPS] = ivec2[TAA_MAX_TAPS](ivec2(0, 0), ivec2(0, -1), ivec2(-1, 0), ivec2(1, 0),
                                                           ivec2(0, 1), ivec2(-1, -1), ivec2(1, -1), ivec2(-1, 1),
                                                           ivec2(1, 1));

// History at ring-pixel position p of the previous footprint (common/taa.glsl: taa_catmull_rom_taps,
// taa_history_sum). Coverage: one bilinear tap (its history needs no sharpening).
vec4 fetch_history(vec2 p, int layer, vec2 prev_size, out float cov)
{
    vec2 lo = vec2(0.5), hi = prev_size - 0.5;
    vec4 t[5];
    float w[5];
#ifdef TAA_HISTORY_CATMULL_ROM
    vec3 taps[5];
    taa_catmull_rom_taps(p, prev_size, taps);
    for (int k = 0; k < 5; k++) {
        t[k] = textureLod(u_hist_color, vec3(taps[k].xy / u_array_px, float(layer)), 0.0);
        w[k] = taps[k].z;
    }
    const int n = 5;
#else
    t[0] = textureLod(u_hist_color, vec3(clamp(p, lo, hi) / u_array_px, float(layer)), 0.0);
    w[0] = 1.0;
    for (int k = 1; k < 5; k++) {
        t[k] = vec4(0.0);
        w[k] = 0.0;
    }
    const int n = 1;
#endif
    cov = taa_sanitize(textureLod(u_hist_coverage, vec3(clamp(p, lo, hi) / u_array_px, float(layer)), 0.0).r);
    return taa_history_sum(t, w, n, TAA_PER_TAP);
}

#ifdef TAA_DISOCCLUSION
// The history's nearest surface around ring-pixel position p of layer `layer` (the nearest of the
// four texels around it), at hist_ndc (xy) of this ring's previous frame: does it land on this
// pixel (common/taa.glsl: taa_history_surface_here)?
bool surface_here(vec2 p, int layer, vec2 hist_ndc, vec3 motion, vec2 here_ndc, float depth_cur, out float keep,
                  out vec2 offset)
{
    vec4 g = textureGather(u_hist_depth, vec3(p / u_array_px, float(layer)), 0);
    float z = min(min(g.x, g.y), min(g.z, g.w));
    return taa_history_surface_here(vec3(hist_ndc, z * 2.0 - 1.0), motion, u_prev_inv_view_proj, u_view_proj, here_ndc,
                                    u_size, depth_cur, float(TAA_PARALLAX_PX), keep, offset);
}
#endif

// p (ring pixels) lies where the Catmull-Rom fetch has rendered texels around it.
bool inside_footprint(vec2 p, vec2 size)
{
    return all(greaterThanEqual(p, vec2(0.5))) && all(lessThanEqual(p, size - 0.5));
}

void main()
{
    ivec2 pix = ivec2(gl_FragCoord.xy);
    // The neighbourhood's statistics in YCoCg (variance clipping); its centre is the current sample.
    vec4 taps[TAA_MAX_TAPS];
    float covs[TAA_MAX_TAPS];
    for (int k = 0; k < TAA_MAX_TAPS; k++) {
        if (k < TAA_NEIGHBOURS) {
            ivec2 q = clamp(pix + TAA_OFFSET[k], ivec2(0), ivec2(u_size) - 1);
            taps[k] = texelFetch(u_cur_color, ivec3(q, u_layer), 0);
            covs[k] = texelFetch(u_cur_coverage, ivec3(q, u_layer), 0).r;
        } else {
            taps[k] = vec4(0.0);
            covs[k] = 0.0;
        }
    }
    taa_box box = taa_neighbourhood(taps, covs, TAA_NEIGHBOURS, TAA_PER_TAP);
    vec4 cur = taa_sanitize4(taps[0]);
    float cur_cov = taa_sanitize(covs[0]);

    // Reproject through depth into last frame's ring.
    bool valid = u_history_valid;
    vec2 prev = vec2(0.0), prev_size = u_prev_size;
    int prev_layer = u_layer;
#if defined(TAA_CAMERA_MOTION) || defined(TAA_OBJECT_MOTION)
    vec2 ndc = (vec2(pix) + 0.5) / u_size * 2.0 - 1.0; // this pixel's centre, this frame's NDC
    vec2 prev_ndc = ndc;                               // where it was last frame
    vec3 motion = vec3(0.0);                           // its own motion (world, last frame - now)
    float depth_cur = texelFetch(u_depth, pix, 0).r;   // its own sample's window depth
#endif
    if (valid) {
#if defined(TAA_CAMERA_MOTION) || defined(TAA_OBJECT_MOTION)
        // The camera moves, or instances sway: through depth and last frame's camera and ring
        // frustum, plus where the fragment's own motion (swaying instances) moved it.
        // Through the nearest surface of the neighbourhood (Karis 2014): a pixel whose sample missed a
        // thin leaf or wire the neighbours hit follows that leaf, whose history it shares.
        ivec2 near_px = pix;
        float zw = depth_cur;
        for (int k = 1; k < TAA_NEIGHBOURS; k++) {
            ivec2 q = clamp(pix + TAA_OFFSET[k], ivec2(0), ivec2(u_size) - 1);
            float zq = texelFetch(u_depth, q, 0).r;
            near_px = zq < zw ? q : near_px;
            zw = min(zq, zw);
        }
        float z = zw * 2.0 - 1.0;
#ifdef TAA_OBJECT_MOTION
        motion = texelFetch(u_motion, near_px, 0).xyz;
        valid = taa_reproject_moving(vec3(ndc, z), motion, u_inv_view_proj, u_prev_view_proj, prev_ndc);
#else
        valid = taa_reproject(vec3(ndc, z), u_inv_view_proj, u_prev_view_proj, prev_ndc);
#endif
        prev = (prev_ndc * 0.5 + 0.5) * u_prev_size;
#else
        // Still camera (the plan knows): a pixel stays on the same display pixel, and only the
        // ring's footprint may have moved with the gaze. No depth needed.
        vec2 disp = vec2(u_rect.x + (float(pix.x) + 0.5) * u_block, u_rect.w - (float(pix.y) + 0.5) * u_block);
        prev = vec2(disp.x - u_prev_rect.x, u_prev_rect.w - disp.y) / u_block;
#endif
        // Outside last frame's footprint of this ring (a saccade moved it): with stochastic alpha
        // tests, the same display point in the innermost coarser ring whose footprint held it;
        // else no history.
        if (valid && !inside_footprint(prev, u_prev_size)) {
            valid = false;
#ifdef TAA_COARSE_HISTORY
            vec2 at = vec2(u_prev_rect.x + prev.x * u_block, u_prev_rect.w - prev.y * u_block); // display px
            for (int k = u_layer + 1; k < TAA_RING_COUNT && !valid; k++) {
                vec4 r = u_ring_prev_rect[k];
                vec2 size = (r.zw - r.xy) / u_ring_block[k];
                vec2 q = vec2(at.x - r.x, r.w - at.y) / u_ring_block[k];
                if (inside_footprint(q, size)) {
                    valid = true;
                    prev = q;
                    prev_size = size;
                    prev_layer = k;
                }
            }
#endif
        }
#ifdef TAA_RING_CULL
        // History from where last frame's ring drew only part of the scene (its hole): none.
        if (valid) {
            vec4 r = prev_layer == u_layer ? u_prev_rect : u_ring_prev_rect[prev_layer];
            float b = prev_layer == u_layer ? u_block : u_ring_block[prev_layer];
            valid = !culled_history(vec2(r.x + prev.x * b, r.w - prev.y * b), prev_layer);
        }
#endif
    }
#ifdef TAA_DISOCCLUSION
    // Disocclusion: the history records, per pixel, the depth of the nearest surface it holds.
    // Carried into this frame, that surface must still lie on this pixel; where it has moved away
    // (the pixel's surface now moves differently from what the history shows), the history is of
    // something else (taa_history_surface_here; docs/taa.md, "Sparse coverage and disocclusion").
    float keep = depth_cur;
    if (valid) {
        vec2 offset;
        valid = surface_here(prev, prev_layer, prev_ndc, motion, ndc, depth_cur, keep, offset);
        // Not here: the history whose nearest surface does land here lies `offset` back from where
        // this pixel's own surface came from (a missed leaf's history, where the sample saw what is
        // behind it). Look there once, in this ring's own history.
        vec2 back = prev - offset;
        if (!valid && prev_layer == u_layer && inside_footprint(back, u_prev_size) && dot(offset, offset) > 0.0) {
            vec2 back_ndc = back / u_prev_size * 2.0 - 1.0;
            valid = surface_here(back, prev_layer, back_ndc, motion, ndc, depth_cur, keep, offset);
            prev = valid ? back : prev;
        }
    }
    o_depth = vec4(keep, 0.0, 0.0, 1.0);
#endif
    vec4 hist = cur;
    float hist_cov = cur_cov;
    if (valid) {
        hist = fetch_history(prev, prev_layer, prev_size, hist_cov);
        // Sparse coverage: the history's coverage is kept unless this pixel's own sample refutes it
        // (taa_sparse_coverage, docs/taa.md); the colour box and the alpha range widen by what it
        // keeps outside the neighbourhood's range. Without TAA_SPARSE_COVERAGE (--taa-sparse off, or
        // no alpha-tested surface): the plain clamp to the neighbourhood.
        float m;
#ifdef TAA_SPARSE_COVERAGE
        hist_cov = taa_sparse_coverage(hist_cov, cur_cov, box.coverage.x, box.coverage.y, u_sparse, m);
#else
        hist_cov = taa_sparse_coverage(hist_cov, cur_cov, box.coverage.x, box.coverage.y, 0.0, m);
#endif
        vec3 y = taa_clip_to_box(taa_rgb_to_ycocg(hist.rgb), box.mean, box.sigma, u_gamma, float(TAA_SPARSE_COLOR) * m);
        hist = vec4(taa_ycocg_to_rgb(y), clamp(hist.a, box.alpha.x - m, box.alpha.y + m));
    }
    o_color = taa_resolve4(cur, hist, valid, u_blend);
    o_coverage = vec4(taa_resolve(cur_cov, hist_cov, valid, u_blend), 0.0, 0.0, 1.0);
}
