// draw_order.glsl: whether a forward pass knows each fragment's place in the API order of its draws
// (FORWARD_DRAW_ORDER: u_draw_order, the draw's first instance, + the instance in the vertex
// shader's v_instance). The exact reference's list pass orders equal depths by it; stochastic alpha
// tests salt their thresholds with it, so that coplanar layers drawn by different draws or
// instances (same primitive index, same depth) are tested independently. Included by forward.vert
// and forward.frag, after the pass's defines.
#if defined(PASS_LIST)
#define FORWARD_DRAW_ORDER 1
#elif defined(PASS_MASK)
#if ALPHA_MODE == ALPHA_MODE_ID_STOCHASTIC
#define FORWARD_DRAW_ORDER 1
#endif
#endif
