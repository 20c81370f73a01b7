/* compare_foveation.h: a foveation study (`fovsim compare --foveation rings,vrs[,off]`): one
 * compare run per foveation, every one measured in the same rings, each counting what a GPU would
 * shade, then the modes side by side under each (docs/foveation.md "Rings or VRS for alpha-tested
 * foliage"): foveation.csv and the table on stdout.
 *
 * What it does NOT do: draw or measure (compare.c does, and hands each run's figures here).
 */
#ifndef FOVSIM_COMPARE_FOVEATION_H
#define FOVSIM_COMPARE_FOVEATION_H

#include "fov/fov_ring.h"
#include "scene/scene.h"

/* One mode's figures under one foveation: per measurement ring, then the whole display ([rings]);
 * -1 = not measured (a coverage ratio with too little reference coverage, no temporal pair). */
typedef struct foveation_row {
    alpha_mode mode;
    double coverage[MAX_FOV_RINGS + 1], flip[MAX_FOV_RINGS + 1], temporal[MAX_FOV_RINGS + 1];
    double shaded_per_px;   /* what a GPU would shade per display pixel, median frame; -1 = unknown */
    double frame_ms_median; /* llvmpipe's, here */
} foveation_row;

/* What one compare run of the study hands back. */
typedef struct foveation_run {
    char name[16];  /* rings, vrs, off */
    char desc[256]; /* its ring layout or rate map */
    foveation_row rows[ALPHA_MODE_COUNT];
    int count;
} foveation_run;

/* OUT/foveation.csv (atomically; a row per foveation, mode and measurement ring, ring -1 the whole
 * display) and the table on stdout. mrings: the measurement rings, as `layout`. */
fs_status foveation_study_write(const char *out, const fov_layout *layout, const foveation_run *runs, int n);

#endif
