/* fuzz_scene_json.c: the scene-file parser (scene_json_parse over cJSON), as fovsim loads a scene:
 * parse (generators run, glTF assets load) then scene_validate, and the camera path evaluated.
 *
 * Input: the scene file's text, as is (a file fovsim would read). Relative glTF paths resolve
 * against this process's scratch folder (fuzz_common.h), which holds tri.gltf (one MASK triangle
 * "leaf" with buf.bin and tex.png, fuzz_assets.h), so a scene can load a real glTF asset: seed
 * corpus/scene_json/tri_every_key.json does. To run a file through fovsim itself, put it beside a
 * copy of those three files (`fovsim plan FILE`).
 * Checks beyond "no crash": a refused scene is freed (scene_free of it is a no-op); an accepted one
 * has assets, instances and 1.. camera keys, and its camera evaluates to finite values.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_assets.h"
#include "fuzz_common.h"
#include "scene/gltf_shim.h"
#include "scene/scene.h"
#include "scene/scene_json.h"

static bool finite3(vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_init();
    static bool ready;
    if (!ready) {
        fuzz_write_tmp("tri.gltf", k_tri_gltf, sizeof k_tri_gltf - 1);
        fuzz_write_tmp("buf.bin", k_buf_bin, sizeof k_buf_bin);
        fuzz_write_tmp("tex.png", k_tex_png, sizeof k_tex_png);
        gltf_set_pixel_budget((uint64_t)1 << 20, (uint64_t)4 << 20);
        ready = true;
    }
    /* As scene_load_file hands it over: size bytes plus a terminating NUL. */
    char *text = malloc(size + 1);
    FUZZ_CHECK(text != NULL);
    memcpy(text, data, size);
    text[size] = '\0';

    scene sc;
    memset(&sc, 0x5a, sizeof sc); /* the parser must not rely on a zeroed output */
    fs_status s = scene_json_parse(text, size, "fuzz.json", fuzz_tmp_dir(), &sc);
    free(text);
    if (s != FS_OK) {
        FUZZ_CHECK(sc.assets == NULL && sc.instances == NULL && sc.asset_count == 0);
        return 0;
    }
    FUZZ_CHECK(sc.asset_count >= 1 && sc.instance_count >= 1);
    FUZZ_CHECK(sc.camera.count >= 1 && sc.camera.count <= MAX_CAMERA_KEYS);
    if (scene_validate(&sc) == FS_OK) {
        const float t[] = {0.0f, 0.5f * sc.duration, sc.duration, sc.duration + 1.0f};
        for (size_t k = 0; k < sizeof t / sizeof t[0]; k++) {
            camera_state c = camera_path_eval(&sc.camera, t[k]);
            FUZZ_CHECK(finite3(c.position) && finite3(c.target) && isfinite(c.hfov_deg));
        }
        (void)camera_path_cut_between(&sc.camera, 0.0f, sc.duration);
        (void)scene_content_hash(&sc);
    }
    scene_free(&sc);
    return 0;
}
