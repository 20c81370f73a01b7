/* reference.c: the ground truth (see reference.h for the method and docs/reference.md for why). */
#include "reference/reference.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/embedded.h"
#include "core/file_read.h"
#include "core/hash.h"
#include "core/log.h"
#include "passes/plan.h"
#include "passes/renderer.h"

/* Bump when the method changes what a reference frame holds: old cache files then miss. */
#define REFERENCE_FORMAT_VERSION 1

enum { REF_CHANNELS = 5 }; /* R, G, B, A, coverage */
static const char *const k_channels[REF_CHANNELS] = {"R", "G", "B", "A", "coverage"};

struct reference {
    const scene *sc;
    int width, height, ss, k;
    char cache_dir[900];
    plan pl;
    renderer *r;
    uint64_t base_key; /* scene content, shaders, size, S, K */
    bool animated;     /* instances sway: the frame's time decides the image too */
    float *half[2];    /* sums of the two halves, REF_CHANNELS planes of width * height each */
    void (*on_pass)(void *user, int done, int total);
    void *user;
};

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
    rf->width = desc->width;
    rf->height = desc->height;
    rf->ss = desc->supersample > 0 ? desc->supersample : REFERENCE_SUPERSAMPLE_DEFAULT;
    rf->k = desc->samples > 0 ? desc->samples : REFERENCE_SAMPLES_DEFAULT;
    FS_ASSERT(rf->ss <= REFERENCE_SUPERSAMPLE_MAX && rf->k <= REFERENCE_SAMPLES_MAX && rf->k % 2 == 0);
    if (desc->cache_dir)
        snprintf(rf->cache_dir, sizeof rf->cache_dir, "%s", desc->cache_dir);
    rf->on_pass = desc->on_pass;
    rf->user = desc->user;

    /* One full-resolution ring whose LOD bias makes each pass sample the mip level of an S x S
     * supersampled pixel (its derivatives are S times smaller). */
    fov_layout layout = fov_layout_off();
    layout.kind = FOV_LAYOUT_EXPLICIT;
    layout.rings[0].mip_bias = -log2f((float)rf->ss);
    plan_options po = {.width = rf->width, .height = rf->height, .frames = 1, .layout = layout, .reference = true};
    *status = plan_build(sc, &po, &rf->pl);
    size_t n = (size_t)rf->width * (size_t)rf->height * REF_CHANNELS;
    for (int h = 0; h < 2 && *status == FS_OK; h++)
        if (!(rf->half[h] = malloc(sizeof(float) * n)))
            *status = FS_ERR_NOMEM;
    if (*status == FS_OK)
        rf->r = renderer_create(&(renderer_desc){.scene = sc, .plan = &rf->pl}, status);
    if (*status != FS_OK) {
        reference_destroy(rf);
        return NULL;
    }
    uint64_t h = hash_u64(hash_str(HASH_FNV_INIT, "fovsim reference"), REFERENCE_FORMAT_VERSION);
    h = hash_u64(h, scene_content_hash(sc));
    h = hash_shaders(h);
    uint64_t dims[4] = {(uint64_t)rf->width, (uint64_t)rf->height, (uint64_t)rf->ss, (uint64_t)rf->k};
    for (int i = 0; i < 4; i++)
        h = hash_u64(h, dims[i]);
    rf->base_key = h;
    rf->animated = scene_sway_count(sc) > 0;
    return rf;
}

void reference_destroy(reference *rf)
{
    if (!rf)
        return;
    renderer_destroy(rf->r);
    free(rf->half[0]);
    free(rf->half[1]);
    free(rf);
}

int reference_supersample(const reference *rf)
{
    return rf->ss;
}

int reference_samples(const reference *rf)
{
    return rf->k;
}

int reference_pass_count(const reference *rf)
{
    return rf->ss * rf->ss * rf->k;
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

/* A cached frame is usable when it reads back whole, with this key, size and every channel. */
static bool cache_load(const reference *rf, const char *path, const char *hex, exr_image *img, bool *existed)
{
    FILE *f = fopen(path, "rb");
    *existed = f != NULL;
    if (!f)
        return false;
    fclose(f);
    log_set_quiet_errors(true); /* a broken cache file is expected here: we rebuild it */
    fs_status st = exr_read_file(path, img);
    log_set_quiet_errors(false);
    if (st != FS_OK)
        return false;
    const exr_attr *k = exr_image_attr(img, "fovsim:ref_key");
    bool ok = img->width == rf->width && img->height == rf->height && k && k->type == FS_EXR_ATTR_STRING &&
              !strcmp(k->s, hex);
    for (int c = 0; c < REF_CHANNELS && ok; c++)
        ok = exr_image_channel(img, k_channels[c]) != NULL;
    if (!ok)
        exr_image_free(img);
    return ok;
}

/* >>drawing */

/* Adds the renderer's current frame into one half's sums. */
static fs_status accumulate(reference *rf, float *sum)
{
    exr_image img;
    fs_status st = renderer_read(rf->r, &img);
    if (st != FS_OK)
        return st;
    size_t n = (size_t)rf->width * (size_t)rf->height;
    for (int c = 0; c < REF_CHANNELS; c++) {
        const float *p = exr_image_channel(&img, k_channels[c]);
        float *s = sum + (size_t)c * n;
        for (size_t i = 0; i < n; i++)
            s[i] += isfinite(p[i]) ? p[i] : 0.0f; /* a broken sample must not poison the truth */
    }
    exr_image_free(&img);
    return FS_OK;
}

static fs_status draw(reference *rf, const frame_record *fr0, exr_image *img, reference_info *info)
{
    size_t n = (size_t)rf->width * (size_t)rf->height;
    memset(rf->half[0], 0, sizeof(float) * n * REF_CHANNELS);
    memset(rf->half[1], 0, sizeof(float) * n * REF_CHANNELS);
    display_desc d = {rf->width, rf->height, fr0->hfov_deg};
    int total = reference_pass_count(rf), done = 0;
    fs_status st = FS_OK;
    /* Sample k of every sub-sample before sample k + 1, so half A holds the first K/2 tests. */
    for (int k = 0; k < rf->k && st == FS_OK; k++)
        for (int sy = 0; sy < rf->ss && st == FS_OK; sy++)
            for (int sx = 0; sx < rf->ss && st == FS_OK; sx++) {
                frame_record fr = *fr0;
                fov_layout off = rf->pl.layout;
                frame_record_set_gaze(&fr, &off, &d, 0.5f, 0.5f);
                frame_record_shift(&fr, &d, ((float)sx + 0.5f) / (float)rf->ss - 0.5f,
                                   ((float)sy + 0.5f) / (float)rf->ss - 0.5f);
                /* The stochastic thresholds hash the frame index: a new one for every pass. */
                fr.index = (int)(((uint32_t)fr0->index * (uint32_t)total + (uint32_t)done) & 0x7fffffffu);
                st = renderer_draw(rf->r, &fr);
                if (st == FS_OK)
                    st = accumulate(rf, rf->half[k < rf->k / 2 ? 0 : 1]);
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

fs_status reference_frame(reference *rf, const frame_record *fr, exr_image *img, reference_info *info)
{
    memset(info, 0, sizeof *info);
    info->key = reference_key(rf, fr);
    char hex[17];
    key_hex(info->key, hex);
    if (rf->cache_dir[0]) {
        snprintf(info->path, sizeof info->path, "%s/ref-%s.exr", rf->cache_dir, hex);
        bool existed = false;
        if (cache_load(rf, info->path, hex, img, &existed)) {
            const exr_attr *e = exr_image_attr(img, "fovsim:ref_error");
            info->error = e && e->type == FS_EXR_ATTR_FLOAT ? e->f[0] : 0.0;
            info->cached = true;
            return FS_OK;
        }
        if (existed) {
            info->rebuilt = true;
            log_info("REFERENCE: %s is truncated or stale; drawing it again", info->path);
        }
    }
    fs_status st = draw(rf, fr, img, info);
    if (st != FS_OK)
        return st;
    exr_image_set_string(img, "fovsim:ref_key", hex);
    exr_image_set_float(img, "fovsim:ref_error", (float)info->error);
    char what[160];
    snprintf(what, sizeof what, "%dx%d sub-samples x %d stochastic alpha tests, box filter, LOD bias %.2f", rf->ss,
             rf->ss, rf->k, (double)-log2f((float)rf->ss));
    exr_image_set_string(img, "fovsim:ref_samples", what);
    exr_image_set_float(img, "fovsim:time", fr->time);
    if (rf->cache_dir[0]) {
        st = file_make_dirs(rf->cache_dir);
        if (st == FS_OK)
            st = exr_write_file(info->path, img, EXR_COMPRESS_ZIP);
        if (st != FS_OK)
            exr_image_free(img);
    }
    return st;
}
