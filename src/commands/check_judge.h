/* check_judge.h: what check_judge.c (the comparison) and check_report.c (the report, JUnit and
 * JSON of its failures) share: one failure, and the state of one comparison. */
#ifndef FOVSIM_CHECK_JUDGE_H
#define FOVSIM_CHECK_JUDGE_H

#include <stdbool.h>

#include "commands/check.h"
#include "scene/scene.h"

typedef struct failure {
    int frame;           /* -1: the run's (rows, frame time) */
    char image[32];      /* a mode, "reference", or "" */
    int ring;            /* -1: the whole display */
    check_metric metric; /* CHECK_METRIC_COUNT: a structural difference, `note` says which */
    double base, now, tol;
    char note[96];
} failure;

typedef struct judge {
    const check_judge_desc *d;
    int *frames, nframes;      /* the baseline's frames, ascending */
    char images[ALPHA_MODE_COUNT + 1][32];
    int nimages;               /* the modes in the CSV's order, then "reference" */
    bool *case_failed;         /* [frame index * nimages + image], and [nframes * nimages]: the run's */
    failure *f;
    int nf, capf;
    check_verdict *v;
    double worst[CHECK_METRIC_COUNT], worst_tol[CHECK_METRIC_COUNT];
    bool have_worst[CHECK_METRIC_COUNT];
    int block[MAX_FOV_RINGS];  /* display pixels per ring texel (the render's layout) */
    int *diffs, ndiffs;        /* the frames with a diff image */
} judge;

/* qsort comparison of ints, ascending. */
int check_cmp_int(const void *a, const void *b);

/* The one-screen report on stdout (check_report.c). */
void check_report_print(judge *j);
/* The JUnit XML file of d->junit. */
fs_status check_report_junit(const judge *j);
/* Every failure as a JSON array (malloc'd), NULL when out of memory. */
char *check_report_failures_json(const judge *j);

#endif
