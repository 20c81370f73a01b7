/* svg_chart.h: small line and scatter charts as inline SVG for report.html (no scripts, no fonts
 * beyond the browser's sans-serif). Every string goes in HTML-escaped. */
#ifndef FOVSIM_SVG_CHART_H
#define FOVSIM_SVG_CHART_H

#include <stdbool.h>

#include "core/strbuf.h"

typedef struct svg_series {
    const char *name;    /* the legend's entry */
    const char *colour;  /* "#rrggbb" (alpha_mode_colour) */
    const double *x, *y; /* n points; a non-finite y is a gap */
    int n;
    bool line;           /* a polyline through the points in order (else points only) */
    bool points;         /* a dot at each point */
} svg_series;

typedef struct svg_chart_desc {
    const char *title, *xlabel, *ylabel; /* the labels say "lower is better" where it is */
    int width, height;                   /* pixels; 0: 640 x 300 */
    const svg_series *series;
    int count;
    const char *id; /* the <svg> element's id (for tests), NULL for none */
    bool x_whole;   /* x ticks at whole numbers only (frames) */
} svg_chart_desc;

/* Appends `s` with & < > " ' as entities (text and attribute values alike). */
void html_escape(sbuf *b, const char *s);
/* Appends the chart as an <svg> element: axes with their range and labels, a legend. */
void svg_chart(sbuf *b, const svg_chart_desc *d);

#endif
