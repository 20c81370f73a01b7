/* exr_views.c: several views (a head-mounted display's two eyes) in one single-part EXR, by
 * OpenEXR's multi-view convention: the multiView attribute and the channel naming rule (see
 * exr_write.h ">>views"). */
#include "output/exr_write.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

#define MULTI_VIEW "multiView"
/* OpenEXR attribute and channel names up to this length need no long-name flag. */
#define VIEW_NAME_MAX 31

static bool view_name_ok(const char *v)
{
    size_t len = strlen(v);
    if (len == 0 || len > VIEW_NAME_MAX)
        return false;
    for (size_t i = 0; i < len; i++)
        if (v[i] == '.' || isspace((unsigned char)v[i]))
            return false;
    return true;
}

/* Why `views` cannot be a multiView list, or NULL. */
static const char *check_views(const char *const *views, int count)
{
    if (count < 1 || count > EXR_MAX_VIEWS)
        return "the number of views is outside 1..EXR_MAX_VIEWS";
    for (int k = 0; k < count; k++) {
        if (!view_name_ok(views[k]))
            return "a view name is empty, longer than 31 characters or holds '.' or white space";
        for (int j = 0; j < k; j++)
            if (strcmp(views[j], views[k]) == 0)
                return "a view name is listed twice";
    }
    return NULL;
}

bool exr_image_set_views(exr_image *img, const char *const *views, int count)
{
    FS_ASSERT(img && views);
    const char *why = check_views(views, count);
    if (why) {
        log_warn("EXR: multiView not set: %s", why);
        return false;
    }
    return exr_image_set_string_vector(img, MULTI_VIEW, views, count);
}

int exr_image_view_count(const exr_image *img)
{
    FS_ASSERT(img);
    const exr_attr *a = exr_image_attr(img, MULTI_VIEW);
    return a && a->type == FS_EXR_ATTR_STRING_VECTOR ? a->i : 0;
}

const char *exr_image_view_name(const exr_image *img, int k)
{
    FS_ASSERT(img);
    const exr_attr *a = exr_image_attr(img, MULTI_VIEW);
    return a ? exr_attr_string_at(a, k) : NULL;
}

// >>channel names

bool exr_view_channel_name(const char *base, const char *view, bool default_view, char *out,
                           size_t cap)
{
    FS_ASSERT(base && view && out);
    const char *last_dot = strrchr(base, '.');
    int n;
    if (!last_dot)
        n = default_view ? snprintf(out, cap, "%s", base) : snprintf(out, cap, "%s.%s", view, base);
    else /* the view goes before the last component: "hashed.R" -> "hashed.right.R" */
        n = snprintf(out, cap, "%.*s.%s%s", (int)(last_dot - base), base, view, last_dot);
    return n >= 0 && (size_t)n < cap;
}

/* The second-last '.'-separated component of `name`: its start, and its length in *len; NULL
 * when the name has no '.'. */
static const char *second_last(const char *name, size_t *len)
{
    const char *last_dot = strrchr(name, '.');
    if (!last_dot)
        return NULL;
    const char *start = last_dot;
    while (start > name && start[-1] != '.')
        start--;
    *len = (size_t)(last_dot - start);
    return start;
}

/* Index of the view named by the `len` characters at `s` in `views`, or -1. */
static int view_index(const char *s, size_t len, const char *const *views, int count)
{
    for (int k = 0; k < count; k++)
        if (strlen(views[k]) == len && strncmp(views[k], s, len) == 0)
            return k;
    return -1;
}

/* exr_channel_view on a list of views. */
static int channel_view(const char *name, const char *const *views, int count, char *base,
                        size_t cap)
{
    size_t len = 0;
    const char *comp = second_last(name, &len);
    int k = comp ? view_index(comp, len, views, count) : 0;
    if (k < 0 || !base)
        return k;
    if (!comp) {
        snprintf(base, cap, "%s", name);
    } else {
        /* Drop "<view>." from the name: what precedes it and what follows. */
        size_t pre = (size_t)(comp - name);
        snprintf(base, cap, "%.*s%s", (int)pre, name, comp + len + 1);
    }
    return k;
}

/* The views of img's multiView attribute as an array (at most EXR_MAX_VIEWS); their count. */
static int image_views(const exr_image *img, const char *views[EXR_MAX_VIEWS])
{
    int n = exr_image_view_count(img);
    if (n > EXR_MAX_VIEWS)
        n = EXR_MAX_VIEWS;
    for (int k = 0; k < n; k++)
        views[k] = exr_image_view_name(img, k);
    return n;
}

int exr_channel_view(const exr_image *img, const char *name, char *base, size_t cap)
{
    FS_ASSERT(img && name);
    const char *views[EXR_MAX_VIEWS];
    int n = image_views(img, views);
    return n > 0 ? channel_view(name, views, n, base, cap) : -1;
}

// >>join

static bool attrs_equal(const exr_attr *a, const exr_attr *b)
{
    if (a->type != b->type)
        return false;
    switch (a->type) {
    case FS_EXR_ATTR_STRING: return strcmp(a->s, b->s) == 0;
    case FS_EXR_ATTR_INT: return a->i == b->i;
    case FS_EXR_ATTR_FLOAT: return memcmp(&a->f[0], &b->f[0], sizeof a->f[0]) == 0;
    case FS_EXR_ATTR_V2F: return memcmp(a->f, b->f, sizeof a->f) == 0;
    case FS_EXR_ATTR_STRING_VECTOR: return a->i == b->i && memcmp(a->s, b->s, sizeof a->s) == 0;
    }
    return false;
}

/* Whether `name` starts with "<one of views>.": an attribute name join would give another
 * view's attribute. */
static bool has_view_prefix(const char *name, const char *const *views, int count)
{
    const char *dot = strchr(name, '.');
    return dot && view_index(name, (size_t)(dot - name), views, count) >= 0;
}

/* Copies attribute `a` into `out` under `name` (an existing one of that name is replaced).
 * False when out has no room. */
static bool put_attr(exr_image *out, const exr_attr *a, const char *name)
{
    exr_attr *d = (exr_attr *)exr_image_attr(out, name);
    if (!d) {
        if (out->attr_count >= EXR_MAX_ATTRS || strlen(name) >= sizeof d->name)
            return false;
        d = &out->attrs[out->attr_count++];
    }
    *d = *a;
    snprintf(d->name, sizeof d->name, "%s", name);
    return true;
}

/* Why images[k] cannot be view k of a join, or NULL. */
static const char *check_view_image(const exr_image *img, const exr_image *first,
                                    const char *const *views, int count)
{
    if (img->next_part)
        return "an image has further parts (join the views of each part instead)";
    if (exr_image_attr(img, MULTI_VIEW))
        return "an image already has a multiView attribute";
    if (img->width != first->width || img->height != first->height)
        return "the images differ in size";
    if (img->channel_count <= 0)
        return "an image has no channels";
    for (int c = 0; c < img->channel_count; c++)
        if (strchr(img->channel_names[c], '.') &&
            channel_view(img->channel_names[c], views, count, NULL, 0) >= 0)
            return "a channel name already holds a view name where the view goes";
    for (int a = 0; a < img->attr_count; a++)
        if (has_view_prefix(img->attrs[a].name, views, count))
            return "an attribute name already starts with '<view>.'";
    return NULL;
}

/* Why the channels of `images` cannot all go into one image under their multi-view names, or
 * NULL. Checked before anything is copied or moved, so that a move never stops halfway. */
static const char *check_channels(const exr_image *const *images, const char *const *views,
                                  int count)
{
    int total = 0;
    for (int k = 0; k < count; k++) {
        total += images[k]->channel_count;
        for (int c = 0; c < images[k]->channel_count; c++) {
            char name[sizeof images[k]->channel_names[0]];
            if (!exr_view_channel_name(images[k]->channel_names[c], views[k], k == 0, name,
                                       sizeof name))
                return "a channel's multi-view name is longer than 63 characters";
        }
    }
    return total > EXR_MAX_CHANNELS ? "more than EXR_MAX_CHANNELS channels in all" : NULL;
}

/* Puts view k's channels into out under their multi-view names (check_channels passed): copies
 * of the planes, or with `take` the planes themselves, img left without channels. */
static fs_status join_channels(exr_image *out, exr_image *img, const char *view, bool dflt,
                               bool take)
{
    const size_t px = (size_t)img->width * (size_t)img->height;
    for (int c = 0; c < img->channel_count; c++) {
        char name[sizeof out->channel_names[0]];
        exr_view_channel_name(img->channel_names[c], view, dflt, name, sizeof name);
        if (take) { /* names are unique: each view's are, and the view in them differs */
            int d = out->channel_count++;
            memcpy(out->channel_names[d], name, sizeof name);
            out->planes[d] = img->planes[c];
            img->planes[c] = NULL;
            continue;
        }
        float *dst = exr_image_add_channel(out, name);
        if (!dst) {
            log_error("EXR views: out of memory for channel '%s'", name);
            return FS_ERR_NOMEM;
        }
        memcpy(dst, img->planes[c], px * sizeof *dst);
    }
    if (take)
        img->channel_count = 0;
    return FS_OK;
}

/* The attributes of view k (k > 0) that differ from the default view's, as "<view>.<name>". */
static bool join_attrs(exr_image *out, const exr_image *img, const exr_image *dflt,
                       const char *view)
{
    for (int a = 0; a < img->attr_count; a++) {
        const exr_attr *at = &img->attrs[a];
        const exr_attr *d = exr_image_attr(dflt, at->name);
        if (d && attrs_equal(d, at))
            continue;
        char name[sizeof at->name];
        int n = snprintf(name, sizeof name, "%s.%s", view, at->name);
        if (n < 0 || (size_t)n >= sizeof name || !put_attr(out, at, name))
            return false;
    }
    return true;
}

/* Every view's attributes and the multiView list into out. False when they do not fit. */
static bool join_all_attrs(exr_image *out, const exr_image *const *images,
                           const char *const *views, int count)
{
    bool ok = true;
    for (int a = 0; ok && a < images[0]->attr_count; a++)
        ok = put_attr(out, &images[0]->attrs[a], images[0]->attrs[a].name);
    ok = ok && out->attr_count < EXR_MAX_ATTRS &&
         exr_image_set_string_vector(out, MULTI_VIEW, views, count);
    for (int k = 1; ok && k < count; k++)
        ok = join_attrs(out, images[k], images[0], views[k]);
    return ok;
}

/* exr_image_join_views and exr_image_join_views_move: `take` moves the planes. */
static fs_status join_views(exr_image *out, exr_image *const *images, const char *const *views,
                            int count, bool take)
{
    FS_ASSERT(out && images && views);
    memset(out, 0, sizeof *out);
    const exr_image *const *cimages = (const exr_image *const *)images;
    const char *why = check_views(views, count);
    for (int k = 0; !why && k < count; k++)
        why = check_view_image(images[k], images[0], views, count);
    if (!why)
        why = check_channels(cimages, views, count);
    if (!why && !exr_image_init(out, images[0]->width, images[0]->height))
        why = "bad image size";
    /* Attributes first: past this point nothing but memory can fail, and a move cannot. */
    if (!why && !join_all_attrs(out, cimages, views, count))
        why = "more than EXR_MAX_ATTRS attributes, or a '<view>.<name>' longer than 63 characters";
    if (why) {
        log_error("EXR views: cannot join views: %s", why);
        exr_image_free(out);
        return FS_ERR_INTERNAL;
    }
    fs_status st = FS_OK;
    for (int k = 0; k < count && st == FS_OK; k++)
        st = join_channels(out, images[k], views[k], k == 0, take);
    if (st != FS_OK) {
        exr_image_free(out);
        return st;
    }
    for (int k = 0; take && k < count; k++)
        exr_image_free(images[k]); /* attributes only now: the planes are out's */
    return FS_OK;
}

fs_status exr_image_join_views(exr_image *out, const exr_image *const *images,
                               const char *const *views, int count)
{
    /* Not written through: with take == false join_views only reads the images. */
    return join_views(out, (exr_image *const *)images, views, count, false);
}

fs_status exr_image_join_views_move(exr_image *out, exr_image *const *images,
                                    const char *const *views, int count)
{
    return join_views(out, images, views, count, true);
}

static const char *const k_eyes[2] = {"left", "right"};

fs_status exr_image_join_eyes(exr_image *out, const exr_image *left, const exr_image *right)
{
    const exr_image *images[2] = {left, right};
    return exr_image_join_views(out, images, k_eyes, 2);
}

fs_status exr_image_join_eyes_move(exr_image *out, exr_image *left, exr_image *right)
{
    exr_image *images[2] = {left, right};
    return exr_image_join_views_move(out, images, k_eyes, 2);
}

// >>extract

/* Copies the attributes of view k of img into out: the unprefixed ones but multiView, then
 * view k's own "<view>." ones (overriding). False when out has no room. */
static bool extract_attrs(exr_image *out, const exr_image *img, const char *const *views,
                          int count, int k)
{
    size_t vlen = strlen(views[k]);
    for (int a = 0; a < img->attr_count; a++) {
        const exr_attr *at = &img->attrs[a];
        if (strcmp(at->name, MULTI_VIEW) == 0 || has_view_prefix(at->name, views, count))
            continue;
        if (!put_attr(out, at, at->name))
            return false;
    }
    for (int a = 0; a < img->attr_count; a++) {
        const exr_attr *at = &img->attrs[a];
        if (strncmp(at->name, views[k], vlen) == 0 && at->name[vlen] == '.' &&
            !put_attr(out, at, at->name + vlen + 1))
            return false;
    }
    return true;
}

fs_status exr_image_extract_view(const exr_image *img, const char *view, exr_image *out)
{
    FS_ASSERT(img && view && out);
    memset(out, 0, sizeof *out);
    const char *views[EXR_MAX_VIEWS];
    int n = image_views(img, views);
    int k = view_index(view, strlen(view), views, n);
    if (k < 0) {
        log_error("EXR views: no view '%s' (the image lists %d views)", view, n);
        return FS_ERR_IO;
    }
    if (!exr_image_init(out, img->width, img->height))
        return FS_ERR_IO;
    const size_t px = (size_t)img->width * (size_t)img->height;
    for (int c = 0; c < img->channel_count; c++) {
        char base[sizeof img->channel_names[0]];
        if (channel_view(img->channel_names[c], views, n, base, sizeof base) != k)
            continue;
        bool twice = exr_image_channel(out, base) != NULL; /* "R" and "left.R" */
        float *dst = twice ? NULL : exr_image_add_channel(out, base);
        if (!dst) {
            exr_image_free(out);
            if (twice)
                log_error("EXR views: view '%s' has channel '%s' twice", view, base);
            return twice ? FS_ERR_IO : FS_ERR_NOMEM;
        }
        memcpy(dst, img->planes[c], px * sizeof *dst);
    }
    if (out->channel_count == 0 || !extract_attrs(out, img, views, n, k)) {
        log_error("EXR views: view '%s' has no channels, or too many attributes", view);
        exr_image_free(out);
        return FS_ERR_IO;
    }
    return FS_OK;
}
