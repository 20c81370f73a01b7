/* reference.c: the ground truth (see reference.h for the method and docs/reference.md for why). */
#include "reference/reference.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/embedded.h"
#include "core/file_read.h"
#include "core/hash.h"
#include "core/log.h"
#include "core/progress.h"
#include "gl/gl_device.h"
#include "passes/abuffer.h"
#include "passes/plan.h"
#include "passes/renderer.h"
#include "output/out_path.h"

/* Bump when the method changes what a reference frame holds: old cache files then miss.
 * 3: entries carry fovsim:ref_checksum (a tampered entry is drawn again). 4: the key holds the GL renderer and version
 * (a cache many machines share). */
#define REFERENCE_FORMAT_VERSION 4

enum { REF_CHANNELS = 5 }; /* R, G, B, A, coverage */
static const char *const k_channels[REF_CHANNELS] = {"R", "G", "B", "A", "coverage"};

struct reference {
    const scene *sc;
    reference_kind kind;
    int width, height, ss, k;
    /* exact, the error estimate: even S compares with the four (S/2) x (S/2) sub-grids of every
     * other sub-sample (sub: their RGB sums, 4 x 3 planes; no extra passes); odd S with a C x C
     * grid drawn for it (grid_c = S / 2, or 2 when S = 1). */
    int grid_c;
    float *sub;
    char cache_dir[900];
    char describe[128];
    plan pl;
    renderer *r;
    uint64_t base_key; /* scene content, shaders, size, kind, S, K, budget */
    bool animated;     /* instances sway: the frame's time decides the image too */
    /* Sums, REF_CHANNELS planes of width * height each: stochastic the two halves, exact the S grid
     * and the C grid. */
    float *half[2];
    /* exact */
    bool lists;              /* the scene has MASK or BLEND materials: a list pass runs */
    uint64_t budget_nodes;   /* the list store may grow to this many nodes */
    float *sample;           /* one resolved sub-sample, REF_CHANNELS planes */
    unsigned char *lost;     /* its pixels whose lists overflowed */
    abuffer_scratch scratch;
    plan fallback_pl;        /* the stochastic passes for overflowed pixels, made on first use */
    renderer *fallback;
    float *fallback_sum;
    void (*on_pass)(void *user, int done, int total);
    void *user;
};

const char *reference_kind_name(reference_kind k)
{
    return k == REFERENCE_STOCHASTIC ? "stochastic" : "exact";
}

void reference_default_cache_dir(char *buf, int size)
{
    const char *env = getenv("FOVSIM_CACHE"), *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    if (env && env[0])
        snprintf(buf, (size_t)size, "%s", env);
    else if (xdg && xdg[0])
        snprintf(buf, (size_t)size, "%s/fovsim/reference", xdg);
    else if (home && home[0])
        snprintf(buf, (size_t)size, "%s/.cache/fovsim/reference", home);
    else
        snprintf(buf, (size_t)size, ".fovsim-cache/reference");
}

/* Every embedded shader: a changed shader may change what the reference looks like. */
static uint64_t hash_shaders(uint64_t h)
{
    for (const embedded_file *f = embedded_files; f->path; f++)
        if (!strncmp(f->path, "shaders/", 8)) {
            h = hash_str(h, f->path);
            h = hash_bytes(h, f->data, f->size);
        }
    return h;
}

reference *reference_create(const scene *sc, const reference_desc *desc, fs_status *status)
{
    reference *rf = calloc(1, sizeof *rf);
    if (!rf) {
        *status = FS_ERR_NOMEM;
        return NULL;
    }
    rf->sc = sc;
    rf->kind = desc->kind;
    rf->width = desc->width;
    rf->height = desc->height;
    rf->ss = desc->supersample > 0 ? desc->supersample : REFERENCE_SUPERSAMPLE_DEFAULT;
    rf->k = desc->samples > 0 ? desc->samples : REFERENCE_SAMPLES_DEFAULT;
    FS_ASSERT(rf->ss <= REFERENCE_SUPERSAMPLE_MAX && rf->k <= REFERENCE_SAMPLES_MAX && rf->k % 2 == 0);
    if (desc->cache_dir) {
        snprintf(rf->cache_dir, sizeof rf->cache_dir, "%s", desc->cache_dir);
        out_dir_remove_stale_temps(rf->cache_dir); /* what killed runs left (README "Output folders") */
    }
    rf->on_pass = desc->on_pass;
    rf->user = desc->user;

    /* One full-resolution ring whose LOD bias makes each pass sample the mip level of an S x S
     * supersampled pixel (its derivatives are S times smaller). */
    fov_layout layout = fov_layout_off();
    layout.kind = FOV_LAYOUT_EXPLICIT;
    layout.rings[0].mip_bias = -log2f((float)rf->ss);
    plan_options po = {.width = rf->width, .height = rf->height, .frames = 1, .layout = layout, .reference = true};
    bool exact = rf->kind == REFERENCE_EXACT;
    po.reference_lists = exact;
    *status = plan_build(sc, &po, &rf->pl);
    rf->lists = exact && plan_find(&rf->pl, PLAN_PASS_FORWARD_LIST, ALPHA_MODE_DEFAULT) != NULL;
    rf->grid_c = rf->ss % 2 == 0 ? 0 : rf->ss >= 3 ? rf->ss / 2 : 2;
    size_t npix = (size_t)rf->width * (size_t)rf->height, n = npix * REF_CHANNELS;
    for (int h = 0; h < 2 && *status == FS_OK; h++)
        if (!(rf->half[h] = malloc(sizeof(float) * n)))
            *status = FS_ERR_NOMEM;
    if (*status == FS_OK && exact && (!(rf->sample = malloc(sizeof(float) * n)) || !(rf->lost = malloc(npix))))
        *status = FS_ERR_NOMEM;
    if (*status == FS_OK && exact && rf->grid_c == 0 && !(rf->sub = malloc(sizeof(float) * 12 * npix)))
        *status = FS_ERR_NOMEM;
    if (*status == FS_OK) {
        /* The budget in nodes: what the caller asked for, capped by what one GL store can hold. */
        uint64_t mb = desc->list_mb > 0 ? (uint64_t)desc->list_mb : REFERENCE_LIST_MB_DEFAULT;
        uint64_t budget = desc->list_nodes ? desc->list_nodes : (mb << 20) / sizeof(abuffer_node);
        uint64_t max = renderer_list_nodes_max();
        rf->budget_nodes = budget < max ? budget : max;
        /* Start with 4 nodes per pixel (within the budget); passes that need more grow it. */
        uint64_t start = 4 * (uint64_t)npix;
        rf->r = renderer_create(&(renderer_desc){.scene = sc, .plan = &rf->pl,
                                                 .list_nodes = start < rf->budget_nodes ? start : rf->budget_nodes},
                                status);
    }
    if (*status != FS_OK) {
        reference_destroy(rf);
        return NULL;
    }
    uint64_t h = hash_u64(hash_str(HASH_FNV_INIT, "fovsim reference"), REFERENCE_FORMAT_VERSION);
    h = hash_str(h, reference_kind_name(rf->kind)); /* exact and stochastic frames never collide */
    h = hash_u64(h, scene_content_hash(sc));
    h = hash_shaders(h);
    /* The GL that draws it: another GPU or driver can rasterise and filter slightly differently, and
     * a key must mean the same bytes also in a cache that many machines share (docs/reference.md "A cache on shared storage"). */
    const char *gl_renderer = gl_device_renderer(), *gl_version = gl_device_version();
    h = hash_str(h, gl_renderer ? gl_renderer : "");
    h = hash_str(h, gl_version ? gl_version : "");
    uint64_t dims[5] = {(uint64_t)rf->width, (uint64_t)rf->height, (uint64_t)rf->ss, (uint64_t)rf->k,
                        exact ? rf->budget_nodes : 0};
    for (int i = 0; i < 5; i++)
        h = hash_u64(h, dims[i]);
    rf->base_key = h;
    if (exact)
        snprintf(rf->describe, sizeof rf->describe, "exact (per-pixel fragment lists), %dx%d sub-samples", rf->ss, rf->ss);
    else
        snprintf(rf->describe, sizeof rf->describe, "stochastic, %dx%d sub-samples x %d alpha tests", rf->ss, rf->ss,
                 rf->k);
    rf->animated = scene_sway_count(sc) > 0;
    return rf;
}

void reference_destroy(reference *rf)
{
    if (!rf)
        return;
    renderer_destroy(rf->r);
    renderer_destroy(rf->fallback);
    free(rf->half[0]);
    free(rf->half[1]);
    free(rf->sample);
    free(rf->sub);
    free(rf->lost);
    free(rf->fallback_sum);
    abuffer_scratch_free(&rf->scratch);
    free(rf);
}

reference_kind reference_get_kind(const reference *rf)
{
    return rf->kind;
}

const char *reference_describe(const reference *rf)
{
    return rf->describe;
}

int reference_supersample(const reference *rf)
{
    return rf->ss;
}

int reference_samples(const reference *rf)
{
    return rf->k;
}

int reference_compare_grid(const reference *rf)
{
    return rf->grid_c ? rf->grid_c : rf->ss / 2;
}

int reference_pass_count(const reference *rf)
{
    return rf->kind == REFERENCE_EXACT ? rf->ss * rf->ss + rf->grid_c * rf->grid_c : rf->ss * rf->ss * rf->k;
}

uint64_t reference_key(const reference *rf, const frame_record *fr)
{
    /* view_proj holds the camera, the fov and the clip planes; the gaze does not enter. Swaying
     * instances move with time, so then the time enters (a still camera sees a new image). */
    uint64_t h = hash_floats(rf->base_key, fr->view_proj.m, 16);
    h = hash_floats(h, &fr->hfov_deg, 1);
    return rf->animated ? hash_floats(h, &fr->time, 1) : h;
}

/* >>cache */

static void key_hex(uint64_t key, char out[17])
{
    snprintf(out, 17, "%016" PRIx64, key);
}

/* The checksum of a frame's pixels, as 16 hex digits (docs/reference.md, "Cache"): 64-bit FNV-1a
 * (hash.h) over the channels R, G, B, A, coverage in that order, each its name (with the NUL)
 * then its width * height values row by row, top row first, each rounded to half as the file
 * stores it (exr_half_round), -0 as +0, fed as the 8 little-endian bytes of its float32 bits
 * (hash_floats). So the drawn frame and its cached copy have the same checksum, and a pixel
 * changed in the file, even by one half-float step, changes it. */
static void pixel_checksum(const exr_image *img, char out[17])
{
    uint64_t h = hash_str(HASH_FNV_INIT, "fovsim reference pixels");
    size_t w = (size_t)img->width;
    float *row = malloc(w * sizeof *row);
    for (int c = 0; c < REF_CHANNELS; c++) {
        const float *p = exr_image_channel(img, k_channels[c]);
        h = hash_str(h, k_channels[c]);
        for (int y = 0; p && row && y < img->height; y++) {
            for (size_t x = 0; x < w; x++)
                row[x] = exr_half_round(p[(size_t)y * w + x]);
            h = hash_floats(h, row, w);
        }
    }
    if (!row)
        h = 0; /* out of memory: a checksum that matches nothing written by a working run */
    free(row);
    key_hex(h, out);
}

typedef enum cache_result {
    CACHE_HIT = 0,
    CACHE_ABSENT,      /* no entry */
    CACHE_NOT_REGULAR, /* a directory, FIFO, socket or device at the entry's path */
    CACHE_BAD,         /* unreadable, truncated, another key, size or channels */
    CACHE_CHECKSUM,    /* reads back whole with the right key, but its pixels are not the ones written */
} cache_result;

/* A cached frame is usable when it is a regular file that reads back whole, with this key, size,
 * every channel and its pixels' checksum. Nothing but a regular file is opened (stat first; the
 * reader also opens without blocking and refuses anything else): a FIFO would wait for a writer. */
static cache_result cache_load(const reference *rf, const char *path, const char *hex, exr_image *img,
                               mode_t *mode)
{
    struct stat sb;
    *mode = 0;
    if (stat(path, &sb) != 0)
        return CACHE_ABSENT;
    *mode = sb.st_mode;
    if (!S_ISREG(sb.st_mode))
        return CACHE_NOT_REGULAR;
    log_set_quiet_errors(true); /* a broken cache file is expected here: we rebuild it */
    fs_status st = exr_read_file(path, img);
    log_set_quiet_errors(false);
    if (st != FS_OK)
        return CACHE_BAD;
    const exr_attr *k = exr_image_attr(img, "fovsim:ref_key");
    bool ok = img->width == rf->width && img->height == rf->height && k && k->type == FS_EXR_ATTR_STRING &&
              !strcmp(k->s, hex);
    for (int c = 0; c < REF_CHANNELS && ok; c++)
        ok = exr_image_channel(img, k_channels[c]) != NULL;
    if (!ok) {
        exr_image_free(img);
        return CACHE_BAD;
    }
    const exr_attr *sum = exr_image_attr(img, "fovsim:ref_checksum");
    char want[17];
    pixel_checksum(img, want);
    if (!sum || sum->type != FS_EXR_ATTR_STRING || strcmp(sum->s, want)) {
        exr_image_free(img);
        return CACHE_CHECKSUM;
    }
    return CACHE_HIT;
}

static const char *file_kind(mode_t m)
{
    return S_ISDIR(m) ? "a directory" : S_ISFIFO(m) ? "a FIFO" : S_ISSOCK(m) ? "a socket"
         : S_ISCHR(m) || S_ISBLK(m) ? "a device" : "not a regular file";
}

/* >>drawing */

/* Adds the first `count` planes (of n values) into a sum of as many planes; a broken sample must
 * not poison the truth. */
static void add_planes(float *sum, const float *const planes[REF_CHANNELS], int count, size_t n)
{
    for (int c = 0; c < count; c++) {
        const float *p = planes[c];
        float *s = sum + (size_t)c * n;
        for (size_t i = 0; i < n; i++)
            s[i] += isfinite(p[i]) ? p[i] : 0.0f;
    }
}

/* Adds the renderer's current frame into a sum. */
static fs_status accumulate(reference *rf, renderer *r, float *sum)
{
    exr_image img;
    fs_status st = renderer_read(r, &img);
    if (st != FS_OK)
        return st;
    const float *planes[REF_CHANNELS];
    for (int c = 0; c < REF_CHANNELS; c++)
        planes[c] = exr_image_channel(&img, k_channels[c]);
    add_planes(sum, planes, REF_CHANNELS, (size_t)rf->width * (size_t)rf->height);
    exr_image_free(&img);
    return FS_OK;
}

/* Sub-sample (sx, sy) of a grid x grid pattern in the pixel: the frame moved by its offset, with
 * the pass number `pass` in its index (the stochastic thresholds hash it: a new one every pass). */
static frame_record sub_sample(const reference *rf, const frame_record *fr0, int grid, int sx, int sy, int pass)
{
    display_desc d = frame_display(fr0, rf->width, rf->height);
    frame_record fr = *fr0;
    fov_layout off = rf->pl.layout;
    frame_record_set_gaze(&fr, &off, &d, 0.5f, 0.5f);
    frame_record_shift(&fr, &d, ((float)sx + 0.5f) / (float)grid - 0.5f, ((float)sy + 0.5f) / (float)grid - 0.5f);
    fr.index = (int)(((uint32_t)fr0->index * (uint32_t)reference_pass_count(rf) + (uint32_t)pass) & 0x7fffffffu);
    return fr;
}

static fs_status draw_stochastic(reference *rf, const frame_record *fr0, exr_image *img, reference_info *info)
{
    size_t n = (size_t)rf->width * (size_t)rf->height;
    memset(rf->half[0], 0, sizeof(float) * n * REF_CHANNELS);
    memset(rf->half[1], 0, sizeof(float) * n * REF_CHANNELS);
    int total = reference_pass_count(rf), done = 0;
    fs_status st = FS_OK;
    /* Sample k of every sub-sample before sample k + 1, so half A holds the first K/2 tests. */
    for (int k = 0; k < rf->k && st == FS_OK; k++)
        for (int sy = 0; sy < rf->ss && st == FS_OK; sy++)
            for (int sx = 0; sx < rf->ss && st == FS_OK; sx++) {
                frame_record fr = sub_sample(rf, fr0, rf->ss, sx, sy, done);
                st = renderer_draw(rf->r, &fr);
                if (st == FS_OK)
                    st = accumulate(rf, rf->r, rf->half[k < rf->k / 2 ? 0 : 1]);
                done++;
                if (rf->on_pass)
                    rf->on_pass(rf->user, done, total);
            }
    if (st != FS_OK)
        return st;
    if (!exr_image_init(img, rf->width, rf->height))
        return FS_ERR_NOMEM;
    double inv = 1.0 / (0.5 * total), err2 = 0.0;
    for (int c = 0; c < REF_CHANNELS; c++) {
        float *p = exr_image_add_channel(img, k_channels[c]);
        if (!p) {
            exr_image_free(img);
            return FS_ERR_NOMEM;
        }
        const float *a = rf->half[0] + (size_t)c * n, *b = rf->half[1] + (size_t)c * n;
        for (size_t i = 0; i < n; i++) {
            double ma = a[i] * inv, mb = b[i] * inv;
            /* Rounded as the cache stores it: a drawn frame and its cached copy measure alike. */
            p[i] = exr_half_round((float)(0.5 * (ma + mb)));
            if (c < 3)
                err2 += 0.25 * (ma - mb) * (ma - mb);
        }
    }
    info->error = sqrt(err2 / (3.0 * (double)n));
    info->passes = total;
    return FS_OK;
}

/* The overflowed pixels of one exact sub-sample from K stochastic tests of it (the stochastic
 * reference's passes, drawn whole: the lost pixels can lie anywhere). */
static fs_status exact_fallback(reference *rf, const frame_record *fr, float bias)
{
    size_t n = (size_t)rf->width * (size_t)rf->height;
    fs_status st = FS_OK;
    if (!rf->fallback) {
        plan_options po = {.width = rf->width, .height = rf->height, .frames = 1, .layout = rf->pl.layout,
                           .reference = true};
        st = plan_build(rf->sc, &po, &rf->fallback_pl);
        if (st == FS_OK && !(rf->fallback_sum = malloc(sizeof(float) * n * REF_CHANNELS)))
            st = FS_ERR_NOMEM;
        if (st == FS_OK)
            rf->fallback = renderer_create(&(renderer_desc){.scene = rf->sc, .plan = &rf->fallback_pl}, &st);
        if (st != FS_OK)
            return st;
    }
    renderer_set_mip_bias(rf->fallback, 0, bias);
    memset(rf->fallback_sum, 0, sizeof(float) * n * REF_CHANNELS);
    for (int k = 0; k < rf->k && st == FS_OK; k++) {
        frame_record f = *fr;
        f.index = (int)(((uint32_t)fr->index * (uint32_t)rf->k + (uint32_t)k) & 0x7fffffffu);
        st = renderer_draw(rf->fallback, &f);
        if (st == FS_OK)
            st = accumulate(rf, rf->fallback, rf->fallback_sum);
    }
    for (int c = 0; c < REF_CHANNELS && st == FS_OK; c++)
        for (size_t i = 0; i < n; i++)
            if (rf->lost[i])
                rf->sample[(size_t)c * n + i] = rf->fallback_sum[(size_t)c * n + i] / (float)rf->k;
    return st;
}

/* One exact sub-sample into rf->sample: the opaque pass's image with every pixel's fragment list
 * composited over it front to back, by the GPU resolve (list_resolve.frag), lists longer than it
 * sorts by its C twin (abuffer_resolve_pixel). A pass whose lists outgrow the store is drawn again
 * with a store grown to what it asked for, up to the budget; pixels that still lose fragments take
 * the stochastic estimate (exact_fallback). */
static fs_status exact_sample(reference *rf, const frame_record *fr, float bias, reference_info *info)
{
    size_t n = (size_t)rf->width * (size_t)rf->height;
    renderer_set_mip_bias(rf->r, 0, bias);
    fs_status st = renderer_draw(rf->r, fr);
    abuffer_lists l = {0};
    for (int attempt = 0; st == FS_OK && rf->lists; attempt++) {
        st = renderer_read_lists(rf->r, &l, false);
        if (st != FS_OK || l.count <= l.capacity || l.capacity >= rf->budget_nodes || attempt == 2)
            break;
        uint64_t want = l.count + l.count / 8;
        if (renderer_reserve_list_nodes(rf->r, want < rf->budget_nodes ? want : rf->budget_nodes) != FS_OK) {
            /* The GL could not give us the budget: keep what we have, and the fallback. */
            log_warn("REFERENCE: the GL has no room for %llu fragment-list nodes; overflowed pixels use %d "
                     "stochastic tests", (unsigned long long)want, rf->k);
            rf->budget_nodes = l.capacity;
            break;
        }
        st = renderer_draw(rf->r, fr);
    }
    exr_image img;
    if (st == FS_OK)
        st = renderer_read(rf->r, &img);
    if (st != FS_OK)
        return st;
    for (int c = 0; c < REF_CHANNELS; c++)
        memcpy(rf->sample + (size_t)c * n, exr_image_channel(&img, k_channels[c]), sizeof(float) * n);
    if (!rf->lists) {
        exr_image_free(&img);
        return FS_OK;
    }
    info->list_nodes = l.count > info->list_nodes ? l.count : info->list_nodes;
    const float *flag = exr_image_channel(&img, RENDERER_LIST_FLAG_CHANNEL);
    long lost = 0, longer = 0;
    for (size_t i = 0; i < n; i++) {
        rf->lost[i] = flag[i] == (float)ABUFFER_FLAG_OVERFLOW;
        lost += rf->lost[i];
        longer += flag[i] == (float)ABUFFER_FLAG_LONG;
    }
    if (longer > 0) { /* the C twin sorts what the GPU resolve had no room for */
        exr_image base;
        st = renderer_read_lists(rf->r, &l, true);
        if (st == FS_OK)
            st = renderer_read_opaque(rf->r, &base);
        bool have_base = st == FS_OK;
        const float *bp[REF_CHANNELS];
        for (int c = 0; c < REF_CHANNELS && have_base; c++)
            bp[c] = exr_image_channel(&base, k_channels[c]);
        for (size_t i = 0; i < n && st == FS_OK; i++) {
            if (flag[i] != (float)ABUFFER_FLAG_LONG)
                continue;
            float b[REF_CHANNELS], o[REF_CHANNELS];
            for (int c = 0; c < REF_CHANNELS; c++)
                b[c] = bp[c][i];
            int over = abuffer_resolve_pixel(&l, i, b, o, &rf->scratch);
            if (over < 0) {
                st = FS_ERR_NOMEM;
                break;
            }
            for (int c = 0; c < REF_CHANNELS; c++)
                rf->sample[(size_t)c * n + i] = o[c];
            rf->lost[i] = (unsigned char)over;
            lost += over;
        }
        if (have_base)
            exr_image_free(&base);
    }
    exr_image_free(&img);
    info->long_lists += longer;
    if (st == FS_OK && lost > 0) {
        info->overflow_pixels += lost;
        st = exact_fallback(rf, fr, bias);
    }
    return st;
}

/* The exact kind: the S x S grid, and for the error estimate its four sub-grids (even S) or a
 * C x C grid drawn for it (odd S). */
static fs_status draw_exact(reference *rf, const frame_record *fr0, exr_image *img, reference_info *info)
{
    size_t n = (size_t)rf->width * (size_t)rf->height;
    int grids[2] = {rf->ss, rf->grid_c}, total = reference_pass_count(rf), done = 0;
    fs_status st = FS_OK;
    if (rf->sub)
        memset(rf->sub, 0, sizeof(float) * 12 * n);
    for (int g = 0; g < 2 && grids[g] > 0 && st == FS_OK; g++) {
        memset(rf->half[g], 0, sizeof(float) * n * REF_CHANNELS);
        float bias = -log2f((float)grids[g]);
        for (int sy = 0; sy < grids[g] && st == FS_OK; sy++)
            for (int sx = 0; sx < grids[g] && st == FS_OK; sx++) {
                frame_record fr = sub_sample(rf, fr0, grids[g], sx, sy, done);
                st = exact_sample(rf, &fr, bias, info);
                if (st == FS_OK) {
                    const float *planes[REF_CHANNELS];
                    for (int c = 0; c < REF_CHANNELS; c++)
                        planes[c] = rf->sample + (size_t)c * n;
                    add_planes(rf->half[g], planes, REF_CHANNELS, n);
                    if (g == 0 && rf->sub) /* RGB of sub-grid (sx % 2, sy % 2) */
                        add_planes(rf->sub + (size_t)(3 * (2 * (sy % 2) + sx % 2)) * n, planes, 3, n);
                }
                done++;
                if (rf->on_pass)
                    rf->on_pass(rf->user, done, total);
            }
    }
    if (st != FS_OK)
        return st;
    if (!exr_image_init(img, rf->width, rf->height))
        return FS_ERR_NOMEM;
    int half = rf->ss / 2;
    double inv_s = 1.0 / (double)(rf->ss * rf->ss), err2 = 0.0;
    double inv_c = rf->grid_c ? 1.0 / (double)(rf->grid_c * rf->grid_c) : 1.0 / (double)(half * half);
    for (int c = 0; c < REF_CHANNELS; c++) {
        float *p = exr_image_add_channel(img, k_channels[c]);
        if (!p) {
            exr_image_free(img);
            return FS_ERR_NOMEM;
        }
        const float *a = rf->half[0] + (size_t)c * n;
        for (size_t i = 0; i < n; i++) {
            double ms = a[i] * inv_s;
            p[i] = exr_half_round((float)ms); /* rounded as the cache stores it */
            if (c >= 3)
                continue;
            if (rf->grid_c) {
                double mc = rf->half[1][(size_t)c * n + i] * inv_c;
                err2 += (ms - mc) * (ms - mc);
            } else {
                for (int k = 0; k < 4; k++) {
                    double mc = rf->sub[(size_t)(3 * k + c) * n + i] * inv_c;
                    err2 += 0.25 * (ms - mc) * (ms - mc);
                }
            }
        }
    }
    info->error = sqrt(err2 / (3.0 * (double)n));
    info->passes = total;
    return FS_OK;
}

/* >>the entry's lock */

/* The lock of a cache entry, ref-KEY.lock beside it: an exclusive flock(2) held while the entry is
 * drawn and written, so that processes sharing the cache (a sweep's tasks, on one machine or on a
 * cluster's shared storage) draw each frame once: the one that takes the lock draws, the others
 * wait for it and then read the entry. Polled (a blocking flock cannot be interrupted); the kernel
 * releases the lock of a process that dies, so a killed writer blocks nobody. The lock files stay:
 * removing one could split waiters between two files (but see unlock_entry). -1 when no lock
 * can be had (a read-only cache, a file system without locks): the frame is then drawn unlocked,
 * as before. `path` (n bytes) receives the lock's path. */
static int lock_entry(const char *dir, const char *hex, char *path, size_t n)
{
    snprintf(path, n, "%s/ref-%s.lock", dir, hex);
    int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) {
        log_info("REFERENCE: %s: cannot open the entry's lock (%s); drawing unlocked", path, strerror(errno));
        return -1;
    }
    bool said = false;
    while (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        if (errno != EWOULDBLOCK && errno != EAGAIN && errno != EINTR) {
            log_info("REFERENCE: %s: cannot lock (%s); drawing unlocked", path, strerror(errno));
            close(fd);
            return -1;
        }
        if (!said)
            log_info("REFERENCE: another process is drawing %s/ref-%s.exr; waiting for it", dir, hex);
        said = true;
        nanosleep(&(struct timespec){.tv_nsec = 100 * 1000 * 1000}, NULL);
    }
    return fd;
}

/* Releases the lock (closing the last descriptor releases the flock). After a failure (a full
 * disk, a failed draw) its file goes too, so that a run that writes nothing leaves nothing in the
 * cache; a process waiting on it then draws under a file a newcomer does not see, which at worst
 * draws the frame twice, never wrongly. */
static void unlock_entry(int fd, const char *path, bool failed)
{
    if (fd < 0)
        return;
    if (failed)
        unlink(path);
    close(fd);
}

/* The cached entry when it is usable (a hit fills img and info); *cr says why not. */
static bool cache_hit(reference *rf, const char *hex, exr_image *img, reference_info *info, cache_result *cr,
                      mode_t *mode)
{
    *cr = cache_load(rf, info->path, hex, img, mode);
    if (*cr != CACHE_HIT)
        return false;
    const exr_attr *e = exr_image_attr(img, "fovsim:ref_error");
    info->error = e && e->type == FS_EXR_ATTR_FLOAT ? e->f[0] : 0.0;
    info->cached = true;
    return true;
}

/* What a miss says: nothing when absent, a line when something unusable was there; an error for a
 * directory at the entry's path. */
static fs_status report_miss(const reference_info *info, cache_result cr, mode_t mode)
{
    if (cr == CACHE_BAD)
        log_info("REFERENCE: %s is truncated or stale; drawing it again", info->path);
    else if (cr == CACHE_CHECKSUM)
        log_warn("REFERENCE: %s: its pixels do not match their checksum (changed after it was written); "
                 "drawing it again", info->path);
    else if (cr == CACHE_NOT_REGULAR && S_ISDIR(mode)) {
        /* One rule for an entry the cache cannot hold (docs/reference.md "Cache"): the run fails with one line,
         * as it does when the cache folder cannot be made or written; before, a directory here
         * was bypassed with a warning and every run drew the frame again. */
        log_error("%s: is a directory where the reference cache keeps an entry; remove it or use another "
                  "--cache", info->path);
        return FS_ERR_IO;
    } else if (cr == CACHE_NOT_REGULAR)
        log_warn("REFERENCE: %s is %s, not a cache entry; drawing the frame and replacing it", info->path,
                 file_kind(mode));
    return FS_OK;
}

static fs_status draw_frame(reference *rf, const frame_record *fr, const char *hex, exr_image *img,
                            reference_info *info);

fs_status reference_frame(reference *rf, const frame_record *fr, exr_image *img, reference_info *info)
{
    memset(info, 0, sizeof *info);
    info->key = reference_key(rf, fr);
    char hex[17];
    key_hex(info->key, hex);
    if (!rf->cache_dir[0])
        return draw_frame(rf, fr, hex, img, info);
    snprintf(info->path, sizeof info->path, "%s/ref-%s.exr", rf->cache_dir, hex);
    mode_t mode = 0;
    cache_result cr;
    if (cache_hit(rf, hex, img, info, &cr, &mode))
        return FS_OK;
    /* A miss: the folder (a run that cannot make it fails before drawing), the entry's lock, and a
     * second look, for the lock's holder may have just written the entry. */
    fs_status st = file_make_dirs(rf->cache_dir);
    if (st != FS_OK)
        return st;
    char lock_path[1100];
    int lock = lock_entry(rf->cache_dir, hex, lock_path, sizeof lock_path);
    if (lock >= 0 && cache_hit(rf, hex, img, info, &cr, &mode)) {
        unlock_entry(lock, lock_path, false);
        return FS_OK;
    }
    info->rebuilt = cr != CACHE_ABSENT;
    st = report_miss(info, cr, mode);
    if (st == FS_OK)
        st = draw_frame(rf, fr, hex, img, info);
    if (st == FS_OK) {
        st = exr_write_file(info->path, img, EXR_COMPRESS_ZIP);
        if (st != FS_OK)
            exr_image_free(img);
    }
    unlock_entry(lock, lock_path, st != FS_OK);
    return st;
}

/* >>drawing a frame */

/* Draws the frame and sets its attributes (key, kind, error and how it was measured, checksum). */
static fs_status draw_frame(reference *rf, const frame_record *fr, const char *hex, exr_image *img,
                            reference_info *info)
{
    bool exact = rf->kind == REFERENCE_EXACT;
    fs_status st = exact ? draw_exact(rf, fr, img, info) : draw_stochastic(rf, fr, img, info);
    if (st != FS_OK)
        return st;
    exr_image_set_string(img, "fovsim:ref_key", hex);
    exr_image_set_string(img, "fovsim:ref_kind", reference_kind_name(rf->kind));
    exr_image_set_float(img, "fovsim:ref_error", (float)info->error);
    char what[200];
    if (exact && rf->grid_c)
        snprintf(what, sizeof what, "RMS over linear RGB of this frame minus the same drawn at %dx%d sub-samples",
                 rf->grid_c, rf->grid_c);
    else if (exact)
        snprintf(what, sizeof what, "RMS over linear RGB of this frame minus each of its four %dx%d sub-grids (every "
                 "other sub-sample)", rf->ss / 2, rf->ss / 2);
    else
        snprintf(what, sizeof what, "RMS over linear RGB of half the difference of the two halves of the %d tests", rf->k);
    exr_image_set_string(img, "fovsim:ref_error_method", what);
    snprintf(what, sizeof what, "%s, box filter, LOD bias %.2f", rf->describe, (double)-log2f((float)rf->ss));
    exr_image_set_string(img, "fovsim:ref_samples", what);
    if (exact)
        exr_image_set_int(img, "fovsim:ref_overflow_pixels", (int)(info->overflow_pixels < INT32_MAX ? info->overflow_pixels : INT32_MAX));
    exr_image_set_float(img, "fovsim:time", fr->time);
    char sum[17];
    pixel_checksum(img, sum);
    exr_image_set_string(img, "fovsim:ref_checksum", sum);
    return FS_OK;
}
