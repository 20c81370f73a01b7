// composite.frag: foveation rings to display resolution (docs/design.md "Foveation", "Composite").
// Every display pixel takes the innermost ring that covers it, upsampled bilinearly, blended with the
// next ring inside the band at each border. Outputs colour, coverage and, with DEBUG_CHANNELS,
// ring.id (ring + blend weight of the next) and eccentricity (degrees).
// The rings are layers of one texture array, so a pixel fetches only the one or two rings it uses
// (a sampler array would need a dynamically uniform index, i.e. fetching every ring everywhere).
// The display is drawn as cells classified on the CPU (composite.vert): with COMPOSITE_TILE
// this program draws the cells whose every pixel takes one ring without blending, and skips
// the eccentricity and the search (a branch would not: llvmpipe runs both sides of it), taking the
// ring's rectangle and block from the cell (flat inputs); without, it draws the others and
// searches per pixel. Both fetch exactly the same texels, so the result
// does not depend on the classification (tested: tiled == per-pixel, bit for bit).
#include "common/foveation.glsl"

layout(binding = 0) uniform sampler2DArray u_ring_color;    // layer i = ring i
layout(binding = 1) uniform sampler2DArray u_ring_coverage;
uniform vec2 u_array_px;                     // width, height of the array layers (texels)
uniform vec4 u_ring_rect[FOV_RING_COUNT];    // x0, y0, x1, y1 in display pixels (top-left origin)
uniform float u_ring_block[FOV_RING_COUNT];  // display pixels per ring pixel (1, 2, 4, ...)

flat in int v_ring;                          // COMPOSITE_TILE: the cell's ring,
#ifdef COMPOSITE_TILE
flat in vec4 v_ring_rect;                    // its u_ring_rect
flat in float v_ring_block;                  // and its u_ring_block
#endif

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_coverage;
#ifdef DEBUG_CHANNELS
layout(location = 2) out vec4 o_debug;       // .r = ring.id, .g = eccentricity
#endif

// Texture coordinate of display point p in ring i (ring row 0 is the bottom of the rect). A ring
// renders into the corner of its layer, so bilinear taps are clamped to the rendered texel centres:
// where a footprint was clipped at the display edge this replicates the edge, as clamp-to-edge
// would, instead of reading texels outside the rendered region.
vec3 ring_uvw_of(vec4 r, float b, int i, vec2 p)
{
    vec2 t = vec2(p.x - r.x, r.w - p.y) / b;      // ring texels
    vec2 size = vec2(r.z - r.x, r.w - r.y) / b;   // rendered texels
    return vec3(clamp(t, vec2(0.5), size - 0.5) / u_array_px, float(i));
}

vec3 ring_uvw(int i, vec2 p)
{
    return ring_uvw_of(u_ring_rect[i], u_ring_block[i], i, p);
}

void main()
{
    vec2 p = vec2(gl_FragCoord.x, u_display_px.y - gl_FragCoord.y); // pixel centre, top-left origin
#ifdef COMPOSITE_TILE
    int ring = v_ring;
    float next = 0.0;
#if defined(DEBUG_CHANNELS)
    float e = fov_eccentricity_deg(p);
#endif
#else
    float e = fov_eccentricity_deg(p);
    int ring;
    float next;
    fov_composite_weight(e, ring, next);
#endif
#ifdef COMPOSITE_TILE
    vec3 uvw = ring_uvw_of(v_ring_rect, v_ring_block, ring, p);
#else
    vec3 uvw = ring_uvw(ring, p);
#endif
    vec4 c = textureLod(u_ring_color, uvw, 0.0);
    float cov = textureLod(u_ring_coverage, uvw, 0.0).r;
    if (next > 0.0) {
        vec3 uvw1 = ring_uvw(ring + 1, p);
        c = mix(c, textureLod(u_ring_color, uvw1, 0.0), next);
        cov = mix(cov, textureLod(u_ring_coverage, uvw1, 0.0).r, next);
    }
#ifdef OVERLAY
    // Ring borders (1 display pixel wide) and a gaze marker (a cross, 9 pixels).
    float px_deg = fwidth(e);
    for (int i = 0; i < FOV_RING_COUNT - 1; i++)
        if (abs(e - u_ring_outer[i]) < 0.75 * px_deg)
            c = vec4(1.0, 0.9, 0.1, 1.0);
    vec2 d = abs(p - (floor(u_gaze_px) + 0.5)); // centred on the display pixel holding the gaze
    if ((d.x < 0.5 && d.y < 4.5) || (d.y < 0.5 && d.x < 4.5))
        c = vec4(1.0, 0.0, 1.0, 1.0);
#endif
    o_color = c;
    o_coverage = vec4(cov, 0.0, 0.0, 1.0);
#ifdef DEBUG_CHANNELS
    o_debug = vec4(float(ring) + next, e, 0.0, 1.0);
#endif
}
