/* gnuplot.h: the plots of merge and bench --accuracy. Every string fovsim puts into a gnuplot
 * script goes through gnuplot_str; gnuplot runs in the plot's folder (so the script names its files
 * by fixed relative names, never by a path given to fovsim) through spawn_run, without a shell. */
#ifndef FOVSIM_GNUPLOT_H
#define FOVSIM_GNUPLOT_H

#include <stdbool.h>

#include "core/status.h"
#include "core/strbuf.h"

/* Appends `s` as a gnuplot string literal: single-quoted (gnuplot expands neither backquotes nor
 * @macros there), a quote doubled, control bytes as '?' (a script line cannot hold them). */
void gnuplot_str(sbuf *b, const char *s);
/* Whether gnuplot is on PATH. */
bool gnuplot_available(void);
/* Writes `script` to DIR/NAME and runs gnuplot on it in DIR; its messages go to DIR/gnuplot.log,
 * removed when it succeeds. FS_ERR_IO (one line naming the log) when it fails. */
fs_status gnuplot_run(const char *dir, const char *name, const sbuf *script);

/* Draws DIR/STEM.png (width x height, pngcairo) from `plot`, the script after its terminal and
 * output lines, through DIR/STEM.gp: gnuplot writes a temporary name, renamed into place when it
 * succeeded and removed when not. */
fs_status gnuplot_png(const char *dir, const char *stem, int width, int height, const sbuf *plot);

#endif
