/* shader_src.h: assembling GLSL from the embedded shaders/ tree (no GL calls).
 *
 * shader_src_build("shaders/forward.frag", defines) returns one source string:
 *   #version 450 core
 *   #define <each define>          (e.g. "ALPHA_TEST 1", sorted by the caller's plan)
 *   #line 1 <file number>
 *   <file text, with every `#include "x.glsl"` replaced by x.glsl's text (paths relative to
 *    shaders/), each wrapped in #line directives so driver messages point at the right file>
 * Shader files therefore carry no #version line. Files are numbered in the order first seen;
 * shader_src_file_name maps a number back to a path, and shader_src_translate_log rewrites a driver
 * log ("0:12(3): error: ..." from Mesa, "0(12) : error ..." from NVIDIA) into
 * "shaders/common/lighting.glsl:12: error: ...".
 *
 * What it does NOT do: compile (gl_util does), read files from disk (the binary runs anywhere).
 */
#ifndef FOVSIM_SHADER_SRC_H
#define FOVSIM_SHADER_SRC_H

#include "core/status.h"

#ifndef SHADER_MAX_FILES
#define SHADER_MAX_FILES 32 /* distinct files (main + includes) in one shader */
#endif

typedef struct shader_src {
    char *text;                            /* owned, NUL-terminated */
    int file_count;
    char files[SHADER_MAX_FILES][128];     /* file number -> path under the source root */
} shader_src;

/* Builds the source of embedded file `path` with `define_count` defines ("NAME VALUE" or "NAME").
 * Missing file or include, include cycle: message "<file>:<line>: ..." and FS_ERR_SHADER. */
fs_status shader_src_build(const char *path, const char *const *defines, int define_count, shader_src *out);
void shader_src_free(shader_src *s);
/* Rewrites a driver log (see above) into `out` (always NUL-terminated). */
void shader_src_translate_log(const shader_src *s, const char *log, char *out, int out_size);

#endif
