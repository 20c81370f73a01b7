/* ring_lod.c: per-ring stochastic simplification of foliage (ring_lod.h); GLSL twin
 * shaders/common/ring_lod.glsl.
 *
 * The laws are computed in double and rounded to float once; ring_lod_weight, ring_lod_scale,
 * ring_lod_apply and ring_lod_rank evaluate the same float operations in the same order as the
 * GLSL (tests/gpu/test_ring_lod_twin.c compares them). */
#include "fov/ring_lod.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/shared_defs.h"
#include "core/log.h"

/* >>the law */

static ring_lod_law identity_law(void)
{
    return (ring_lod_law){.a = 1.0f, .k = 0.0f, .gain = 1.0f};
}

/* u* = 1 / (1 + B/2): the largest u whose ramp [a, a + B u] still ends inside [0, 1]. */
static double u_star(void)
{
    return 1.0 / (1.0 + 0.5 * RING_LOD_BAND);
}

double ring_lod_expected_weight(float af, float kf)
{
    double a = af, k = kf;
    if (k == 0.0)
        return 1.0;
    if (!(k > 0.0) || !isfinite(a) || !isfinite(k))
        return NAN;
    /* g = 1 on [0, lo), the ramp 1 - k (r - a) on [lo, hi), 0 beyond; lo, hi clamped to [0, 1]. */
    double e = a + 1.0 / k;
    double lo = a < 0.0 ? 0.0 : (a > 1.0 ? 1.0 : a), hi = e < 0.0 ? 0.0 : (e > 1.0 ? 1.0 : e);
    if (hi < lo)
        hi = lo;
    return hi - 0.5 * k * ((hi - a) * (hi - a) - (lo - a) * (lo - a));
}

ring_lod_law ring_lod_law_for(float u)
{
    if (!(u > 0.0f) || u >= 1.0f)
        return identity_law();
    /* float operations in common/ring_lod.glsl's order: the GPU computes this per card */
    const float B = (float)RING_LOD_BAND, us = 1.0f / (1.0f + 0.5f * (float)RING_LOD_BAND);
    float uu = u > (float)RING_LOD_U_FLOOR ? u : (float)RING_LOD_U_FLOOR;
    float a, k;
    if (uu <= us) {
        a = uu * (1.0f - 0.5f * B);
        k = 1.0f / (B * uu);
    } else {
        a = 1.0f - B * us;
        float w = 1.0f - a;
        k = 2.0f * (1.0f - uu) / (w * w);
    }
    return (ring_lod_law){.a = a, .k = k, .gain = 1.0f / uu};
}

bool ring_lod_law_is_identity(const ring_lod_law *l)
{
    return l->k == 0.0f && l->gain == 1.0f;
}

double ring_lod_max_rate(float u)
{
    const double B = RING_LOD_BAND, us = u_star();
    double uu = u > 1.0f ? 1.0 : (u >= RING_LOD_U_FLOOR ? (double)u : RING_LOD_U_FLOOR); /* NaN: the floor */
    if (uu <= us)
        return (1.0 + 0.5 * B) / (B * uu);
    return 2.0 * (1.0 + 0.5 * B) / B;
}

float ring_lod_weight(const ring_lod_law *l, float rank)
{
    if (rank < 0.0f)
        return 1.0f;
    float t = rank - l->a;
    t = l->k * t;
    float g = 1.0f - t;
    g = g > 0.0f ? g : 0.0f; /* max, then min, as GLSL's clamp */
    g = g < 1.0f ? g : 1.0f;
    return g;
}

float ring_lod_scale(const ring_lod_law *l, float rank)
{
    if (rank < 0.0f)
        return 1.0f;
    float g = ring_lod_weight(l, rank);
    return sqrtf(g * l->gain);
}

float ring_lod_max_scale(const ring_lod_law *l)
{
    return sqrtf(l->gain > 1.0f ? l->gain : 1.0f);
}

vec3 ring_lod_apply(const ring_lod_law *l, vec3 p, const float card[4])
{
    float s = ring_lod_scale(l, card[3]);
    if (s == 1.0f)
        return p;
    float dx = p.x - card[0], dy = p.y - card[1], dz = p.z - card[2];
    dx = dx * s;
    dy = dy * s;
    dz = dz * s;
    return v3(card[0] + dx, card[1] + dy, card[2] + dz);
}

/* >>ranks per instance */

uint32_t ring_lod_instance_offset(uint32_t key)
{
    uint32_t x = key ^ RING_LOD_INSTANCE_SEED; /* lowbias32 (Wellons) */
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x >> (32 - RING_LOD_RANK_BITS);
}

float ring_lod_rank(float card_rank, uint32_t instance_key)
{
    if (!(card_rank >= 0.0f && card_rank < 1.0f)) /* KEEP (and anything else not a rank) */
        return card_rank;
    uint32_t k = (uint32_t)(card_rank * (float)RING_LOD_RANK_ONE) + ring_lod_instance_offset(instance_key);
    return (float)(k & RING_LOD_RANK_MASK) * (float)(1.0 / RING_LOD_RANK_ONE);
}

/* >>schedule */

float ring_lod_card_u(float side_px)
{
    float area = side_px * side_px;
    float u = area / (float)RING_LOD_AREA_REF;
    u = u > (float)RING_LOD_U_MIN ? u : (float)RING_LOD_U_MIN; /* max, then min, as GLSL's clamp */
    return u < 1.0f ? u : 1.0f;
}

/* >>text form */

#define LOD_EXPECTED "expected off, simplify, simplify:area=A or simplify:U1,...,Un"

/* "0.25", "1/4" (blanks around '/' allowed) -> a keep fraction in [RING_LOD_U_FLOOR, 1]. */
static bool parse_fraction(const char *tok, float *u)
{
    double v;
    if (!fov_parse_ratio(tok, &v))
        return false;
    float f = (float)v;
    if (!(f >= (float)RING_LOD_U_FLOOR) || !(f <= 1.0f))
        return false;
    *u = f;
    return true;
}

fs_status ring_lod_parse(const char *text, ring_lod_spec *out, char *err, int err_size)
{
    if (err && err_size > 0)
        err[0] = '\0';
    if (!text) {
        fov_set_err(err, err_size, "empty ring LOD (" LOD_EXPECTED ")");
        return FS_ERR_USAGE;
    }
    const char *b = text, *e = text + strlen(text);
    fov_trim(&b, &e);
    size_t len = (size_t)(e - b);
    ring_lod_spec s;
    memset(&s, 0, sizeof s);
    if (len == 0) {
        fov_set_err(err, err_size, "empty ring LOD (" LOD_EXPECTED ")");
        return FS_ERR_USAGE;
    }
    if (len == 3 && memcmp(b, "off", 3) == 0) {
        if (out)
            *out = s;
        return FS_OK;
    }
    static const char kw[] = "simplify";
    const size_t kl = sizeof kw - 1;
    if (len < kl || memcmp(b, kw, kl) != 0 || (len > kl && b[kl] != ':')) {
        fov_set_err(err, err_size, "ring LOD '%.*s' is not understood (" LOD_EXPECTED ")", (int)(len > 40 ? 40 : len), b);
        return FS_ERR_USAGE;
    }
    if (len == kl) {
        s.kind = RING_LOD_SCHEDULE;
        if (out)
            *out = s;
        return FS_OK;
    }
    const char *q = b + kl + 1;
    if (e - q >= 5 && memcmp(q, "area=", 5) == 0) { /* the per-card schedule with another area */
        char tok[FOV_TOKEN_MAX];
        double v;
        if (!fov_take_token(q + 5, e, tok) || !fov_parse_ratio(tok, &v) || !(v >= RING_LOD_AREA_MIN) ||
            !(v <= RING_LOD_AREA_MAX)) {
            fov_set_err(err, err_size, "ring LOD area '%.*s' is not a number of ring pixels in [%g, %g]",
                    (int)(e - q - 5 > 40 ? 40 : e - q - 5), q + 5, RING_LOD_AREA_MIN, RING_LOD_AREA_MAX);
            return FS_ERR_USAGE;
        }
        s.kind = RING_LOD_SCHEDULE;
        s.area = (float)v;
        if (out)
            *out = s;
        return FS_OK;
    }
    s.kind = RING_LOD_EXPLICIT;
    for (;;) {
        const char *c = q;
        while (c < e && *c != ',')
            c++;
        int n = s.count + 1;
        if (s.count == MAX_FOV_RINGS) {
            fov_set_err(err, err_size, "ring LOD ring %d: more than %d rings", n, MAX_FOV_RINGS);
            return FS_ERR_USAGE;
        }
        char tok[FOV_TOKEN_MAX];
        if (!fov_take_token(q, c, tok)) {
            fov_set_err(err, err_size, "ring LOD ring %d: keep fraction is too long", n);
            return FS_ERR_USAGE;
        }
        if (!tok[0]) {
            fov_set_err(err, err_size, "ring LOD ring %d: keep fraction is empty (" LOD_EXPECTED ")", n);
            return FS_ERR_USAGE;
        }
        if (!parse_fraction(tok, &s.u[s.count])) {
            fov_set_err(err, err_size, "ring LOD ring %d: keep fraction '%s' is not in [1/%g, 1] (e.g. 0.25 or 1/4)", n, tok,
                    1.0 / RING_LOD_U_FLOOR);
            return FS_ERR_USAGE;
        }
        s.count++;
        if (c == e)
            break;
        q = c + 1;
    }
    if (out)
        *out = s;
    return FS_OK;
}

fs_status ring_lod_check(const ring_lod_spec *s, const fov_layout *l, char *err, int err_size)
{
    if (err && err_size > 0)
        err[0] = '\0';
    if (s->kind != RING_LOD_OFF && s->kind != RING_LOD_SCHEDULE && s->kind != RING_LOD_EXPLICIT) {
        fov_set_err(err, err_size, "ring LOD: unknown kind %d", (int)s->kind);
        return FS_ERR_USAGE;
    }
    if (s->kind != RING_LOD_EXPLICIT)
        return FS_OK;
    if (s->count != l->count) {
        fov_set_err(err, err_size, "ring LOD: %d keep fraction%s for %d ring%s (expected one per ring)", s->count,
                s->count == 1 ? "" : "s", l->count, l->count == 1 ? "" : "s");
        return FS_ERR_USAGE;
    }
    for (int i = 0; i < s->count; i++)
        if (!(s->u[i] >= (float)RING_LOD_U_FLOOR) || !(s->u[i] <= 1.0f)) {
            fov_set_err(err, err_size, "ring LOD ring %d: keep fraction %g is not in [1/%g, 1]", i + 1, (double)s->u[i],
                    1.0 / RING_LOD_U_FLOOR);
            return FS_ERR_USAGE;
        }
    return FS_OK;
}

float ring_lod_u(const ring_lod_spec *s, const fov_layout *l, int ring)
{
    if (!s || !l || ring < 0 || ring >= l->count || ring >= MAX_FOV_RINGS)
        return 1.0f;
    if (s->kind == RING_LOD_SCHEDULE) /* per card: at least RING_LOD_U_MIN in a reduced ring */
        return l->rings[ring].scale_log2 > 0 ? (float)RING_LOD_U_MIN : 1.0f;
    if (s->kind == RING_LOD_EXPLICIT && ring < s->count && s->u[ring] > 0.0f && s->u[ring] <= 1.0f)
        return s->u[ring];
    return 1.0f;
}

float ring_lod_area(const ring_lod_spec *s)
{
    return s && s->area > 0.0f ? s->area : (float)RING_LOD_AREA_REF;
}

bool ring_lod_ring_is_per_card(const ring_lod_spec *s, const fov_layout *l, int ring)
{
    return s && l && s->kind == RING_LOD_SCHEDULE && ring >= 0 && ring < l->count && ring < MAX_FOV_RINGS &&
           l->rings[ring].scale_log2 > 0;
}

ring_lod_law ring_lod_ring_law(const ring_lod_spec *s, const fov_layout *l, int ring)
{
    return ring_lod_law_for(ring_lod_u(s, l, ring));
}

bool ring_lod_active(const ring_lod_spec *s, const fov_layout *l)
{
    for (int i = 0; l && i < l->count && i < MAX_FOV_RINGS; i++) {
        ring_lod_law law = ring_lod_ring_law(s, l, i);
        if (!ring_lod_law_is_identity(&law))
            return true;
    }
    return false;
}

static void format_list(const float *u, int count, const char *prefix, char *buf, int size)
{
    size_t n = 0, cap = (size_t)size;
    int w = snprintf(buf, cap, "%s", prefix);
    if (w < 0 || (size_t)w >= cap)
        return;
    n = (size_t)w;
    for (int i = 0; i < count && n < cap; i++) {
        char v[32];
        fov_format_float(v, sizeof v, u[i]);
        w = snprintf(buf + n, cap - n, "%s%s", i ? "," : "", v);
        if (w < 0)
            break;
        n += (size_t)w;
    }
}

void ring_lod_format(const ring_lod_spec *s, char *buf, int size)
{
    if (!buf || size <= 0)
        return;
    buf[0] = '\0';
    if (!s || s->kind == RING_LOD_OFF)
        snprintf(buf, (size_t)size, "off");
    else if (s->kind == RING_LOD_SCHEDULE && ring_lod_area(s) != (float)RING_LOD_AREA_REF) {
        char v[32];
        fov_format_float(v, sizeof v, ring_lod_area(s));
        snprintf(buf, (size_t)size, "simplify:area=%s", v);
    } else if (s->kind == RING_LOD_SCHEDULE)
        snprintf(buf, (size_t)size, "simplify");
    else
        format_list(s->u, s->count < 0 ? 0 : (s->count > MAX_FOV_RINGS ? MAX_FOV_RINGS : s->count), "simplify:", buf,
                    size);
}

void ring_lod_format_u(const ring_lod_spec *s, const fov_layout *l, char *buf, int size)
{
    if (!buf || size <= 0)
        return;
    buf[0] = '\0';
    if (!l)
        return;
    float u[MAX_FOV_RINGS];
    int n = l->count < 0 ? 0 : (l->count > MAX_FOV_RINGS ? MAX_FOV_RINGS : l->count);
    for (int i = 0; i < n; i++)
        u[i] = ring_lod_u(s, l, i);
    if (s && s->kind == RING_LOD_SCHEDULE) { /* "1" for a full-resolution ring, "card" for the others */
        size_t o = 0;
        for (int i = 0; i < n && o < (size_t)size; i++) {
            int w = snprintf(buf + o, (size_t)size - o, "%s%s", i ? "," : "", ring_lod_ring_is_per_card(s, l, i) ? "card" : "1");
            if (w < 0)
                break;
            o += (size_t)w;
        }
        return;
    }
    format_list(u, n, "", buf, size);
}
