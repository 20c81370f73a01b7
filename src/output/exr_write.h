/* exr_write.h: OpenEXR output through the Core C API (openexr.h), and a reader for tests.
 *
 * An exr_image is a set of named float planes (one per channel, rows top first) plus header
 * attributes. exr_write_file stores it as a scanline EXR with half-float pixels and ZIP
 * compression (default) — values beyond ±65504 are clamped and NaN becomes 0, so a file never
 * holds Inf or NaN. ZIP uses deflate level EXR_ZIP_LEVEL_DEFAULT. The file is written to a
 * temporary name in the same directory (`.<name>.tmp.<host>.<pid>.<n>`, out_path_temp_name, <n>
 * new for every write) and renamed over the final name only when complete: an interrupted or
 * failed write (a full disk) never leaves a truncated frame under the final name. That holds also when the disk is full
 * before the first byte (the header write fails): the Core's error callback never calls back into
 * the Core, whose context lock is held then (see tl_stream in exr_write.c).
 *
 * exr_writer runs exr_write_file on background threads (exr_writer_desc.thread_count, each
 * writing whole frames) fed by a bounded queue (EXR_QUEUE_DEPTH), so rendering does not wait on
 * compression. Frames are independent files and may complete in any order; two frames queued for
 * the same path (the same string) are written one after the other, in submission order, the
 * queue waiting meanwhile. The first failure is kept and returned by exr_writer_finish (and by
 * later submits).
 *
 * Multi-part files (the comparison frames of `fovsim compare`): an exr_image heads a chain of
 * further parts (exr_image_append_part). A chain of two or more parts is written as a multi-part
 * file, part 0 first: each part a scanline part with its own name (required, unique), size,
 * channels and custom attributes; compression and deflate level are the same for every part. The
 * format requires the shared attributes (displayWindow, pixelAspectRatio) to be equal in every
 * part, so all parts get one display window, (0,0) to (largest width - 1, largest height - 1),
 * and each part's data window is its own size at the origin. Readers unaware of parts (old
 * libraries, most viewers) show part 0: put the picture everyone should see there. An image with
 * no next_part is written exactly as before (a plain single-part file, which also carries the
 * name attribute when part_name is set).
 *
 * What it does NOT do: tiled or deep files, mip levels, choosing file names (callers do:
 * `<name>.<frame:04d>.exr`).
 */
#ifndef FOVSIM_EXR_WRITE_H
#define FOVSIM_EXR_WRITE_H

#include <stdbool.h>
#include <stddef.h>

#include "core/status.h"

#ifndef EXR_MAX_CHANNELS
/* Channels in one part. The "layers" part of a comparison frame holds 6 per alpha mode
 * (<mode>.R/G/B/A, .coverage, .error) for up to 9 modes, the reference's 5 and ring.id: 60;
 * twice that with two views (a head-mounted display's eyes): 120. */
#define EXR_MAX_CHANNELS 192
#endif
#ifndef EXR_MAX_ATTRS
/* Custom header attributes in one part: a render frame has about 25; a two-view frame keeps the
 * shared ones once plus the right eye's own (gaze, ...), and multiView. */
#define EXR_MAX_ATTRS 48
#endif
#ifndef EXR_MAX_VECTOR_STRINGS
#define EXR_MAX_VECTOR_STRINGS 16 /* strings in one string-vector attribute (views of a file) */
#endif
#ifndef EXR_MAX_WRITER_THREADS
#define EXR_MAX_WRITER_THREADS 16 /* most threads one exr_writer runs */
#endif
/* Deflate level (1 fastest .. 9 smallest) of ZIP files; zlib's own default is 6. 4 writes a
 * frame in about 25-40 % less time than 6 for files about 3 % larger (numbers in exr_write.c). */
#ifndef EXR_ZIP_LEVEL_DEFAULT
#define EXR_ZIP_LEVEL_DEFAULT 4
#endif

typedef enum exr_attr_type {
    FS_EXR_ATTR_STRING = 0,
    FS_EXR_ATTR_INT,
    FS_EXR_ATTR_FLOAT,
    FS_EXR_ATTR_V2F,
    FS_EXR_ATTR_STRING_VECTOR, /* OpenEXR's stringvector (the multiView attribute) */
} exr_attr_type;

typedef struct exr_attr {
    char name[64];
    exr_attr_type type;
    char s[512];  /* FS_EXR_ATTR_STRING; FS_EXR_ATTR_STRING_VECTOR: the i strings one after the
                   * other, each ending in '\0' (exr_attr_string_at) */
    int i;        /* FS_EXR_ATTR_INT; FS_EXR_ATTR_STRING_VECTOR: the number of strings */
    float f[2];   /* FS_EXR_ATTR_FLOAT uses f[0]; FS_EXR_ATTR_V2F uses both */
} exr_attr;

typedef struct exr_image {
    int width, height;
    int channel_count;
    char channel_names[EXR_MAX_CHANNELS][64]; /* e.g. "R", "coverage", "hashed.R" */
    float *planes[EXR_MAX_CHANNELS];          /* width * height floats each, owned */
    int attr_count;
    exr_attr attrs[EXR_MAX_ATTRS];
    char part_name[64];              /* the part's "name" attribute; "" = unnamed (only a
                                      * single-part file may have an unnamed part) */
    struct exr_image *next_part;     /* the next part of a multi-part file, or NULL; owned (heap,
                                      * freed with this image by exr_image_free) */
} exr_image;

typedef enum exr_compression_kind {
    EXR_COMPRESS_ZIP = 0, /* default */
    EXR_COMPRESS_NONE,
    EXR_COMPRESS_PIZ,
} exr_compression_kind;

/* Sets up an image with no channels and no further parts (all of *img is overwritten: free a
 * used image first). Returns false on bad size. */
bool exr_image_init(exr_image *img, int width, int height);
/* Adds a zero-filled channel; returns its plane, or NULL (no memory / too many / duplicate name). */
float *exr_image_add_channel(exr_image *img, const char *name);
/* The plane of a channel by name, or NULL. Borrowed: valid until exr_image_free. */
float *exr_image_channel(const exr_image *img, const char *name);
void exr_image_set_string(exr_image *img, const char *name, const char *value);
void exr_image_set_int(exr_image *img, const char *name, int value);
void exr_image_set_float(exr_image *img, const char *name, float value);
void exr_image_set_v2f(exr_image *img, const char *name, float x, float y);
/* A stringvector attribute of `count` strings. Unlike the setters above it truncates nothing:
 * false (and nothing set) when count is outside 0..EXR_MAX_VECTOR_STRINGS or the strings with
 * their terminators exceed sizeof exr_attr.s. */
bool exr_image_set_string_vector(exr_image *img, const char *name, const char *const *values,
                                 int count);
/* String k of a FS_EXR_ATTR_STRING_VECTOR attribute, or NULL (other type, k out of range). */
const char *exr_attr_string_at(const exr_attr *a, int k);
/* An attribute by name, or NULL. */
const exr_attr *exr_image_attr(const exr_image *img, const char *name);
/* Sets the part name ("" for none). Returns false when longer than 63 characters. */
bool exr_image_set_part_name(exr_image *img, const char *name);
/* Appends `part` (and any parts chained after it) at the end of first's chain. Takes ownership:
 * part's planes and chain move into a heap copy owned by `first`, and *part is zeroed, as after
 * exr_image_free. On failure (no memory; part == first) returns false and leaves both untouched,
 * `part` still the caller's to free. */
bool exr_image_append_part(exr_image *first, exr_image *part);
/* Parts in the chain headed by `img` (1 for a plain image, 0 for NULL). */
int exr_image_part_count(const exr_image *img);
/* Part `index` of the chain (0 = img itself), or NULL. Borrowed: valid until exr_image_free of
 * the head. */
exr_image *exr_image_part(const exr_image *img, int index);
/* Frees planes and every further part; no-op on a zeroed image. */
void exr_image_free(exr_image *img);
/* Frees *dst and moves *src into it; *src is left empty (a frame becoming the previous one). */
void exr_image_move(exr_image *dst, exr_image *src);

/* >>views: two eyes in one file, OpenEXR's multi-view convention ("Storing Multi-View Images in
 * OpenEXR Files", single-part scheme; docs/output.md "Two eyes: multi-view EXR").
 *
 * A `multiView` stringvector attribute lists the views; the first is the default view. A channel
 * whose name has no '.' belongs to the default view; otherwise the view is the name's
 * second-last '.'-separated component, and a channel whose second-last component is not a view
 * belongs to no view. So a view's channel `base` is stored as: default view, `base` without a
 * '.' -> `base` ("R", "coverage"); any other view, or a layered `base` -> the view inserted before
 * the last component ("right.R", "right.coverage", "hashed.left.R", "hashed.right.R"). This is
 * what OpenEXR's own exrmultiview and ImfMultiView.h (insertViewName) produce.
 *
 * Attributes have no such convention. exr_image_join_views keeps every attribute of the default
 * view unprefixed and stores another view's attribute only where it differs from the default
 * view's (or the default view lacks it), as `<view>.<name>` ("right.fovsim:gaze").
 * exr_image_extract_view undoes both. An attribute only the default view has reads as shared. */
#define EXR_MAX_VIEWS EXR_MAX_VECTOR_STRINGS
/* Sets img's multiView attribute to `views` (count >= 1; views[0] is the default view). A view
 * name is 1..31 characters without '.' or white space (the convention forbids periods and
 * spaces), and no two are alike. False, with a warning and nothing set, otherwise. */
bool exr_image_set_views(exr_image *img, const char *const *views, int count);
/* The number of views img's multiView attribute lists (0: none, a single-view image). */
int exr_image_view_count(const exr_image *img);
/* View k of img's multiView attribute (0 = the default view), or NULL. */
const char *exr_image_view_name(const exr_image *img, int k);
/* The name channel `base` of view `view` gets in a multi-view file (rule above); default_view
 * says whether `view` is the file's first view. False when it does not fit in cap bytes. */
bool exr_view_channel_name(const char *base, const char *view, bool default_view, char *out,
                           size_t cap);
/* Which of img's views channel `name` belongs to: its index in the multiView list, or -1 (no
 * view, or img has no multiView). When it belongs to one and base is not NULL, *base (cap bytes)
 * gets the name without the view ("hashed.right.R" -> "hashed.R", "right.R" -> "R"). */
int exr_channel_view(const exr_image *img, const char *name, char *base, size_t cap);
/* Joins `count` single-view images of one size (views[k] names images[k]; views[0] is the
 * default view) into *out, one single-part multi-view image: channels renamed by the rule above,
 * attributes as above, the multiView attribute, part name and next_part none. The images are
 * copied, not consumed. Refused (FS_ERR_INTERNAL, or FS_ERR_NOMEM, with a one-line message; *out
 * left empty): count outside 1..EXR_MAX_VIEWS, a bad view name, an image with further parts or
 * its own multiView, sizes that differ, a channel or attribute name that already holds a view
 * name where the rule puts one, too many channels or attributes in all. */
fs_status exr_image_join_views(exr_image *out, const exr_image *const *images,
                               const char *const *views, int count);
/* The same, moving the planes instead of copying them: on success every image is left empty,
 * as after exr_image_free; on failure all are untouched. Copying two 1280x720 eyes of 6 channels
 * took 22 ms of CPU, moving them 0.013 ms, writing the joined file (ZIP level 4) 152 ms
 * (best of 5, process CPU time, AMD EPYC 2 cores shared with other helpers' builds). */
fs_status exr_image_join_views_move(exr_image *out, exr_image *const *images,
                                    const char *const *views, int count);
/* exr_image_join_views of two eyes: views "left" (the default view: every viewer that knows
 * nothing of views shows it) and "right"; and the moving form. */
fs_status exr_image_join_eyes(exr_image *out, const exr_image *left, const exr_image *right);
fs_status exr_image_join_eyes_move(exr_image *out, exr_image *left, exr_image *right);
/* The single-view image of view `view` of multi-view image img (as read by exr_read_file):
 * its channels under their base names, the attributes of that view (shared ones and its own
 * `<view>.` ones, unprefixed), no multiView. FS_ERR_IO with a message when img has no such view
 * or the view has no channels; FS_ERR_NOMEM. */
fs_status exr_image_extract_view(const exr_image *img, const char *view, exr_image *out);

/* f as exr_write_file stores it, read back: rounded to the nearest half-float (ties to even), NaN
 * as 0, clamped to +-65504. Lets a value computed now equal the same value read from a file. */
float exr_half_round(float f);
/* Writes `img` (with its chain of parts, if any) to `path` atomically (see above). Prints
 * `<path>: <what>` on failure and returns FS_ERR_IO; nothing is left at `path` or at the
 * temporary name. */
fs_status exr_write_file(const char *path, const exr_image *img, exr_compression_kind compression);
/* Reads part 0: every channel as float, every string/int/float/v2f/stringvector attribute (a
 * stringvector that does not fit an exr_attr is left out with a warning) and the part name
 * into *out (for tests and for golden comparisons); out->next_part is NULL. FS_ERR_IO with a
 * message on failure. */
fs_status exr_read_file(const char *path, exr_image *out);
/* The same for part `part_index` (0-based). Whichever part is asked for, a file whose chunks do
 * not all lie inside it (truncated) is refused, so a damaged frame never reads as complete. */
fs_status exr_read_part(const char *path, int part_index, exr_image *out);
/* Number of parts in the file (1 for a single-part file) into *count, from the headers alone
 * (pixels are not checked: exr_read_part does that). FS_ERR_IO with a message when the file
 * cannot be read or its headers are not a valid EXR. */
fs_status exr_file_part_count(const char *path, int *count);

/* >>writer threads */

typedef struct exr_writer exr_writer;

/* Zero in any field means "default". Memory: up to queue_depth + thread_count frames are held
 * (queued or being written) besides the caller's own. */
typedef struct exr_writer_desc {
    exr_compression_kind compression; /* default ZIP */
    int queue_depth;                  /* frames queued before submit blocks;
                                       * default EXR_QUEUE_DEPTH */
    int thread_count;                 /* writer threads; default: online CPUs
                                       * (sysconf(_SC_NPROCESSORS_ONLN)); clamped to
                                       * [1, EXR_MAX_WRITER_THREADS] */
    int zip_level;                    /* deflate level 1..9 for ZIP (larger is clamped to 9);
                                       * default EXR_ZIP_LEVEL_DEFAULT */
    double *cpu_seconds;              /* NULL, or where exr_writer_finish stores the CPU time
                                       * its threads used, all together (--verbose timing) */
} exr_writer_desc;

/* `*d` (NULL: all zero) with zero or negative fields (and an unknown compression) replaced by
 * their defaults, and thread_count and zip_level clamped to their ranges. */
exr_writer_desc exr_writer_desc_defaults(const exr_writer_desc *d);
/* Starts the writer threads; NULL when out of memory or no thread can start (fewer threads than
 * asked for only warn). `desc` may be NULL (all defaults). */
exr_writer *exr_writer_create(const exr_writer_desc *desc);
/* Queues `img` for `path`; the writer takes ownership of img's planes and its chain of parts
 * (img is zeroed). Blocks
 * while the queue is full. Returns the first error of an earlier write, if any (then img is freed
 * and nothing is queued). Not to be called after exr_writer_finish. */
fs_status exr_writer_submit(exr_writer *w, const char *path, exr_image *img);
/* Waits for all queued writes, stops and joins the threads, frees the writer; returns the first
 * error. */
fs_status exr_writer_finish(exr_writer *w);

#endif
