/* scene_json.c: JSON scene files -> struct scene (format: docs/scene-format.md).
 *
 * The document is read in three phases so that cheap mistakes are reported before any glTF file
 * is loaded: (1) check display, light, every asset description, every instance and the camera
 * path; (2) load the assets in order; (3) apply the per-material overrides, which need the loaded
 * materials. Messages name the document and the JSON path of the offending value.
 */
#include "scene/scene_json.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/shared_defs.h"
#include "core/log.h"
#include "fov/fov_ring.h"
#include "fov/ring_lod.h"
#include "scene/scene_json_internal.h"

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
        if ((s = jopt_comment(c, it, ip)) != FS_OK)
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

/* "fov_left"/"fov_right": four angles in degrees [left, right, up, down], signed as OpenXR's XrFovf. */
static fs_status parse_hmd_fov(const jctx *c, const cJSON *obj, const char *key, hmd_fov *out, bool *given)
{
    static const nrange r_angle = {-HMD_ANGLE_MAX_DEG, HMD_ANGLE_MAX_DEG, false, false, false, false};
    char kp[JPATH_MAX], ip[JPATH_MAX], got[64];
    const cJSON *arr = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!arr)
        return FS_OK;
    jkey_path(kp, sizeof kp, "display", key);
    if (!cJSON_IsArray(arr) || cJSON_GetArraySize(arr) != 4)
        return jfail(c, kp, "expected [left, right, up, down] in degrees, got %s", jgot(arr, got, sizeof got));
    double deg[4];
    for (int i = 0; i < 4; i++) {
        fs_status s = jnum(c, cJSON_GetArrayItem(arr, i), jidx_path(ip, sizeof ip, kp, i), r_angle, &deg[i]);
        if (s != FS_OK)
            return s;
    }
    if (!hmd_fov_from_deg(deg, out))
        return jfail(c, kp, "expected left < right and down < up (degrees, left and down negative)");
    *given = true;
    return FS_OK;
}

/* An hmd display (docs/hmd.md "The display"): a preset and the keys of --display hmd:... */
static fs_status parse_hmd(const jctx *c, const cJSON *it)
{
    static const char *const keys[] = {"kind", "preset", "width", "height", "ipd", "hz", "fov_left",
                                       "fov_right", "comment", NULL};
    static const nrange r_ipd = {HMD_IPD_MIN_MM, HMD_IPD_MAX_MM, false, false, false, false};
    static const nrange r_hz = {HMD_HZ_MIN, HMD_HZ_MAX, false, false, false, false};
    hmd_keys k = {0};
    const char *preset = NULL;
    char err[320];
    fs_status s = jkeys(c, it, "display", keys);
    const cJSON *jp = cJSON_GetObjectItemCaseSensitive(it, "preset");
    if (s == FS_OK && !jp)
        return jfail(c, "display", "missing \"preset\" (an hmd display starts from one of: %s)", hmd_preset_list());
    if (s == FS_OK)
        s = jstring(c, jp, "display.preset", &preset);
    if (s == FS_OK)
        s = jopt_int(c, it, "display", "width", 16, MAX_DISPLAY_SIZE, &k.width);
    if (s == FS_OK)
        s = jopt_int(c, it, "display", "height", 16, MAX_DISPLAY_SIZE, &k.height);
    if (s == FS_OK)
        s = jopt_float(c, it, "display", "ipd", r_ipd, &k.ipd_mm);
    if (s == FS_OK)
        s = jopt_float(c, it, "display", "hz", r_hz, &k.refresh_hz);
    if (s == FS_OK)
        s = parse_hmd_fov(c, it, "fov_left", &k.fov[HMD_LEFT], &k.fov_given[HMD_LEFT]);
    if (s == FS_OK)
        s = parse_hmd_fov(c, it, "fov_right", &k.fov[HMD_RIGHT], &k.fov_given[HMD_RIGHT]);
    if (s == FS_OK)
        s = jopt_comment(c, it, "display");
    if (s == FS_OK && !hmd_make(preset, &k, &c->sc->hmd, err, sizeof err))
        return jfail(c, "display", "%s", err);
    if (s == FS_OK)
        c->sc->display_kind = DISPLAY_HMD;
    return s;
}

static fs_status parse_display(const jctx *c, const cJSON *it)
{
    static const char *const keys[] = {"kind", "width", "height", "hfov", "comment", NULL};
    display_desc *d = &c->sc->display;
    const cJSON *kind = cJSON_IsObject(it) ? cJSON_GetObjectItemCaseSensitive(it, "kind") : NULL;
    const char *k = "planar";
    fs_status s = kind ? jstring(c, kind, "display.kind", &k) : FS_OK;
    if (s != FS_OK)
        return s;
    if (!strcmp(k, "hmd"))
        return parse_hmd(c, it);
    if (strcmp(k, "planar") != 0)
        return jfail(c, "display.kind", "expected \"planar\" or \"hmd\", got \"%s\"", k);
    s = jkeys(c, it, "display", keys);
    if (s == FS_OK)
        s = jopt_int(c, it, "display", "width", 16, MAX_DISPLAY_SIZE, &d->width);
    if (s == FS_OK)
        s = jopt_int(c, it, "display", "height", 16, MAX_DISPLAY_SIZE, &d->height);
    if (s == FS_OK)
        s = jopt_float(c, it, "display", "hfov", R_HFOV, &d->hfov_deg);
    if (s == FS_OK)
        s = jopt_comment(c, it, "display");
    return s;
}

static fs_status parse_light(const jctx *c, const cJSON *it)
{
    static const char *const keys[] = {"direction", "color", "ambient", "sky", "comment", NULL};
    light_desc *l = &c->sc->light;
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
    if (s == FS_OK)
        s = jopt_vec3(c, it, "light", "color", R_NONNEG, &l->color);
    if (s == FS_OK)
        s = jopt_vec3(c, it, "light", "ambient", R_NONNEG, &l->ambient);
    if (s == FS_OK)
        s = jopt_vec3(c, it, "light", "sky", R_NONNEG, &l->sky);
    if (s == FS_OK)
        s = jopt_comment(c, it, "light");
    return s;
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
    static const char *const keys[] = {"alpha_mode", "alpha_cutoff", "double_sided", "alpha_lod_max", "comment", NULL};
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
        const cJSON *jlod = cJSON_GetObjectItemCaseSensitive(ov, "alpha_lod_max");
        alpha_mode mode = ALPHA_MODE_DEFAULT;
        float cutoff = 0, lod_max = 0;
        bool ds = false;
        if (jmode_ && (s = jmode(c, jmode_, jkey_path(kp, sizeof kp, mp, "alpha_mode"), &mode)) != FS_OK)
            return s;
        if (jcut && (s = jfloat(c, jcut, jkey_path(kp, sizeof kp, mp, "alpha_cutoff"), R_UNIT, &cutoff)) != FS_OK)
            return s;
        if (jds && (s = jbool(c, jds, jkey_path(kp, sizeof kp, mp, "double_sided"), &ds)) != FS_OK)
            return s;
        /* A mip level (docs/hashed-alpha.md "Alpha LOD clamp"). */
        if (jlod && (s = jfloat(c, jlod, jkey_path(kp, sizeof kp, mp, "alpha_lod_max"),
                                (nrange){0, ALPHA_LOD_MAX_LIMIT, false, false, false, false}, &lod_max)) != FS_OK)
            return s;
        if ((s = jopt_comment(c, ov, mp)) != FS_OK)
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
                if (jlod) {
                    mat->has_alpha_lod_max = true;
                    mat->alpha_lod_max = lod_max;
                }
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

/* "gaze": "map" and "screen", the CLI's --gaze-map and --gaze-screen (gaze.h, gaze_place). */
static fs_status parse_gaze_place(const jctx *c, const cJSON *j)
{
    gaze_place_opts *o = &c->sc->gaze_place;
    const cJSON *it;
    const char *str;
    fs_status s;
    if ((it = cJSON_GetObjectItemCaseSensitive(j, "map"))) {
        if ((s = jstring(c, it, "gaze.map", &str)) != FS_OK)
            return s;
        o->map_set = true;
        if (strcmp(str, "angle") != 0 && strcmp(str, "normalized") != 0)
            return jfail(c, "gaze.map", "expected \"angle\" or \"normalized\", got \"%s\"", str);
        o->desc.map = strcmp(str, "angle") == 0 ? GAZE_MAP_ANGLE : GAZE_MAP_NORMALIZED;
    }
    if ((it = cJSON_GetObjectItemCaseSensitive(j, "screen"))) {
        char err[256];
        if ((s = jstring(c, it, "gaze.screen", &str)) != FS_OK)
            return s;
        o->screen_set = true;
        if (!gaze_screen_parse(str, &o->desc.screen, err, sizeof err))
            return jfail(c, "gaze.screen", "%s", err);
    }
    return FS_OK;
}

/* "gaze": the eye tracker between the true gaze and the renderer (gaze_tracker.h), the keys of the
 * CLI's --gaze-latency, --gaze-rate, --gaze-noise, --gaze-seed and --gaze-loss. */
static fs_status parse_gaze_tracker(const jctx *c, const cJSON *j)
{
    static const char *const keys[] = {"latency", "rate", "noise", "seed", "loss", "map", "screen", "comment", NULL};
    gaze_tracker_opts *o = &c->sc->tracker;
    fs_status s = jkeys(c, j, "gaze", keys);
    const cJSON *it;
    const char *str;
    double seed = 0;
    if (s == FS_OK && (o->latency_set = cJSON_GetObjectItemCaseSensitive(j, "latency") != NULL))
        s = jopt_float(c, j, "gaze", "latency", (nrange){0, GAZE_TRACKER_MAX_LATENCY_MS, false, false, false, false},
                       &o->desc.latency_ms);
    if (s == FS_OK && (o->rate_set = cJSON_GetObjectItemCaseSensitive(j, "rate") != NULL))
        s = jopt_float(c, j, "gaze", "rate", (nrange){0, GAZE_TRACKER_MAX_RATE_HZ, false, false, false, false},
                       &o->desc.rate_hz);
    if (s == FS_OK && (o->noise_set = cJSON_GetObjectItemCaseSensitive(j, "noise") != NULL))
        s = jopt_float(c, j, "gaze", "noise", (nrange){0, GAZE_TRACKER_MAX_NOISE_DEG, false, false, false, false},
                       &o->desc.noise_deg);
    if (s == FS_OK && (o->seed_set = cJSON_GetObjectItemCaseSensitive(j, "seed") != NULL)) {
        s = jopt_num(c, j, "gaze", "seed", (nrange){0, 2147483647.0, false, false, true, false}, &seed);
        o->desc.seed = (uint32_t)seed;
    }
    if (s == FS_OK && (it = cJSON_GetObjectItemCaseSensitive(j, "loss"))) {
        if ((s = jstring(c, it, "gaze.loss", &str)) != FS_OK)
            return s;
        o->loss_set = true;
        o->desc.loss = gaze_loss_parse(str);
        if (o->desc.loss == GAZE_LOSS_COUNT)
            return jfail(c, "gaze.loss", "expected \"hold\", \"centre\" or \"full\", got \"%s\"", str);
    }
    return s == FS_OK ? parse_gaze_place(c, j) : s;
}

/* "foveation", "vrs" and "vrs_tile" (vrs_map.h). "vrs" and "vrs_tile" may stand without
 * "foveation": "vrs" (they shape VRS when --foveation vrs chooses it); "foveation": "off" with a
 * "rings" layout other than "off" contradicts itself. */
static fs_status parse_foveation(const jctx *c, const cJSON *root)
{
    scene *sc = c->sc;
    const char *str;
    const cJSON *j;
    fs_status s = FS_OK;
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "foveation"))) {
        if ((s = jstring(c, j, "foveation", &str)) != FS_OK)
            return s;
        if (!foveation_kind_parse(str, &sc->foveation))
            return jfail(c, "foveation", "expected \"rings\", \"vrs\" or \"off\", got \"%s\"", str);
        if (sc->foveation == FOVEATION_OFF && sc->rings[0] && sc->rings_layout.kind != FOV_LAYOUT_OFF)
            return jfail(c, "foveation", "\"off\" contradicts \"rings\": \"%s\" (give one of them)", sc->rings);
    }
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "vrs"))) {
        if ((s = jstring(c, j, "vrs", &str)) != FS_OK)
            return s;
        char err[256];
        if (strlen(str) >= sizeof sc->vrs || vrs_spec_parse(str, &sc->vrs_spec, err, sizeof err) != FS_OK)
            return jfail(c, "vrs", "expected \"auto\" or a rate map like \"10:1x1,25:2x2,*:4x4\" (%s)",
                         strlen(str) >= sizeof sc->vrs ? "too long" : err);
        snprintf(sc->vrs, sizeof sc->vrs, "%s", str);
    }
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "vrs_tile"))) {
        if ((s = jint(c, j, "vrs_tile", 8, 32, &sc->vrs_tile)) != FS_OK)
            return s;
        if (!vrs_tile_valid(sc->vrs_tile))
            return jfail(c, "vrs_tile", "expected 8, 16 or 32 (pixels), got %d", sc->vrs_tile);
    }
    return s;
}

static fs_status parse_root(const jctx *c, const cJSON *root, asset_spec *specs)
{
    static const char *const keys[] = {"display", "alpha_mode", "light", "assets", "instances",
                                       "camera", "materials", "rings", "ring_lod", "foveation", "vrs", "vrs_tile",
                                       "taa", "gaze", "comment", NULL};
    char got[64];
    scene *sc = c->sc;
    const char *str;
    if (!cJSON_IsObject(root))
        return jfail(c, NULL, "expected a JSON object at the top level, got %s", jgot(root, got, sizeof got));
    fs_status s = jkeys(c, root, "", keys);
    if (s != FS_OK)
        return s;
    const cJSON *j;
    if ((s = jopt_comment(c, root, "")) != FS_OK)
        return s;
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "display")) && (s = parse_display(c, j)) != FS_OK)
        return s;
    if ((s = jopt_mode(c, root, "", "alpha_mode", &sc->alpha_mode)) != FS_OK)
        return s;
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "light")) && (s = parse_light(c, j)) != FS_OK)
        return s;
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "taa"))) {
        static const char *const tkeys[] = {"enabled", "blend", "gamma", "sparse", "jitter_length", "comment", NULL};
        if ((s = jkeys(c, j, "taa", tkeys)) != FS_OK)
            return s;
        const cJSON *t;
        bool enabled = true;
        sc->taa.given = true;
        if ((s = jopt_bool(c, j, "taa", "enabled", &enabled)) != FS_OK)
            return s;
        sc->taa.off = !enabled;
        if ((s = jopt_float(c, j, "taa", "blend", (nrange){0, 1, true, false, false, false}, &sc->taa.blend)) != FS_OK)
            return s;
        if ((s = jopt_float(c, j, "taa", "gamma", (nrange){0, 16, true, false, false, false}, &sc->taa.gamma)) != FS_OK)
            return s;
        if ((t = cJSON_GetObjectItemCaseSensitive(j, "sparse"))) {
            float f = 0.0f; /* checked as the float it is used as: 1e-300 is not 0 ("off") */
            if (!cJSON_IsFalse(t) &&
                (s = jfloat(c, t, "taa.sparse", (nrange){0, 1, false, false, false, false}, &f)) != FS_OK)
                return s;
            sc->taa.sparse = f > 0 ? f : -1.0f;
        }
        if ((s = jopt_int(c, j, "taa", "jitter_length", 1, 1024, &sc->taa.jitter_length)) != FS_OK)
            return s;
    }
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "gaze"))) {
        if (!cJSON_IsObject(j))
            return jfail(c, "gaze", "expected an object {\"latency\", \"rate\", \"noise\", \"seed\", \"loss\", \"map\", "
                         "\"screen\"}, got %s",
                         jgot(j, got, sizeof got));
        if ((s = parse_gaze_tracker(c, j)) != FS_OK)
            return s;
    }
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "rings"))) {
        /* A ring layout, checked now against the display parsed above (fov_ring.h). */
        if ((s = jstring(c, j, "rings", &str)) != FS_OK)
            return s;
        char err[256];
        if (strlen(str) >= sizeof sc->rings ||
            fov_layout_parse(str, &sc->display, &sc->rings_layout, err, sizeof err) != FS_OK)
            return jfail(c, "rings", "expected \"auto\", \"off\" or a layout like \"10:1:0,25:1/2:0,*:1/4:0.5\" (%s)",
                         strlen(str) >= sizeof sc->rings ? "too long" : err);
        snprintf(sc->rings, sizeof sc->rings, "%s", str);
    }
    if ((s = parse_foveation(c, root)) != FS_OK)
        return s;
    if ((j = cJSON_GetObjectItemCaseSensitive(root, "ring_lod"))) {
        /* Ring LOD (ring_lod.h): the form now; one keep fraction per ring once the layout is known. */
        if ((s = jstring(c, j, "ring_lod", &str)) != FS_OK)
            return s;
        ring_lod_spec spec;
        char err[256];
        if (strlen(str) >= sizeof sc->ring_lod || ring_lod_parse(str, &spec, err, sizeof err) != FS_OK)
            return jfail(c, "ring_lod", "expected \"off\", \"simplify\", \"simplify:area=A\" or \"simplify:U1,U2,...\" (%s)",
                         strlen(str) >= sizeof sc->ring_lod ? "too long" : err);
        snprintf(sc->ring_lod, sizeof sc->ring_lod, "%s", str);
    }
    int nspecs = 0;
    s = scene_json_parse_asset_specs(c, cJSON_GetObjectItemCaseSensitive(root, "assets"), specs, &nspecs);
    if (s == FS_OK)
        s = scene_json_parse_instances(c, cJSON_GetObjectItemCaseSensitive(root, "instances"), specs, nspecs);
    const cJSON *jcam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    if (s == FS_OK && jcam)
        s = parse_camera(c, jcam);
    const cJSON *jmat = cJSON_GetObjectItemCaseSensitive(root, "materials");
    if (s == FS_OK && jmat)
        s = apply_materials(c, jmat, false); /* syntax errors before any asset is loaded */
    if (s == FS_OK)
        s = scene_json_load_assets(c, specs, nspecs);
    if (s == FS_OK)
        scene_json_resolve_sway_heights(sc);
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

/* Where cJSON stopped on a document nested deeper than CJSON_NESTING_LIMIT arrays and objects
 * (it fails at the '[' or '{' one level too deep and says no more than at a syntax error), the line
 * of that bracket; 0 when the text up to `at` is not that deep. Brackets inside strings do not count. */
static int too_deep_line(const char *text, const char *at)
{
    int depth = 0, line = 1;
    bool in_string = false;
    for (const char *p = text; *p && p <= at; p++) {
        if (*p == '\n')
            line++;
        if (in_string) {
            if (*p == '\\' && p[1])
                p++;
            else if (*p == '"')
                in_string = false;
        } else if (*p == '"') {
            in_string = true;
        } else if (*p == '[' || *p == '{') {
            if (++depth > CJSON_NESTING_LIMIT)
                return line;
        } else if (*p == ']' || *p == '}') {
            depth--;
        }
    }
    return 0;
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
        int deep = end ? too_deep_line(text, end) : 0;
        if (deep)
            log_error("%s:%d: arrays and objects nested deeper than %d (cJSON's limit); expected a scene file",
                      name, deep, CJSON_NESTING_LIMIT);
        else
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
