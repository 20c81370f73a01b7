/* scene.c: scene lifetime, validation, bounds, the camera path and the content hash.
 *
 * Loading is one level above, in scene_load.c: it dispatches to the JSON format (scene_json.c),
 * glTF assets (gltf_shim.cpp) and the built-in scenes, which all build a scene through the
 * functions here. This file only owns, checks and evaluates.
 */
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"
#include "core/hash.h"
#include "core/log.h"


/* >>lifetime */

void scene_init_defaults(scene *sc)
{
    memset(sc, 0, sizeof *sc);
    sc->display = (display_desc){.width = 1280, .height = 720, .hfov_deg = 90.0f};
    sc->light.direction = v3_norm_or(v3(-0.4f, -1.0f, -0.3f), v3(0, -1, 0));
    sc->light.color = v3(1.0f, 0.97f, 0.9f);
    sc->light.ambient = v3(0.25f, 0.28f, 0.32f);
    sc->light.sky = v3(0.45f, 0.6f, 0.8f);
    sc->alpha_mode = ALPHA_MODE_DEFAULT;
    sc->camera.count = 1;
    sc->camera.keys[0] = (camera_key){.time = 0, .position = v3(0, 1.6f, 5), .target = v3(0, 1, 0)};
    sc->duration = 0;
}

void scene_free(scene *sc)
{
    if (!sc)
        return;
    for (int i = 0; i < sc->asset_count; i++)
        asset_free(&sc->assets[i]);
    free(sc->assets);
    free(sc->instances);
    memset(sc, 0, sizeof *sc);
}

/* On failure (-1: MAX_SCENE_ASSETS reached or out of memory) *a is left untouched, still owned by
 * the caller. */
int scene_add_asset(scene *sc, asset *a)
{
    if (sc->asset_count >= MAX_SCENE_ASSETS)
        return -1;
    asset *grown = realloc(sc->assets, sizeof *grown * (size_t)(sc->asset_count + 1));
    if (!grown)
        return -1;
    sc->assets = grown;
    sc->assets[sc->asset_count] = *a;
    memset(a, 0, sizeof *a);
    return sc->asset_count++;
}

bool scene_add_instance(scene *sc, int asset_index, mat4 transform)
{
    /* The array's capacity is implicit: 16 (FS_GROW_FIRST), then the next power of two >= instance_count, so it
     * grows by doubling without a stored capacity field. */
    int n = sc->instance_count;
    if (n == 0 || (n >= 16 && (n & (n - 1)) == 0)) {
        size_t cap = (size_t)n; /* full: fs_grow doubles it (16 from 0) */
        if (!FS_GROW(sc->instances, cap, (size_t)n + 1))
            return false;
    }
    sc->instances[n] = (instance){.asset = asset_index, .transform = transform};
    sc->instance_count = n + 1;
    return true;
}

bool instance_sways(const instance *in)
{
    return in->sway.offset.x != 0.0f || in->sway.offset.y != 0.0f || in->sway.offset.z != 0.0f;
}

int scene_sway_count(const scene *sc)
{
    int n = 0;
    for (int i = 0; i < sc->instance_count; i++)
        n += instance_sways(&sc->instances[i]);
    return n;
}

/* >>bounds */

void scene_bounds(const scene *sc, vec3 *min, vec3 *max)
{
    vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (int i = 0; i < sc->instance_count; i++) {
        const instance *in = &sc->instances[i];
        if (in->asset < 0 || in->asset >= sc->asset_count)
            continue;
        vec3 a = sc->assets[in->asset].bounds_min, b = sc->assets[in->asset].bounds_max;
        for (int k = 0; k < 8; k++) {
            vec3 corner = v3(k & 1 ? b.x : a.x, k & 2 ? b.y : a.y, k & 4 ? b.z : a.z);
            vec3 w = m4_point(in->transform, corner);
            lo = v3_min(lo, w);
            hi = v3_max(hi, w);
        }
    }
    if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) /* no instances */
        lo = hi = v3(0, 0, 0);
    *min = lo;
    *max = hi;
}

/* One still key looking at the centre of the bounds from the front (+Z) and 15 degrees above, at
 * the distance where the bounding sphere (grown by a 10 % margin) fits the smaller of the
 * horizontal and vertical fov. Golden images depend on this framing. */
/* Frames the scene's bounding box: the camera looks at the box centre from the front (+Z), 20
 * degrees up, at the smallest distance where all 8 corners project inside the display with a 10 %
 * margin. A box fit, not a sphere fit, so flat plants (a fern is wide and low) fill the frame. */
void scene_fit_camera(scene *sc)
{
    vec3 lo, hi;
    scene_bounds(sc, &lo, &hi);
    vec3 centre = v3_scale(v3_add(lo, hi), 0.5f);
    float aspect = sc->display.width > 0 && sc->display.height > 0
                       ? (float)sc->display.width / (float)sc->display.height : 16.0f / 9.0f;
    float hfov = sc->display.hfov_deg > 1.0f && sc->display.hfov_deg < 179.0f ? sc->display.hfov_deg : 90.0f;
    float tan_h = tanf(0.5f * hfov * (float)(FS_PI / 180.0)) / 1.1f; /* 10 % margin */
    float tan_v = tan_h / aspect;
    vec3 dir = v3_norm_or(v3(0, 0.364f, 1), v3(0, 0, 1)); /* atan(0.364) = 20 degrees up */
    vec3 right = v3_norm_or(v3_cross(v3(0, 1, 0), dir), v3(1, 0, 0));
    vec3 up = v3_cross(dir, right);
    /* Corner c at camera distance D: depth D - dot(c, dir); it fits when
     * |dot(c, right)| <= tan_h * depth and |dot(c, up)| <= tan_v * depth. */
    float dist = 0.0f;
    for (int k = 0; k < 8; k++) {
        vec3 c = v3_sub(v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z), centre);
        float z = v3_dot(c, dir);
        dist = fmaxf(dist, z + fabsf(v3_dot(c, right)) / tan_h);
        dist = fmaxf(dist, z + fabsf(v3_dot(c, up)) / tan_v);
    }
    if (!(dist > 1e-3f) || !isfinite(dist))
        dist = 1.0f;
    sc->camera.count = 1;
    sc->camera.keys[0] = (camera_key){
        .time = 0,
        .position = v3_add(centre, v3_scale(dir, dist)),
        .target = centre,
        .hfov_deg = 0, /* the display's */
        .cut = false,
    };
    sc->duration = 0;
}

/* >>camera path */

static vec3 key_point(const camera_key *k, bool target) { return target ? k->target : k->position; }

/* Last key of the spline that key k belongs to: a cut key starts a new spline. */
static int span_end(const camera_path *p, int k)
{
    while (k + 1 < p->count && !p->keys[k + 1].cut)
        k++;
    return k;
}

/* Velocity (units per second) of the spline at key k, whose spline covers keys [a, b].
 *
 * Interior keys take the non-uniform Catmull-Rom tangent (Barry & Goldman's formulation with the
 * key times as knots; it equals the slope at t_k of the parabola through the three keys):
 *   m = (h1 * d0 + h0 * d1) / (h0 + h1),   d0, d1 the chord velocities before and after, h0, h1
 * the time spans. End keys of a spline duplicate the end point one span away, which gives m = d/2.
 * Because m depends on times, not on key indices, velocity is continuous across keys however
 * unevenly they are spaced, and evenly moving keys give exactly linear motion.
 *
 * Then, Fritsch & Carlson (1980): a cubic Hermite segment is monotone along its chord when both
 * end tangents project onto the chord with 0 <= m.u <= 3 |d|. The tangent is scaled down (never
 * turned) to meet that on both chords it touches, and zeroed at a reversal or a pause, so a camera
 * dollying along a straight line never runs backwards, whatever the key spacing. The scale depends
 * only on the key's own neighbours, so both segments still share the tangent (C1 kept). */
static vec3 key_tangent(const camera_path *p, int k, int a, int b, bool target)
{
    const camera_key *K = p->keys;
    bool has_prev = k > a, has_next = k < b;
    if (!has_prev && !has_next)
        return v3(0, 0, 0);
    vec3 P = key_point(&K[k], target);
    vec3 d0 = v3(0, 0, 0), d1 = v3(0, 0, 0);
    float h0 = 0, h1 = 0;
    if (has_prev) {
        h0 = K[k].time - K[k - 1].time;
        if (!(h0 > 0))
            return v3(0, 0, 0);
        d0 = v3_scale(v3_sub(P, key_point(&K[k - 1], target)), 1.0f / h0);
    }
    if (has_next) {
        h1 = K[k + 1].time - K[k].time;
        if (!(h1 > 0))
            return v3(0, 0, 0);
        d1 = v3_scale(v3_sub(key_point(&K[k + 1], target), P), 1.0f / h1);
    }
    vec3 m;
    if (!has_prev)
        m = v3_scale(d1, 0.5f);
    else if (!has_next)
        m = v3_scale(d0, 0.5f);
    else
        m = v3_scale(v3_add(v3_scale(d0, h1), v3_scale(d1, h0)), 1.0f / (h0 + h1));

    float scale = 1.0f;
    for (int side = 0; side < 2; side++) {
        if (side == 0 ? !has_prev : !has_next)
            continue;
        vec3 d = side == 0 ? d0 : d1;
        float speed = v3_len(d);
        if (!(speed > 0))
            return v3(0, 0, 0); /* a pause: stop at the key instead of wandering off and back */
        float along = v3_dot(m, d) / speed;
        if (!(along > 0))
            return v3(0, 0, 0); /* a reversal */
        if (along > 3.0f * speed)
            scale = fminf(scale, 3.0f * speed / along);
    }
    return v3_scale(m, scale);
}

camera_state camera_path_eval(const camera_path *path, float t)
{
    camera_state st = {v3(0, 0, 0), v3(0, 0, -1), 0};
    if (!path || path->count <= 0)
        return st;
    int n = path->count < MAX_CAMERA_KEYS ? path->count : MAX_CAMERA_KEYS;
    const camera_key *K = path->keys;
    /* Clamp to the path; NaN goes to the start. */
    if (!(t > K[0].time))
        t = K[0].time;
    if (t >= K[n - 1].time)
        t = K[n - 1].time;
    /* Key i with K[i].time <= t < K[i+1].time (binary search), or the last key. */
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (K[mid].time <= t)
            lo = mid;
        else
            hi = mid;
    }
    int i = (n > 1 && t >= K[n - 1].time) ? n - 1 : lo;
    const camera_key *k0 = &K[i];
    st = (camera_state){k0->position, k0->target, k0->hfov_deg};
    if (i == n - 1 || t <= k0->time)
        return st; /* exactly on a key, or past the end */
    const camera_key *k1 = &K[i + 1];
    if (k1->cut)
        return st; /* the segment into a cut key holds the key before (as if the path ended there) */
    float h = k1->time - k0->time;
    if (!(h > 0))
        return st;
    float s = (t - k0->time) / h;
    if (s > 1.0f)
        s = 1.0f;
    int a = i;
    while (a > 0 && !K[a].cut)
        a--;
    int b = span_end(path, i);
    /* Cubic Hermite basis on [0, 1]; tangents are per second, so they scale by h. */
    float s2 = s * s, s3 = s2 * s;
    float h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    for (int which = 0; which < 2; which++) {
        bool target = which == 1;
        vec3 p0 = key_point(k0, target), p1 = key_point(k1, target);
        vec3 m0 = key_tangent(path, i, a, b, target), m1 = key_tangent(path, i + 1, a, b, target);
        /* Two equal keys hold still (key_tangent gives a pause zero tangents): the key itself, not
         * p0 h00 + p1 h01, which rounds to an ulp off p0 at some s and would jitter a still camera
         * (and make its frames' view-projections differ). */
        bool hold = p0.x == p1.x && p0.y == p1.y && p0.z == p1.z && m0.x == 0.0f && m0.y == 0.0f && m0.z == 0.0f &&
                    m1.x == 0.0f && m1.y == 0.0f && m1.z == 0.0f;
        vec3 r = hold ? p0
                      : v3_add(v3_add(v3_scale(p0, h00), v3_scale(m0, h10 * h)),
                               v3_add(v3_scale(p1, h01), v3_scale(m1, h11 * h)));
        if (target)
            st.target = r;
        else
            st.position = r;
    }
    /* 0 means "the display's": only blend two explicit values (the parser never mixes them). */
    if (k0->hfov_deg > 0 && k1->hfov_deg > 0)
        st.hfov_deg = k0->hfov_deg + (k1->hfov_deg - k0->hfov_deg) * s;
    else
        st.hfov_deg = k0->hfov_deg > 0 ? k0->hfov_deg : k1->hfov_deg;
    return st;
}

bool camera_path_cut_between(const camera_path *path, float t0, float t1)
{
    if (!path)
        return false;
    for (int i = 0; i < path->count && i < MAX_CAMERA_KEYS; i++)
        if (path->keys[i].cut && path->keys[i].time > t0 && path->keys[i].time <= t1)
            return true;
    return false;
}

/* >>validate */

static bool all_finite(const float *v, size_t n, size_t *bad)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i])) {
            *bad = i;
            return false;
        }
    return true;
}

static fs_status validate_asset(const scene *sc, int ai)
{
    const asset *as = &sc->assets[ai];
    const char *P = sc->path;
    size_t bad;
    if (as->prim_count < 0 || as->material_count < 0 || as->image_count < 0 ||
        (as->prim_count > 0 && !as->prims) || (as->material_count > 0 && !as->materials) ||
        (as->image_count > 0 && !as->images)) {
        log_error("%s: assets[%d] (%s): inconsistent counts (%d prims, %d materials, %d images)", P, ai,
                  as->name, as->prim_count, as->material_count, as->image_count);
        return FS_ERR_SCENE;
    }
    for (int ii = 0; ii < as->image_count; ii++) {
        const image_rgba8 *im = &as->images[ii];
        if (im->width < 1 || im->height < 1 || im->width > MAX_TEXTURE_SIZE || im->height > MAX_TEXTURE_SIZE || !im->rgba) {
            log_error("%s: assets[%d] (%s): images[%d] (%s): size %dx%d%s, expected 1..%d texels a side", P,
                      ai, as->name, ii, im->name, im->width, im->height, im->rgba ? "" : " without pixels",
                      MAX_TEXTURE_SIZE);
            return FS_ERR_SCENE;
        }
    }
    for (int mi = 0; mi < as->material_count; mi++) {
        const material *m = &as->materials[mi];
        if (m->base_color_image < -1 || m->base_color_image >= as->image_count) {
            log_error("%s: assets[%d] (%s): materials[%d] (%s): image %d out of range (%d images)", P, ai,
                      as->name, mi, m->name, m->base_color_image, as->image_count);
            return FS_ERR_SCENE;
        }
        if (!all_finite(m->base_color, 4, &bad) || !(m->alpha_cutoff >= 0 && m->alpha_cutoff <= 1) ||
            (unsigned)m->alpha_mode >= ALPHA_MODE_COUNT) {
            log_error("%s: assets[%d] (%s): materials[%d] (%s): bad colour factor, alpha cutoff %g or mode %d",
                      P, ai, as->name, mi, m->name, m->alpha_cutoff, (int)m->alpha_mode);
            return FS_ERR_SCENE;
        }
    }
    for (int pi = 0; pi < as->prim_count; pi++) {
        const prim *p = &as->prims[pi];
        if (p->index_count % 3 != 0) {
            log_error("%s: assets[%d] (%s): prims[%d]: %u indices, not a multiple of 3", P, ai, as->name, pi,
                      p->index_count);
            return FS_ERR_SCENE;
        }
        if (p->vertex_count > 0 && (!p->positions || !p->normals || !p->uvs || !p->colors)) {
            log_error("%s: assets[%d] (%s): prims[%d]: missing vertex attributes", P, ai, as->name, pi);
            return FS_ERR_SCENE;
        }
        if (p->index_count > 0 && !p->indices) {
            log_error("%s: assets[%d] (%s): prims[%d]: missing indices", P, ai, as->name, pi);
            return FS_ERR_SCENE;
        }
        if (p->material < 0 || p->material >= as->material_count) {
            log_error("%s: assets[%d] (%s): prims[%d]: material %d out of range (%d materials)", P, ai, as->name,
                      pi, p->material, as->material_count);
            return FS_ERR_SCENE;
        }
        for (uint32_t k = 0; k < p->index_count; k++)
            if (p->indices[k] >= p->vertex_count) {
                log_error("%s: assets[%d] (%s): prims[%d]: index %u >= %u vertices", P, ai, as->name, pi,
                          p->indices[k], p->vertex_count);
                return FS_ERR_SCENE;
            }
        static const char *const names[] = {"position", "normal", "uv", "colour"};
        const float *arrays[] = {p->positions, p->normals, p->uvs, p->colors};
        const int widths[] = {3, 3, 2, 4};
        for (int k = 0; k < 4; k++)
            if (p->vertex_count > 0 && !all_finite(arrays[k], (size_t)p->vertex_count * widths[k], &bad)) {
                log_error("%s: assets[%d] (%s): prims[%d]: vertex %zu: %s is not finite", P, ai, as->name, pi,
                          bad / widths[k], names[k]);
                return FS_ERR_SCENE;
            }
    }
    return FS_OK;
}

fs_status scene_validate(const scene *sc)
{
    const char *P = sc->path[0] ? sc->path : "scene";
    size_t bad;
    if (sc->asset_count < 0 || sc->instance_count < 0 || (sc->asset_count > 0 && !sc->assets) ||
        (sc->instance_count > 0 && !sc->instances)) {
        log_error("%s: inconsistent counts (%d assets, %d instances)", P, sc->asset_count, sc->instance_count);
        return FS_ERR_SCENE;
    }
    for (int ai = 0; ai < sc->asset_count; ai++) {
        fs_status s = validate_asset(sc, ai);
        if (s != FS_OK)
            return s;
    }
    for (int i = 0; i < sc->instance_count; i++) {
        const instance *in = &sc->instances[i];
        if (in->asset < 0 || in->asset >= sc->asset_count) {
            log_error("%s: instances[%d]: asset %d out of range (%d assets)", P, i, in->asset, sc->asset_count);
            return FS_ERR_SCENE;
        }
        if (!all_finite(in->transform.m, 16, &bad)) {
            log_error("%s: instances[%d]: transform element %zu is not finite", P, i, bad);
            return FS_ERR_SCENE;
        }
        const instance_sway *w = &in->sway;
        const float sway[6] = {w->offset.x, w->offset.y, w->offset.z, w->height, w->frequency, w->phase};
        if (!all_finite(sway, 6, &bad) || (instance_sways(in) && (!(w->height > 0.0f) || !(w->frequency > 0.0f)))) {
            log_error("%s: instances[%d]: sway needs a finite offset, a height > 0 and a frequency > 0", P, i);
            return FS_ERR_SCENE;
        }
    }
    const camera_path *cp = &sc->camera;
    if (cp->count < 1 || cp->count > MAX_CAMERA_KEYS) {
        log_error("%s: camera: %d keys, expected 1..%d", P, cp->count, MAX_CAMERA_KEYS);
        return FS_ERR_SCENE;
    }
    for (int i = 0; i < cp->count; i++) {
        const camera_key *k = &cp->keys[i];
        float v[8] = {k->time, k->position.x, k->position.y, k->position.z,
                      k->target.x, k->target.y, k->target.z, k->hfov_deg};
        if (!all_finite(v, 8, &bad) || (i > 0 && !(k->time > cp->keys[i - 1].time)) ||
            (k->hfov_deg != 0 && !(k->hfov_deg > 1 && k->hfov_deg < 179))) {
            log_error("%s: camera[%d]: not finite, time not increasing, or hfov %g outside (1, 179)", P, i,
                      k->hfov_deg);
            return FS_ERR_SCENE;
        }
    }
    const display_desc *d = &sc->display;
    if (d->width < 16 || d->width > MAX_DISPLAY_SIZE || d->height < 16 || d->height > MAX_DISPLAY_SIZE ||
        !(d->hfov_deg > 1 && d->hfov_deg < 179)) {
        log_error("%s: display: %dx%d, hfov %g: expected 16..%d pixels a side and hfov in (1, 179)", P,
                  d->width, d->height, d->hfov_deg, MAX_DISPLAY_SIZE);
        return FS_ERR_SCENE;
    }
    return FS_OK;
}

/* >>content hash */

uint64_t scene_content_hash(const scene *sc)
{
    uint64_t h = hash_str(HASH_FNV_INIT, "fovsim scene content v1");
    h = hash_u64(h, (uint64_t)sc->asset_count);
    for (int a = 0; a < sc->asset_count; a++) {
        const asset *as = &sc->assets[a];
        h = hash_u64(h, (uint64_t)as->prim_count);
        for (int i = 0; i < as->prim_count; i++) {
            const prim *p = &as->prims[i];
            h = hash_u64(h, p->vertex_count);
            h = hash_u64(h, p->index_count);
            h = hash_u64(h, (uint64_t)p->material);
            h = hash_floats(h, p->positions, 3 * (size_t)p->vertex_count);
            h = hash_floats(h, p->normals, 3 * (size_t)p->vertex_count);
            h = hash_floats(h, p->uvs, 2 * (size_t)p->vertex_count);
            h = hash_floats(h, p->colors, 4 * (size_t)p->vertex_count);
            h = hash_bytes(h, p->indices, sizeof(uint32_t) * p->index_count);
        }
        h = hash_u64(h, (uint64_t)as->material_count);
        for (int i = 0; i < as->material_count; i++) {
            const material *m = &as->materials[i];
            h = hash_floats(h, m->base_color, 4);
            h = hash_floats(h, &m->alpha_cutoff, 1);
            uint64_t e[6] = {(uint64_t)m->base_color_image, m->wrap_s, m->wrap_t, m->mag_filter, m->alpha_kind,
                             m->double_sided};
            for (int k = 0; k < 6; k++)
                h = hash_u64(h, e[k]);
        }
        h = hash_u64(h, (uint64_t)as->image_count);
        for (int i = 0; i < as->image_count; i++) {
            const image_rgba8 *im = &as->images[i];
            h = hash_u64(h, (uint64_t)im->width);
            h = hash_u64(h, (uint64_t)im->height);
            h = hash_bytes(h, im->rgba, 4 * (size_t)im->width * (size_t)im->height);
        }
    }
    h = hash_u64(h, (uint64_t)sc->instance_count);
    for (int i = 0; i < sc->instance_count; i++) {
        h = hash_u64(h, (uint64_t)sc->instances[i].asset);
        h = hash_floats(h, sc->instances[i].transform.m, 16);
        const instance_sway *w = &sc->instances[i].sway;
        const float sway[6] = {w->offset.x, w->offset.y, w->offset.z, w->height, w->frequency, w->phase};
        h = hash_floats(h, sway, 6);
    }
    const light_desc *L = &sc->light;
    const float light[12] = {L->direction.x, L->direction.y, L->direction.z, L->color.x, L->color.y, L->color.z,
                             L->ambient.x, L->ambient.y, L->ambient.z, L->sky.x, L->sky.y, L->sky.z};
    h = hash_floats(h, light, 12);
    return hash_floats(h, &sc->display.hfov_deg, 1);
}
