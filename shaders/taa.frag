// taa.frag: temporal antialiasing of one foveation ring (DESIGN.md "Temporal antialiasing").
// Runs over the ring's footprint in ring pixels, right after the ring was drawn with sub-pixel
// jitter. Each pixel reprojects through its depth (and, with TAA_OBJECT_MOTION, its swaying
// instance's own motion) into the PREVIOUS frame's ring (the ring frustum moves with the gaze),
// fetches that history with a Catmull-Rom filter, clips it to the variance box of the current 3x3
// neighbourhood in YCoCg (widened where sparse stochastic coverage
// makes that neighbourhood miss what the history holds), and blends. History that falls outside the
// previous ring's footprint (a saccade) comes, with TAA_COARSE_HISTORY (stochastic alpha tests),
// from the innermost coarser ring whose previous footprint holds it; where none does, without it,
// or where the point was behind the previous camera, the pixel takes the current sample. NaN and
// Inf never enter history. The math is in common/taa.glsl (C twin:
// src/passes/taa_math.c).
#include "common/taa.glsl"

layout(binding = 0) uniform sampler2DArray u_cur_color;     // this frame's rings (jittered)
layout(binding = 1) uniform sampler2DArray u_cur_coverage;
layout(binding = 2) uniform sampler2D u_depth;              // this ring's depth
layout(binding = 3) uniform sampler2DArray u_hist_color;    // last frame's resolved rings
layout(binding = 4) uniform sampler2DArray u_hist_coverage;
#ifdef TAA_OBJECT_MOTION
layout(binding = 5) uniform sampler2D u_motion;             // this ring's per-object motion (world)
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
uniform vec2 u_cull_display_px;  // display width, height
uniform float u_cull_focal_px;   // last frame's focal length, display pixels
uniform float u_ring_hole_deg[TAA_RING_COUNT]; // fov_ring_hole_deg of each ring (0: no hole)

// Last frame, ring `layer` skipped the instances that lay wholly in its hole around the gaze of
// then (plan.ring_cull): its history at display point `at` is valid only outside that hole. The
// hole is the culled region grown by FOV_CULL_MARGIN_BLOCKS ring pixels, which covers the
// Catmull-Rom taps around `at` (2 ring pixels) and the jitter.
bool culled_history(vec2 at, int layer)
{
    return fov_angle_deg(at, u_cull_gaze_px, u_cull_display_px, u_cull_focal_px) < u_ring_hole_deg[layer];
}
#endif

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_coverage;

vec4 fetch_cur(ivec2 p)
{
    p = clamp(p, ivec2(0), ivec2(u_size) - 1);
    return taa_sanitize4(texelFetch(u_cur_color, ivec3(p, u_layer), 0));
}

// Catmull-Rom history fetch at ring-pixel position p of the previous footprint, with 5 bilinear
// taps instead of 16 point taps (the 4x4 Catmull-Rom kernel's inner 2x2 taps merged into one
// bilinear fetch per row/column and the four corner taps, whose weights are tiny, dropped:
// Jimenez's approximation). Tap positions are clamped to the rendered texels' centres.
vec4 fetch_history(vec2 p, int layer, vec2 prev_size, out float cov)
{
    vec2 t1 = floor(p - 0.5) + 0.5;
    vec2 f = p - t1;
    vec4 wx = taa_catmull_rom_weights(f.x), wy = taa_catmull_rom_weights(f.y);
    vec2 w0 = vec2(wx.x, wy.x), w12 = vec2(wx.y + wx.z, wy.y + wy.z), w3 = vec2(wx.w, wy.w);
    vec2 t12 = t1 + vec2(wx.z, wy.z) / max(w12, vec2(1e-6));
    vec2 lo = vec2(0.5), hi = prev_size - 0.5;
    vec2 t0 = clamp(t1 - 1.0, lo, hi), t3 = clamp(t1 + 2.0, lo, hi);
    t12 = clamp(t12, lo, hi);
    vec3 taps[5] = vec3[5](vec3(t12.x, t0.y, w12.x * w0.y), vec3(t0.x, t12.y, w0.x * w12.y),
                           vec3(t12.x, t12.y, w12.x * w12.y), vec3(t3.x, t12.y, w3.x * w12.y),
                           vec3(t12.x, t3.y, w12.x * w3.y));
    vec4 c = vec4(0.0);
    float wsum = 0.0;
    for (int i = 0; i < 5; i++) {
        vec3 uvw = vec3(taps[i].xy / u_array_px, float(layer));
        c += taps[i].z * taa_sanitize4(textureLod(u_hist_color, uvw, 0.0));
        wsum += taps[i].z;
    }
    // Coverage: one bilinear tap (its history needs no sharpening).
    cov = taa_sanitize(textureLod(u_hist_coverage, vec3(clamp(p, lo, hi) / u_array_px, float(layer)), 0.0).r);
    return max(c / wsum, vec4(0.0)); // Catmull-Rom undershoots below 0 at sharp edges
}

// p (ring pixels) lies where the Catmull-Rom fetch has rendered texels around it.
bool inside_footprint(vec2 p, vec2 size)
{
    return all(greaterThanEqual(p, vec2(0.5))) && all(lessThanEqual(p, size - 0.5));
}

void main()
{
    ivec2 pix = ivec2(gl_FragCoord.xy);
    vec4 cur = fetch_cur(pix);
    float cur_cov = taa_sanitize(texelFetch(u_cur_coverage, ivec3(pix, u_layer), 0).r);

    // Neighbourhood statistics in YCoCg (variance clipping).
    vec3 m1 = vec3(0.0), m2 = vec3(0.0);
    float a_min = 1e9, a_max = -1e9, c_min = 1e9, c_max = -1e9;
    for (int j = -1; j <= 1; j++)
        for (int i = -1; i <= 1; i++) {
            vec4 s = fetch_cur(pix + ivec2(i, j));
            vec3 y = taa_rgb_to_ycocg(s.rgb);
            m1 += y;
            m2 += y * y;
            a_min = min(a_min, s.a);
            a_max = max(a_max, s.a);
            ivec2 q = clamp(pix + ivec2(i, j), ivec2(0), ivec2(u_size) - 1);
            float cv = taa_sanitize(texelFetch(u_cur_coverage, ivec3(q, u_layer), 0).r);
            c_min = min(c_min, cv);
            c_max = max(c_max, cv);
        }
    vec3 mean = m1 / 9.0;
    vec3 sigma = sqrt(max(m2 / 9.0 - mean * mean, vec3(0.0)));

    // Reproject through depth into last frame's ring.
    bool valid = u_history_valid;
    vec2 prev = vec2(0.0), prev_size = u_prev_size;
    int prev_layer = u_layer;
    if (valid) {
#if defined(TAA_CAMERA_MOTION) || defined(TAA_OBJECT_MOTION)
        // The camera moves, or instances sway: through depth and last frame's camera and ring
        // frustum, plus where the fragment's own motion (swaying instances) moved it.
        vec2 ndc = (vec2(pix) + 0.5) / u_size * 2.0 - 1.0;
        float z = texelFetch(u_depth, pix, 0).r * 2.0 - 1.0;
        vec2 prev_ndc;
#ifdef TAA_OBJECT_MOTION
        vec3 motion = texelFetch(u_motion, pix, 0).xyz;
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
    vec4 hist = cur;
    float hist_cov = cur_cov;
    if (valid) {
        hist = fetch_history(prev, prev_layer, prev_size, hist_cov);
        // Sparse stochastic coverage: where the nine samples all missed (or all hit) a surface the
        // history covers partly, widen the coverage range by what they can miss, and the colour
        // box by a quarter of that (docs/taa.md).
        float m = taa_sparse_margin(hist_cov, c_min, c_max, u_sparse);
        vec3 y = taa_clip_to_box(taa_rgb_to_ycocg(hist.rgb), mean, sigma, u_gamma, float(TAA_SPARSE_COLOR) * m);
        hist = vec4(taa_ycocg_to_rgb(y), clamp(hist.a, a_min - m, a_max + m));
        hist_cov = clamp(hist_cov, c_min - m, c_max + m);
    }
    o_color = taa_resolve4(cur, hist, valid, u_blend);
    o_coverage = vec4(taa_resolve(cur_cov, hist_cov, valid, u_blend), 0.0, 0.0, 1.0);
}
