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
    float znear, zfar;  /* world units */
    mat4 view, proj, view_proj;
    float gaze[2];      /* normalised display coordinates, origin top-left (centre by default) */
    float gaze_px[2];   /* the same in display pixels */
    float gaze_deg[2];  /* the gaze ray's angle from the view axis, degrees (x right, y up) */
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
/* Sets the gaze (normalised, origin top-left; clamped to the display) and computes each ring's
 * footprint and cropped view-projection for layout `l` on display `d` (the frame's size). */
void frame_record_set_gaze(frame_record *fr, const fov_layout *l, const display_desc *d, float gx, float gy);
/* Moves the image by (dx, dy) display pixels (x right, y down) on display `d`: every pixel then
 * samples the scene at (its centre - (dx, dy)). Projection, view-projection and each ring's
 * view-projection move together. The reference uses it to place its sub-pixel samples. */
void frame_record_shift(frame_record *fr, const display_desc *d, float dx, float dy);

#endif
