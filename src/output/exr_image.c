/* exr_image.c: the exr_image in memory: planes, header attributes, the chain of parts (see
 * exr_write.h). */
#include "output/exr_write.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

bool exr_image_init(exr_image *img, int width, int height)
{
    FS_ASSERT(img);
    memset(img, 0, sizeof *img);
    /* Keep width * height * 4 bytes well inside size_t and int arithmetic. */
    if (width <= 0 || height <= 0 || (size_t)width > (size_t)INT_MAX / (size_t)height / 4u)
        return false;
    img->width = width;
    img->height = height;
    return true;
}

float *exr_image_add_channel(exr_image *img, const char *name)
{
    FS_ASSERT(img && name);
    if (img->width <= 0 || img->height <= 0 || img->channel_count >= EXR_MAX_CHANNELS)
        return NULL;
    size_t len = strlen(name);
    if (len == 0 || len >= sizeof img->channel_names[0] || exr_image_channel(img, name))
        return NULL;
    float *plane = calloc((size_t)img->width * (size_t)img->height, sizeof *plane);
    if (!plane)
        return NULL;
    int c = img->channel_count++;
    memcpy(img->channel_names[c], name, len + 1);
    img->planes[c] = plane;
    return plane;
}

float *exr_image_channel(const exr_image *img, const char *name)
{
    FS_ASSERT(img && name);
    for (int c = 0; c < img->channel_count; c++)
        if (strcmp(img->channel_names[c], name) == 0)
            return img->planes[c];
    return NULL;
}

const exr_attr *exr_image_attr(const exr_image *img, const char *name)
{
    FS_ASSERT(img && name);
    for (int a = 0; a < img->attr_count; a++)
        if (strcmp(img->attrs[a].name, name) == 0)
            return &img->attrs[a];
    return NULL;
}

/* The slot for attribute `name` (an existing one is replaced), or NULL with a warning. Setters
 * return void, and a dropped attribute must not go unnoticed, hence the warning. */
static exr_attr *attr_slot(exr_image *img, const char *name, exr_attr_type type)
{
    FS_ASSERT(img && name);
    size_t len = strlen(name);
    if (len == 0 || len >= sizeof img->attrs[0].name) {
        log_warn("EXR: attribute name '%s' is empty or longer than %zu characters; dropped", name,
                 sizeof img->attrs[0].name - 1);
        return NULL;
    }
    exr_attr *a = (exr_attr *)exr_image_attr(img, name);
    if (!a) {
        if (img->attr_count >= EXR_MAX_ATTRS) {
            log_warn("EXR: more than EXR_MAX_ATTRS (%d) attributes; '%s' dropped", EXR_MAX_ATTRS,
                     name);
            return NULL;
        }
        a = &img->attrs[img->attr_count++];
    }
    memset(a, 0, sizeof *a);
    memcpy(a->name, name, len + 1);
    a->type = type;
    return a;
}

void exr_image_set_string(exr_image *img, const char *name, const char *value)
{
    FS_ASSERT(value);
    exr_attr *a = attr_slot(img, name, FS_EXR_ATTR_STRING);
    if (!a)
        return;
    size_t len = strlen(value);
    if (len >= sizeof a->s) {
        log_warn("EXR: attribute '%s': value longer than %zu characters, truncated", name,
                 sizeof a->s - 1);
        len = sizeof a->s - 1;
    }
    memcpy(a->s, value, len);
    a->s[len] = '\0';
}

void exr_image_set_int(exr_image *img, const char *name, int value)
{
    exr_attr *a = attr_slot(img, name, FS_EXR_ATTR_INT);
    if (a)
        a->i = value;
}

void exr_image_set_float(exr_image *img, const char *name, float value)
{
    exr_attr *a = attr_slot(img, name, FS_EXR_ATTR_FLOAT);
    if (a)
        a->f[0] = value;
}

void exr_image_set_v2f(exr_image *img, const char *name, float x, float y)
{
    exr_attr *a = attr_slot(img, name, FS_EXR_ATTR_V2F);
    if (a) {
        a->f[0] = x;
        a->f[1] = y;
    }
}

bool exr_image_set_string_vector(exr_image *img, const char *name, const char *const *values,
                                 int count)
{
    FS_ASSERT(img && name && (values || count == 0));
    char packed[sizeof img->attrs[0].s];
    size_t used = 0;
    bool fits = count >= 0 && count <= EXR_MAX_VECTOR_STRINGS;
    for (int k = 0; fits && k < count; k++) {
        size_t len = strlen(values[k]);
        fits = len < sizeof packed - used;
        if (fits) {
            memcpy(packed + used, values[k], len + 1);
            used += len + 1;
        }
    }
    if (!fits) {
        log_warn("EXR: attribute '%s': %d strings do not fit (at most %d, %zu bytes in all); not set",
                 name, count, EXR_MAX_VECTOR_STRINGS, sizeof packed);
        return false;
    }
    exr_attr *a = attr_slot(img, name, FS_EXR_ATTR_STRING_VECTOR);
    if (!a)
        return false;
    memcpy(a->s, packed, used);
    a->i = count;
    return true;
}

const char *exr_attr_string_at(const exr_attr *a, int k)
{
    FS_ASSERT(a);
    if (a->type != FS_EXR_ATTR_STRING_VECTOR || k < 0 || k >= a->i)
        return NULL;
    const char *p = a->s;
    for (int j = 0; j < k; j++)
        p += strlen(p) + 1;
    return p;
}

bool exr_image_set_part_name(exr_image *img, const char *name)
{
    FS_ASSERT(img && name);
    size_t len = strlen(name);
    if (len >= sizeof img->part_name)
        return false;
    memcpy(img->part_name, name, len + 1);
    return true;
}

bool exr_image_append_part(exr_image *first, exr_image *part)
{
    FS_ASSERT(first && part);
    if (part == first)
        return false;
    exr_image *node = malloc(sizeof *node);
    if (!node)
        return false;
    *node = *part; /* planes and the rest of part's chain move with it */
    exr_image *tail = first;
    while (tail->next_part)
        tail = tail->next_part;
    tail->next_part = node;
    memset(part, 0, sizeof *part);
    return true;
}

int exr_image_part_count(const exr_image *img)
{
    int n = 0;
    for (; img; img = img->next_part)
        n++;
    return n;
}

exr_image *exr_image_part(const exr_image *img, int index)
{
    for (int i = 0; img && i < index; i++)
        img = img->next_part;
    return index < 0 ? NULL : (exr_image *)img;
}

static void free_planes(exr_image *img)
{
    for (int c = 0; c < img->channel_count && c < EXR_MAX_CHANNELS; c++)
        free(img->planes[c]);
}

void exr_image_free(exr_image *img)
{
    if (!img)
        return;
    /* The head is the caller's; every further part is a heap node of the chain. A loop, not
     * recursion: a chain's length has no limit. */
    exr_image *next = img->next_part;
    free_planes(img);
    memset(img, 0, sizeof *img);
    while (next) {
        exr_image *node = next;
        next = node->next_part;
        free_planes(node);
        free(node);
    }
}

void exr_image_move(exr_image *dst, exr_image *src)
{
    exr_image_free(dst);
    *dst = *src;
    memset(src, 0, sizeof *src);
}
