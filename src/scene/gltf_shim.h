/* gltf_shim.h: the C interface to the one C++ file that uses tinygltf.
 *
 * Loads a glTF 2.0 file (.gltf with its .bin and images, or .glb) into a plain C `asset`:
 * the default scene's node hierarchy is flattened (node transforms baked into vertices and
 * normals), every primitive becomes a `prim` with 32-bit indices, materials keep baseColorFactor,
 * baseColorTexture + sampler, alphaMode, alphaCutoff and doubleSided, and COLOR_0 is kept per
 * vertex. The first perspective camera found in the node tree is returned in asset space.
 *
 * What it does NOT do: upload, mipmaps, scene placement, and it never throws: every C++ exception
 * is caught at the boundary and reported as FS_ERR_ASSET (FS_ERR_NOMEM when out of memory). Assets that require an extension fovsim
 * cannot honour (Draco, meshopt, KTX2/Basis, ...) are refused with a message naming it.
 */
#ifndef FOVSIM_GLTF_SHIM_H
#define FOVSIM_GLTF_SHIM_H

#include <stdint.h>

#include "core/status.h"
#include "scene/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Loads `path` into *out (zeroed first). On failure prints one line
 * `<path>: <where>: <what>` via log_error, leaves *out zeroed, returns FS_ERR_ASSET or FS_ERR_IO. */
fs_status gltf_load(const char *path, asset *out);

/* Process-wide input limits (README "Limits"), set once from the command line before scenes load.
 * asset_root: URIs may also name files under this folder (--asset-root; NULL = only the glTF file's
 * own folder). Returns FS_ERR_USAGE with a message when the folder cannot be resolved. */
fs_status gltf_set_asset_root(const char *dir);
/* Decoded-pixel budgets: per image and per scene, in pixels (0 = the defaults,
 * GLTF_DEFAULT_IMAGE_PIXELS and GLTF_DEFAULT_SCENE_PIXELS). Checked against each image's declared
 * size before it is decoded. */
#define GLTF_DEFAULT_IMAGE_PIXELS ((uint64_t)64 << 20)  /* 64 Mpixel = 8192 x 8192 */
#define GLTF_DEFAULT_SCENE_PIXELS ((uint64_t)256 << 20) /* 256 Mpixel */
void gltf_set_pixel_budget(uint64_t per_image, uint64_t per_scene);
/* Starts a scene: its images count against the per-scene budget from here on. */
void gltf_begin_scene(void);

#ifdef __cplusplus
}
#endif

#endif
