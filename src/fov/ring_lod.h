/* ring_lod.h: per-ring stochastic simplification of foliage (docs/ring-lod.md; Cook, Halstead, Planck & Ryu
 * 2007, "Stochastic Simplification of Aggregate Detail"): the law, the C twin of
 * shaders/common/ring_lod.glsl, the default per-ring schedule and its text form
 * (--ring-lod / a scene's "ring_lod"). The cards and their ranks are src/scene/cards.h.
 *
 * The law
 *   A ring keeps a fraction u in [RING_LOD_U_FLOOR, 1] of each simplified primitive's cards. A card of rank r
 *   (ranks are spread evenly over [0, 1)) gets the weight
 *
 *       g(r) = clamp(1 - k (r - a), 0, 1)
 *
 *   (1 up to the ramp start a, 0 from a + 1/k on, linear between) and is drawn scaled about its
 *   centre by sqrt(g gain), gain = 1 / E[g]: its area becomes g gain times its own, so the expected
 *   area of the aggregate, E[g gain] = 1, is unchanged. A card with g = 0 collapses onto its centre
 *   (zero-area triangles: nothing is rasterised). (a, k, gain) is a ring_lod_law, computed per ring
 *   on the CPU (ring_lod_law_for) and passed to the vertex shader as one vec3 uniform.
 *
 *   With B = RING_LOD_BAND and u* = 1 / (1 + B/2):
 *     u <= u*     the ramp has width w = B u, starts at a = u (1 - B/2), k = 1 / w, and lies in
 *                 [0, 1]: E[g] = a + w/2 = u. Cards leave by shrinking across a band of ranks
 *                 proportional to u (B = 1/4: one card in 4.5 of those drawn is fading).
 *     u* < u < 1  the ramp start stays at a* = 1 - B u* and the ramp flattens, k = 2 (1 - u) /
 *                 (1 - a*)^2, its end beyond r = 1: E[g] = 1 - k (1 - a*)^2 / 2 = u.
 *     u = 1       a = 1, k = 0, gain = 1: every g is exactly 1 and every scale exactly 1
 *                 (ring_lod_law_is_identity): ring_lod_apply returns the position unchanged
 *                 whenever the scale is 1, so u = 1 is bit-identical to no simplification.
 *   So E[g] = u for every u, g is non-increasing in r, non-decreasing in u, continuous and
 *   Lipschitz in u, at most ring_lod_max_rate(u) per unit of u: (1 + B/2) / (B u) below u*,
 *   2 (1 + B/2) / B above. (Keeping the band at B u for every u instead would need the cut to reach
 *   1 + B at u = 1, moving without bound as u -> 1: a card near r = 1 would fade as sqrt(1 - u).)
 *   gain = 1 / u (E[g] = u by construction; ring_lod_expected_weight checks it in closed form).
 *   C and GLSL compute (a, k, gain) with the same float operations: the per-card schedule has the
 *   GPU compute it per card.
 *
 * Ranks per instance
 *   Every instance of an asset shares its cards' ranks (cards.h), so without more every tree would
 *   keep the same leaves. ring_lod_rank rotates a card's rank by a per-instance offset (a hash of a
 *   stable instance key, e.g. the instance's scene slot as the hashed alpha modes use it: the
 *   draw's first slot + gl_InstanceID), modulo 1 in 24-bit integers: exact in both twins, still
 *   one rank per stratum in each instance, independent between instances, stable over frames and
 *   rings (not the culled draw order). A rank below 0 (RING_LOD_RANK_KEEP) is left as it is.
 *
 * The schedule
 *   Default ("simplify"), per card (Cook et al. choose u from an element's size on screen): in a
 *   ring of reduced scale, a card whose side spans s ring pixels (its sqrt(area), scaled by its
 *   instance, over its distance from the eye, times the ring's pixels per unit at distance 1)
 *   keeps u = clamp(s^2 / RING_LOD_AREA_REF, RING_LOD_U_MIN, 1): cards of a ring pixel or more are
 *   drawn as they are, so near trees keep their outlines, and smaller ones are thinned until the
 *   kept ones cover about a ring pixel each (at most 4 times their side). The vertex shader
 *   evaluates it (ring_lod_card_u, then ring_lod_law_for per card); u changes smoothly with
 *   distance, and so does every card's weight. Full-resolution rings keep every card.
 *   "simplify:area=A" is the per-card schedule with A ring pixels (in [1/16, 256]) in place of
 *   RING_LOD_AREA_REF: cards up to sqrt(A) ring pixels wide are thinned, a dial between detail and
 *   work.
 *   Text form: "off" (no simplification), "simplify" (the default schedule), "simplify:area=A" or
 *   "simplify:U1,U2,...,Un", one keep fraction per ring, innermost first, each in
 *   [RING_LOD_U_FLOOR, 1] (1/4096: kept cards are then drawn 64 times their size), written
 *   as a decimal or a fraction ("0.25" or "1/4"); the count must equal the layout's
 *   (ring_lod_check). A zeroed ring_lod_spec is "off". A u of 1 in any form is exactly no
 *   simplification of that ring.
 *
 * What it does NOT do: GL, choosing which primitives take part (cards.h), the reference (never
 * simplified: its caller passes no law).
 */
#ifndef FOVSIM_RING_LOD_H
#define FOVSIM_RING_LOD_H

#include <stdbool.h>
#include <stdint.h>

#include "core/config.h"
#include "core/fmath.h"
#include "core/status.h"
#include "fov/fov_ring.h"

#ifdef __cplusplus
extern "C" {
#endif

/* >>the law (GLSL twin: common/ring_lod.glsl) */

/* One ring's law: the vertex shader's vec3 uniform (a, k, gain). */
typedef struct ring_lod_law {
    float a;    /* ramp start: ranks below keep weight 1 */
    float k;    /* ramp slope (1 / its width); 0 = no ramp */
    float gain; /* area gain 1 / E[g] */
} ring_lod_law;

/* The law keeping a fraction u. u >= 1, u <= 0 and NaN give the identity law {1, 0, 1}; u in
 * (0, RING_LOD_U_FLOOR) is taken as RING_LOD_U_FLOOR (ring_lod_parse never yields u outside
 * [RING_LOD_U_FLOOR, 1]). */
ring_lod_law ring_lod_law_for(float u);
/* True for a law under which every card has weight 1 and scale 1 (u = 1): the ring is not
 * simplified and the renderer draws it exactly as without simplification. */
bool ring_lod_law_is_identity(const ring_lod_law *l);
/* g(rank) in [0, 1]; 1 for a rank below 0 (RING_LOD_RANK_KEEP). */
float ring_lod_weight(const ring_lod_law *l, float rank);
/* The card's linear scale about its centre, sqrt(g gain); 1 for a rank below 0. */
float ring_lod_scale(const ring_lod_law *l, float rank);
/* A vertex at asset-space p of a card (card[0..2] its centre, card[3] its rank, as the ATTR_CARD
 * attribute): centre + (p - centre) * scale, or p itself, bit for bit, when the scale is 1. */
vec3 ring_lod_apply(const ring_lod_law *l, vec3 p, const float card[4]);
/* The largest scale any card gets under the law, sqrt(gain) (g <= 1): for culling bounds
 * (asset_cards_bounds). 1 for the identity law. */
float ring_lod_max_scale(const ring_lod_law *l);
/* E[g] over rank uniform in [0, 1), closed form (also for a ramp crossing r = 0 or r = 1), in
 * double, of the law's float a and k. */
double ring_lod_expected_weight(float a, float k);
/* The largest |dg/du| over every rank at u (the law's Lipschitz bound there; at u = 1 the limit from
 * below; u is clamped to [RING_LOD_U_FLOOR, 1]): a card's weight changes by at most this times a
 * small change of u. */
double ring_lod_max_rate(float u);

/* The per-instance rank rotation, in [0, 2^24). Any 32-bit key that is stable per instance. */
uint32_t ring_lod_instance_offset(uint32_t instance_key);
/* A card's rank as one instance sees it: (rank + offset) mod 1 in units of 2^-24; a value outside
 * [0, 1) (RING_LOD_RANK_KEEP) is returned unchanged. `card_rank` must be a rank of cards.h (a multiple of 2^-24 in [0, 1)). */
float ring_lod_rank(float card_rank, uint32_t instance_key);

/* >>schedule and text form */

/* The default schedule's keep fraction of a card whose side spans side_px ring pixels. */
float ring_lod_card_u(float side_px);

typedef enum ring_lod_kind {
    RING_LOD_OFF = 0,    /* no simplification */
    RING_LOD_SCHEDULE,   /* "simplify": per card in reduced rings (ring_lod_card_u) */
    RING_LOD_EXPLICIT,   /* "simplify:U1,...,Un" */
} ring_lod_kind;

typedef struct ring_lod_spec {
    ring_lod_kind kind;
    int count;                /* EXPLICIT: keep fractions given, 1..MAX_FOV_RINGS */
    float u[MAX_FOV_RINGS];   /* EXPLICIT: each in [RING_LOD_U_FLOOR, 1], innermost ring first */
    float area;               /* SCHEDULE: the card area in ring pixels from which cards are kept
                               * ("simplify:area=A"); 0 = RING_LOD_AREA_REF */
} ring_lod_spec;

/* Parses "off", "simplify" or "simplify:U1,...,Un" (surrounding whitespace allowed). On error
 * writes one line into err (e.g. "ring LOD ring 3: keep fraction '0' is not in [1/4096, 1] (e.g.
 * 0.25 or 1/4)"), leaves *out alone and returns FS_ERR_USAGE. out may be NULL (validation only). */
fs_status ring_lod_parse(const char *text, ring_lod_spec *out, char *err, int err_size);
/* Checks a spec against the layout it will run with: an explicit spec needs one keep fraction per
 * ring ("ring LOD: 3 keep fractions for 5 rings (expected one per ring)"). FS_ERR_USAGE. */
fs_status ring_lod_check(const ring_lod_spec *s, const fov_layout *l, char *err, int err_size);
/* Ring i's keep fraction: 1 for OFF and for a ring index the spec has no value for; under the
 * per-card schedule the smallest a card of the ring can get (RING_LOD_U_MIN in a reduced ring),
 * which bounds how far its cards grow (culling). */
float ring_lod_u(const ring_lod_spec *s, const fov_layout *l, int ring);
/* The per-card schedule's area in ring pixels (RING_LOD_AREA_REF unless "simplify:area=A"). The
 * renderer divides the ring's pixels per unit by its square root, so ring_lod_card_u keeps its
 * RING_LOD_AREA_REF. */
float ring_lod_area(const ring_lod_spec *s);
/* True when ring i's cards each take their own u (the default schedule in a reduced ring). */
bool ring_lod_ring_is_per_card(const ring_lod_spec *s, const fov_layout *l, int ring);
/* Ring i's law: ring_lod_law_for(ring_lod_u(...)); for a per-card ring the law of its smallest u. */
ring_lod_law ring_lod_ring_law(const ring_lod_spec *s, const fov_layout *l, int ring);
/* True when some ring of the layout is simplified (its law is not the identity). False for OFF,
 * for foveation off under the schedule and for explicit specs of all 1s. */
bool ring_lod_active(const ring_lod_spec *s, const fov_layout *l);
/* "off", "simplify" or "simplify:1,1,0.25,0.0625,0.0625" (shortest round-trip decimals): the
 * spec's text form, which ring_lod_parse reads back to the same spec (records, EXR headers). */
void ring_lod_format(const ring_lod_spec *s, char *buf, int size);
/* Every ring's u as "1,1,0.25,0.0625,0.0625" for `fovsim plan` ("1" for each ring when OFF;
 * "card" for a ring whose cards take their own u). */
void ring_lod_format_u(const ring_lod_spec *s, const fov_layout *l, char *buf, int size);

#ifdef __cplusplus
}
#endif

#endif
