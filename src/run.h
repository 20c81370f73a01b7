/* run.h: the commands of fovsim (render, plan, demo, bench, reference, compare, view), given a
 * parsed run_desc. What the commands share is in session.h. */
#ifndef FOVSIM_RUN_H
#define FOVSIM_RUN_H

#include "cli.h"

fs_status run(const run_desc *d);

#endif
