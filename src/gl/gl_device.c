/* gl_device.c: EGL (surfaceless / platform device) + OpenGL 4.5 core through libepoxy, or a context
 * adopted from a window (GLX through GLFW); libepoxy dispatches for both. */
#include "gl/gl_device.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

#ifndef EGL_PLATFORM_SURFACELESS_MESA
#define EGL_PLATFORM_SURFACELESS_MESA 0x31DD
#endif

static struct {
    bool valid;
    bool adopted;         /* a context made elsewhere (the viewer's GLFW window): not ours to destroy */
    EGLDisplay display;
    EGLContext context;
    char renderer[256];
    char version[256];
    char description[128];
    bool timer_query;
    bool pipeline_stats;
} g_dev;

static bool has_ext(const char *list, const char *name)
{
    if (!list)
        return false;
    size_t n = strlen(name);
    for (const char *p = list; (p = strstr(p, name)) != NULL; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return true;
    return false;
}

static void APIENTRY gl_debug_cb(GLenum source, GLenum type, GLuint id, GLenum severity,
                                 GLsizei length, const GLchar *msg, const void *user)
{
    (void)source; (void)id; (void)length; (void)user;
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION)
        return;
    fprintf(stderr, "GL: [%s] %s\n", type == GL_DEBUG_TYPE_ERROR ? "error" : "debug", msg);
}

/* EGL devices from EGL_EXT_device_enumeration; returns the count (0 when unsupported). */
static int query_devices(EGLDeviceEXT *devs, int max)
{
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_ext(client, "EGL_EXT_device_enumeration") && !has_ext(client, "EGL_EXT_device_base"))
        return 0;
    EGLint n = 0;
    if (!eglQueryDevicesEXT(max, devs, &n))
        return 0;
    return n;
}

static bool device_is_software(EGLDeviceEXT dev)
{
    const char *ext = eglQueryDeviceStringEXT(dev, EGL_EXTENSIONS);
    return has_ext(ext, "EGL_MESA_device_software");
}

void gl_device_list(void)
{
    EGLDeviceEXT devs[16];
    int n = query_devices(devs, 16);
    if (n == 0) {
        printf("no EGL devices enumerable (EGL_EXT_device_enumeration missing); "
               "the default is Mesa's surfaceless platform\n");
        return;
    }
    for (int i = 0; i < n; i++) {
        const char *ext = eglQueryDeviceStringEXT(devs[i], EGL_EXTENSIONS);
        const char *drm = has_ext(ext, "EGL_EXT_device_drm")
                              ? eglQueryDeviceStringEXT(devs[i], 0x3233 /* EGL_DRM_DEVICE_FILE_EXT */)
                              : NULL;
        printf("%d: %s%s%s\n", i, device_is_software(devs[i]) ? "software" : "hardware",
               drm ? " " : "", drm ? drm : "");
    }
}

static EGLDisplay open_display(int gpu_index)
{
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    EGLDeviceEXT devs[16];
    int n = query_devices(devs, 16);
    if (gpu_index >= 0) {
        if (gpu_index >= n) {
            log_error("--gpu %d: no such EGL device (%d found; see `fovsim --list-gpus`)", gpu_index, n);
            return EGL_NO_DISPLAY;
        }
        snprintf(g_dev.description, sizeof g_dev.description, "EGL device %d (%s)", gpu_index,
                 device_is_software(devs[gpu_index]) ? "software" : "hardware");
        return eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devs[gpu_index], NULL);
    }
    if (has_ext(client, "EGL_EXT_platform_device")) {
        for (int i = 0; i < n; i++) {
            if (device_is_software(devs[i]))
                continue;
            EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devs[i], NULL);
            if (d != EGL_NO_DISPLAY && eglInitialize(d, NULL, NULL)) {
                snprintf(g_dev.description, sizeof g_dev.description, "EGL device %d (hardware)", i);
                return d;
            }
        }
    }
    if (has_ext(client, "EGL_MESA_platform_surfaceless")) {
        snprintf(g_dev.description, sizeof g_dev.description, "Mesa surfaceless platform");
        return eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    }
    log_error("EGL: neither a hardware EGL device nor EGL_MESA_platform_surfaceless is available "
              "(install Debian's libegl-mesa0 and libgl1-mesa-dri)");
    return EGL_NO_DISPLAY;
}

/* What both kinds of context share once current: the GL 4.5 check, the cached strings and
 * capabilities (queried once: no glGet* in the frame loop), debug output. On failure the device is destroyed. */
static fs_status cache_context_state(bool debug)
{
    if (epoxy_gl_version() < 45) {
        log_error("GL: %s offers OpenGL %d.%d, fovsim needs 4.5 core", (const char *)glGetString(GL_RENDERER),
                  epoxy_gl_version() / 10, epoxy_gl_version() % 10);
        gl_device_destroy();
        return FS_ERR_GL;
    }
    snprintf(g_dev.renderer, sizeof g_dev.renderer, "%s", (const char *)glGetString(GL_RENDERER));
    snprintf(g_dev.version, sizeof g_dev.version, "%s", (const char *)glGetString(GL_VERSION));
    g_dev.timer_query = true; /* core since GL 3.3 */
    /* FOVSIM_NO_PIPELINE_STATS: behave as a driver without the extension (tests of "unknown"). */
    g_dev.pipeline_stats = epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query") &&
                           getenv("FOVSIM_NO_PIPELINE_STATS") == NULL;
    if (debug) {
        glEnable(GL_DEBUG_OUTPUT);
        glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        glDebugMessageCallback(gl_debug_cb, NULL);
    }
    return FS_OK;
}

fs_status gl_device_create(const gl_device_desc *desc)
{
    FS_ASSERT(!g_dev.valid);
    gl_device_desc d = desc ? *desc : (gl_device_desc){.gpu_index = -1};
    memset(&g_dev, 0, sizeof g_dev);

    EGLDisplay dpy = open_display(d.gpu_index);
    if (dpy == EGL_NO_DISPLAY)
        return FS_ERR_GL;
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor)) {
        log_error("EGL: eglInitialize failed (error 0x%x) on %s", eglGetError(), g_dev.description);
        return FS_ERR_GL;
    }
    if (!has_ext(eglQueryString(dpy, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context")) {
        log_error("EGL: %s lacks EGL_KHR_surfaceless_context", g_dev.description);
        eglTerminate(dpy);
        return FS_ERR_GL;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        log_error("EGL: desktop OpenGL is not supported by %s", g_dev.description);
        eglTerminate(dpy);
        return FS_ERR_GL;
    }
    static const EGLint cfg_attrs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig cfg;
    EGLint ncfg = 0;
    bool no_config = !eglChooseConfig(dpy, cfg_attrs, &cfg, 1, &ncfg) || ncfg < 1;

    bool debug = d.gl_debug || getenv("FOVSIM_GL_DEBUG") != NULL;
#ifndef NDEBUG
    debug = true;
#endif
    const EGLint ctx_attrs[] = {
        EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
        EGL_CONTEXT_OPENGL_DEBUG, debug ? EGL_TRUE : EGL_FALSE, EGL_NONE};
    /* EGL_KHR_no_config_context lets a surfaceless context exist without any config. */
    EGLContext ctx = eglCreateContext(dpy, no_config ? EGL_NO_CONFIG_KHR : cfg, EGL_NO_CONTEXT, ctx_attrs);
    if (ctx == EGL_NO_CONTEXT) {
        log_error("EGL: cannot create an OpenGL 4.5 core context on %s (error 0x%x)", g_dev.description,
                  eglGetError());
        eglTerminate(dpy);
        return FS_ERR_GL;
    }
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        log_error("EGL: eglMakeCurrent failed (error 0x%x)", eglGetError());
        eglDestroyContext(dpy, ctx);
        eglTerminate(dpy);
        return FS_ERR_GL;
    }
    g_dev.display = dpy;
    g_dev.context = ctx;
    g_dev.valid = true;
    fs_status st = cache_context_state(debug);
    if (st != FS_OK)
        return st;
    log_info("GL: %s, OpenGL %s, on %s (EGL %d.%d)", g_dev.renderer, g_dev.version, g_dev.description, major, minor);
    return FS_OK;
}

fs_status gl_device_adopt_current(const char *description, bool gl_debug)
{
    FS_ASSERT(!g_dev.valid && description);
    memset(&g_dev, 0, sizeof g_dev);
    bool debug = gl_debug || getenv("FOVSIM_GL_DEBUG") != NULL;
#ifndef NDEBUG
    debug = true;
#endif
    snprintf(g_dev.description, sizeof g_dev.description, "%s", description);
    g_dev.adopted = true;
    g_dev.valid = true;
    fs_status st = cache_context_state(debug);
    if (st == FS_OK)
        log_info("GL: %s, OpenGL %s, on %s", g_dev.renderer, g_dev.version, g_dev.description);
    return st;
}

void gl_device_destroy(void)
{
    if (!g_dev.valid)
        return;
    if (g_dev.adopted) { /* the window that made the context destroys it */
        memset(&g_dev, 0, sizeof g_dev);
        return;
    }
    eglMakeCurrent(g_dev.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(g_dev.display, g_dev.context);
    eglTerminate(g_dev.display);
    memset(&g_dev, 0, sizeof g_dev);
}

bool gl_device_is_valid(void) { return g_dev.valid; }
const char *gl_device_renderer(void) { return g_dev.renderer; }
const char *gl_device_version(void) { return g_dev.version; }
const char *gl_device_description(void) { return g_dev.description; }
bool gl_device_has_timer_query(void) { return g_dev.timer_query; }
bool gl_device_has_pipeline_stats(void) { return g_dev.pipeline_stats; }
