/* compare_grid.h: the picture every viewer shows, part 0 ("compare") of a comparison frame
 * (docs/compare.md "The grid"): one column per alpha mode, then the reference's; three rows of
 * tiles the frame's size:
 *   row 0  each mode's image                          | the reference's image
 *   row 1  each mode's LDR-FLIP map vs the reference  | the reference's coverage (grey)
 *   row 2  each mode's coverage minus the reference's | the legend of row 2 (annotated grids)
 * Row 1 is a heat map (black 0, red, yellow, white 1); row 2 diverging (annot_diverging: blue -1
 * lost, white 0, red +1 extra). Annotated (the default; --grid-annotate off for a clean grid):
 * every tile gets a label at its top-left corner (a square of the mode's fixed colour,
 * alpha_mode_colour, then "<mode>: <what>"), the measurement rings' borders and the gaze marker;
 * none of it ever reaches the `layers` part that the metrics read.
 *
 * compare writes the grid into every frame; anything else that shows the grid (a video) builds
 * it with the same call from the same inputs. */
#ifndef FOVSIM_COMPARE_GRID_H
#define FOVSIM_COMPARE_GRID_H

#include <stdbool.h>
#include <stddef.h>

#include "core/status.h"
#include "output/exr_write.h"
#include "scene/scene.h"

/* Rows of the grid. */
#define COMPARE_GRID_ROWS 3

typedef struct compare_grid_desc {
    int mode_count;                 /* 1..ALPHA_MODE_COUNT columns before the reference's */
    const alpha_mode *modes;        /* each column's mode */
    const exr_image *const *images; /* each mode's frame: R, G, B and coverage, the reference's size */
    const float *const *flip;       /* each mode's LDR-FLIP map against the reference (w x h) */
    const exr_image *ref;           /* the reference frame: R, G, B and coverage */
    const unsigned char *rings;     /* w x h measurement ring of each pixel (ring_mask), for the ring
                                     * borders; NULL: none drawn */
    float gaze_px[2];               /* the frame's gaze, display pixels (frame_record gaze_px) */
    bool annotate;                  /* labels, gaze marker, ring borders and legend */
} compare_grid_desc;

/* The grid as a single-part image named "compare" with channels R, G, B, A (A = 1), linear,
 * (mode_count + 1) * w x COMPARE_GRID_ROWS * h. FS_ERR_USAGE for a missing channel or a size
 * mismatch, FS_ERR_NOMEM; *out is zeroed on failure. */
fs_status compare_grid_build(const compare_grid_desc *d, exr_image *out);
/* The `fovsim:grid` header attribute: which tile is which, the colours, the annotation. */
void compare_grid_describe(const compare_grid_desc *d, char *buf, size_t size);
/* The label text scale for w x h tiles (1 up to 299 rows, then one more per 300 rows). */
int compare_grid_text_scale(int w, int h);

#endif
