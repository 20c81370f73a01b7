/* image_diff.c: squared differences and the block guard of two images (image_diff.h). */
#include "image_diff.h"

#include <math.h>

/* A difference as a file could hold it: finite, at most the largest half. */
static double finite_diff(double d)
{
    return isfinite(d) ? d : 65504.0;
}

void image_diff_add(image_diff *d, const float *a, const float *b, int w, int h, int bs, const int *region, int r)
{
    if (bs < 1)
        bs = 1;
    for (int y0 = 0; y0 < h; y0 += bs)
        for (int x0 = 0; x0 < w; x0 += bs) {
            int y1 = y0 + bs < h ? y0 + bs : h, x1 = x0 + bs < w ? x0 + bs : w;
            double sum = 0;
            int n = 0, in_region = 0;
            for (int y = y0; y < y1; y++)
                for (int x = x0; x < x1; x++) {
                    long i = (long)y * w + x;
                    double e = finite_diff((double)a[i] - (double)b[i]);
                    sum += e;
                    n++;
                    if (!region || region[i] == r) {
                        in_region++;
                        d->sq_sum += e * e;
                        d->count++;
                    }
                }
            if (in_region && fabs(sum / n) > d->max_block)
                d->max_block = fabs(sum / n);
        }
}

double image_diff_rmse(const image_diff *d)
{
    return d->count ? sqrt(d->sq_sum / (double)d->count) : 0.0;
}
