/* frame.h: the CPU front end of one frame (STYLE.md "front end / back end").
 *
 * frame_record_make evaluates everything a frame needs before any GL call: time, camera, view and
 * projection matrices, clip planes fitted to the scene. The renderer consumes the record; replay
 * and metrics read the same record. Pure C.
 */
#ifndef FOVSIM_FRAME_H
#define FOVSIM_FRAME_H

#include "scene/scene.h"

typedef struct frame_record {
    int index;          /* frame number, 0-based */
    float time;         /* seconds */
    camera_state camera;
    float hfov_deg;     /* effective horizontal fov */
    float znear, zfar;  /* world units */
    mat4 view, proj, view_proj;
    float gaze[2];      /* normalised display coordinates, origin top-left (centre until gaze lands) */
    bool cut;           /* camera cut between the previous frame and this one */
} frame_record;

/* Frame `index` at `fps` frames per second for a width x height target. */
frame_record frame_record_make(const scene *sc, int index, float fps, int width, int height);
/* Frame at an explicit time; `prev_time` < 0 means no previous frame (no cut detection). */
frame_record frame_record_at(const scene *sc, int index, float time, float prev_time, int width, int height);

#endif
