// composite.vert: the composite draws the display as cells classified on the CPU
// (src/passes/renderer_composite.c): points (x, y = the cell's centre) or, where the display's edge
// cuts a cell, two triangles (x, y = corners), in display pixels, top-left origin; and the ring
// every pixel of the cell takes without blending (-1: the pixels differ, the fragment shader
// searches).
layout(location = 0) in vec3 a_tile; // x, y (display pixels), ring
uniform vec2 u_display_px;           // width, height
flat out int v_ring;
#ifdef COMPOSITE_TILE
// The cell's ring's rectangle and block, looked up once per cell rather than per pixel: llvmpipe
// gathers a per-pixel index into a uniform array lane by lane.
uniform vec4 u_ring_rect[FOV_RING_COUNT];
uniform float u_ring_block[FOV_RING_COUNT];
flat out vec4 v_ring_rect;
flat out float v_ring_block;
#endif

void main()
{
    v_ring = int(a_tile.z);
#ifdef COMPOSITE_TILE
    v_ring_rect = u_ring_rect[v_ring];
    v_ring_block = u_ring_block[v_ring];
#endif
    gl_Position = vec4(2.0 * a_tile.x / u_display_px.x - 1.0, 1.0 - 2.0 * a_tile.y / u_display_px.y, 0.0, 1.0);
}
