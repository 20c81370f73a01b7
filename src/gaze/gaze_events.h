/* gaze_events.h: eye-movement events of the TRUE gaze trace: fixation, saccade, smooth pursuit
 * (and lost), by a velocity-threshold method with a pursuit band (docs/latency.md "Eye-movement
 * events"), and the saccades' landings that the post-saccade foveal error counts from. Pure C.
 *
 * The velocities are angular (degrees of visual angle per second) on display `d`, from the
 * trace's display-normalised samples through the same exact angle mapping as frame_record's
 * gaze_deg (atan of the offset from the principal point over the focal length, per axis).
 *
 * What it does NOT do: read the tracker model's delivered gaze (events are the viewer's, not the
 * system's), blink detection beyond the trace's own invalid samples (those are LOST).
 */
#ifndef FOVSIM_GAZE_EVENTS_H
#define FOVSIM_GAZE_EVENTS_H

#include <stdbool.h>

#include "core/display.h"
#include "core/status.h"
#include "gaze/gaze.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum gaze_event {
    GAZE_EVENT_FIXATION = 0,
    GAZE_EVENT_SACCADE,
    GAZE_EVENT_PURSUIT,
    GAZE_EVENT_LOST, /* the trace's sample is invalid (blink, missing value, low confidence) */
    GAZE_EVENT_COUNT
} gaze_event;

/* The classifier's parameters; 0 = the documented default of each. */
typedef struct gaze_events_desc {
    float saccade_deg_s; /* at or above: saccade */
    float pursuit_deg_s; /* at or above (and below saccade_deg_s): smooth pursuit; below: fixation */
    float window_ms;     /* the velocity's time window */
} gaze_events_desc;

/* One saccade: from its first to its last sample classified saccade; it LANDS at `end`. */
typedef struct gaze_saccade {
    double start, end;   /* seconds since the trace start (the trace's sample times) */
    float amplitude_deg; /* the angle between the gaze at start and at end (measured at the edges of
                            their velocity windows: docs/latency.md "Eye-movement events") */
    float peak_deg_s;    /* its peak velocity */
} gaze_saccade;

typedef struct gaze_events {
    int count;             /* the trace's sample count */
    unsigned char *event;  /* per trace sample: a gaze_event */
    gaze_saccade *saccades; /* in time order */
    int saccade_count;
    gaze_events_desc desc; /* the parameters used (defaults filled in) */
} gaze_events;

/* "fixation", "saccade", "pursuit", "lost"; NULL out of range. */
const char *gaze_event_name(gaze_event e);
/* The event named `name` (gaze_event_name's names); GAZE_EVENT_COUNT for anything else. */
gaze_event gaze_event_parse(const char *name);
/* Classifies every sample of trace t on display d. An empty trace gives count 0. */
fs_status gaze_events_classify(const gaze_trace *t, const display_desc *d, const gaze_events_desc *ed,
                               gaze_events *out);
void gaze_events_free(gaze_events *e);
/* The event at `time` (seconds since the trace start): that of the trace sample at or before it
 * (the first sample's before the trace, the last one's after it); FIXATION for an empty trace. */
gaze_event gaze_events_at(const gaze_events *e, const gaze_trace *t, double time);
/* The last saccade that LANDED at or before `time` (its end <= time), or NULL if none. */
const gaze_saccade *gaze_events_landed(const gaze_events *e, double time);

#ifdef __cplusplus
}
#endif

#endif
