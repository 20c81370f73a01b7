/* check_report.c: what `fovsim check --baseline` says about a comparison (check_judge.c): the
 * one-screen report grouped by what failed, the JUnit XML file and the JSON array of failures. */
#include "commands/check_judge.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/strbuf.h"
#include "output/out_path.h"


static void case_name(int frame, const char *image, char *buf, size_t n)
{
    if (frame < 0)
        snprintf(buf, n, "run%s%s", image[0] ? " " : "", image);
    else
        snprintf(buf, n, "frame %04d %s", frame, image[0] ? image : "(all images)");
}

static void failure_text(const failure *f, char *buf, size_t n)
{
    char ring[16];
    snprintf(ring, sizeof ring, f->ring < 0 ? "all" : "%d", f->ring);
    if (f->metric == CHECK_METRIC_COUNT)
        snprintf(buf, n, "ring %s: %s", ring, f->note);
    else if (f->metric == CHECK_PIXEL || f->metric == CHECK_PIXEL_RMSE)
        snprintf(buf, n, "ring %s: %s %.4g (tolerance %.4g)", ring, check_metric_name(f->metric), f->now, f->tol);
    else
        snprintf(buf, n, "ring %s: %s %.4g in the baseline, %.4g now (tolerance %s%.4g)", ring,
                 check_metric_name(f->metric), f->base, f->now, f->metric == CHECK_COVERAGE ? "+-" : f->metric == CHECK_TIME ? "x" : "+", f->tol);
}

int check_cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* The distinct values of v[0..n) in ascending order with runs as ranges, "0-2, 5" (cut with "..."
 * past cap); -1 (the whole display) written last as "all". Sorts v. */
static void list_ints(int *v, int n, char *buf, size_t cap)
{
    qsort(v, (size_t)n, sizeof *v, check_cmp_int);
    size_t o = 0;
    buf[0] = '\0';
    for (int i = 0; i < n && o + 16 < cap; i++) {
        if (v[i] < 0 || (i && v[i] == v[i - 1]))
            continue;
        int k = i;
        while (k + 1 < n && (v[k + 1] == v[k] || v[k + 1] == v[k] + 1))
            k++;
        o += (size_t)snprintf(buf + o, cap - o, v[k] > v[i] ? "%s%d-%d" : "%s%d", o ? ", " : "", v[i], v[k]);
        i = k;
    }
    if (o + 16 >= cap)
        snprintf(buf + o, cap - o, ", ...");
    else if (n && v[0] < 0)
        snprintf(buf + o, cap - o, "%sall", o ? ", " : "");
}

/* What a failure's tolerance bounds (judge_value's `change`). */
static double change_of(const failure *f)
{
    return f->metric == CHECK_COVERAGE ? fabs(f->now - f->base)
           : f->metric == CHECK_PIXEL || f->metric == CHECK_PIXEL_RMSE ? f->now
           : f->metric == CHECK_TIME ? f->now / f->base
                                     : f->now - f->base;
}

/* The report's order: image, ring (the whole display last), metric, problem, frame. */
static int cmp_failure(const void *pa, const void *pb)
{
    const failure *a = pa, *b = pb;
    int c = strcmp(a->image, b->image);
    int ra = a->ring < 0 ? MAX_FOV_RINGS : a->ring, rb = b->ring < 0 ? MAX_FOV_RINGS : b->ring;
    c = c ? c : (ra > rb) - (ra < rb);
    c = c ? c : ((int)a->metric > (int)b->metric) - ((int)a->metric < (int)b->metric);
    c = c ? c : strcmp(a->note, b->note);
    return c ? c : (a->frame > b->frame) - (a->frame < b->frame);
}

static bool same_group(const failure *a, const failure *b)
{
    return !strcmp(a->image, b->image) && a->ring == b->ring && a->metric == b->metric && !strcmp(a->note, b->note);
}

/* One line per image x ring x metric that failed: the frames, and the frame where it changed most. */
static void print_groups(const judge *j)
{
    failure *g = malloc(sizeof *g * (size_t)j->nf);
    int *frames = malloc(sizeof(int) * (size_t)j->nf);
    if (!g || !frames) {
        free(g);
        free(frames);
        return;
    }
    memcpy(g, j->f, sizeof *g * (size_t)j->nf);
    qsort(g, (size_t)j->nf, sizeof *g, cmp_failure);
    int lines = 0, groups = 0;
    printf("  %-12s %-4s %-16s %-14s %5s %10s %10s %10s\n", "image", "ring", "metric", "frames", "worst", "baseline",
           "now", "tolerance");
    for (int i = 0, k; i < j->nf; i = k) {
        int worst = i, n = 0;
        for (k = i; k < j->nf && same_group(&g[i], &g[k]); k++) {
            frames[n++] = g[k].frame;
            worst = change_of(&g[k]) > change_of(&g[worst]) ? k : worst;
        }
        groups++;
        if (lines >= j->d->max_lines)
            continue;
        lines++;
        const failure *f = &g[worst];
        char fl[64], rg[8], wf[16], img[32];
        list_ints(frames, n, fl, sizeof fl);
        snprintf(rg, sizeof rg, f->ring < 0 ? "all" : "%d", f->ring);
        if (f->frame < 0)
            wf[0] = '\0';
        else
            snprintf(wf, sizeof wf, "%04d", f->frame);
        snprintf(img, sizeof img, "%s", f->image[0] ? f->image : "(frame)");
        if (f->metric == CHECK_METRIC_COUNT)
            printf("  %-12s %-4s %-16s %-14s %s\n", img, rg, "-", f->frame < 0 ? "run" : fl, f->note);
        else if (f->metric == CHECK_PIXEL || f->metric == CHECK_PIXEL_RMSE)
            printf("  %-12s %-4s %-16s %-14s %5s %10s %10.5f %10.4g\n", img, rg, check_metric_name(f->metric), fl,
                   wf, "", f->now, f->tol);
        else
            printf("  %-12s %-4s %-16s %-14s %5s %10.5f %10.5f %4s%.4g\n", img, rg, check_metric_name(f->metric),
                   f->frame < 0 ? "run" : fl, wf, f->base, f->now, f->metric == CHECK_COVERAGE ? "+-" : f->metric == CHECK_TIME ? "x" : "+", f->tol);
    }
    if (groups > lines)
        printf("  ... and %d more lines: every failure is in %s/check.json%s%s\n", groups - lines, j->d->next,
               j->d->junit ? " and " : "", j->d->junit ? j->d->junit : "");
    free(g);
    free(frames);
}

void check_report_print(judge *j)
{
    const check_verdict *v = j->v;
    int *frames = malloc(sizeof(int) * (size_t)(j->nf + 1)), *rings = malloc(sizeof(int) * (size_t)(j->nf + 1));
    int nfr = 0;
    for (int i = 0; frames && rings && i < j->nf; i++) {
        rings[i] = j->f[i].ring;
        if (j->f[i].frame >= 0)
            frames[nfr++] = j->f[i].frame;
    }
    char fl[256] = "", rl[128] = "";
    if (frames && rings) {
        list_ints(frames, nfr, fl, sizeof fl);
        list_ints(rings, j->nf, rl, sizeof rl);
    }
    free(frames);
    free(rings);
    if (v->failed_values == 0) {
        printf("fovsim check: PASS, %d values in %d cases within tolerance of the baseline %s\n", v->values, v->cases,
               j->d->baseline);
    } else {
        printf("fovsim check: REGRESSION against the baseline %s: %d of %d values outside tolerance, in %d of %d "
               "cases (frames %s; rings %s)\n", j->d->baseline, v->failed_values, v->values, v->failed_cases,
               v->cases, nfr ? fl : "none: the run's", rl);
        print_groups(j);
        if (j->ndiffs) {
            list_ints(j->diffs, j->ndiffs, fl, sizeof fl);
            printf("diff images: %s/diff.NNNN.exr for frames %s\n", j->d->next, fl);
        }
    }
    printf("largest change per metric (tolerance):");
    for (int m = 0, col = 0; m < CHECK_METRIC_COUNT; m++)
        if (j->have_worst[m])
            printf("%s %s %.3g (%.3g)", col++ % 4 ? "," : "\n ", check_metric_name(m), j->worst[m], j->worst_tol[m]);
    printf("\n");
}

/* >>JUnit and JSON */

/* s with &, <, >, " and ' as entities and control characters (not allowed in XML 1.0) as '?'. */
static void xml_text(sbuf *b, const char *s)
{
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '&')
            sb_puts(b, "&amp;");
        else if (c == '<')
            sb_puts(b, "&lt;");
        else if (c == '>')
            sb_puts(b, "&gt;");
        else if (c == '"')
            sb_puts(b, "&quot;");
        else if (c == '\'')
            sb_puts(b, "&apos;");
        else if (c < 0x20 && c != '\n' && c != '\t')
            sb_puts(b, "?");
        else
            sb_append(b, s, 1);
    }
}

/* One testcase per frame x image (the modes, then the reference's pixels) and one for the run's
 * rows and frame times; each failing one carries every failure of the case. */
fs_status check_report_junit(const judge *j)
{
    sbuf b = {0};
    char label[256], text[512];
    snprintf(label, sizeof label, "%s", j->d->label);
    for (char *p = label; *p; p++)
        *p = *p == '.' ? '_' : *p; /* dots split classnames into packages */
    sb_printf(&b, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"fovsim check\" tests=\"%d\" "
              "failures=\"%d\" errors=\"0\">\n  <testsuite name=\"", j->v->cases, j->v->failed_cases);
    snprintf(text, sizeof text, "fovsim check %s", j->d->baseline);
    xml_text(&b, text);
    sb_printf(&b, "\" tests=\"%d\" failures=\"%d\" errors=\"0\" skipped=\"0\">\n", j->v->cases, j->v->failed_cases);
    for (int c = 0; c <= j->nframes * j->nimages; c++) {
        int frame = c < j->nframes * j->nimages ? j->frames[c / j->nimages] : -1;
        const char *image = c < j->nframes * j->nimages ? j->images[c % j->nimages] : "";
        case_name(frame, image, text, sizeof text);
        sb_puts(&b, "    <testcase name=\"");
        xml_text(&b, text);
        snprintf(text, sizeof text, "check.%s.%s", label, frame < 0 ? "run" : image);
        sb_puts(&b, "\" classname=\"");
        xml_text(&b, text);
        if (!j->case_failed[c]) {
            sb_puts(&b, "\"/>\n");
            continue;
        }
        int count = 0, first = -1;
        for (int i = 0; i < j->nf; i++)
            if (j->f[i].frame == frame && (frame < 0 || !strcmp(j->f[i].image, image) || !j->f[i].image[0])) {
                count++;
                first = first < 0 ? i : first;
            }
        failure_text(&j->f[first], text, sizeof text);
        sb_puts(&b, "\">\n      <failure type=\"regression\" message=\"");
        if (frame < 0 && j->f[first].image[0]) {
            xml_text(&b, j->f[first].image);
            sb_puts(&b, " ");
        }
        xml_text(&b, text);
        if (count > 1)
            sb_printf(&b, " (and %d more)", count - 1);
        sb_puts(&b, "\">");
        for (int i = 0; i < j->nf; i++)
            if (j->f[i].frame == frame && (frame < 0 || !strcmp(j->f[i].image, image) || !j->f[i].image[0])) {
                failure_text(&j->f[i], text, sizeof text);
                if (frame < 0 && j->f[i].image[0]) {
                    xml_text(&b, j->f[i].image);
                    sb_puts(&b, " ");
                }
                xml_text(&b, text);
                sb_puts(&b, "\n");
            }
        sb_puts(&b, "</failure>\n    </testcase>\n");
    }
    sb_puts(&b, "  </testsuite>\n</testsuites>\n");
    fs_status st = b.oom ? FS_ERR_NOMEM : out_write_atomic(j->d->junit, b.p);
    free(b.p);
    return st;
}

char *check_report_failures_json(const judge *j)
{
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; a && i < j->nf; i++) {
        const failure *f = &j->f[i];
        cJSON *o = cJSON_CreateObject();
        if (!o)
            break;
        cJSON_AddItemToArray(a, o);
        cJSON_AddNumberToObject(o, "frame", f->frame);
        cJSON_AddStringToObject(o, "image", f->image);
        if (f->ring < 0)
            cJSON_AddStringToObject(o, "ring", "all");
        else
            cJSON_AddNumberToObject(o, "ring", f->ring);
        if (f->metric == CHECK_METRIC_COUNT) {
            cJSON_AddStringToObject(o, "problem", f->note);
            continue;
        }
        cJSON_AddStringToObject(o, "metric", check_metric_name(f->metric));
        if (f->metric != CHECK_PIXEL && f->metric != CHECK_PIXEL_RMSE)
            cJSON_AddNumberToObject(o, "baseline", f->base);
        cJSON_AddNumberToObject(o, "now", f->now);
        cJSON_AddNumberToObject(o, "tolerance", f->tol);
    }
    char *s = a ? cJSON_PrintUnformatted(a) : NULL;
    cJSON_Delete(a);
    return s;
}
