/* reference.h: the converged ground truth every method is measured against (DESIGN.md "Ground
 * truth and metrics", docs/reference.md).
 *
 * A reference frame is the display at full resolution with S x S sub-samples per pixel (box
 * filter) and K stochastic alpha tests per sub-sample, each with its own threshold. A stochastic
 * test keeps a surface with probability alpha, so with the depth test the expected colour of a
 * sample is order-correct alpha compositing: the estimate converges to the sorted-blend ground
 * truth with error proportional to 1/sqrt(K). It is drawn as S*S*K full-resolution passes, each
 * moved by its sub-sample's offset (frame_record_shift), with texture LOD biased by -log2(S) so each
 * pass samples the mip level an S x S supersampled pixel would; the passes are summed in two
 * halves A (the first K/2 tests of every sub-sample) and B (the rest). The frame is (A + B) / 2, and
 * its convergence is RMS((A - B) / 2) over linear RGB: the RMS difference between the K/2 and the K
 * estimate, which is also an unbiased estimate of the K estimate's own RMS error. Memory is two
 * display-sized float accumulators whatever S and K are, so 1920x1080 at 4x4 x 64 fits easily.
 *
 * The reference depends on the scene, the frame's camera (and time, when instances sway), the display
 * size, S, K and the shaders,
 * not on the gaze or the alpha mode: frames are cached as EXR files named by a 64-bit key of those
 * (reference_key); a cached file is reused when it reads back completely with the same key and
 * size, else it is rebuilt (truncated, stale, or written by another version).
 *
 * Usage (a GL context must be current):
 *   reference *rf = reference_create(&sc, &(reference_desc){.width = w, .height = h,
 *                                    .cache_dir = dir}, &st);
 *   reference_frame(rf, &fr, &img, &info);   ...   reference_destroy(rf);
 */
#ifndef FOVSIM_REFERENCE_H
#define FOVSIM_REFERENCE_H

#include <stdbool.h>
#include <stdint.h>

#include "core/status.h"
#include "output/exr_write.h"
#include "scene/frame.h"
#include "scene/scene.h"

#define REFERENCE_SUPERSAMPLE_DEFAULT 4 /* S: S x S sub-samples per pixel */
#define REFERENCE_SAMPLES_DEFAULT 64    /* K: stochastic alpha tests per sub-sample */
#define REFERENCE_SUPERSAMPLE_MAX 16
#define REFERENCE_SAMPLES_MAX 4096

typedef struct reference_desc {
    int width, height;     /* display */
    int supersample;       /* S, 0 = default */
    int samples;           /* K (even), 0 = default */
    const char *cache_dir; /* where frames are cached; NULL = no cache */
    /* Called after every pass of a frame that is drawn (not for cached frames); may be NULL. */
    void (*on_pass)(void *user, int done, int total);
    void *user;
} reference_desc;

typedef struct reference_info {
    bool cached;       /* read from the cache, not drawn */
    bool rebuilt;      /* a cache file existed but was unusable (truncated / stale) and was redrawn */
    double error;      /* convergence: RMS((A - B) / 2) over linear RGB (see above) */
    int passes;        /* passes drawn (0 when cached) */
    char path[1024];   /* the cache file ("" without a cache) */
    uint64_t key;
} reference_info;

typedef struct reference reference;

/* Builds the reference's plan and renderer for the scene; NULL with *status on failure. */
reference *reference_create(const scene *sc, const reference_desc *desc, fs_status *status);
void reference_destroy(reference *rf);
/* The cache key of frame `fr` (its camera; not its gaze or index). */
uint64_t reference_key(const reference *rf, const frame_record *fr);
/* The reference for frame `fr`: channels R, G, B, A, coverage (img initialised here), from the
 * cache when possible, else drawn (and stored in the cache when there is one). */
fs_status reference_frame(reference *rf, const frame_record *fr, exr_image *img, reference_info *info);
/* S and K in effect. */
int reference_supersample(const reference *rf);
int reference_samples(const reference *rf);
/* Passes a drawn frame takes: S * S * K. */
int reference_pass_count(const reference *rf);

/* The default cache directory: $FOVSIM_CACHE, else $XDG_CACHE_HOME/fovsim/reference, else
 * $HOME/.cache/fovsim/reference, else .fovsim-cache/reference. Written into buf. */
void reference_default_cache_dir(char *buf, int size);

#endif
