/* report_html.h: DIR/report.html, one self-contained page per compare, demo, bench --accuracy and
 * merged sweep folder (docs/compare.md "Video and report page"). It is built from the files the
 * run wrote beside it, so its numbers are theirs: the settings and the summary table from
 * summary.json, the video (video.mp4) or a frame scrubber over preview/frame.NNNN.png, per-ring
 * coverage over time from metrics.csv, the accuracy-vs-cost plot with its Pareto front from
 * accuracy.csv, the FovVideoVDP JODs when summary.json has them. Charts are inline SVG
 * (svg_chart.h); no network, no external script: files beside it are named by relative path.
 * Every string read from a file is HTML-escaped. Written atomically. */
#ifndef FOVSIM_REPORT_HTML_H
#define FOVSIM_REPORT_HTML_H

#include "core/status.h"

typedef struct report_html_desc {
    const char *dir;  /* the folder, where report.html goes */
    const char *kind; /* "compare", "demo", "bench --accuracy", "merge": the page's title */
    double fps;       /* the run's frame rate (compare, demo); 0 unknown */
    /* bench --accuracy and merge: accuracy.csv's error column plotted against frame_ms_median and
     * its axis label; NULL: "flip" */
    const char *acc_error, *acc_error_label;
} report_html_desc;

/* Writes DIR/report.html. FS_ERR_IO (one line) or FS_ERR_NOMEM on failure, no partial file. */
fs_status report_html_write(const report_html_desc *d);

#endif
