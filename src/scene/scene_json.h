/* scene_json.h: the JSON scene-file parser behind scene_load_file and scene_load_builtin.
 *
 * Turns one JSON document (docs/scene-format.md) into a `scene`: checks every key and value,
 * loads the glTF assets and runs the generators it names, places the instances (scatter included),
 * reads the camera path and applies per-material overrides. Every problem is one log_error line
 * naming the document and the JSON path: `scenes/x.json: instances[3].scale: expected ...`.
 *
 * What it does NOT do: read files (scene.c does), bounds-check asset data (scene_validate).
 *
 * Usage: scene.c calls scene_json_parse with the file's text; tests go through scene_load_file.
 */
#ifndef FOVSIM_SCENE_JSON_H
#define FOVSIM_SCENE_JSON_H

#include <stddef.h>

#include "core/status.h"
#include "scene/scene.h"

/* Parses `text` (`size` bytes plus a terminating NUL) into *out. `name` prefixes every message
 * and becomes scene.path ("scenes/forest.json" or "builtin:forest"). Relative glTF paths resolve
 * against `base_dir` ("" = the current directory); base_dir NULL refuses glTF assets (built-in
 * scenes are generators only). FS_ERR_SCENE for a bad document; FS_ERR_ASSET / FS_ERR_IO /
 * FS_ERR_NOMEM pass through from the asset loaders. On failure *out is freed and zeroed. */
fs_status scene_json_parse(const char *text, size_t size, const char *name, const char *base_dir,
                           scene *out);

#endif
