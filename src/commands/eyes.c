/* eyes.c: an hmd display's two eyes brought together (eyes.h). */
#include "commands/eyes.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "core/file_read.h"
#include "core/log.h"
#include "core/strbuf.h"
#include "output/out_path.h"

static const char *const k_eye_dirs[2] = {"eye-left", "eye-right"};

run_desc eyes_run_desc(const run_desc *d, const char *out, int e, char *sub, size_t cap)
{
    snprintf(sub, cap, "%s/%s", out, k_eye_dirs[e - 1]);
    run_desc de = *d;
    de.eye_run = e;
    de.out_dir = sub;
    if (!d->quiet) {
        printf("\n== %s eye: %s/\n", e == 1 ? "left" : "right", sub);
        fflush(stdout);
    }
    return de;
}

/* Part `part` of eye e's frame i. */
static fs_status read_eye(const char *out, const char *name, int e, int i, int part, exr_image *img)
{
    char path[1300];
    snprintf(path, sizeof path, "%s/%s/%s.%04d.exr", out, k_eye_dirs[e], name, i);
    return exr_read_part(path, part, img);
}

/* Two images of one height and the same channels, side by side: left's attributes and part name. */
static fs_status side_by_side(const exr_image *l, const exr_image *r, exr_image *out)
{
    if (l->height != r->height || l->channel_count != r->channel_count || !exr_image_init(out, l->width + r->width, l->height)) {
        log_error("eyes: the two eyes' grids differ in height or channels");
        return FS_ERR_INTERNAL;
    }
    for (int c = 0; c < l->channel_count; c++) {
        const float *a = l->planes[c], *b = exr_image_channel(r, l->channel_names[c]);
        float *o = exr_image_add_channel(out, l->channel_names[c]);
        if (!o || !b) {
            exr_image_free(out);
            return b ? FS_ERR_NOMEM : FS_ERR_INTERNAL;
        }
        for (int y = 0; y < l->height; y++) {
            memcpy(o + (size_t)y * (size_t)out->width, a + (size_t)y * (size_t)l->width, sizeof(float) * (size_t)l->width);
            memcpy(o + (size_t)y * (size_t)out->width + l->width, b + (size_t)y * (size_t)r->width,
                   sizeof(float) * (size_t)r->width);
        }
    }
    memcpy(out->attrs, l->attrs, sizeof l->attrs);
    out->attr_count = l->attr_count;
    exr_image_set_part_name(out, l->part_name);
    return FS_OK;
}

/* Frame i's eyes joined into joined[0] (img[0], img[1]: scratch for the eyes' images): part `part`
 * as one multi-view image; for compare (part > 0) part 0 holds the eyes' grids side by side and the
 * multi-view layers follow as joined[0]'s second part. */
static fs_status join_frame(const char *out, const char *name, int i, int part, exr_image *img, exr_image *joined)
{
    fs_status st = FS_OK;
    for (int e = 0; e < 2 && st == FS_OK; e++)
        st = read_eye(out, name, e, i, part, &img[e]);
    if (st == FS_OK)
        st = exr_image_join_eyes_move(joined, &img[0], &img[1]);
    if (st == FS_OK && part > 0) { /* the grids side by side in part 0, the layers joined after them */
        exr_image *layers = joined + 1;
        *layers = *joined;
        memset(joined, 0, sizeof *joined);
        exr_image_set_part_name(layers, "layers"); /* compare's name for it (the join names no part) */
        for (int e = 0; e < 2 && st == FS_OK; e++) {
            exr_image_free(&img[e]);
            st = read_eye(out, name, e, i, 0, &img[e]);
        }
        if (st == FS_OK)
            st = side_by_side(&img[0], &img[1], joined);
        if (st == FS_OK && !exr_image_append_part(joined, layers))
            st = FS_ERR_NOMEM;
        exr_image_free(layers);
    }
    exr_image_free(&img[0]);
    exr_image_free(&img[1]);
    return st;
}

fs_status eyes_join_frames(const char *out, const char *name, int first, int frames, exr_compression_kind compression,
                           int part)
{
    exr_image *img = calloc(4, sizeof *img); /* left, right, joined, layers: large structs */
    if (!img)
        return FS_ERR_NOMEM;
    fs_status st = FS_OK;
    for (int i = first; i < frames && st == FS_OK; i++) {
        st = join_frame(out, name, i, part, img, img + 2);
        char path[1300];
        snprintf(path, sizeof path, "%s/%s.%04d.exr", out, name, i);
        if (st == FS_OK)
            st = exr_write_file(path, &img[2], compression);
        exr_image_free(&img[2]);
    }
    free(img);
    return st;
}

/* >>compare: metrics.csv with an eye column, summary.json per eye and both */

static fs_status read_eye_text(const char *out, int e, const char *file, char **text)
{
    char path[1300];
    size_t n;
    snprintf(path, sizeof path, "%s/%s/%s", out, k_eye_dirs[e], file);
    return file_read_all(path, (size_t)1 << 30, "a compare run's output", FS_ERR_IO, text, &n);
}

fs_status eyes_join_metrics(const char *out)
{
    char *text[2] = {NULL, NULL};
    fs_status st = FS_OK;
    for (int e = 0; e < 2 && st == FS_OK; e++)
        st = read_eye_text(out, e, "metrics.csv", &text[e]);
    sbuf b = {0};
    for (int e = 0; e < 2 && st == FS_OK; e++) {
        char *line = text[e];
        for (bool header = true; *line; header = false) {
            size_t n = strcspn(line, "\n");
            if (!(header && e == 1)) /* one header: "eye," before the eyes' own */
                sb_printf(&b, "%s%.*s\n", header ? "eye," : e == 0 ? "left," : "right,", (int)n, line);
            line += n + (line[n] == '\n');
        }
    }
    char path[1300];
    snprintf(path, sizeof path, "%s/metrics.csv", out);
    if (st == FS_OK)
        st = b.oom ? FS_ERR_NOMEM : out_write_atomic(path, b.p);
    free(b.p);
    free(text[0]);
    free(text[1]);
    return st;
}

/* The first element of array `key` of o, or NULL. */
static const cJSON *first_of(const cJSON *o, const char *key)
{
    const cJSON *a = o ? cJSON_GetObjectItemCaseSensitive(o, key) : NULL;
    return cJSON_IsArray(a) ? a->child : NULL;
}

static double num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : -1.0;
}

/* A ring of both eyes into b: coverage as the ratio of the summed coverage (as over frames), FLIP,
 * RMSE and temporal error the mean of the eyes' (each eye the same frames and pixels). Returns the
 * coverage ratio, -1 without reference coverage. */
static double both_ring(sbuf *b, const cJSON *rl, const cJSON *rr, bool comma)
{
    double ref = num(rl, "ref_coverage_px") + num(rr, "ref_coverage_px");
    double cov = ref > 0 ? (num(rl, "coverage_px") + num(rr, "coverage_px")) / ref : -1.0;
    sb_printf(b, "%s\n        {\"ring\": %d, \"coverage_ratio\": %.5f, \"flip\": %.6f, \"rmse\": %.6f, "
                 "\"temporal_error\": %.6f}", comma ? "," : "", (int)num(rl, "ring"), cov,
              (num(rl, "flip") + num(rr, "flip")) / 2, (num(rl, "rmse") + num(rr, "rmse")) / 2,
              (num(rl, "temporal_error") + num(rr, "temporal_error")) / 2);
    return cov;
}

fs_status eyes_join_summary(const char *out)
{
    char *text[2] = {NULL, NULL};
    cJSON *js[2] = {NULL, NULL};
    fs_status st = FS_OK;
    for (int e = 0; e < 2 && st == FS_OK; e++) {
        st = read_eye_text(out, e, "summary.json", &text[e]);
        if (st == FS_OK && !(js[e] = cJSON_Parse(text[e]))) {
            log_error("%s/%s/summary.json: not the JSON compare writes", out, k_eye_dirs[e]);
            st = FS_ERR_IO;
        }
    }
    sbuf b = {0};
    if (st == FS_OK) {
        sb_printf(&b, "{\n  \"eyes\": {\"left\": %s,\n  \"right\": %s},\n  \"both\": {\"modes\": [", text[0], text[1]);
        printf("\nboth eyes: coverage / the reference's per ring (both eyes' coverage summed), FLIP (the eyes' mean)\n");
        const cJSON *ml, *mr = first_of(js[1], "modes");
        bool first = true;
        cJSON_ArrayForEach(ml, cJSON_GetObjectItemCaseSensitive(js[0], "modes"))
        {
            const char *mode = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(ml, "mode"));
            sb_printf(&b, "%s\n    {\"mode\": \"%s\", \"rings\": [", first ? "" : ",", mode ? mode : "?");
            printf("%-12s", mode ? mode : "?");
            const cJSON *rl, *rr = first_of(mr, "rings");
            bool rfirst = true;
            cJSON_ArrayForEach(rl, cJSON_GetObjectItemCaseSensitive(ml, "rings"))
            {
                if (!rr)
                    break;
                double cov = both_ring(&b, rl, rr, !rfirst);
                if (cov < 0)
                    printf(" %9s", "n/a");
                else
                    printf(" %9.3f", cov);
                if (num(rl, "ring") < 0)
                    printf("   FLIP %.4f", (num(rl, "flip") + num(rr, "flip")) / 2);
                rfirst = false;
                rr = rr->next;
            }
            printf("\n");
            sb_puts(&b, "]}");
            first = false;
            mr = mr ? mr->next : NULL;
        }
        sb_puts(&b, "\n  ]}\n}\n");
    }
    char path[1300];
    snprintf(path, sizeof path, "%s/summary.json", out);
    if (st == FS_OK)
        st = b.oom ? FS_ERR_NOMEM : out_write_atomic(path, b.p);
    free(b.p);
    for (int e = 0; e < 2; e++) {
        cJSON_Delete(js[e]);
        free(text[e]);
    }
    return st;
}
