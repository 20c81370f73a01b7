/* shared_defs.h: constants shared by the GLSL shaders and their C twins.
 *
 * This file is valid C and valid GLSL: only #define lines and comments. C includes it as
 * "common/shared_defs.h" (shaders/ is on the include path); GLSL includes it with
 * #include "common/shared_defs.h". Change a value here and both sides change together.
 */
#ifndef FOVSIM_SHARED_DEFS_H
#define FOVSIM_SHARED_DEFS_H

/* Alpha-test strategies: the one table of them (docs/alpha-modes.md; docs/design-notes.md "Adding
 * an alpha mode"). One row per mode, X(NAME, name, COLOUR, TRAITS):
 *   NAME    C: enum alpha_mode's ALPHA_MODE_<NAME> (src/scene/scene.h); GLSL: ALPHA_MODE_ID_<NAME>,
 *           which shader_src_build defines in every shader (the plan sets ALPHA_MODE to one of them)
 *   name    what --alpha, --modes, scene files and every output call it; NAME is it in capitals
 *   COLOUR  its colour in plots, 0xRRGGBB
 *   TRAITS  what its passes need, ALPHA_TRAIT_* below or'ed (0: none); plan.c turns them into
 *           passes, targets and defines
 * A mode's id (both enums) is its row: 1 for the first; 0 is ALPHA_MODE_DEFAULT, "not set". The
 * table holds only identifiers and numbers, so GLSL reads this file too (it never expands it). */
#define ALPHA_TRAIT_MSAA 1          /* drawn through MSAA_SAMPLES x MSAA targets (define MSAA) */
#define ALPHA_TRAIT_GL_A2C 2        /* GL turns alpha into coverage (GL_SAMPLE_ALPHA_TO_COVERAGE and
                                     * _TO_ONE); --a2c-sharpen applies (define A2C_SHARPEN) */
#define ALPHA_TRAIT_HASH 4          /* hashed thresholds: defines ALPHA_HASH_KIND and ALPHA_HASH_ANISO,
                                     * with TAA TAA_HASH_OFFSET; a fade-in length per material */
#define ALPHA_TRAIT_NOISE 8         /* thresholds are noise that changes with the frame or the pixel
                                     * (TAA's coarse-ring history helps) */
#define ALPHA_TRAIT_COVERAGE_MIPS 16 /* the traditional test on coverage-preserving mips (seed 001) */
#define FS_ALPHA_MODES(X)                                                                        \
    X(TRADITIONAL, traditional, 0x1f77b4, 0)                                                     \
    X(STOCHASTIC, stochastic, 0xd62728, ALPHA_TRAIT_NOISE)                                       \
    X(HASHED, hashed, 0x2ca02c, ALPHA_TRAIT_HASH | ALPHA_TRAIT_NOISE)                            \
    X(A2C, a2c, 0x9467bd, ALPHA_TRAIT_MSAA | ALPHA_TRAIT_GL_A2C)                                 \
    X(HASHED_A2C, hashed_a2c, 0xff7f0e, ALPHA_TRAIT_MSAA | ALPHA_TRAIT_HASH | ALPHA_TRAIT_NOISE) \
    X(CASTANO, castano, 0x8c564b, ALPHA_TRAIT_COVERAGE_MIPS)                                     \
    X(MIPSCALE, mipscale, 0xe377c2, 0)

/* Smallest alpha we divide premultiplied colour by (texels with less are treated as empty). */
#define PREMUL_ALPHA_EPS 1.0e-6

/* Vertex attribute locations of the forward pass (positions, normals, uv, colour, instance matrix
 * in 4 consecutive slots). */
#define ATTR_POSITION 0
#define ATTR_NORMAL 1
#define ATTR_UV 2
#define ATTR_COLOR 3
#define ATTR_INSTANCE 4
/* Primitives of the passes that key fragments by their triangle (hashed and stochastic MASK, the
 * exact reference's MASK and BLEND): per vertex, uvec2(the asset's triangle, the primitive's
 * triangle = gl_PrimitiveID) of the triangle it is the provoking (last) vertex of, read flat
 * (common/draw_order.glsl). */
#define ATTR_TRIANGLE 12
/* Swaying instances only (the plan's SWAY variant): per instance, the sway offset and height
 * (ATTR_SWAY) and its frequency and phase (ATTR_SWAY_WAVE); see common/sway.glsl. */
#define ATTR_SWAY 8
#define ATTR_SWAY_WAVE 9

/* Wind sway of instances (docs/scene-format.md "sway"). GLSL: common/sway.glsl, C twin:
 * src/scene/sway.c. */
#define SWAY_TWO_PI 6.28318530717958648
#define SWAY_FREQUENCY_DEFAULT 0.5  /* Hz */
#define SWAY_WAVELENGTH_DEFAULT 10.0 /* metres between instances swaying in phase along the wind */
#define SWAY_OFFSET_MAX 1.0e6       /* an offset component beyond this (or not finite) = no sway */

/* Per-ring stochastic simplification of foliage cards (docs/ring-lod.md; Cook et al. 2007). GLSL:
 * common/ring_lod.glsl, C twin: src/fov/ring_lod.c (ring_lod.h documents the law); the cards and
 * their ranks: src/scene/cards.c. */
#define ATTR_CARD 10                /* per vertex: card centre xyz (asset space), rank w */
#define ATTR_CARD_SIDE 11           /* per vertex: the card's side, sqrt(area), asset units */
#define RING_LOD_BAND 0.25          /* transition band: ranks within B * u below the cut fade out */
#define RING_LOD_AREA_REF 1.0       /* default schedule: a card covering this many ring pixels or more
                                     * is kept; a smaller one keeps u = its area / this */
#define RING_LOD_AREA_MIN 0.0625    /* "simplify:area=A": the range of A */
#define RING_LOD_AREA_MAX 256.0
#define RING_LOD_U_MIN 0.0625       /* default schedule: the fewest cards kept, 1/16 (kept cards at most
                                     * 4 times their side) */
#define RING_LOD_U_FLOOR (1.0 / 4096.0) /* smallest keep fraction at all (kept cards scale by 64) */
#define RING_LOD_MIN_CARDS 16       /* a primitive with fewer cards is never simplified */
#define RING_LOD_RANK_BITS 24       /* ranks are k / 2^24: exact in a float, rotated in integers */
#define RING_LOD_RANK_ONE 16777216.0
#define RING_LOD_RANK_MASK 0xFFFFFFu
#define RING_LOD_RANK_KEEP (-1.0)    /* rank of a card that is never simplified nor scaled */
#define RING_LOD_INSTANCE_SEED 0x5bd1e995u /* salt of the per-instance rank rotation */

/* Texture units. */
#define TEX_UNIT_BASE_COLOR 0
#define TEX_UNIT_VRS_RATE 7   /* VRS foveation: the rate image (R8UI, one texel per tile) */

/* Samples per pixel of the alpha-to-coverage modes' multisampled targets (a power of two). */
#define MSAA_SAMPLES 4

/* Seed 002 (Golus): alpha is scaled by 1 + lod * ALPHA_MIPSCALE_PER_LOD in the mipscale mode. */
#define ALPHA_MIPSCALE_PER_LOD 0.25

/* Alpha LOD clamp (docs/hashed-alpha.md "Alpha LOD clamp"): the alpha test of a MASK material reads
 * alpha at most at mip level N (scene "alpha_lod_max", --alpha-lod-max), colour keeps the whole
 * chain. Values in [0, ALPHA_LOD_MAX_LIMIT]; ALPHA_LOD_OFF (or any negative value) = no clamp. */
#define ALPHA_LOD_MAX_LIMIT 16.0
#define ALPHA_LOD_OFF (-1.0)

/* Hashed / stochastic alpha thresholds (seed 000 §4-6). GLSL: common/alpha_hash.glsl, C twin:
 * src/passes/alpha_hash.c; docs/hashed-alpha.md explains each choice. */
#define ALPHA_HASH_PCG 0            /* pcg3d integer hash (Jarzynski & Olano 2020) */
#define ALPHA_HASH_SINE 1           /* the paper's nested sine hash (seed 000 §5.1) */
#define ALPHA_HASH_DEFAULT ALPHA_HASH_PCG /* uniform at any coordinate magnitude, cheaper on CPU */
#define ALPHA_HASH_SCALE_DEFAULT 1.0 /* g_HashScale: noise cell size in pixels (seed 000 §5.4.1) */
#define ALPHA_FADE_N_DEFAULT 6.0    /* n of seed 000 Eq. 3: mip levels until the noise is full */
#define ALPHA_THRESHOLD_MIN 1.0e-6  /* smallest threshold: alpha = 0 never passes */
#define ALPHA_HASH_LOG2_CLAMP 60.0  /* log2(pixScale) and LODs are clamped to [-60, 60] */
#define ALPHA_MAX_ANISO_LOG2 4      /* anisotropic hash: at most 2^4 = 16 x finer cells per axis */
#define ALPHA_A2C_MAX_SAMPLES 16    /* hashed A2C: n is a power of two <= this */
/* Each noise level hashes its own lattice (docs/hashed-alpha.md "Assets a pixel or two wide"): the level key of level e, XORed into the
 * layer key, is (e + ALPHA_HASH_LEVEL_BIAS) * ALPHA_HASH_LEVEL_MUL (mod 2^32). The multiplier is odd
 * (2^32 / golden ratio), so the 121 levels of [-60, 60] get 121 distinct keys, none of them 0
 * (docs/hashed-alpha.md, "Listing 1, and where we depart from it"). */
#define ALPHA_HASH_LEVEL_BIAS 128
#define ALPHA_HASH_LEVEL_MUL 0x9e3779b9u
/* With TAA, hashed thresholds shift by frame * this (mod 1), a low-discrepancy sequence: each pixel
 * cycles through thresholds spread evenly over (0, 1], which TAA averages (docs/hashed-alpha.md). */
#define ALPHA_FRAME_OFFSET_STEP 0.61803398875

/* TAA: temporal antialiasing (docs/design.md "Temporal antialiasing"). GLSL: common/taa.glsl, C twin:
 * src/passes/taa_math.c (taa_math.h documents each function). */
#define TAA_JITTER_LENGTH_DEFAULT 16 /* Halton(2,3) jitter period in frames */
#define TAA_JITTER_LENGTH_MAX 4096   /* longest period (keeps the 24-bit Halton values nonzero) */
#define TAA_HALTON_BITS 24           /* taa_halton is truncated to this many fraction bits (exact) */
#define TAA_GAMMA_DEFAULT 1.0        /* variance clipping box: mean +- gamma * sigma */
#define TAA_BLEND_DEFAULT 0.1        /* weight of the current sample in the exponential blend */
#define TAA_MAX_VALUE 65504.0        /* half-float max: history is RGBA16F, larger values clamp */
#define TAA_SPARSE_SLACK 0.95        /* default 1 - alpha: the largest coverage difference one binary
                                        sample cannot refute at significance alpha = 0.05
                                        (taa_sparse_coverage, docs/taa.md) */
#define TAA_SPARSE_COLOR 0.25        /* colour box widening per unit of coverage kept outside the
                                        neighbourhood's range (docs/taa.md) */
#define TAA_PARALLAX_PX 0.5          /* history is of this pixel's surfaces while its nearest surface,
                                        carried to this frame, lands within this many ring pixels
                                        (taa_history_surface_here, docs/taa.md "Disocclusion") */
#define TAA_MAX_TAPS 9               /* neighbourhood taps at most (3x3; the cross uses the first 5) */

/* The exact reference's per-pixel fragment lists (A-buffer; docs/reference.md). GLSL:
 * common/abuffer.glsl, C twin (the resolve): src/passes/abuffer.c. A node is two RGBA32UI texels
 * of a buffer texture: (next, depth bits, draw order, primitive) and (premultiplied r, g, b, alpha
 * bits). The head image holds each pixel's first node; ABUFFER_END ends a list; a pointer with
 * ABUFFER_OVERFLOW_BIT set means the pixel lost a fragment because the store was full. */
#define ABUFFER_NODE_TEXELS 2
#define ABUFFER_END 0x7FFFFFFFu
#define ABUFFER_OVERFLOW_BIT 0x80000000u
#define ABUFFER_IMAGE_HEAD 0            /* image units of the list pass */
#define ABUFFER_IMAGE_NODES 1
#define ABUFFER_COUNTER_BINDING 0       /* shader storage binding of the node counter */
/* The GPU resolve (shaders/list_resolve.frag) sorts lists of up to this many nodes; it flags longer
 * ones (ABUFFER_FLAG_LONG) for the C twin and those that lost fragments (ABUFFER_FLAG_OVERFLOW) for
 * the stochastic fallback. */
#define ABUFFER_RESOLVE_MAX 24
#define ABUFFER_FLAG_DONE 0.0
#define ABUFFER_FLAG_LONG 1.0
#define ABUFFER_FLAG_OVERFLOW 2.0

/* Work counts (docs/benchmarks.md "Work counts"): the counting variant of the forward passes
 * (define COUNT_FRAGMENTS; bench draws it in a frame of its own, never in a timed one) adds 1 per
 * covered fragment to slot u_count_slot (ring * pass count + pass) of this shader storage buffer. */
#define COUNT_FRAGMENTS_BINDING 1
/* ... and 1 per fragment-shader invocation a GPU would run to slot COUNT_SHADED_OFFSET + u_count_slot:
 * per covered fragment, or under VRS per primitive and coarse pixel with a covered pixel (docs/
 * benchmarks.md "VRS: coarse-shading invocations"). Word COUNT_KEY_SEQUENCE hands each primitive
 * of the VRS twin its key (forward_vrs.geom); COUNT_COARSE_KEYS_BINDING holds, per display pixel
 * that is a coarse pixel's top-left corner, the key of the primitive that last shaded there. */
#define COUNT_SHADED_OFFSET 128
#define COUNT_KEY_SEQUENCE 256
#define COUNT_WORDS 257
#define COUNT_COARSE_KEYS_BINDING 2

#endif
