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
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz_assets.h"
#include "fuzz_common.h"
#include "scene/gltf_shim.h"
#include "scene/scene.h"

/* Legal but costly: an accessor without a bufferView is all zeros, and fovsim accepts up to 2^24
 * elements of it (a 200-byte file with one such POSITION: 11 s and 1.5 GB in the release build, 13 s
 * here); the flattener copies a mesh for every node that uses it. libFuzzer would report such files
 * as timeouts or out-of-memory again and again; they are known (tests/fuzz/README.md, "Known
 * costs"), so an input is skipped when a bound on the vertices it could make is over 2 M: the
 * largest "count" times the number of "attributes" objects (primitives) times the number of "mesh"
 * references (nodes), read from the JSON outside strings (the GLB's JSON chunk). Keys spelled with
 * \u escapes are not recognised: a fuzzer is unlikely to find one. */
static bool too_costly(const uint8_t *d, size_t n, bool binary)
{
    if (binary) { /* 12-byte header, then chunk 0 (length, type) holds the JSON */
        if (n < 20)
            return false;
        uint32_t len;
        memcpy(&len, d + 12, 4);
        d += 20;
        n = len < n - 20 ? len : n - 20;
    }
    double max_count = 1, prims = 0, refs = 0;
    char key[16] = "";
    bool after_key = false;
    for (size_t i = 0; i < n; i++) {
        if (d[i] == '"') { /* a string: a key when ':' follows */
            size_t b = ++i;
            while (i < n && d[i] != '"')
                i += d[i] == '\\' ? 2 : 1;
            size_t e = i < n ? i : n, j = i + 1;
            while (j < n && (d[j] == ' ' || d[j] == '\t' || d[j] == '\n' || d[j] == '\r'))
                j++;
            after_key = j < n && d[j] == ':';
            if (after_key) {
                size_t k = e - b < sizeof key - 1 ? e - b : sizeof key - 1;
                memcpy(key, d + b, k);
                key[k] = '\0';
                prims += strcmp(key, "attributes") == 0;
                refs += strcmp(key, "mesh") == 0;
            }
        } else if (after_key && (d[i] == '-' || (d[i] >= '0' && d[i] <= '9'))) {
            char num[64];
            size_t k = 0;
            while (i < n && k < sizeof num - 1 && strchr("+-.eE0123456789", d[i]))
                num[k++] = (char)d[i++];
            num[k] = '\0';
            double v = strtod(num, NULL);
            if (strcmp(key, "count") == 0 && v > max_count)
                max_count = v;
            after_key = false;
            i--;
        } else if (d[i] != ' ' && d[i] != ':' && d[i] != '\t' && d[i] != '\n' && d[i] != '\r') {
            after_key = false;
        }
    }
    return max_count * (prims > 1 ? prims : 1) * (refs > 1 ? refs : 1) > 2e6;
}

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
    const bool binary = (data[0] & 1) || (size >= 5 && memcmp(data + 1, "glTF", 4) == 0);
    if (too_costly(data + 1, size - 1, binary))
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
