/* scene_json.c: JSON scene files -> struct scene (format: docs/scene-format.md).
 *
 * The document is read in three phases so that cheap mistakes are reported before any glTF file
 * is loaded: (1) check display, light, every asset description, every instance and the camera
 * path; (2) load the assets in order; (3) apply the per-material overrides, which need the loaded
 * materials. Messages name the document and the JSON path of the offending value.
 */
#include "scene/scene_json.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "fov/fov_ring.h"
#include "scene/generators.h"
#include "scene/gltf_shim.h"
#include "common/shared_defs.h"


/* >>context */

typedef struct jctx {
    const char *file;     /* document name for messages */
    const char *base_dir; /* NULL: no files allowed (built-in scene) */
    scene *sc;
} jctx;

static fs_status jfail(const jctx *c, const char *path, const char *fmt, ...) FS_PRINTF(3, 4);

static fs_status jfail(const jctx *c, const char *path, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (path && path[0])
        log_error("%s: %s: %s", c->file, path, msg);
    else
        log_error("%s: %s", c->file, msg);
    return FS_ERR_SCENE;
}

/* Appends `src` to the path in buf (length *len), truncating at n - 1 characters. */
static void path_cat(char *buf, size_t n, size_t *len, const char *src)
{
    size_t k = strlen(src);
    if (k > n - 1 - *len)
        k = n - 1 - *len;
    memcpy(buf + *len, src, k);
    *len += k;
    buf[*len] = '\0';
}

/* "parent.key" (or "key" at the top level). */
static const char *jkey_path(char *buf, size_t n, const char *parent, const char *key)
{
    size_t len = 0;
    buf[0] = '\0';
    if (parent && parent[0]) {
        path_cat(buf, n, &len, parent);
        path_cat(buf, n, &len, ".");
    }
    path_cat(buf, n, &len, key);
    return buf;
}

/* "parent[i]". */
static const char *jidx_path(char *buf, size_t n, const char *parent, int i)
{
    char idx[16];
    size_t len = 0;
    snprintf(idx, sizeof idx, "[%d]", i);
    buf[0] = '\0';
    path_cat(buf, n, &len, parent);
    path_cat(buf, n, &len, idx);
    return buf;
}

/* What a value is, for "got ..." in messages: numbers and booleans by value, the rest by type. */
static const char *jgot(const cJSON *it, char *buf, size_t n)
{
    if (!it)
        return "nothing";
    if (cJSON_IsNumber(it)) {
        snprintf(buf, n, "%.9g", it->valuedouble);
        return buf;
    }
    if (cJSON_IsTrue(it))
        return "true";
    if (cJSON_IsFalse(it))
        return "false";
    if (cJSON_IsNull(it))
        return "null";
    if (cJSON_IsString(it))
        return "a string";
    if (cJSON_IsArray(it)) {
        snprintf(buf, n, "an array of %d element%s", cJSON_GetArraySize(it),
                 cJSON_GetArraySize(it) == 1 ? "" : "s");
        return buf;
    }
    if (cJSON_IsObject(it))
        return "an object";
    return "an invalid value";
}

/* Checks that `obj` is an object whose keys are all in `allowed` (NULL-terminated), once each. */
static fs_status jkeys(const jctx *c, const cJSON *obj, const char *path, const char *const *allowed)
{
    char got[64], kp[256];
    if (!cJSON_IsObject(obj))
        return jfail(c, path, "expected an object, got %s", jgot(obj, got, sizeof got));
    for (const cJSON *ch = obj->child; ch; ch = ch->next) {
        bool ok = false;
        for (int i = 0; allowed[i]; i++)
            ok = ok || strcmp(ch->string, allowed[i]) == 0;
        if (!ok) {
            char list[512] = "";
            for (int i = 0; allowed[i]; i++) {
                size_t l = strlen(list);
                snprintf(list + l, sizeof list - l, "%s%s", i ? ", " : "", allowed[i]);
            }
            return jfail(c, jkey_path(kp, sizeof kp, path, ch->string),
                         "unknown key (expected one of: %s)", list);
        }
        for (const cJSON *prev = obj->child; prev != ch; prev = prev->next)
            if (strcmp(prev->string, ch->string) == 0)
                return jfail(c, jkey_path(kp, sizeof kp, path, ch->string), "duplicate key");
    }
    return FS_OK;
}

/* >>numbers */

typedef struct nrange {
    double lo, hi;
    bool lo_open, hi_open; /* exclusive bounds */
    bool integer;
    bool pow2;             /* integer power of two */
} nrange;

static const nrange R_ANY = {-INFINITY, INFINITY, false, false, false, false};
static const nrange R_NONNEG = {0, INFINITY, false, false, false, false};
static const nrange R_POS = {0, INFINITY, true, false, false, false};
static const nrange R_UNIT = {0, 1, false, false, false, false};
static const nrange R_HFOV = {1, 179, true, true, false, false};

static void nrange_describe(nrange r, char *buf, size_t n)
{
    const char *kind = r.pow2 ? "a power of two" : r.integer ? "an integer" : "a number";
    bool has_lo = isfinite(r.lo), has_hi = isfinite(r.hi);
    if (has_lo && has_hi)
        snprintf(buf, n, "%s in %c%.9g, %.9g%c", kind, r.lo_open ? '(' : '[', r.lo, r.hi,
                 r.hi_open ? ')' : ']');
    else if (has_lo)
        snprintf(buf, n, "%s %s %.9g", kind, r.lo_open ? ">" : ">=", r.lo);
    else if (has_hi)
        snprintf(buf, n, "%s %s %.9g", kind, r.hi_open ? "<" : "<=", r.hi);
    else
        snprintf(buf, n, "%s", kind);
}

static bool nrange_holds(nrange r, double v)
{
    if (!isfinite(v))
        return false;
    if (r.lo_open ? !(v > r.lo) : !(v >= r.lo))
        return false;
    if (r.hi_open ? !(v < r.hi) : !(v <= r.hi))
        return false;
    if ((r.integer || r.pow2) && v != floor(v))
        return false;
    if (r.pow2) {
        double f = frexp(v, &(int){0});
        if (f != 0.5)
            return false;
    }
    return true;
}

static fs_status jnum(const jctx *c, const cJSON *it, const char *path, nrange r, double *out)
{
    char want[128], got[64];
    if (!cJSON_IsNumber(it) || !nrange_holds(r, it->valuedouble)) {
        nrange_describe(r, want, sizeof want);
        if (cJSON_IsNumber(it) && !isfinite(it->valuedouble))
            return jfail(c, path, "expected a finite number, got %s", jgot(it, got, sizeof got));
        return jfail(c, path, "expected %s, got %s", want, jgot(it, got, sizeof got));
    }
    *out = it->valuedouble;
    return FS_OK;
}

static fs_status jfloat(const jctx *c, const cJSON *it, const char *path, nrange r, float *out)
{
    double v;
    fs_status s = jnum(c, it, path, r, &v);
    if (s == FS_OK) {
        if (!isfinite((float)v))
            return jfail(c, path, "expected a number that fits a float, got %.9g", v);
        *out = (float)v;
    }
    return s;
}

static fs_status jint(const jctx *c, const cJSON *it, const char *path, int lo, int hi, int *out)
{
    nrange r = {lo, hi, false, false, true, false};
    double v;
    fs_status s = jnum(c, it, path, r, &v);
    if (s == FS_OK)
        *out = (int)v;
    return s;
}

static fs_status jbool(const jctx *c, const cJSON *it, const char *path, bool *out)
{
    char got[64];
    if (!cJSON_IsBool(it))
        return jfail(c, path, "expected true or false, got %s", jgot(it, got, sizeof got));
    *out = cJSON_IsTrue(it);
    return FS_OK;
}

static fs_status jstring(const jctx *c, const cJSON *it, const char *path, const char **out)
{
    char got[64];
    if (!cJSON_IsString(it) || !it->valuestring)
        return jfail(c, path, "expected a string, got %s", jgot(it, got, sizeof got));
    *out = it->valuestring;
    return FS_OK;
}

/* An array of exactly 3 numbers, each in r. */
static fs_status jvec3(const jctx *c, const cJSON *it, const char *path, nrange r, vec3 *out)
{
    char got[64], ep[256];
    if (!cJSON_IsArray(it) || cJSON_GetArraySize(it) != 3)
        return jfail(c, path, "expected 3 numbers, got %s", jgot(it, got, sizeof got));
    float v[3];
    for (int i = 0; i < 3; i++) {
        fs_status s = jfloat(c, cJSON_GetArrayItem(it, i), jidx_path(ep, sizeof ep, path, i), r, &v[i]);
        if (s != FS_OK)
            return s;
    }
    *out = v3(v[0], v[1], v[2]);
    return FS_OK;
}

static fs_status jmode(const jctx *c, const cJSON *it, const char *path, alpha_mode *out)
{
    const char *name;
    fs_status s = jstring(c, it, path, &name);
    if (s != FS_OK)
        return s;
    alpha_mode m = alpha_mode_parse(name);
    if (m == ALPHA_MODE_DEFAULT)
        return jfail(c, path, "unknown alpha mode \"%s\" (modes are: %s)", name, alpha_mode_list());
    *out = m;
    return FS_OK;
}

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

/* >>assets */

enum { GEN_TREE, GEN_GRASS, GEN_FENCE, GEN_FERN, GEN_COUNT };

typedef enum ptype { P_U32, P_INT, P_FLOAT } ptype;

typedef struct gparam {
    const char *name; /* the gen_*_desc field name */
    ptype type;
    size_t offset;
    nrange range;
} gparam;

/* Ranges are the ones each generator documents; 0 ("default") is not accepted because a scene
 * that names a parameter means a value. Counts are capped to keep memory bounded. */
#define R_SEED ((nrange){0, 4294967295.0, false, false, true, false})
#define R_COUNT ((nrange){1, 100000, false, false, true, false})
#define R_TEX ((nrange){8, 4096, false, false, true, true})
#define R_CUTOFF ((nrange){0, 1, true, false, false, false})
#define R_WIRE ((nrange){1, 5, false, false, true, false})
#define R_LEN ((nrange){0, 1e5, true, false, false, false})

#define GP(desc, field, type, range) {#field, type, offsetof(desc, field), range}
static const gparam k_tree_params[] = {
    GP(gen_tree_desc, seed, P_U32, R_SEED),          GP(gen_tree_desc, height, P_FLOAT, R_LEN),
    GP(gen_tree_desc, crown_radius, P_FLOAT, R_LEN), GP(gen_tree_desc, card_count, P_INT, R_COUNT),
    GP(gen_tree_desc, card_size, P_FLOAT, R_LEN),    GP(gen_tree_desc, texture_size, P_INT, R_TEX),
    GP(gen_tree_desc, alpha_cutoff, P_FLOAT, R_CUTOFF),
    {.name = NULL},
};
static const gparam k_grass_params[] = {
    GP(gen_grass_desc, seed, P_U32, R_SEED),           GP(gen_grass_desc, extent, P_FLOAT, R_LEN),
    GP(gen_grass_desc, card_count, P_INT, R_COUNT),    GP(gen_grass_desc, blade_height, P_FLOAT, R_LEN),
    GP(gen_grass_desc, texture_size, P_INT, R_TEX),    GP(gen_grass_desc, alpha_cutoff, P_FLOAT, R_CUTOFF),
    {.name = NULL},
};
static const gparam k_fence_params[] = {
    GP(gen_fence_desc, seed, P_U32, R_SEED),         GP(gen_fence_desc, length, P_FLOAT, R_LEN),
    GP(gen_fence_desc, height, P_FLOAT, R_LEN),      GP(gen_fence_desc, cell_size, P_FLOAT, R_LEN),
    GP(gen_fence_desc, texture_size, P_INT, R_TEX),  GP(gen_fence_desc, wire_texels, P_INT, R_WIRE),
    GP(gen_fence_desc, alpha_cutoff, P_FLOAT, R_CUTOFF),
    {.name = NULL},
};
static const gparam k_fern_params[] = {
    GP(gen_fern_desc, seed, P_U32, R_SEED),          GP(gen_fern_desc, size, P_FLOAT, R_LEN),
    GP(gen_fern_desc, frond_count, P_INT, R_COUNT),  GP(gen_fern_desc, texture_size, P_INT, R_TEX),
    GP(gen_fern_desc, alpha_cutoff, P_FLOAT, R_CUTOFF),
    {.name = NULL},
};
#undef GP

typedef union gen_desc {
    gen_tree_desc tree;
    gen_grass_desc grass;
    gen_fence_desc fence;
    gen_fern_desc fern;
} gen_desc;

static fs_status run_tree(const gen_desc *d, asset *a) { return gen_tree(&d->tree, a); }
static fs_status run_grass(const gen_desc *d, asset *a) { return gen_grass(&d->grass, a); }
static fs_status run_fence(const gen_desc *d, asset *a) { return gen_fence(&d->fence, a); }
static fs_status run_fern(const gen_desc *d, asset *a) { return gen_fern(&d->fern, a); }

static const struct generator_info {
    const char *name;
    const gparam *params;
    fs_status (*run)(const gen_desc *d, asset *out);
} k_generators[GEN_COUNT] = {
    [GEN_TREE] = {"tree", k_tree_params, run_tree},
    [GEN_GRASS] = {"grass", k_grass_params, run_grass},
    [GEN_FENCE] = {"fence", k_fence_params, run_fence},
    [GEN_FERN] = {"fern", k_fern_params, run_fern},
};

/* One entry of "assets", checked but not loaded yet. */
typedef struct asset_spec {
    char name[128];
    int generator;   /* GEN_*, or -1 for glTF */
    gen_desc desc;
    char *gltf_path; /* resolved path, owned */
} asset_spec;

static fs_status parse_params(const jctx *c, const cJSON *params, const char *path, int gen,
                              gen_desc *d)
{
    char got[64], kp[256];
    const gparam *table = k_generators[gen].params;
    if (!cJSON_IsObject(params))
        return jfail(c, path, "expected an object, got %s", jgot(params, got, sizeof got));
    for (const cJSON *ch = params->child; ch; ch = ch->next) {
        jkey_path(kp, sizeof kp, path, ch->string);
        const gparam *p = NULL;
        for (int i = 0; table[i].name; i++)
            if (strcmp(table[i].name, ch->string) == 0)
                p = &table[i];
        if (!p) {
            char list[256] = "";
            for (int i = 0; table[i].name; i++) {
                size_t l = strlen(list);
                snprintf(list + l, sizeof list - l, "%s%s", i ? ", " : "", table[i].name);
            }
            return jfail(c, kp, "unknown parameter of generator \"%s\" (expected one of: %s)",
                         k_generators[gen].name, list);
        }
        for (const cJSON *prev = params->child; prev != ch; prev = prev->next)
            if (strcmp(prev->string, ch->string) == 0)
                return jfail(c, kp, "duplicate key");
        double v;
        fs_status s = jnum(c, ch, kp, p->range, &v);
        if (s != FS_OK)
            return s;
        char *field = (char *)d + p->offset;
        if (p->type == P_U32)
            *(uint32_t *)field = (uint32_t)v;
        else if (p->type == P_INT)
            *(int *)field = (int)v;
        else
            *(float *)field = (float)v;
    }
    return FS_OK;
}

/* "dir/../x/Bush.gltf" -> "Bush" (the default asset name of a glTF asset). */
static void file_stem(const char *path, char *buf, size_t n)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    snprintf(buf, n, "%s", base);
    char *dot = strrchr(buf, '.');
    if (dot && dot != buf)
        *dot = '\0';
}

static fs_status parse_asset(const jctx *c, const cJSON *it, const char *path, asset_spec *spec)
{
    static const char *const keys[] = {"name", "generator", "params", "gltf", "comment", NULL};
    char kp[256];
    fs_status s = jkeys(c, it, path, keys);
    if (s != FS_OK)
        return s;
    const cJSON *jname = cJSON_GetObjectItemCaseSensitive(it, "name");
    const cJSON *jgen = cJSON_GetObjectItemCaseSensitive(it, "generator");
    const cJSON *jparams = cJSON_GetObjectItemCaseSensitive(it, "params");
    const cJSON *jgltf = cJSON_GetObjectItemCaseSensitive(it, "gltf");
    const cJSON *jcomment = cJSON_GetObjectItemCaseSensitive(it, "comment");
    const char *str;

    if (jcomment && (s = jstring(c, jcomment, jkey_path(kp, sizeof kp, path, "comment"), &str)) != FS_OK)
        return s;
    if (jgen && jgltf)
        return jfail(c, path, "give either \"generator\" or \"gltf\", not both");
    if (!jgen && !jgltf)
        return jfail(c, path, "missing \"generator\" or \"gltf\"");
    if (jgltf && jparams)
        return jfail(c, jkey_path(kp, sizeof kp, path, "params"),
                     "only generator assets take parameters");

    spec->generator = -1;
    if (jgen) {
        if ((s = jstring(c, jgen, jkey_path(kp, sizeof kp, path, "generator"), &str)) != FS_OK)
            return s;
        for (int g = 0; g < GEN_COUNT; g++)
            if (strcmp(str, k_generators[g].name) == 0)
                spec->generator = g;
        if (spec->generator < 0)
            return jfail(c, kp, "unknown generator \"%s\" (generators are: tree, grass, fence, fern)", str);
        memset(&spec->desc, 0, sizeof spec->desc);
        if (jparams && (s = parse_params(c, jparams, jkey_path(kp, sizeof kp, path, "params"),
                                         spec->generator, &spec->desc)) != FS_OK)
            return s;
        snprintf(spec->name, sizeof spec->name, "%s", str);
    } else {
        if ((s = jstring(c, jgltf, jkey_path(kp, sizeof kp, path, "gltf"), &str)) != FS_OK)
            return s;
        if (!str[0])
            return jfail(c, kp, "expected a file path, got an empty string");
        if (!c->base_dir)
            return jfail(c, kp, "built-in scenes cannot load files");
        size_t n = strlen(c->base_dir) + strlen(str) + 2;
        spec->gltf_path = malloc(n);
        if (!spec->gltf_path)
            return FS_ERR_NOMEM;
        if (str[0] == '/' || !c->base_dir[0])
            snprintf(spec->gltf_path, n, "%s", str);
        else
            snprintf(spec->gltf_path, n, "%s/%s", c->base_dir, str);
        file_stem(str, spec->name, sizeof spec->name);
    }
    if (jname) {
        if ((s = jstring(c, jname, jkey_path(kp, sizeof kp, path, "name"), &str)) != FS_OK)
            return s;
        if (!str[0] || strlen(str) >= sizeof spec->name)
            return jfail(c, kp, "expected a name of 1 to %zu characters", sizeof spec->name - 1);
        snprintf(spec->name, sizeof spec->name, "%s", str);
    }
    return FS_OK;
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
    const cJSON *jseed = cJSON_GetObjectItemCaseSensitive(it, "seed");
    const cJSON *jmin = cJSON_GetObjectItemCaseSensitive(it, "min");
    const cJSON *jmax = cJSON_GetObjectItemCaseSensitive(it, "max");
    const cJSON *jscale = cJSON_GetObjectItemCaseSensitive(it, "scale");
    const cJSON *jyaw = cJSON_GetObjectItemCaseSensitive(it, "random_yaw");
    const cJSON *jcomment = cJSON_GetObjectItemCaseSensitive(it, "comment");
    const char *str;
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
    if (jseed && (s = jnum(c, jseed, jkey_path(kp, sizeof kp, path, "seed"), R_SEED, &seed)) != FS_OK)
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
    if (jyaw && (s = jbool(c, jyaw, jkey_path(kp, sizeof kp, path, "random_yaw"), &yaw)) != FS_OK)
        return s;
    if (jcomment && (s = jstring(c, jcomment, jkey_path(kp, sizeof kp, path, "comment"), &str)) != FS_OK)
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
 * as a travelling wave. A height of 0 stands for the asset's top (resolve_sway_heights, once the
 * assets are loaded). */
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
    const cJSON *jf = cJSON_GetObjectItemCaseSensitive(it, "frequency");
    const cJSON *jd = cJSON_GetObjectItemCaseSensitive(it, "direction");
    const cJSON *jh = cJSON_GetObjectItemCaseSensitive(it, "height");
    const cJSON *jw = cJSON_GetObjectItemCaseSensitive(it, "wavelength");
    const cJSON *jcomment = cJSON_GetObjectItemCaseSensitive(it, "comment");
    const char *str;
    float amplitude = 0, frequency = (float)SWAY_FREQUENCY_DEFAULT, height = 0,
          wavelength = (float)SWAY_WAVELENGTH_DEFAULT;
    vec3 dir = v3(1, 0, 0);
    if (!ja)
        return jfail(c, path, "missing \"amplitude\" (metres the top moves)");
    if ((s = jfloat(c, ja, jkey_path(kp, sizeof kp, path, "amplitude"), R_AMPLITUDE, &amplitude)) != FS_OK)
        return s;
    if (jf && (s = jfloat(c, jf, jkey_path(kp, sizeof kp, path, "frequency"), R_FREQUENCY, &frequency)) != FS_OK)
        return s;
    if (jd) {
        if ((s = jvec3(c, jd, jkey_path(kp, sizeof kp, path, "direction"), R_ANY, &dir)) != FS_OK)
            return s;
        if (!(v3_len(dir) > 1e-6f))
            return jfail(c, kp, "expected a nonzero direction, got (%g, %g, %g)", dir.x, dir.y, dir.z);
        dir = v3_norm_or(dir, v3(1, 0, 0));
    }
    if (jh && (s = jfloat(c, jh, jkey_path(kp, sizeof kp, path, "height"), R_SWAY_LEN, &height)) != FS_OK)
        return s;
    if (jw && (s = jfloat(c, jw, jkey_path(kp, sizeof kp, path, "wavelength"), R_SWAY_LEN, &wavelength)) != FS_OK)
        return s;
    if (jcomment && (s = jstring(c, jcomment, jkey_path(kp, sizeof kp, path, "comment"), &str)) != FS_OK)
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
static void resolve_sway_heights(scene *sc)
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
    const cJSON *jr = cJSON_GetObjectItemCaseSensitive(it, "rotation_deg");
    const cJSON *js = cJSON_GetObjectItemCaseSensitive(it, "scale");
    const cJSON *jscatter = cJSON_GetObjectItemCaseSensitive(it, "scatter");
    const cJSON *jcomment = cJSON_GetObjectItemCaseSensitive(it, "comment");
    const char *str;
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
    if (jr && (s = jvec3(c, jr, jkey_path(kp, sizeof kp, path, "rotation_deg"), R_ANY, &pl.rotation_deg)) != FS_OK)
        return s;
    if (js && (s = parse_scale(c, js, jkey_path(kp, sizeof kp, path, "scale"), &pl.scale)) != FS_OK)
        return s;
    if (jcomment && (s = jstring(c, jcomment, jkey_path(kp, sizeof kp, path, "comment"), &str)) != FS_OK)
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

/* >>camera */

static fs_status parse_camera(const jctx *c, const cJSON *arr)
{
    static const char *const keys[] = {"time", "position", "target", "hfov", "cut", "comment", NULL};
    char kp[256], ip[64], got[64];
    camera_path *cp = &c->sc->camera;
    fs_status s;
    if (!cJSON_IsArray(arr))
        return jfail(c, "camera", "expected an array of camera keys, got %s", jgot(arr, got, sizeof got));
    int n = cJSON_GetArraySize(arr);
    if (n < 1 || n > MAX_CAMERA_KEYS)
        return jfail(c, "camera", "expected 1 to %d camera keys, got %d", MAX_CAMERA_KEYS, n);
    bool any_hfov = false;
    int i = 0;
    for (const cJSON *it = arr->child; it; it = it->next, i++) {
        jidx_path(ip, sizeof ip, "camera", i);
        if ((s = jkeys(c, it, ip, keys)) != FS_OK)
            return s;
        camera_key k = {0};
        const cJSON *jtime = cJSON_GetObjectItemCaseSensitive(it, "time");
        const cJSON *jpos = cJSON_GetObjectItemCaseSensitive(it, "position");
        const cJSON *jtgt = cJSON_GetObjectItemCaseSensitive(it, "target");
        const cJSON *jhfov = cJSON_GetObjectItemCaseSensitive(it, "hfov");
        const cJSON *jcut = cJSON_GetObjectItemCaseSensitive(it, "cut");
        const cJSON *jcomment = cJSON_GetObjectItemCaseSensitive(it, "comment");
        const char *str;
        if (!jtime && n > 1)
            return jfail(c, ip, "missing \"time\" (needed when the path has more than one key)");
        if (!jpos || !jtgt)
            return jfail(c, ip, "missing \"%s\"", jpos ? "target" : "position");
        if (jtime && (s = jfloat(c, jtime, jkey_path(kp, sizeof kp, ip, "time"), R_NONNEG, &k.time)) != FS_OK)
            return s;
        if (i > 0 && !(k.time > cp->keys[i - 1].time))
            return jfail(c, kp, "expected times strictly increasing, %.9g <= %.9g", k.time,
                         cp->keys[i - 1].time);
        if ((s = jvec3(c, jpos, jkey_path(kp, sizeof kp, ip, "position"), R_ANY, &k.position)) != FS_OK)
            return s;
        if ((s = jvec3(c, jtgt, jkey_path(kp, sizeof kp, ip, "target"), R_ANY, &k.target)) != FS_OK)
            return s;
        if (!(v3_len(v3_sub(k.target, k.position)) > 1e-6f))
            return jfail(c, kp, "expected a point different from \"position\"");
        if (jhfov) {
            if ((s = jfloat(c, jhfov, jkey_path(kp, sizeof kp, ip, "hfov"), R_HFOV, &k.hfov_deg)) != FS_OK)
                return s;
            any_hfov = true;
        }
        if (jcut && (s = jbool(c, jcut, jkey_path(kp, sizeof kp, ip, "cut"), &k.cut)) != FS_OK)
            return s;
        if (k.cut && i == 0)
            return jfail(c, kp, "the first key cannot be a cut (nothing comes before it)");
        if (jcomment && (s = jstring(c, jcomment, jkey_path(kp, sizeof kp, ip, "comment"), &str)) != FS_OK)
            return s;
        cp->keys[i] = k;
    }
    cp->count = n;
    /* hfov is interpolated linearly; a key without one must not blend towards "0 = display's". */
    if (any_hfov)
        for (int j = 0; j < n; j++)
            if (cp->keys[j].hfov_deg == 0)
                cp->keys[j].hfov_deg = c->sc->display.hfov_deg;
    return FS_OK;
}

/* >>top level */

static fs_status parse_display(const jctx *c, const cJSON *it)
{
    static const char *const keys[] = {"width", "height", "hfov", "comment", NULL};
    display_desc *d = &c->sc->display;
    const char *str;
    fs_status s = jkeys(c, it, "display", keys);
    const cJSON *j;
    if (s == FS_OK && (j = cJSON_GetObjectItemCaseSensitive(it, "width")))
        s = jint(c, j, "display.width", 16, MAX_DISPLAY_SIZE, &d->width);
    if (s == FS_OK && (j = cJSON_GetObjectItemCaseSensitive(it, "height")))
        s = jint(c, j, "display.height", 16, MAX_DISPLAY_SIZE, &d->height);
    if (s == FS_OK && (j = cJSON_GetObjectItemCaseSensitive(it, "hfov")))
        s = jfloat(c, j, "display.hfov", R_HFOV, &d->hfov_deg);
    if (s == FS_OK && (j = cJSON_GetObjectItemCaseSensitive(it, "comment")))
        s = jstring(c, j, "display.comment", &str);
    return s;
}

static fs_status parse_light(const jctx *c, const cJSON *it)
{
    static const char *const keys[] = {"direction", "color", "ambient", "sky", "comment", NULL};
    light_desc *l = &c->sc->light;
    const char *str;
    fs_status s = jkeys(c, it, "light", keys);
    const cJSON *j;
    if (s == FS_OK && (j = cJSON_GetObjectItemCaseSensitive(it, "direction"))) {
        vec3 d;
        s = jvec3(c, j, "light.direction", R_ANY, &d);
        if (s == FS_OK && !(v3_len(d) > 1e-6f))
            return jfail(c, "light.direction", "expected a non-zero vector");
        if (s == FS_OK)
            l->direction = v3_norm_or(d, l->direction);
    }
    if (s == FS_OK && (j = cJSON_GetObjectItemCaseSensitive(it, "color")))
        s = jvec3(c, j, "light.color", R_NONNEG, &l->color);
    if (s == FS_OK && (j = cJSON_GetObjectItemCaseSensitive(it, "ambient")))
        s = jvec3(c, j, "light.ambient", R_NONNEG, &l->ambient);
    if (s == FS_OK && (j = cJSON_GetObjectItemCaseSensitive(it, "sky")))
        s = jvec3(c, j, "light.sky", R_NONNEG, &l->sky);
    if (s == FS_OK && (j = cJSON_GetObjectItemCaseSensitive(it, "comment")))
        s = jstring(c, j, "light.comment", &str);
    return s;
}

static fs_status parse_asset_specs(const jctx *c, const cJSON *arr, asset_spec *specs, int *n_out)
{
    char ip[64], got[64];
    if (!arr)
        return jfail(c, "assets", "missing (a scene needs at least one asset)");
    if (!cJSON_IsArray(arr))
        return jfail(c, "assets", "expected an array of assets, got %s", jgot(arr, got, sizeof got));
    int n = cJSON_GetArraySize(arr);
    if (n < 1 || n > MAX_SCENE_ASSETS)
        return jfail(c, "assets", "expected 1 to %d assets, got %d", MAX_SCENE_ASSETS, n);
    int i = 0;
    for (const cJSON *it = arr->child; it; it = it->next, i++) {
        jidx_path(ip, sizeof ip, "assets", i);
        *n_out = i + 1; /* so the caller frees what this entry allocated */
        fs_status s = parse_asset(c, it, ip, &specs[i]);
        if (s != FS_OK)
            return s;
        for (int j = 0; j < i; j++)
            if (strcmp(specs[j].name, specs[i].name) == 0)
                return jfail(c, ip, "duplicate asset name \"%s\" (also assets[%d]); give each a distinct \"name\"",
                             specs[i].name, j);
    }
    return FS_OK;
}

static fs_status parse_instances(const jctx *c, const cJSON *arr, const asset_spec *specs, int nspecs)
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

static fs_status load_assets(const jctx *c, asset_spec *specs, int n)
{
    gltf_begin_scene(); /* the per-scene pixel budget counts this scene's images */
    for (int i = 0; i < n; i++) {
        asset a = {0};
        fs_status s;
        if (specs[i].generator >= 0)
            s = k_generators[specs[i].generator].run(&specs[i].desc, &a);
        else
            s = gltf_load(specs[i].gltf_path, &a);
        if (s != FS_OK) {
            asset_free(&a);
            return s;
        }
        if (!a.name[0])
            snprintf(a.name, sizeof a.name, "%s", specs[i].name);
        if (scene_add_asset(c->sc, &a) != i) {
            asset_free(&a);
            log_error("%s: out of memory adding assets[%d]", c->file, i);
            return FS_ERR_NOMEM;
        }
    }
    return FS_OK;
}

/* Appends the distinct material names of the scene to `list` (for "no material named ..."). */
static void material_names(const scene *sc, char *list, size_t n)
{
    list[0] = '\0';
    bool first = true;
    for (int a = 0; a < sc->asset_count; a++)
        for (int m = 0; m < sc->assets[a].material_count; m++) {
            const char *name = sc->assets[a].materials[m].name;
            bool seen = false;
            for (int b = 0; b <= a && !seen; b++)
                for (int k = 0; k < (b == a ? m : sc->assets[b].material_count) && !seen; k++)
                    seen = strcmp(sc->assets[b].materials[k].name, name) == 0;
            if (seen)
                continue;
            size_t l = strlen(list);
            if (l + strlen(name) + 8 >= n) {
                snprintf(list + l, n - l, ", ...");
                return;
            }
            snprintf(list + l, n - l, "%s\"%s\"", first ? "" : ", ", name);
            first = false;
        }
}

/* Checks the "materials" overrides; with `apply`, also applies them to the loaded assets (and
 * reports a name that matches no material). */
static fs_status apply_materials(const jctx *c, const cJSON *obj, bool apply)
{
    static const char *const keys[] = {"alpha_mode", "alpha_cutoff", "double_sided", "comment", NULL};
    char got[64], mp[256], kp[300];
    scene *sc = c->sc;
    if (!cJSON_IsObject(obj))
        return jfail(c, "materials", "expected an object mapping material names to overrides, got %s",
                     jgot(obj, got, sizeof got));
    for (const cJSON *ov = obj->child; ov; ov = ov->next) {
        jkey_path(mp, sizeof mp, "materials", ov->string);
        for (const cJSON *prev = obj->child; prev != ov; prev = prev->next)
            if (strcmp(prev->string, ov->string) == 0)
                return jfail(c, mp, "duplicate key");
        fs_status s = jkeys(c, ov, mp, keys);
        if (s != FS_OK)
            return s;
        const cJSON *jmode_ = cJSON_GetObjectItemCaseSensitive(ov, "alpha_mode");
        const cJSON *jcut = cJSON_GetObjectItemCaseSensitive(ov, "alpha_cutoff");
        const cJSON *jds = cJSON_GetObjectItemCaseSensitive(ov, "double_sided");
        const cJSON *jcomment = cJSON_GetObjectItemCaseSensitive(ov, "comment");
        alpha_mode mode = ALPHA_MODE_DEFAULT;
        float cutoff = 0;
        bool ds = false;
        const char *str;
        if (jmode_ && (s = jmode(c, jmode_, jkey_path(kp, sizeof kp, mp, "alpha_mode"), &mode)) != FS_OK)
            return s;
        if (jcut && (s = jfloat(c, jcut, jkey_path(kp, sizeof kp, mp, "alpha_cutoff"), R_UNIT, &cutoff)) != FS_OK)
            return s;
        if (jds && (s = jbool(c, jds, jkey_path(kp, sizeof kp, mp, "double_sided"), &ds)) != FS_OK)
            return s;
        if (jcomment && (s = jstring(c, jcomment, jkey_path(kp, sizeof kp, mp, "comment"), &str)) != FS_OK)
            return s;
        if (!apply)
            continue;
        int matched = 0;
        for (int a = 0; a < sc->asset_count; a++)
            for (int m = 0; m < sc->assets[a].material_count; m++) {
                material *mat = &sc->assets[a].materials[m];
                if (strcmp(mat->name, ov->string) != 0)
                    continue;
                matched++;
                if (jmode_)
                    mat->alpha_mode = mode;
                if (jcut)
                    mat->alpha_cutoff = cutoff;
                if (jds)
                    mat->double_sided = ds;
            }
        if (!matched) {
            char list[512];
            material_names(sc, list, sizeof list);
            return jfail(c, mp, "no material named \"%s\" in any asset (materials are: %s)", ov->string,
                         list[0] ? list : "none");
        }
    }
    return FS_OK;
}

static fs_status parse_root(const jctx *c, const cJSON *root, asset_spec *specs)
{
    static const char *const keys[] = {"display", "alpha_mode", "light", "assets", "instances",
                                       "camera", "materials", "rings", "taa", "comment", NULL};
    char got[64];
    scene *sc = c->sc;
    const char *str;
    if (!cJSON_IsObject(root))
        return jfail(c, NULL, "expected a JSON object at the top level, got %s", jgot(root, got, sizeof got));
    fs_status s = jkeys(c, root, "", keys);
    if (s != FS_OK)
        return s;
    const cJSON *j;
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "comment")) && (s = jstring(c, j, "comment", &str)) != FS_OK)
        return s;
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "display")) && (s = parse_display(c, j)) != FS_OK)
        return s;
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "alpha_mode")) && (s = jmode(c, j, "alpha_mode", &sc->alpha_mode)) != FS_OK)
        return s;
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "light")) && (s = parse_light(c, j)) != FS_OK)
        return s;
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "taa"))) {
        static const char *const tkeys[] = {"enabled", "blend", "gamma", "sparse", "jitter_length", "comment", NULL};
        if ((s = jkeys(c, j, "taa", tkeys)) != FS_OK)
            return s;
        const cJSON *t;
        bool enabled = true;
        double v;
        sc->taa.given = true;
        if ((t = cJSON_GetObjectItemCaseSensitive(j, "enabled")) && (s = jbool(c, t, "taa.enabled", &enabled)) != FS_OK)
            return s;
        sc->taa.off = !enabled;
        if ((t = cJSON_GetObjectItemCaseSensitive(j, "blend"))) {
            if ((s = jnum(c, t, "taa.blend", (nrange){0, 1, true, false, false, false}, &v)) != FS_OK)
                return s;
            sc->taa.blend = (float)v;
        }
        if ((t = cJSON_GetObjectItemCaseSensitive(j, "gamma"))) {
            if ((s = jnum(c, t, "taa.gamma", (nrange){0, 16, true, false, false, false}, &v)) != FS_OK)
                return s;
            sc->taa.gamma = (float)v;
        }
        if ((t = cJSON_GetObjectItemCaseSensitive(j, "sparse"))) {
            if (cJSON_IsFalse(t))
                v = 0;
            else if ((s = jnum(c, t, "taa.sparse", (nrange){0, 1, false, false, false, false}, &v)) != FS_OK)
                return s;
            sc->taa.sparse = v > 0 ? (float)v : -1.0f;
        }
        if ((t = cJSON_GetObjectItemCaseSensitive(j, "jitter_length")) &&
            (s = jint(c, t, "taa.jitter_length", 1, 1024, &sc->taa.jitter_length)) != FS_OK)
            return s;
    }
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "rings"))) {
        /* A ring layout, checked now against the display parsed above (fov_ring.h). */
        if ((s = jstring(c, j, "rings", &str)) != FS_OK)
            return s;
        fov_layout l;
        char err[256];
        if (strlen(str) >= sizeof sc->rings || fov_layout_parse(str, &sc->display, &l, err, sizeof err) != FS_OK)
            return jfail(c, "rings", "expected \"auto\", \"off\" or a layout like \"10:1:0,25:1/2:0,*:1/4:0.5\" (%s)",
                         strlen(str) >= sizeof sc->rings ? "too long" : err);
        snprintf(sc->rings, sizeof sc->rings, "%s", str);
    }
    int nspecs = 0;
    s = parse_asset_specs(c, cJSON_GetObjectItemCaseSensitive(root, "assets"), specs, &nspecs);
    if (s == FS_OK)
        s = parse_instances(c, cJSON_GetObjectItemCaseSensitive(root, "instances"), specs, nspecs);
    const cJSON *jcam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    if (s == FS_OK && jcam)
        s = parse_camera(c, jcam);
    const cJSON *jmat = cJSON_GetObjectItemCaseSensitive(root, "materials");
    if (s == FS_OK && jmat)
        s = apply_materials(c, jmat, false); /* syntax errors before any asset is loaded */
    if (s == FS_OK)
        s = load_assets(c, specs, nspecs);
    if (s == FS_OK)
        resolve_sway_heights(sc);
    if (s == FS_OK && jmat)
        s = apply_materials(c, jmat, true);
    if (s == FS_OK && !jcam)
        scene_fit_camera(sc);
    return s;
}

/* >>entry */

/* `file:line: JSON syntax error near '...'`: the line from cJSON's error position, the excerpt a
 * little of that line around it (cJSON often stops one character past the culprit). */
static void syntax_error(const jctx *c, const char *text, size_t size, const char *at)
{
    if (!at || at < text || at > text + size)
        at = text + size;
    int line = 1;
    const char *line_start = text;
    for (const char *p = text; p < at; p++)
        if (*p == '\n') {
            line++;
            line_start = p + 1;
        }
    const char *from = at - 12 > line_start ? at - 12 : line_start;
    while (from < at && (*from == ' ' || *from == '\t'))
        from++;
    char near[40];
    size_t n = 0;
    for (const char *p = from; *p && *p != '\n' && *p != '\r' && n < 32; p++)
        near[n++] = (*p >= 0x20 && *p < 0x7f && *p != '\'') ? *p : '?';
    near[n] = '\0';
    if (n == 0)
        log_error("%s:%d: JSON syntax error near the end of the file", c->file, line);
    else
        log_error("%s:%d: JSON syntax error near '%s'", c->file, line, near);
}

fs_status scene_json_parse(const char *text, size_t size, const char *name, const char *base_dir,
                           scene *out)
{
    scene_init_defaults(out);
    snprintf(out->path, sizeof out->path, "%s", name);
    jctx c = {.file = name, .base_dir = base_dir, .sc = out};
    if (strlen(text) != size) {
        log_error("%s:%d: contains a NUL byte (not a text file?)", name, 1);
        scene_free(out);
        return FS_ERR_SCENE;
    }
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithOpts(text, &end, 1);
    if (!root) {
        syntax_error(&c, text, size, end);
        scene_free(out);
        return FS_ERR_SCENE;
    }
    asset_spec *specs = calloc(MAX_SCENE_ASSETS, sizeof *specs);
    fs_status s = specs ? parse_root(&c, root, specs) : FS_ERR_NOMEM;
    if (specs)
        for (int i = 0; i < MAX_SCENE_ASSETS; i++)
            free(specs[i].gltf_path);
    free(specs);
    cJSON_Delete(root);
    if (s != FS_OK) {
        scene_free(out);
        return s;
    }
    out->duration = out->camera.keys[out->camera.count - 1].time;
    log_info("SCENE: [%s] %d assets, %d instances, %d camera keys, %.2f s", out->path,
             out->asset_count, out->instance_count, out->camera.count, out->duration);
    return FS_OK;
}
