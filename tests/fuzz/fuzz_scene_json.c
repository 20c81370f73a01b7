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
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_assets.h"
#include "fuzz_common.h"
#include "scene/gltf_shim.h"
#include "scene/scene.h"
#include "scene/scene_json.h"

static bool finite3(vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/* Legal but costly: the documented limits let a small scene ask for seconds of generator work
 * under ASan (measured here: a tree with texture_size 4096, 17 s, 4.4 s in the release build; 12
 * generators at 4096, 44 s and 1.1 GB in the release build; 100,000 cards, fronds or scattered
 * instances, 2-4 s; a 100 km fence, 1.3 s). libFuzzer would report them as timeouts and
 * out-of-memory again and again; they are known (tests/fuzz/README.md, "Known costs"), so an input
 * is skipped when, anywhere in it, a texture_size is over 512, the texture_size^2 add up to more
 * than 2 M texels, card_count + frond_count + count to more than 20,000, or the lengths to more
 * than 10 km. The document is read with cJSON as the parser reads it, escapes decoded. */
typedef struct cost {
    double texels, counts, length;
    bool big_texture;
} cost;

static void add_cost(const cJSON *j, cost *c)
{
    for (const cJSON *it = j ? j->child : NULL; it; it = it->next) {
        if (it->string && cJSON_IsNumber(it)) {
            const double v = fabs(it->valuedouble);
            if (strcmp(it->string, "texture_size") == 0) {
                c->big_texture = c->big_texture || v > 512;
                c->texels += v * v;
            } else if (strcmp(it->string, "card_count") == 0 || strcmp(it->string, "frond_count") == 0 ||
                       strcmp(it->string, "count") == 0) {
                c->counts += v;
            } else if (strcmp(it->string, "length") == 0) {
                c->length += v;
            }
        }
        add_cost(it, c);
    }
}

static bool too_costly(const char *text)
{
    cJSON *root = cJSON_Parse(text);
    if (!root)
        return false; /* the parser refuses it too, quickly */
    cost c = {0};
    add_cost(root, &c);
    cJSON_Delete(root);
    return c.big_texture || c.texels > 2e6 || c.counts > 20000 || c.length > 10000;
}

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
    if (too_costly(text)) {
        free(text);
        return 0;
    }

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
