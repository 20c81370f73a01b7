/* gl_window.h: the viewer's window (GLFW, OpenGL 4.5 core; GLX under X11) and its input.
 *
 * gl_window_create opens a resizable window, makes its GL 4.5 core context current and adopts it
 * as the gl_device (gl_device_adopt_current), so the renderer runs on it exactly as on the
 * headless EGL context. Input is collected by GLFW callbacks: key presses are queued by name
 * (gl_window_next_key), the cursor is kept as its latest position. Presenting blits display-sized
 * framebuffers (renderer_output_framebuffer) into the window, scaled to fit and letterboxed,
 * encoding linear colour to sRGB on the way (GL_FRAMEBUFFER_SRGB).
 *
 * Usage:
 *   gl_window *w = gl_window_create(&(gl_window_desc){.width = 1280, .height = 720, .title = "x"}, &st);
 *   while (!gl_window_should_close(w)) {
 *       gl_window_poll(w, 0);  char key[GL_WINDOW_KEY_NAME];  while (gl_window_next_key(w, key)) ...
 *       renderer_draw(...);  gl_window_present(w, src, n, 1280, 720);  gl_window_swap(w);
 *   }
 *   gl_window_destroy(w);
 *
 * Key names are those of a US layout, by position: "A".."Z", "0".."9", "SPACE", "ESCAPE",
 * "LEFT_BRACKET", "RIGHT_BRACKET", "LEFT", "RIGHT", "UP", "DOWN", "F1".."F12", "MINUS", "EQUAL",
 * "TAB", "ENTER", "BACKSPACE". Other keys are ignored.
 *
 * What it does NOT do: decide what keys mean (src/view), draw text, more than one window.
 */
#ifndef FOVSIM_GL_WINDOW_H
#define FOVSIM_GL_WINDOW_H

#include <stdbool.h>

#include "core/status.h"
#include "output/exr_write.h"

#define GL_WINDOW_KEY_NAME 16   /* longest key name + NUL ("RIGHT_BRACKET") */
#ifndef GL_WINDOW_KEY_QUEUE
#define GL_WINDOW_KEY_QUEUE 64  /* key presses kept between two polls; more are dropped */
#endif

typedef struct gl_window gl_window;

typedef struct gl_window_desc {
    int width, height;  /* window size in screen coordinates, required */
    const char *title;  /* default "fovsim" */
    bool gl_debug;      /* GL debug output (always on in debug builds) */
} gl_window_desc;

/* Opens the window and adopts its context as the gl_device. Prints one line and returns NULL with
 * FS_ERR_GL when there is no display or no GL 4.5 core context. */
gl_window *gl_window_create(const gl_window_desc *desc, fs_status *status);
/* Destroys the gl_device, the window and GLFW. No-op on NULL. */
void gl_window_destroy(gl_window *w);

/* Processes window-system events; waits up to `wait_s` seconds for one when > 0. */
void gl_window_poll(gl_window *w, double wait_s);
/* The next queued key press (its name into `name`, GL_WINDOW_KEY_NAME bytes); false when none. */
bool gl_window_next_key(gl_window *w, char *name);
/* Latest cursor position in window coordinates (origin top-left); false when it is outside the
 * window or has not entered it yet. */
bool gl_window_cursor(const gl_window *w, double *x, double *y);
/* Maps window coordinates to normalised display coordinates (origin top-left) of a
 * disp_w x disp_h image presented in the window (letterboxed as gl_window_present does); false
 * when the point lies outside the image (the coordinates are still computed, unclamped). */
bool gl_window_to_display(const gl_window *w, double x, double y, int disp_w, int disp_h, float *nx, float *ny);
bool gl_window_should_close(const gl_window *w);
void gl_window_request_close(gl_window *w);
/* Minimised, or a zero-sized framebuffer: nothing to draw into. */
bool gl_window_is_hidden(const gl_window *w);
void gl_window_set_title(gl_window *w, const char *title);
/* Resizes the window (screen coordinates), as dragging its border would (scripts, tests). */
void gl_window_set_size(gl_window *w, int width, int height);
/* Whether the window's framebuffer encodes sRGB (else colour is shown linear, darker). */
bool gl_window_is_srgb(const gl_window *w);

/* One display-sized framebuffer to show: its columns [x0, x1) go to the same columns of the
 * image in the window (x0 = 0, x1 = width for the whole image; two sources for a split screen). */
typedef struct gl_window_source {
    unsigned framebuffer; /* GL framebuffer name, colour attachment 0 read */
    int x0, x1;           /* display columns */
    int shift;            /* the framebuffer's column of display column x is x - shift (0: the same) */
} gl_window_source;

/* Clears the back buffer and blits the sources (each disp_w x disp_h) into it, scaled to fit the
 * window with the display's aspect ratio (bars around); a 1-pixel line marks each source border
 * inside the image. Linear colour is encoded to sRGB when the window is sRGB-capable. */
void gl_window_present(gl_window *w, const gl_window_source *src, int count, int disp_w, int disp_h);
/* Reads the back buffer as presented (before gl_window_swap) into *img: channels R, G, B in
 * [0, 1] as displayed (sRGB-encoded when gl_window_is_srgb), rows top first, at the framebuffer's
 * size. FS_ERR_NOMEM on failure. */
fs_status gl_window_read(gl_window *w, exr_image *img);
void gl_window_swap(gl_window *w);

#endif
