/* run.h: the commands of fovsim (render, plan, demo, bench), given a parsed run_desc. */
#ifndef FOVSIM_RUN_H
#define FOVSIM_RUN_H

#include "cli.h"

fs_status run(const run_desc *d);

#endif
