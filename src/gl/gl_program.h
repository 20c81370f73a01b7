/* gl_program.h: compiling and linking GLSL programs from the embedded shaders/ tree.
 *
 * Sources are assembled by shader_src (defines, #include, #line); a compile error prints the
 * driver log rewritten to "shaders/<file>:<line>: ..." and returns FS_ERR_SHADER.
 * What it does NOT do: cache (the renderer compiles each plan pass once), uniforms.
 */
#ifndef FOVSIM_GL_PROGRAM_H
#define FOVSIM_GL_PROGRAM_H

#include <stdint.h>

#include "core/status.h"

typedef struct gpu_program_handle {
    uint32_t id; /* GL program name, 0 = invalid */
} gpu_program_handle;

typedef struct gl_program_desc {
    const char *vs, *fs;            /* embedded paths, e.g. "shaders/forward.vert" */
    const char *gs;                 /* optional geometry shader between them (NULL: none) */
    const char *cs;                 /* or a compute shader alone (vs and fs NULL) */
    const char *const *defines;     /* "NAME VALUE" strings */
    int define_count;
    const char *label;              /* for messages, e.g. the plan pass name */
} gl_program_desc;

fs_status gl_program_build(const gl_program_desc *desc, gpu_program_handle *out);
void gl_program_destroy(gpu_program_handle p);

#endif
