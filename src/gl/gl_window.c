/* gl_window.c: GLFW window + GL 4.5 core context for the viewer, adopted as the gl_device. */
#include "gl/gl_window.h"

#include <epoxy/gl.h>
/* After epoxy: GLFW must not pull in a GL header of its own. */
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "gl/gl_device.h"

struct gl_window {
    GLFWwindow *win;
    char keys[GL_WINDOW_KEY_QUEUE][GL_WINDOW_KEY_NAME]; /* ring buffer of key presses */
    int key_head, key_count;
    double cursor_x, cursor_y;  /* window coordinates */
    bool cursor_in;
    bool srgb;
};

/* >>keys: GLFW key codes (US layout positions) -> the names scripts and the viewer use. */
static const struct {
    int key;
    const char *name;
} k_key_names[] = {
    {GLFW_KEY_SPACE, "SPACE"},         {GLFW_KEY_ESCAPE, "ESCAPE"},  {GLFW_KEY_LEFT_BRACKET, "LEFT_BRACKET"},
    {GLFW_KEY_RIGHT_BRACKET, "RIGHT_BRACKET"}, {GLFW_KEY_LEFT, "LEFT"}, {GLFW_KEY_RIGHT, "RIGHT"},
    {GLFW_KEY_UP, "UP"},               {GLFW_KEY_DOWN, "DOWN"},      {GLFW_KEY_MINUS, "MINUS"},
    {GLFW_KEY_EQUAL, "EQUAL"},         {GLFW_KEY_TAB, "TAB"},        {GLFW_KEY_ENTER, "ENTER"},
    {GLFW_KEY_BACKSPACE, "BACKSPACE"},
};

static bool key_name(int key, char *out)
{
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) {
        out[0] = (char)('A' + (key - GLFW_KEY_A));
        out[1] = '\0';
        return true;
    }
    if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) {
        out[0] = (char)('0' + (key - GLFW_KEY_0));
        out[1] = '\0';
        return true;
    }
    if (key >= GLFW_KEY_F1 && key <= GLFW_KEY_F12) {
        snprintf(out, GL_WINDOW_KEY_NAME, "F%d", 1 + key - GLFW_KEY_F1);
        return true;
    }
    for (size_t i = 0; i < sizeof k_key_names / sizeof k_key_names[0]; i++)
        if (k_key_names[i].key == key) {
            snprintf(out, GL_WINDOW_KEY_NAME, "%s", k_key_names[i].name);
            return true;
        }
    return false;
}

static void on_key(GLFWwindow *win, int key, int scancode, int action, int mods)
{
    (void)scancode;
    (void)mods;
    gl_window *w = glfwGetWindowUserPointer(win);
    /* Held keys repeat only where repeating makes sense (stepping values, stepping frames). */
    bool repeats = key == GLFW_KEY_LEFT_BRACKET || key == GLFW_KEY_RIGHT_BRACKET || key == GLFW_KEY_RIGHT;
    if (action != GLFW_PRESS && !(action == GLFW_REPEAT && repeats))
        return;
    char name[GL_WINDOW_KEY_NAME];
    if (!key_name(key, name))
        return;
    if (w->key_count == GL_WINDOW_KEY_QUEUE) {
        log_warn("VIEW: more than %d key presses between two frames; '%s' dropped", GL_WINDOW_KEY_QUEUE, name);
        return;
    }
    memcpy(w->keys[(w->key_head + w->key_count++) % GL_WINDOW_KEY_QUEUE], name, GL_WINDOW_KEY_NAME);
}

static void on_cursor(GLFWwindow *win, double x, double y)
{
    gl_window *w = glfwGetWindowUserPointer(win);
    w->cursor_x = x;
    w->cursor_y = y;
}

static void on_enter(GLFWwindow *win, int entered)
{
    gl_window *w = glfwGetWindowUserPointer(win);
    w->cursor_in = entered != 0;
}

/* >>lifetime */
static const char *glfw_error(void)
{
    const char *desc = NULL;
    int code = glfwGetError(&desc);
    return code != GLFW_NO_ERROR && desc ? desc : "unknown GLFW error";
}

gl_window *gl_window_create(const gl_window_desc *desc, fs_status *status)
{
    FS_ASSERT(desc && desc->width > 0 && desc->height > 0);
    *status = FS_ERR_GL;
    if (!glfwInit()) {
        log_error("VIEW: cannot open a window: %s (the viewer needs an X server; without one, run it under "
                  "xvfb-run)", glfw_error());
        return NULL;
    }
    gl_window *w = calloc(1, sizeof *w);
    if (!w) {
        glfwTerminate();
        *status = FS_ERR_NOMEM;
        return NULL;
    }
    bool debug = desc->gl_debug || getenv("FOVSIM_GL_DEBUG") != NULL;
#ifndef NDEBUG
    debug = true;
#endif
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, debug ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_TRUE); /* frames are linear; the screen wants sRGB */
    glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    glfwWindowHint(GLFW_DEPTH_BITS, 0); /* the renderer draws into its own targets */
    glfwWindowHint(GLFW_STENCIL_BITS, 0);
    w->win = glfwCreateWindow(desc->width, desc->height, desc->title ? desc->title : "fovsim", NULL, NULL);
    if (!w->win) {
        log_error("VIEW: cannot create a window with an OpenGL 4.5 core context: %s", glfw_error());
        free(w);
        glfwTerminate();
        return NULL;
    }
    glfwSetWindowUserPointer(w->win, w);
    glfwSetKeyCallback(w->win, on_key);
    glfwSetCursorPosCallback(w->win, on_cursor);
    glfwSetCursorEnterCallback(w->win, on_enter);
    glfwMakeContextCurrent(w->win);
    glfwSwapInterval(0); /* the viewer paces frames itself (scene time steps of 1/fps) */
    /* A cursor already over the new window sends no enter event. */
    glfwGetCursorPos(w->win, &w->cursor_x, &w->cursor_y);
    w->cursor_in = glfwGetWindowAttrib(w->win, GLFW_HOVERED) != 0;
    fs_status st = gl_device_adopt_current("GLFW window (GLX)", debug);
    if (st != FS_OK) {
        glfwDestroyWindow(w->win);
        free(w);
        glfwTerminate();
        *status = st;
        return NULL;
    }
    /* Once, not per frame: no glGet* in the frame loop (it stalls the pipeline). */
    GLint enc = GL_LINEAR;
    glGetNamedFramebufferAttachmentParameteriv(0, GL_BACK_LEFT, GL_FRAMEBUFFER_ATTACHMENT_COLOR_ENCODING, &enc);
    w->srgb = enc == GL_SRGB;
    if (!w->srgb)
        log_warn("VIEW: the window is not sRGB-capable; linear colour is shown as is (darker than on a display "
                 "that encodes it)");
    *status = FS_OK;
    return w;
}

void gl_window_destroy(gl_window *w)
{
    if (!w)
        return;
    gl_device_destroy();
    glfwDestroyWindow(w->win);
    free(w);
    glfwTerminate();
}

/* >>input */
void gl_window_poll(gl_window *w, double wait_s)
{
    (void)w;
    if (wait_s > 0)
        glfwWaitEventsTimeout(wait_s);
    else
        glfwPollEvents();
}

bool gl_window_next_key(gl_window *w, char *name)
{
    if (w->key_count == 0)
        return false;
    memcpy(name, w->keys[w->key_head], GL_WINDOW_KEY_NAME);
    w->key_head = (w->key_head + 1) % GL_WINDOW_KEY_QUEUE;
    w->key_count--;
    return true;
}

bool gl_window_cursor(const gl_window *w, double *x, double *y)
{
    *x = w->cursor_x;
    *y = w->cursor_y;
    return w->cursor_in;
}

/* Where a disp_w x disp_h image goes in the framebuffer: scaled to fit, centred. Rectangle in
 * framebuffer pixels, origin top-left. */
typedef struct fit_rect {
    int x, y, w, h;
    int fb_w, fb_h;
} fit_rect;

static fit_rect fit(const gl_window *w, int disp_w, int disp_h)
{
    fit_rect r = {0};
    glfwGetFramebufferSize(w->win, &r.fb_w, &r.fb_h);
    if (r.fb_w <= 0 || r.fb_h <= 0 || disp_w <= 0 || disp_h <= 0)
        return r;
    double s = fmin((double)r.fb_w / disp_w, (double)r.fb_h / disp_h);
    r.w = (int)lround(disp_w * s);
    r.h = (int)lround(disp_h * s);
    r.x = (r.fb_w - r.w) / 2;
    r.y = (r.fb_h - r.h) / 2;
    return r;
}

bool gl_window_to_display(const gl_window *w, double x, double y, int disp_w, int disp_h, float *nx, float *ny)
{
    int ww = 0, wh = 0;
    glfwGetWindowSize(w->win, &ww, &wh);
    fit_rect r = fit(w, disp_w, disp_h);
    if (ww <= 0 || wh <= 0 || r.w <= 0 || r.h <= 0) {
        *nx = *ny = 0.5f;
        return false;
    }
    /* Window coordinates -> framebuffer pixels (they differ on high-DPI screens). */
    double fx = x * r.fb_w / ww, fy = y * r.fb_h / wh;
    *nx = (float)((fx - r.x) / r.w);
    *ny = (float)((fy - r.y) / r.h);
    return *nx >= 0.0f && *nx <= 1.0f && *ny >= 0.0f && *ny <= 1.0f;
}

bool gl_window_should_close(const gl_window *w)
{
    return glfwWindowShouldClose(w->win) != 0;
}

void gl_window_request_close(gl_window *w)
{
    glfwSetWindowShouldClose(w->win, GLFW_TRUE);
}

bool gl_window_is_hidden(const gl_window *w)
{
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(w->win, &fw, &fh);
    return fw <= 0 || fh <= 0 || glfwGetWindowAttrib(w->win, GLFW_ICONIFIED);
}

void gl_window_set_title(gl_window *w, const char *title)
{
    glfwSetWindowTitle(w->win, title);
}

void gl_window_set_size(gl_window *w, int width, int height)
{
    glfwSetWindowSize(w->win, width, height);
}

bool gl_window_is_srgb(const gl_window *w)
{
    return w->srgb;
}

/* >>present */
void gl_window_present(gl_window *w, const gl_window_source *src, int count, int disp_w, int disp_h)
{
    fit_rect r = fit(w, disp_w, disp_h);
    static const float bars[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDisable(GL_SCISSOR_TEST); /* a blit is scissored too */
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glViewport(0, 0, r.fb_w, r.fb_h);
    glClearNamedFramebufferfv(0, GL_COLOR, 0, bars);
    if (r.w <= 0 || r.h <= 0)
        return;
    /* Same size: copy texels exactly; scaled: bilinear. */
    GLenum filter = r.w == disp_w && r.h == disp_h ? GL_NEAREST : GL_LINEAR;
    int y0 = r.fb_h - r.y - r.h; /* GL rows are bottom first, and so are the sources' */
    if (w->srgb)
        glEnable(GL_FRAMEBUFFER_SRGB);
    for (int i = 0; i < count; i++) {
        int dx0 = r.x + (int)lround((double)src[i].x0 * r.w / disp_w);
        int dx1 = r.x + (int)lround((double)src[i].x1 * r.w / disp_w);
        glBlitNamedFramebuffer(src[i].framebuffer, 0, src[i].x0 - src[i].shift, 0, src[i].x1 - src[i].shift, disp_h,
                               dx0, y0, dx1, y0 + r.h, GL_COLOR_BUFFER_BIT, filter);
    }
    glDisable(GL_FRAMEBUFFER_SRGB);
    /* Where one source ends and the next begins (split screen), a 1-pixel grey line. */
    static const float line[4] = {0.6f, 0.6f, 0.6f, 1.0f};
    glEnable(GL_SCISSOR_TEST);
    for (int i = 1; i < count; i++) {
        glScissor(r.x + (int)lround((double)src[i].x0 * r.w / disp_w), y0, 1, r.h);
        glClearNamedFramebufferfv(0, GL_COLOR, 0, line);
    }
    glDisable(GL_SCISSOR_TEST);
}

fs_status gl_window_read(gl_window *w, exr_image *img)
{
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(w->win, &fw, &fh);
    size_t n = (size_t)fw * (size_t)fh;
    unsigned char *px = malloc(4 * n);
    if (!px || !exr_image_init(img, fw, fh)) {
        free(px);
        return FS_ERR_NOMEM;
    }
    static const char *const names[3] = {"R", "G", "B"};
    float *planes[3];
    for (int c = 0; c < 3; c++)
        if (!(planes[c] = exr_image_add_channel(img, names[c]))) {
            free(px);
            exr_image_free(img);
            return FS_ERR_NOMEM;
        }
    glNamedFramebufferReadBuffer(0, GL_BACK);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadnPixels(0, 0, fw, fh, GL_RGBA, GL_UNSIGNED_BYTE, (GLsizei)(4 * n), px);
    for (int y = 0; y < fh; y++) /* GL rows bottom first, EXR top first */
        for (int x = 0; x < fw; x++) {
            const unsigned char *p = px + 4 * ((size_t)(fh - 1 - y) * (size_t)fw + (size_t)x);
            for (int c = 0; c < 3; c++)
                planes[c][(size_t)y * (size_t)fw + (size_t)x] = (float)p[c] / 255.0f;
        }
    free(px);
    return FS_OK;
}

void gl_window_swap(gl_window *w)
{
    glfwSwapBuffers(w->win);
}
