/* frame.h: the CPU front end of one frame. It sits above the scene and foveation (it combines
 * the camera path with the gaze's ring layout) and below the renderer, the reference and the
 * outputs that consume it (docs/design.md).
 *
 * frame_record_make evaluates everything a frame needs before any GL call: time, camera, view and
 * projection matrices, clip planes fitted to the scene. The renderer consumes the record; replay
 * and metrics read the same record. Pure C.
 */
#ifndef FOVSIM_FRAME_H
#define FOVSIM_FRAME_H

#include "fov/fov_ring.h"
#include "scene/scene.h"

typedef struct frame_record {
    int index;          /* frame number, 0-based */
    float time;         /* seconds */
    camera_state camera;
    float hfov_deg;     /* effective horizontal fov */
    display_desc display; /* what the frame was made for: its size, hfov_deg and the scene display's
                             principal point in its pixels (frame_display) */
    float znear, zfar;  /* world units */
    mat4 view, proj, view_proj;
    /* The gaze the frame is RENDERED around (the eye tracker's, gaze_tracker.h): the rings, their
     * footprints and the composite follow it. */
    float gaze[2];      /* normalised display coordinates, origin top-left (centre by default) */
    float gaze_px[2];   /* the same in display pixels */
    float gaze_deg[2];  /* the gaze ray's angle from the view axis, degrees (x right, y up) */
    /* The TRUE gaze (where the viewer looks): what every metric's rings, eccentricities and foveal
     * figures are measured around. The same as the rendered gaze unless the tracker model
     * (latency, sampling, noise, loss) moved it; frame_record_set_gaze sets both. */
    float true_gaze[2], true_gaze_px[2], true_gaze_deg[2];
    bool full_res;      /* tracking lost with policy full: every ring's footprint is the display at
                           one pixel per pixel (frame_record_set_full_res) */
    bool cut;           /* camera cut between the previous frame and this one */
    int ring_count;     /* foveation rings (1 = full resolution) */
    fov_ring_rect ring_rect[MAX_FOV_RINGS];  /* footprint of each ring for this frame's gaze */
    mat4 ring_view_proj[MAX_FOV_RINGS];      /* view-projection of each ring (cropped frustum) */
} frame_record;

/* Frame `index` at `fps` frames per second for a width x height target. */
frame_record frame_record_make(const scene *sc, int index, float fps, int width, int height);
/* Frame at an explicit time; `prev_time` < 0 means no previous frame (no cut detection).
 * The gaze is the display centre and there is one full-resolution ring until
 * frame_record_set_gaze says otherwise. */
frame_record frame_record_at(const scene *sc, int index, float time, float prev_time, int width, int height);
/* The frame's display at width x height (the size it was made for, or a multiple of it such as the
 * reference's supersampled one): hfov_deg, and the principal point scaled to that size. Every
 * pixel <-> angle computation about the frame takes its display from here. */
display_desc frame_display(const frame_record *fr, int width, int height);
/* Frame at an explicit time for a camera given by its position and view matrix (world -> view,
 * m4_look_at's convention: a recorded head pose, pose_trace.h) instead of the scene's camera path:
 * the display's field of view, no cut. Otherwise as frame_record_at. */
frame_record frame_record_posed(const scene *sc, int index, float time, vec3 position, mat4 view, int width,
                                int height);
/* An eye of a head camera: the frame `head` (the scene's camera path is the head) seen from `offset`
 * (metres, the head frame: +x right, +y up, -z forward), view_eye = T(-offset) view; its cut kept. */
frame_record frame_record_eye(const scene *sc, const frame_record *head, vec3 offset, int width, int height);
/* Sets the gaze (normalised, origin top-left; clamped to the display) and computes each ring's
 * footprint and cropped view-projection for layout `l` on display `d` (the frame's size). */
void frame_record_set_gaze(frame_record *fr, const fov_layout *l, const display_desc *d, float gx, float gy);
/* The same frame for layout `l` (another configuration's rings): the rendered gaze's rings redone,
 * the true gaze and full_res kept. */
void frame_record_set_layout(frame_record *fr, const fov_layout *l, const display_desc *d);
/* Sets the true gaze only (after frame_record_set_gaze, which set it to the rendered one). */
void frame_record_set_true_gaze(frame_record *fr, const display_desc *d, float gx, float gy);
/* Draws the frame at full resolution without changing the layout's ring count (the renderer keeps
 * its targets): every ring's footprint becomes the whole display at block 1, so every ring the
 * composite picks holds full-resolution pixels. Each ring keeps its mip bias and ring LOD. */
void frame_record_set_full_res(frame_record *fr, const display_desc *d);
/* Moves the image by (dx, dy) display pixels (x right, y down) on display `d`: every pixel then
 * samples the scene at (its centre - (dx, dy)). Projection, view-projection and each ring's
 * view-projection move together. The reference uses it to place its sub-pixel samples. */
void frame_record_shift(frame_record *fr, const display_desc *d, float dx, float dy);

#endif
