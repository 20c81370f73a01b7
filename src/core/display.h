/* display.h: the display a frame is drawn for: its size in pixels and horizontal field of view.
 * The scene file names it; foveation, metrics and the frame record read it. It lives in core/ so
 * that those layers need not include the scene. */
#ifndef FOVSIM_DISPLAY_H
#define FOVSIM_DISPLAY_H

typedef struct display_desc {
    int width, height; /* pixels, default 1280 x 720 */
    float hfov_deg;    /* horizontal field of view, default 90 */
} display_desc;

#endif
