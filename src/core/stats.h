/* stats.h: the small statistics every layer shares (sorting doubles, quantiles of a sorted array).
 * Pure C. */
#ifndef FOVSIM_STATS_H
#define FOVSIM_STATS_H

/* qsort's comparator for doubles, ascending (NaN compares equal to everything: filter it first). */
int stats_cmp_double(const void *a, const void *b);
/* The q-quantile of sorted v[0..n), linear between ranks (q = 0.5 of an even n: the mean of the two
 * middle values); 0 for n == 0. */
double stats_quantile(const double *v, int n, double q);

#endif
