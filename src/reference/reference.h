/* reference.h: the converged ground truth every method is measured against (docs/design.md "Ground
 * truth and metrics", docs/reference.md).
 *
 * A reference frame is the display at full resolution with S x S sub-samples per pixel (box
 * filter), each sub-sample the expectation of a stochastic alpha test: a stochastic test keeps a
 * surface with probability alpha, so with the depth test the expected colour of a sample is
 * order-correct alpha compositing. Each sub-sample is one full-resolution pass moved by its offset
 * (frame_record_shift), with texture LOD biased by -log2(S) so it samples the mip level an S x S
 * supersampled pixel would. Two kinds:
 *
 *   exact (default): the expectation itself. Each pass draws the opaque surfaces and the depth of
 *     alpha-1 MASK texels, then appends every MASK and BLEND fragment in front of them to its
 *     pixel's list (an A-buffer, abuffer.h), which the GPU sorts and composites front to back (lists
 *     longer than ABUFFER_RESOLVE_MAX: the C twin). S*S passes. Convergence is spatial only: the
 *     frame's estimated error is RMS(ref_S - ref_S/2) over linear RGB, for even S against the four
 *     (S/2) x (S/2) sub-grids of every other sub-sample (no extra pass), for odd S against a C x C
 *     grid drawn for it (C = S/2 rounded down; 2 when S = 1). The list store has a memory budget; a
 *     pass that needs more grows it up to the budget, and the pixels that still lose fragments
 *     fall back to a K-test stochastic estimate of that sub-sample (reference_info.overflow_pixels
 *     counts them).
 *   stochastic: K stochastic alpha tests per sub-sample, S*S*K passes, each with its own threshold;
 *     error proportional to 1/sqrt(K). The passes are summed in two halves A (the first K/2 tests of
 *     every sub-sample) and B (the rest); the frame is (A + B) / 2 and its estimated error
 *     RMS((A - B) / 2), an unbiased estimate of the K estimate's own RMS error. An independent
 *     cross-check of the exact kind.
 *
 * The reference depends on the scene, the frame's camera (and time, when instances sway), the
 * display size, the kind, S, K (exact: the fallback's tests), the exact kind's budget and the
 * shaders, not on the gaze or the alpha mode: frames are cached as EXR files named by a 64-bit key
 * of those (reference_key); a cached file is reused when it is a regular file that reads back
 * completely with the same key, size and pixel checksum (fovsim:ref_checksum), else it is rebuilt
 * (truncated, stale, tampered, or written by another version); a directory at its path leaves the
 * frame uncached.
 * A miss takes the entry's lock (an flock on ref-KEY.lock beside it) and looks again before it
 * draws, so processes sharing the cache draw each frame once (docs/reference.md).
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
#include "frame/frame.h"
#include "scene/scene.h"

#define REFERENCE_SUPERSAMPLE_DEFAULT 4 /* S: S x S sub-samples per pixel */
#define REFERENCE_SAMPLES_DEFAULT 64    /* K: stochastic alpha tests per sub-sample */
#define REFERENCE_SUPERSAMPLE_MAX 16
#define REFERENCE_SAMPLES_MAX 4096
#define REFERENCE_LIST_MB_DEFAULT 2048  /* exact: the fragment-list store's budget */

typedef enum reference_kind { REFERENCE_EXACT = 0, REFERENCE_STOCHASTIC } reference_kind;

typedef struct reference_desc {
    int width, height;     /* display */
    reference_kind kind;   /* exact (default) or stochastic */
    int supersample;       /* S, 0 = default */
    int samples;           /* K (even), 0 = default; exact: the overflow fallback's tests */
    int list_mb;           /* exact: fragment-list budget in MB, 0 = default; the GL limit caps it */
    uint64_t list_nodes;   /* exact, for tests: the budget in nodes (overrides list_mb) */
    const char *cache_dir; /* where frames are cached; NULL = no cache */
    /* Called after every pass of a frame that is drawn (not for cached frames); may be NULL. */
    void (*on_pass)(void *user, int done, int total);
    void *user;
} reference_desc;

typedef struct reference_info {
    bool cached;       /* read from the cache, not drawn */
    bool rebuilt;      /* something existed at the cache path but was unusable (truncated, stale,
                        * checksum mismatch, not a regular file) and the frame was redrawn */
    double error;      /* convergence: exact RMS(ref_S - ref_C), stochastic RMS((A - B) / 2), over
                        * linear RGB (see above) */
    int passes;        /* passes drawn (0 when cached) */
    long overflow_pixels; /* exact: sub-sample pixels whose lists overflowed and fell back (summed
                           * over the sub-samples of the frame; 0 when cached) */
    uint64_t list_nodes;  /* exact: the most list nodes one pass asked for (0 when cached) */
    long long_lists;      /* exact: sub-sample pixels whose lists were longer than the GPU resolve
                           * sorts (ABUFFER_RESOLVE_MAX), resolved on the CPU (0 when cached) */
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
/* Kind, S and K in effect. */
reference_kind reference_get_kind(const reference *rf);
int reference_supersample(const reference *rf);
int reference_samples(const reference *rf);
/* Exact: the grid the error estimate compares with (S / 2 rounded down, or 2 when S = 1). */
int reference_compare_grid(const reference *rf);
/* Passes a drawn frame takes: exact S * S (+ C * C for odd S; without fallbacks), stochastic S * S * K. */
int reference_pass_count(const reference *rf);
/* One line for people: "exact (A-buffer), 4x4 sub-samples" or "stochastic, 4x4 sub-samples x 64
 * alpha tests". */
const char *reference_describe(const reference *rf);
/* "exact" or "stochastic". */
const char *reference_kind_name(reference_kind k);

/* The default cache directory: $FOVSIM_CACHE, else $XDG_CACHE_HOME/fovsim/reference, else
 * $HOME/.cache/fovsim/reference, else .fovsim-cache/reference. Written into buf. */
void reference_default_cache_dir(char *buf, int size);

#endif
