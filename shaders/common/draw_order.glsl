// draw_order.glsl: whether a forward pass knows each fragment's place in the API order of its draws
// (FORWARD_DRAW_ORDER: u_draw_order, the draw's first instance, + the instance in the vertex
// shader's v_instance; then the triangle within the draw's primitive, v_primitive). The exact
// reference's list pass orders equal depths by it; stochastic alpha tests salt their thresholds
// with it, so that coplanar layers drawn by different draws or instances (same primitive index,
// same depth) are tested independently. v_primitive is exactly what gl_PrimitiveID counts, read
// from the flat attribute ATTR_TRIANGLE (its y; FORWARD_HASH_LAYER below says why not
// gl_PrimitiveID). Included by forward.vert and forward.frag, after the pass's defines.
#if defined(PASS_LIST)
#define FORWARD_DRAW_ORDER 1
#elif defined(PASS_MASK)
#if ALPHA_MODE == ALPHA_MODE_ID_STOCHASTIC
#define FORWARD_DRAW_ORDER 1
#endif
#endif

// FORWARD_HASH_LAYER: the hashed modes key each fragment's noise lattice by its instance and its
// triangle (alpha_hash_layer, docs/hashed-alpha.md "Layers"). The instance id is its slot in the
// scene (u_hash_instance, the draw's first slot, + gl_InstanceID in v_hash_instance), not its place
// in this frame's draws, which culling changes: the key, and so the noise, stays put over frames,
// rings and modes. The triangle is the asset's triangle index (triangles of its earlier primitives
// + the primitive's own, as gl_PrimitiveID counts them), a flat vertex attribute (ATTR_TRIANGLE,
// v_hash_triangle) that the upload gives each triangle's provoking vertex, duplicating a vertex
// that two triangles end on. Not gl_PrimitiveID: where a fragment shader reads it and no geometry
// shader writes it, llvmpipe's draw module reassembles every triangle (a realloc per triangle and a
// memcpy per vertex: 5 % of a hashed foveated frame, docs/benchmarks.md "Throughput on llvmpipe").
#if defined(PASS_MASK)
#if ALPHA_MODE == ALPHA_MODE_ID_HASHED || ALPHA_MODE == ALPHA_MODE_ID_HASHED_A2C
#define FORWARD_HASH_LAYER 1
#endif
#endif

// FORWARD_TRIANGLE: either of the above reads ATTR_TRIANGLE. The upload gives it to every
// primitive these passes draw (renderer_upload.c, prim_needs_triangles).
#if defined(FORWARD_DRAW_ORDER) || defined(FORWARD_HASH_LAYER)
#define FORWARD_TRIANGLE 1
#endif
