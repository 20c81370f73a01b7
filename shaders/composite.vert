// composite.vert: the composite draws the display as rectangles (fov_composite_tiles in
// src/fov/fov_ring.c): corners in display pixels, top-left origin, and the ring every pixel of the
// rectangle takes without blending (-1: the pixels differ, the fragment shader searches).
layout(location = 0) in vec3 a_tile; // x, y (display pixels), ring
uniform vec2 u_display_px;           // width, height
flat out int v_ring;

void main()
{
    v_ring = int(a_tile.z);
    gl_Position = vec4(2.0 * a_tile.x / u_display_px.x - 1.0, 1.0 - 2.0 * a_tile.y / u_display_px.y, 0.0, 1.0);
}
