/* scene_json_instances.c: the "instances" entries of a scene file: an asset placed by
 * translation, rotation and scale, or scattered in a box (splitmix64, docs/scene-format.md), and
 * the sway of the instances an entry placed. */
#include "scene/scene_json_internal.h"

#include <stdint.h>
#include <string.h>

#include "common/shared_defs.h"

/* >>rng */

/* splitmix64 (Steele, Lea & Flood 2014): the scatter RNG documented in docs/scene-format.md. */
static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1) with 24 bits, exactly representable as a float. */
static double rng_unit(uint64_t *state) { return (double)(splitmix64(state) >> 40) * 0x1p-24; }

/* >>transforms */

static mat4 rot_x(float a)
{
    mat4 r = m4_identity();
    float c = cosf(a), s = sinf(a);
    r.m[5] = c;
    r.m[6] = s;
    r.m[9] = -s;
    r.m[10] = c;
    return r;
}

static mat4 rot_y(float a)
{
    mat4 r = m4_identity();
    float c = cosf(a), s = sinf(a);
    r.m[0] = c;
    r.m[2] = -s;
    r.m[8] = s;
    r.m[10] = c;
    return r;
}

static mat4 rot_z(float a)
{
    mat4 r = m4_identity();
    float c = cosf(a), s = sinf(a);
    r.m[0] = c;
    r.m[1] = s;
    r.m[4] = -s;
    r.m[5] = c;
    return r;
}

static float deg2rad(float d) { return d * (float)(FS_PI / 180.0); }

/* Euler angles in degrees as yaw-pitch-roll: R = Ry * Rx * Rz (roll applies first). */
static mat4 euler_deg(vec3 e)
{
    return m4_mul(rot_y(deg2rad(e.y)), m4_mul(rot_x(deg2rad(e.x)), rot_z(deg2rad(e.z))));
}

/* >>instances */

/* T * R(rotation_deg) * S(scale) of one instance entry (without scatter). */
typedef struct placement {
    vec3 translation, rotation_deg, scale;
} placement;

static fs_status parse_scale(const jctx *c, const cJSON *it, const char *path, vec3 *out)
{
    char got[64];
    if (cJSON_IsNumber(it)) {
        float s = 1;
        fs_status st = jfloat(c, it, path, R_POS, &s);
        if (st == FS_OK)
            *out = v3(s, s, s);
        return st;
    }
    if (cJSON_IsArray(it) && cJSON_GetArraySize(it) == 3)
        return jvec3(c, it, path, R_POS, out);
    return jfail(c, path, "expected a number or 3 numbers, got %s", jgot(it, got, sizeof got));
}

static fs_status asset_lookup(const jctx *c, const cJSON *it, const char *path,
                              const asset_spec *specs, int n, int *out)
{
    const char *name;
    fs_status s = jstring(c, it, path, &name);
    if (s != FS_OK)
        return s;
    for (int i = 0; i < n; i++)
        if (strcmp(specs[i].name, name) == 0) {
            *out = i;
            return FS_OK;
        }
    char list[512] = "";
    for (int i = 0; i < n; i++) {
        size_t l = strlen(list);
        if (l + strlen(specs[i].name) + 8 >= sizeof list) {
            snprintf(list + l, sizeof list - l, ", ...");
            break;
        }
        snprintf(list + l, sizeof list - l, "%s%s", i ? ", " : "", specs[i].name);
    }
    return jfail(c, path, "no asset named \"%s\" (assets are: %s)", name, list);
}

static fs_status add_instance(const jctx *c, const char *path, int asset_index, mat4 m)
{
    if (c->sc->instance_count >= MAX_SCENE_INSTANCES)
        return jfail(c, path, "too many instances (at most %d in one scene)", MAX_SCENE_INSTANCES);
    if (!scene_add_instance(c->sc, asset_index, m)) {
        log_error("%s: out of memory placing instances", c->file);
        return FS_ERR_NOMEM;
    }
    return FS_OK;
}

static fs_status parse_scatter(const jctx *c, const cJSON *it, const char *path, int asset_index,
                               mat4 local)
{
    static const char *const keys[] = {"count", "seed", "min", "max", "scale", "random_yaw", "comment", NULL};
    char kp[256], got[64];
    fs_status s = jkeys(c, it, path, keys);
    if (s != FS_OK)
        return s;
    const cJSON *jcount = cJSON_GetObjectItemCaseSensitive(it, "count");
    const cJSON *jmin = cJSON_GetObjectItemCaseSensitive(it, "min");
    const cJSON *jmax = cJSON_GetObjectItemCaseSensitive(it, "max");
    const cJSON *jscale = cJSON_GetObjectItemCaseSensitive(it, "scale");
    int count;
    double seed = 1;
    vec3 lo, hi;
    float slo = 1, shi = 1;
    bool yaw = false;

    if (!jcount)
        return jfail(c, path, "missing \"count\"");
    if (!jmin || !jmax)
        return jfail(c, path, "missing \"%s\" (the box instances are placed in)", jmin ? "max" : "min");
    if ((s = jint(c, jcount, jkey_path(kp, sizeof kp, path, "count"), 1, MAX_SCATTER_COUNT, &count)) != FS_OK)
        return s;
    if ((s = jopt_num(c, it, path, "seed", R_SEED, &seed)) != FS_OK)
        return s;
    if ((s = jvec3(c, jmin, jkey_path(kp, sizeof kp, path, "min"), R_ANY, &lo)) != FS_OK)
        return s;
    if ((s = jvec3(c, jmax, jkey_path(kp, sizeof kp, path, "max"), R_ANY, &hi)) != FS_OK)
        return s;
    if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z)
        return jfail(c, jkey_path(kp, sizeof kp, path, "max"),
                     "expected max >= min in every component, got min (%g, %g, %g), max (%g, %g, %g)",
                     lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
    if (jscale) {
        jkey_path(kp, sizeof kp, path, "scale");
        if (!cJSON_IsArray(jscale) || cJSON_GetArraySize(jscale) != 2)
            return jfail(c, kp, "expected 2 numbers [min, max], got %s", jgot(jscale, got, sizeof got));
        char ep[300];
        if ((s = jfloat(c, cJSON_GetArrayItem(jscale, 0), jidx_path(ep, sizeof ep, kp, 0), R_POS, &slo)) != FS_OK ||
            (s = jfloat(c, cJSON_GetArrayItem(jscale, 1), jidx_path(ep, sizeof ep, kp, 1), R_POS, &shi)) != FS_OK)
            return s;
        if (slo > shi)
            return jfail(c, kp, "expected min <= max, got %g > %g", slo, shi);
    }
    if ((s = jopt_bool(c, it, path, "random_yaw", &yaw)) != FS_OK)
        return s;
    if ((s = jopt_comment(c, it, path)) != FS_OK)
        return s;

    /* Five draws per instance whatever the options, so toggling random_yaw or scale never moves
     * the positions: x, y, z, yaw, scale. */
    uint64_t state = (uint64_t)seed;
    for (int i = 0; i < count; i++) {
        double u[5];
        for (int k = 0; k < 5; k++)
            u[k] = rng_unit(&state);
        vec3 p = v3((float)(lo.x + (hi.x - lo.x) * u[0]), (float)(lo.y + (hi.y - lo.y) * u[1]),
                    (float)(lo.z + (hi.z - lo.z) * u[2]));
        p = v3_min(v3_max(p, lo), hi); /* float rounding must not leave the box */
        float sc = (float)(slo + (shi - slo) * u[4]);
        mat4 m = m4_translate(p);
        if (yaw)
            m = m4_mul(m, rot_y((float)(2.0 * FS_PI * u[3])));
        m = m4_mul(m, m4_mul(m4_scale(v3(sc, sc, sc)), local));
        if ((s = add_instance(c, path, asset_index, m)) != FS_OK)
            return s;
    }
    return FS_OK;
}

/* An instance entry's "sway" (docs/scene-format.md), applied to the instances [first, count) the
 * entry placed. Each one's phase comes from its position along the wind, so a row of trees sways
 * as a travelling wave. A height of 0 stands for the asset's top (scene_json_resolve_sway_heights,
 * once the assets are loaded). */
static fs_status parse_sway(const jctx *c, const cJSON *it, const char *path, int first)
{
    static const char *const keys[] = {"amplitude", "frequency", "direction", "height", "wavelength", "comment", NULL};
    static const nrange R_AMPLITUDE = {0, 100, false, false, false, false};
    static const nrange R_FREQUENCY = {0, 100, true, false, false, false};
    static const nrange R_SWAY_LEN = {0, 1e5, true, false, false, false};
    char kp[256];
    fs_status s = jkeys(c, it, path, keys);
    if (s != FS_OK)
        return s;
    const cJSON *ja = cJSON_GetObjectItemCaseSensitive(it, "amplitude");
    const cJSON *jd = cJSON_GetObjectItemCaseSensitive(it, "direction");
    float amplitude = 0, frequency = (float)SWAY_FREQUENCY_DEFAULT, height = 0,
          wavelength = (float)SWAY_WAVELENGTH_DEFAULT;
    vec3 dir = v3(1, 0, 0);
    if (!ja)
        return jfail(c, path, "missing \"amplitude\" (metres the top moves)");
    if ((s = jfloat(c, ja, jkey_path(kp, sizeof kp, path, "amplitude"), R_AMPLITUDE, &amplitude)) != FS_OK)
        return s;
    if ((s = jopt_float(c, it, path, "frequency", R_FREQUENCY, &frequency)) != FS_OK)
        return s;
    if (jd) {
        if ((s = jvec3(c, jd, jkey_path(kp, sizeof kp, path, "direction"), R_ANY, &dir)) != FS_OK)
            return s;
        if (!(v3_len(dir) > 1e-6f))
            return jfail(c, kp, "expected a nonzero direction, got (%g, %g, %g)", dir.x, dir.y, dir.z);
        dir = v3_norm_or(dir, v3(1, 0, 0));
    }
    if ((s = jopt_float(c, it, path, "height", R_SWAY_LEN, &height)) != FS_OK)
        return s;
    if ((s = jopt_float(c, it, path, "wavelength", R_SWAY_LEN, &wavelength)) != FS_OK)
        return s;
    if ((s = jopt_comment(c, it, path)) != FS_OK)
        return s;
    for (int i = first; i < c->sc->instance_count; i++) {
        instance *in = &c->sc->instances[i];
        vec3 pos = v3(in->transform.m[12], in->transform.m[13], in->transform.m[14]);
        double along = -(double)v3_dot(pos, dir) / wavelength;
        in->sway = (instance_sway){.offset = v3_scale(dir, amplitude), .height = height, .frequency = frequency,
                                   .phase = (float)(along - floor(along))};
        if (in->sway.phase >= 1.0f) /* along - floor(along) rounds to 1 just below an integer */
            in->sway.phase = 0.0f;
    }
    return FS_OK;
}

/* Sway heights left at 0 (not given) become the asset's top, or 1 for an asset that does not rise
 * above its origin. */
void scene_json_resolve_sway_heights(scene *sc)
{
    for (int i = 0; i < sc->instance_count; i++) {
        instance *in = &sc->instances[i];
        if (instance_sways(in) && in->sway.height <= 0.0f) {
            float top = sc->assets[in->asset].bounds_max.y;
            in->sway.height = top > 0.0f ? top : 1.0f;
        }
    }
}

static fs_status parse_instance(const jctx *c, const cJSON *it, const char *path,
                                const asset_spec *specs, int nspecs)
{
    static const char *const keys[] = {"asset", "translation", "rotation_deg", "scale", "scatter", "sway",
                                       "comment", NULL};
    char kp[256];
    fs_status s = jkeys(c, it, path, keys);
    if (s != FS_OK)
        return s;
    const cJSON *jasset = cJSON_GetObjectItemCaseSensitive(it, "asset");
    const cJSON *jt = cJSON_GetObjectItemCaseSensitive(it, "translation");
    const cJSON *js = cJSON_GetObjectItemCaseSensitive(it, "scale");
    const cJSON *jscatter = cJSON_GetObjectItemCaseSensitive(it, "scatter");
    int index = -1;
    placement pl = {v3(0, 0, 0), v3(0, 0, 0), v3(1, 1, 1)};

    if (!jasset)
        return jfail(c, path, "missing \"asset\"");
    if ((s = asset_lookup(c, jasset, jkey_path(kp, sizeof kp, path, "asset"), specs, nspecs, &index)) != FS_OK)
        return s;
    if (jt && jscatter)
        return jfail(c, jkey_path(kp, sizeof kp, path, "translation"),
                     "not allowed with \"scatter\" (the scatter box places the instances)");
    if (jt && (s = jvec3(c, jt, jkey_path(kp, sizeof kp, path, "translation"), R_ANY, &pl.translation)) != FS_OK)
        return s;
    if ((s = jopt_vec3(c, it, path, "rotation_deg", R_ANY, &pl.rotation_deg)) != FS_OK)
        return s;
    if (js && (s = parse_scale(c, js, jkey_path(kp, sizeof kp, path, "scale"), &pl.scale)) != FS_OK)
        return s;
    if ((s = jopt_comment(c, it, path)) != FS_OK)
        return s;
    mat4 local = m4_mul(euler_deg(pl.rotation_deg), m4_scale(pl.scale));
    int first = c->sc->instance_count;
    if (jscatter)
        s = parse_scatter(c, jscatter, jkey_path(kp, sizeof kp, path, "scatter"), index, local);
    else
        s = add_instance(c, path, index, m4_mul(m4_translate(pl.translation), local));
    const cJSON *jsway = cJSON_GetObjectItemCaseSensitive(it, "sway");
    if (s == FS_OK && jsway)
        s = parse_sway(c, jsway, jkey_path(kp, sizeof kp, path, "sway"), first);
    return s;
}

fs_status scene_json_parse_instances(const jctx *c, const cJSON *arr, const asset_spec *specs, int nspecs)
{
    char ip[64], got[64];
    if (!arr)
        return jfail(c, "instances", "missing (a scene needs at least one instance)");
    if (!cJSON_IsArray(arr))
        return jfail(c, "instances", "expected an array of instances, got %s", jgot(arr, got, sizeof got));
    if (cJSON_GetArraySize(arr) < 1)
        return jfail(c, "instances", "expected at least one instance, got an empty array");
    int i = 0;
    for (const cJSON *it = arr->child; it; it = it->next, i++) {
        fs_status s = parse_instance(c, it, jidx_path(ip, sizeof ip, "instances", i), specs, nspecs);
        if (s != FS_OK)
            return s;
    }
    return FS_OK;
}
