/* gl_device.h: the headless OpenGL 4.5 core context (EGL) and the GL state fovsim caches.
 *
 * gl_device_create picks an EGL display:
 *   - `gpu_index >= 0`: that device of EGL_EXT_platform_device (error if it does not exist);
 *   - `gpu_index < 0` (default): the first hardware device, else Mesa's surfaceless platform
 *     (llvmpipe on machines without a GPU).
 * It makes a surfaceless OpenGL 4.5 core context current on the calling thread; GL entry points
 * come from libepoxy. In debug builds (or with FOVSIM_GL_DEBUG=1) GL debug output goes to stderr.
 * This is the only mutable global state in fovsim (by design): one device per process.
 *
 * A window's context (src/gl/gl_window.c) is adopted instead with gl_device_adopt_current.
 *
 * What it does NOT do: windows (gl_window, the viewer), frame buffers or programs (gl_util).
 */
#ifndef FOVSIM_GL_DEVICE_H
#define FOVSIM_GL_DEVICE_H

#include <stdbool.h>

#include "core/status.h"

typedef struct gl_device_desc {
    int gpu_index;  /* EGL device index, -1 = auto (hardware first, else software) */
    bool gl_debug;  /* force GL debug output on (always on in debug builds) */
} gl_device_desc;

/* Creates the context; prints one line and returns FS_ERR_GL when no GL 4.5 core context can be
 * made. Calling it twice without destroy is a programmer error. */
fs_status gl_device_create(const gl_device_desc *desc);
/* Adopts the OpenGL context current on the calling thread (the viewer's GLFW window, GLX under
 * X11) as the device: the same GL 4.5 check, cached strings and debug output as gl_device_create,
 * so the renderer runs unchanged on it. `description` names it ("GLFW window (GLX)"). On failure
 * prints one line and returns FS_ERR_GL. gl_device_destroy then forgets the context without
 * destroying it: the window that made it does. */
fs_status gl_device_adopt_current(const char *description, bool gl_debug);
void gl_device_destroy(void);
bool gl_device_is_valid(void);

/* GL_RENDERER and GL_VERSION strings, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)". Borrowed. */
const char *gl_device_renderer(void);
const char *gl_device_version(void);
/* "EGL device 0 (hardware)", "Mesa surfaceless (software)", ... Borrowed. */
const char *gl_device_description(void);
/* Whether GL_TIME_ELAPSED queries and GL_ARB_pipeline_statistics_query (vertex/fragment-shader
 * invocations, primitives) are available; the environment variable FOVSIM_NO_PIPELINE_STATS makes
 * the latter false, as on a driver without the extension. */
bool gl_device_has_timer_query(void);
bool gl_device_has_pipeline_stats(void);
/* Lists EGL devices on stdout (for `fovsim --list-gpus`). */
void gl_device_list(void);

#endif
