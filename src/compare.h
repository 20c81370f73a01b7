/* compare.h: `fovsim compare`, `fovsim demo` and `fovsim bench --accuracy` (compare.c). */
#ifndef FOVSIM_COMPARE_H
#define FOVSIM_COMPARE_H

#include "cli.h"
#include "session.h"

fs_status run_compare(const run_desc *d);
fs_status run_demo(const run_desc *d);
fs_status run_bench_accuracy(const run_desc *d);

#endif
