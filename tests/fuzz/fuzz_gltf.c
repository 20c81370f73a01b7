/* fuzz_gltf.c: the glTF loader (gltf_shim.cpp over tinygltf and stb_image), as fovsim loads a
 * .gltf/.glb given on the command line: scene_load_file (glTF as a scene: gltf_load, camera) then
 * scene_validate.
 *
 * Input: one selector byte, then the file. gltf_load takes a path, so the file is written to this
 * process's scratch folder (fuzz_common.h; /dev/shm, one file reused every run) as in.gltf when the
 * selector's low bit is 0, in.glb when it is 1 (the "glTF" magic also makes a .gltf load as binary),
 * and removed after the load.
 * The folder also holds buf.bin and tex.png (fuzz_assets.h), so relative URIs that name them load;
 * any other URI is refused or missing, as the URI rule says.
 * To run a file through fovsim itself: `tail -c +2 FILE > x.gltf` (or x.glb), `fovsim render x.gltf`.
 * The pixel budget is lowered to 1 Mpixel per image so that each run stays fast; the checks against
 * it run the same as at the default.
 */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz_assets.h"
#include "fuzz_common.h"
#include "scene/gltf_shim.h"
#include "scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_init();
    static bool ready;
    if (!ready) {
        fuzz_write_tmp("buf.bin", k_buf_bin, sizeof k_buf_bin);
        fuzz_write_tmp("tex.png", k_tex_png, sizeof k_tex_png);
        gltf_set_pixel_budget((uint64_t)1 << 20, (uint64_t)4 << 20);
        ready = true;
    }
    if (size < 1)
        return 0;
    const char *path = fuzz_write_tmp(data[0] & 1 ? "in.glb" : "in.gltf", data + 1, size - 1);
    scene sc;
    memset(&sc, 0x5a, sizeof sc); /* the loader must not rely on a zeroed output */
    fs_status s = scene_load_file(path, &sc);
    if (s == FS_OK) {
        FUZZ_CHECK(sc.asset_count == 1 && sc.instance_count == 1 && sc.camera.count >= 1);
        (void)scene_validate(&sc);
    } else {
        FUZZ_CHECK(s == FS_ERR_ASSET || s == FS_ERR_IO || s == FS_ERR_NOMEM);
    }
    scene_free(&sc);
    unlink(path); /* the next input must not see this one (as in.gltf or in.glb, or via a URI) */
    return 0;
}
