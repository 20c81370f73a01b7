/* scene_load.c: a scene from a file (scene JSON, or a .gltf/.glb asset on its own) or a built-in
 * name. The top of the scene folder: it calls the JSON parser (scene_json.c) and the glTF shim,
 * which build the scene through scene.c; nothing below calls back up into it.
 */
#include "scene/scene.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/embedded.h"
#include "core/file_read.h"
#include "core/log.h"
#include "scene/gltf_shim.h"
#include "scene/scene_json.h"

static bool has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    if (n < e)
        return false;
    for (size_t i = 0; i < e; i++)
        if (tolower((unsigned char)path[n - e + i]) != ext[i])
            return false;
    return true;
}

/* A glTF file as a scene: the asset at the origin, default light and display, its own camera if
 * it has one, else scene_fit_camera. */
static fs_status load_gltf_scene(const char *path, scene *out)
{
    scene_init_defaults(out);
    snprintf(out->path, sizeof out->path, "%s", path);
    asset a = {0};
    gltf_begin_scene();
    fs_status s = gltf_load(path, &a);
    if (s != FS_OK) {
        asset_free(&a);
        scene_free(out);
        return s;
    }
    camera_key own = {0};
    bool has_camera = a.camera.present && isfinite(a.camera.position.x) && isfinite(a.camera.position.y) &&
                      isfinite(a.camera.position.z) && isfinite(a.camera.target.x) &&
                      isfinite(a.camera.target.y) && isfinite(a.camera.target.z) &&
                      v3_len(v3_sub(a.camera.target, a.camera.position)) > 1e-6f;
    if (a.camera.present && !has_camera)
        log_warn("%s: its camera's position or direction is not finite (or it looks at itself); a camera fitted to "
                 "the asset is used instead", path);
    if (has_camera) {
        own.position = a.camera.position;
        own.target = a.camera.target;
        /* fovsim draws horizontal fields of view in (1, 179) degrees (a scene file's outside is
         * refused); the asset's camera outside keeps its place and takes the display's, said aloud
         * rather than drawn with a degenerate projection. */
        own.hfov_deg = a.camera.hfov_deg > 1 && a.camera.hfov_deg < 179 ? a.camera.hfov_deg : 0;
        if (own.hfov_deg == 0)
            log_warn("%s: its camera's horizontal field of view, %.6g degrees, is not in (1, 179); the display's "
                     "%.6g degrees is used instead", path, (double)a.camera.hfov_deg, (double)out->display.hfov_deg);
    }
    if (scene_add_asset(out, &a) != 0 || !scene_add_instance(out, 0, m4_identity())) {
        asset_free(&a);
        scene_free(out);
        log_error("%s: out of memory", path);
        return FS_ERR_NOMEM;
    }
    if (has_camera) {
        out->camera.count = 1;
        out->camera.keys[0] = own;
        out->duration = 0;
    } else {
        scene_fit_camera(out);
    }
    log_info("SCENE: [%s] glTF as a scene, %s camera", path, has_camera ? "its own" : "fitted");
    return FS_OK;
}

fs_status scene_load_file(const char *path, scene *out)
{
    if (has_ext(path, ".gltf") || has_ext(path, ".glb"))
        return load_gltf_scene(path, out);

    memset(out, 0, sizeof *out);
    char *text;
    size_t size;
    fs_status rs = file_read_all(path, MAX_SCENE_FILE_BYTES, "a scene file", FS_ERR_SCENE, &text, &size);
    if (rs != FS_OK)
        return rs;

    /* Relative glTF paths resolve against the scene file's directory. */
    char dir[4096];
    const char *slash = strrchr(path, '/');
    if (slash && (size_t)(slash - path) < sizeof dir)
        snprintf(dir, sizeof dir, "%.*s", (int)(slash == path ? 1 : slash - path), path);
    else
        dir[0] = '\0';
    fs_status s = scene_json_parse(text, size, path, dir, out);
    free(text);
    return s;
}

static const char *const k_builtin_names[] = {"forest", "fence", "tree", "grass", "wind"};

const char *scene_builtin_list(void) { return "forest fence tree grass wind"; }

bool scene_is_builtin(const char *name)
{
    for (size_t i = 0; name && i < sizeof k_builtin_names / sizeof k_builtin_names[0]; i++)
        if (strcmp(name, k_builtin_names[i]) == 0)
            return true;
    return false;
}

fs_status scene_load_builtin(const char *name, scene *out)
{
    memset(out, 0, sizeof *out);
    bool known = false;
    for (size_t i = 0; i < sizeof k_builtin_names / sizeof k_builtin_names[0]; i++)
        known = known || (name && strcmp(name, k_builtin_names[i]) == 0);
    if (!known) {
        log_error("SCENE: unknown built-in scene \"%s\" (built-in scenes are: %s)", name ? name : "(null)",
                  scene_builtin_list());
        return FS_ERR_SCENE;
    }
    char file[128], label[128];
    snprintf(file, sizeof file, "scenes/builtin/%s.json", name);
    snprintf(label, sizeof label, "builtin:%s", name);
    const embedded_file *ef = embedded_find(file);
    if (!ef) {
        log_error("SCENE: %s is not embedded in this binary (a build problem)", file);
        return FS_ERR_INTERNAL;
    }
    return scene_json_parse(ef->data, ef->size, label, NULL, out);
}

