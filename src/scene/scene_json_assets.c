/* scene_json_assets.c: the "assets" entries of a scene file: a generator with its parameters
 * (checked against each generator's table) or a glTF file, then loading them all in order. */
#include "scene/scene_json_internal.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/gltf_shim.h"

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
    const char *str;

    if ((s = jopt_comment(c, it, path)) != FS_OK)
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

fs_status scene_json_parse_asset_specs(const jctx *c, const cJSON *arr, asset_spec *specs, int *n_out)
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

fs_status scene_json_load_assets(const jctx *c, asset_spec *specs, int n)
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
