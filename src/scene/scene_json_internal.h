/* scene_json_internal.h: what the files of the scene-file parser share (internal to src/scene/;
 * the public contract is scene_json.h).
 *
 * scene_json.c reads the document (top level, display, light, taa, rings, camera, materials) and
 * runs the three phases; scene_json_values.c holds the value readers declared here (every message
 * names the document and the JSON path); scene_json_assets.c the "assets" entries (generator
 * parameters, glTF paths) and their loading; scene_json_instances.c the "instances" entries
 * (placement, scatter, sway).
 */
#ifndef FOVSIM_SCENE_JSON_INTERNAL_H
#define FOVSIM_SCENE_JSON_INTERNAL_H

#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "core/log.h"
#include "scene/generators.h"
#include "scene/scene.h"

/* >>context */

typedef struct jctx {
    const char *file;     /* document name for messages */
    const char *base_dir; /* NULL: no files allowed (built-in scene) */
    scene *sc;
} jctx;

fs_status jfail(const jctx *c, const char *path, const char *fmt, ...) FS_PRINTF(3, 4);
/* "parent.key" (or "key" at the top level). */
const char *jkey_path(char *buf, size_t n, const char *parent, const char *key);
/* "parent[i]". */
const char *jidx_path(char *buf, size_t n, const char *parent, int i);
/* What a value is, for "got ..." in messages. */
const char *jgot(const cJSON *it, char *buf, size_t n);
/* Checks that `obj` is an object whose keys are all in `allowed` (NULL-terminated), once each. */
fs_status jkeys(const jctx *c, const cJSON *obj, const char *path, const char *const *allowed);

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
/* A generator's or a scatter's seed. */
#define R_SEED ((nrange){0, 4294967295.0, false, false, true, false})

fs_status jnum(const jctx *c, const cJSON *it, const char *path, nrange r, double *out);
fs_status jfloat(const jctx *c, const cJSON *it, const char *path, nrange r, float *out);
fs_status jint(const jctx *c, const cJSON *it, const char *path, int lo, int hi, int *out);
fs_status jbool(const jctx *c, const cJSON *it, const char *path, bool *out);
fs_status jstring(const jctx *c, const cJSON *it, const char *path, const char **out);
/* An array of exactly 3 numbers, each in r. */
fs_status jvec3(const jctx *c, const cJSON *it, const char *path, nrange r, vec3 *out);
fs_status jmode(const jctx *c, const cJSON *it, const char *path, alpha_mode *out);

/* >>optional members: the member `key` of the object obj whose path is `parent` ("" at the top
 * level), read by the reader of the same name above with the path "parent.key" (at most
 * JPATH_MAX - 1 characters) when present; absent, *out is left as it is and the result is FS_OK.
 * jopt_comment: a "comment" member, when present, is a string (its text is not kept). */
enum { JPATH_MAX = 300 };
fs_status jopt_num(const jctx *c, const cJSON *obj, const char *parent, const char *key, nrange r, double *out);
fs_status jopt_float(const jctx *c, const cJSON *obj, const char *parent, const char *key, nrange r, float *out);
fs_status jopt_int(const jctx *c, const cJSON *obj, const char *parent, const char *key, int lo, int hi, int *out);
fs_status jopt_bool(const jctx *c, const cJSON *obj, const char *parent, const char *key, bool *out);
fs_status jopt_vec3(const jctx *c, const cJSON *obj, const char *parent, const char *key, nrange r, vec3 *out);
fs_status jopt_mode(const jctx *c, const cJSON *obj, const char *parent, const char *key, alpha_mode *out);
fs_status jopt_comment(const jctx *c, const cJSON *obj, const char *parent);

/* >>assets (scene_json_assets.c) */

typedef union gen_desc {
    gen_tree_desc tree;
    gen_grass_desc grass;
    gen_fence_desc fence;
    gen_fern_desc fern;
} gen_desc;

/* One entry of "assets", checked but not loaded yet. */
typedef struct asset_spec {
    char name[128];
    int generator;   /* GEN_*, or -1 for glTF */
    gen_desc desc;
    char *gltf_path; /* resolved path, owned */
} asset_spec;

/* Checks the "assets" array into specs[0..*n_out) (phase 1; nothing is loaded). */
fs_status scene_json_parse_asset_specs(const jctx *c, const cJSON *arr, asset_spec *specs, int *n_out);
/* Runs the generators and loads the glTF files of specs[0..n), adding each asset to the scene in
 * order (phase 2). */
fs_status scene_json_load_assets(const jctx *c, asset_spec *specs, int n);

/* >>instances (scene_json_instances.c) */

/* Checks the "instances" array and places every instance (phase 1). */
fs_status scene_json_parse_instances(const jctx *c, const cJSON *arr, const asset_spec *specs, int nspecs);
/* Sway heights left at 0 become the asset's top (once the assets are loaded). */
void scene_json_resolve_sway_heights(scene *sc);

#endif
