/* cost_model.c: the stage cost model's fit, errors and JSON file (cost_model.h). */
#include "perf/cost_model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "core/file_read.h"
#include "core/log.h"
#include "core/stats.h"
#include "core/strbuf.h"
#include "output/out_path.h"

static const char *const k_kind_names[COST_KINDS] = {"forward", "ring", "taa", "composite", "fullscreen"};
/* The coefficients' keys in the JSON file, in COST_* order. */
static const char *const k_coef_keys[COST_TERMS] = {"per_primitive", "per_invocation", "per_byte", "per_stage"};

const char *cost_kind_name(cost_kind k)
{
    return k >= 0 && k < COST_KINDS ? k_kind_names[k] : "?";
}

cost_kind cost_kind_of_stage(const char *name, bool geometry)
{
    if (geometry)
        return strncmp(name, "ring ", 5) == 0 ? COST_KIND_RING : COST_KIND_FORWARD;
    if (strstr(name, "taa resolve"))
        return COST_KIND_TAA;
    return strcmp(name, "composite") == 0 ? COST_KIND_COMPOSITE : COST_KIND_FULLSCREEN;
}

void cost_class_name(cost_kind k, const char *mode, char *out, size_t cap)
{
    if (k == COST_KIND_FORWARD || k == COST_KIND_RING)
        snprintf(out, cap, "%s/%s", cost_kind_name(k), mode);
    else
        snprintf(out, cap, "%s", cost_kind_name(k));
}

double cost_predict(const double coef[COST_TERMS], const double x[COST_COUNTS])
{
    double t = coef[COST_CONST];
    for (int j = 0; j < COST_COUNTS; j++)
        t += coef[j] * x[j];
    return t;
}

/* >>the fit */

/* The samples of class k with a positive time, as rows of the relative-error problem: each term
 * divided by the time, so that minimising |z·c - 1|² minimises the squared relative errors
 * (weights 1/t²). Returns the row count; z holds 4 doubles per row. */
static int relative_rows(const cost_sample *s, int n, int k, double *z)
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (s[i].cls != k || !(s[i].ms > 0.0))
            continue;
        for (int j = 0; j < COST_COUNTS; j++)
            z[m * COST_TERMS + j] = s[i].x[j] / s[i].ms;
        z[m * COST_TERMS + COST_CONST] = 1.0 / s[i].ms;
        m++;
    }
    return m;
}

/* Least squares z[:, cols] c = 1 by modified Gram-Schmidt (q: m * k scratch). False when the
 * columns are (numerically) dependent: a column keeps under 1e-9 of its norm once the earlier
 * ones are taken out, as a term proportional to another does. */
static bool solve_subset(const double *z, int m, const int *cols, int k, double *q, double *c)
{
    double r[COST_TERMS][COST_TERMS] = {{0}}, y[COST_TERMS];
    for (int j = 0; j < k; j++) {
        double *v = q + (size_t)j * (size_t)m, n0 = 0.0, n1 = 0.0;
        for (int i = 0; i < m; i++) {
            v[i] = z[i * COST_TERMS + cols[j]];
            n0 += v[i] * v[i];
        }
        for (int p = 0; p < j; p++) {
            const double *u = q + (size_t)p * (size_t)m;
            double d = 0.0;
            for (int i = 0; i < m; i++)
                d += u[i] * v[i];
            r[p][j] = d;
            for (int i = 0; i < m; i++)
                v[i] -= d * u[i];
        }
        for (int i = 0; i < m; i++)
            n1 += v[i] * v[i];
        if (n0 <= 0.0 || n1 <= 1e-18 * n0)
            return false;
        r[j][j] = sqrt(n1);
        for (int i = 0; i < m; i++)
            v[i] /= r[j][j];
    }
    for (int j = 0; j < k; j++) { /* y = Qᵀ·1 */
        y[j] = 0.0;
        for (int i = 0; i < m; i++)
            y[j] += q[(size_t)j * (size_t)m + i];
    }
    for (int j = k - 1; j >= 0; j--) {
        double t = y[j];
        for (int p = j + 1; p < k; p++)
            t -= r[j][p] * c[p];
        c[j] = t / r[j][j];
    }
    return true;
}

/* Sum of squared relative errors of coef on the rows. */
static double objective(const double *z, int m, const double coef[COST_TERMS])
{
    double sum = 0.0;
    for (int i = 0; i < m; i++) {
        double e = -1.0;
        for (int j = 0; j < COST_TERMS; j++)
            e += z[i * COST_TERMS + j] * coef[j];
        sum += e * e;
    }
    return sum;
}

/* Non-negative least squares by trying every subset of terms: the optimum's positive
 * coefficients are the unconstrained solution on their subset, so the best subset whose
 * solution is non-negative is the optimum. Subsets go by size, so a tie keeps the smaller. */
static bool nnls_subsets(const double *z, int m, double *q, double coef[COST_TERMS])
{
    double best = INFINITY;
    for (int size = 1; size <= COST_TERMS && size <= m; size++)
        for (unsigned mask = 1; mask < (1u << COST_TERMS); mask++) {
            int cols[COST_TERMS], k = 0;
            for (int j = 0; j < COST_TERMS; j++)
                if (mask & (1u << j))
                    cols[k++] = j;
            double c[COST_TERMS], full[COST_TERMS] = {0};
            if (k != size || !solve_subset(z, m, cols, k, q, c))
                continue;
            bool nonneg = true;
            for (int j = 0; j < k; j++) {
                nonneg = nonneg && c[j] >= 0.0;
                full[cols[j]] = c[j];
            }
            double o = nonneg ? objective(z, m, full) : INFINITY;
            if (o < best * (1.0 - 1e-12) - 1e-300) {
                best = o;
                memcpy(coef, full, sizeof full);
            }
        }
    return isfinite(best);
}

bool cost_fit_class(const cost_sample *s, int n, int k, double coef[COST_TERMS], char *err, size_t cap)
{
    double *z = malloc(sizeof(double) * COST_TERMS * (size_t)(n > 0 ? n : 1));
    double *q = malloc(sizeof(double) * COST_TERMS * (size_t)(n > 0 ? n : 1));
    bool ok = false;
    int m = z && q ? relative_rows(s, n, k, z) : 0;
    memset(coef, 0, sizeof(double) * COST_TERMS);
    if (!z || !q)
        snprintf(err, cap, "out of memory");
    else if (m < COST_MIN_SAMPLES)
        snprintf(err, cap, "%d sample%s with a positive time, the fit needs at least %d", m, m == 1 ? "" : "s",
                 COST_MIN_SAMPLES);
    else if (!(ok = nnls_subsets(z, m, q, coef)))
        snprintf(err, cap, "no non-negative fit (every term is zero?)");
    free(z);
    free(q);
    return ok;
}

cost_error cost_errors(const cost_sample *s, int n, int k, const double coef[COST_TERMS])
{
    cost_error e = {0, -1.0, -1.0, -1.0};
    double *v = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
    if (!v)
        return e;
    for (int i = 0; i < n; i++)
        if (s[i].cls == k && s[i].ms > 0.0)
            v[e.n++] = fabs(cost_predict(coef, s[i].x) - s[i].ms) / s[i].ms;
    if (e.n > 0) {
        qsort(v, (size_t)e.n, sizeof *v, stats_cmp_double);
        e.median = stats_quantile(v, e.n, 0.5);
        e.p90 = stats_quantile(v, e.n, 0.9);
        e.max = v[e.n - 1];
    }
    free(v);
    return e;
}

bool cost_model_fit(cost_model *m, const cost_sample *fit, int nfit, const cost_sample *held, int nheld, char *err,
                    size_t cap)
{
    bool ok = true;
    size_t o = 0;
    err[0] = '\0';
    for (int k = 0; k < m->count; k++) {
        cost_fit *f = &m->cls[k];
        char why[160];
        f->fitted = cost_fit_class(fit, nfit, k, f->coef, why, sizeof why);
        if (!f->fitted) {
            ok = false;
            if (o < cap)
                o += (size_t)snprintf(err + o, cap - o, "%s%s: %s", o ? "; " : "", f->name, why);
            continue;
        }
        f->fit = cost_errors(fit, nfit, k, f->coef);
        f->held = cost_errors(held, nheld, k, f->coef);
    }
    return ok;
}

int cost_model_find(const cost_model *m, const char *name)
{
    for (int k = 0; k < m->count; k++)
        if (strcmp(m->cls[k].name, name) == 0)
            return k;
    return -1;
}

int cost_model_over_bound(const cost_model *m, char *out, size_t cap)
{
    int count = 0;
    size_t o = 0;
    out[0] = '\0';
    for (int k = 0; k < m->count; k++) {
        const cost_fit *f = &m->cls[k];
        if (!f->fitted || (f->held.n > 0 && f->held.p90 <= m->bound))
            continue;
        count++;
        if (o < cap)
            o += (size_t)snprintf(out + o, cap - o, "%s%s", o ? ", " : "", f->name);
    }
    return count;
}

double cost_model_stage_ms(const cost_model *m, const char *name, const double x[COST_COUNTS])
{
    int k = cost_model_find(m, name);
    return k >= 0 && m->cls[k].fitted ? cost_predict(m->cls[k].coef, x) : -1.0;
}

/* >>the file */

/* A string as a JSON string (the renderer string is printable ASCII in practice; escaped anyway). */
static void json_str(sbuf *b, const char *s)
{
    sb_puts(b, "\"");
    for (; *s; s++) {
        unsigned char ch = (unsigned char)*s;
        if (ch == '"' || ch == '\\')
            sb_printf(b, "\\%c", ch);
        else if (ch < 0x20)
            sb_printf(b, "\\u%04x", ch);
        else
            sb_append(b, s, 1);
    }
    sb_puts(b, "\"");
}

static void json_error(sbuf *b, const char *key, const cost_error *e)
{
    sb_printf(b, "\"%s\": {\"samples\": %d, \"median\": %.6f, \"p90\": %.6f, \"max\": %.6f}", key, e->n, e->median,
              e->p90, e->max);
}

char *cost_model_json(const cost_model *m)
{
    sbuf b = {0};
    sb_puts(&b, "{\n  \"format\": \"fovsim cost model\",\n  \"version\": 1,\n  \"renderer\": ");
    json_str(&b, m->renderer);
    sb_puts(&b, ",\n  \"time_source\": ");
    json_str(&b, m->time_source);
    sb_printf(&b, ",\n  \"terms\": \"ms = per_primitive * primitives submitted + per_invocation * fragment-shader "
                  "invocations + per_byte * (bytes read + written) + per_stage\",\n  \"bound_held_out_p90\": %.4f,\n"
                  "  \"classes\": {",
              m->bound);
    bool first = true;
    for (int k = 0; k < m->count; k++) {
        const cost_fit *f = &m->cls[k];
        if (!f->fitted)
            continue;
        sb_printf(&b, "%s\n    ", first ? "" : ",");
        json_str(&b, f->name);
        sb_puts(&b, ": {\"coefficients_ms\": {");
        for (int j = 0; j < COST_TERMS; j++)
            sb_printf(&b, "%s\"%s\": %.9g", j ? ", " : "", k_coef_keys[j], f->coef[j]);
        sb_puts(&b, "},\n      ");
        json_error(&b, "fit_error", &f->fit);
        sb_puts(&b, ",\n      ");
        json_error(&b, "held_out_error", &f->held);
        sb_puts(&b, "}");
        first = false;
    }
    sb_puts(&b, "\n  }\n}\n");
    return b.p;
}

fs_status cost_model_write(const cost_model *m, const char *path)
{
    char *text = cost_model_json(m);
    if (!text)
        return FS_ERR_NOMEM;
    fs_status st = out_write_atomic(path, text);
    free(text);
    return st;
}

/* What a parse reports its first error into. */
typedef struct parse_ctx {
    const char *path;
    char *err;
    size_t cap;
} parse_ctx;

static bool bad(parse_ctx *c, const char *jpath, const char *expected)
{
    snprintf(c->err, c->cap, "%s: %s: expected %s", c->path, jpath, expected);
    return false;
}

/* obj[key] as a finite number (>= 0 when nonneg); `at` is the JSON path of obj, for the message. */
static bool get_number(parse_ctx *c, const cJSON *obj, const char *key, const char *at, bool nonneg, double *out)
{
    char jpath[160];
    snprintf(jpath, sizeof jpath, "%s%s%s", at, at[0] ? "." : "", key);
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble) || (nonneg && v->valuedouble < 0.0))
        return bad(c, jpath, nonneg ? "a non-negative number" : "a number");
    *out = v->valuedouble;
    return true;
}

static bool get_string(parse_ctx *c, const cJSON *obj, const char *key, char *out, size_t cap)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!cJSON_IsString(v) || strlen(v->valuestring) >= cap)
        return bad(c, key, "a string");
    snprintf(out, cap, "%s", v->valuestring);
    return true;
}

/* An error figure: {"samples", "median", "p90", "max"}; -1 figures only with 0 samples. */
static bool get_error(parse_ctx *c, const cJSON *kind, const char *key, const char *at, cost_error *e)
{
    char jpath[160];
    snprintf(jpath, sizeof jpath, "%s.%s", at, key);
    const cJSON *o = cJSON_GetObjectItemCaseSensitive(kind, key);
    double n = 0;
    if (!cJSON_IsObject(o))
        return bad(c, jpath, "an object {\"samples\", \"median\", \"p90\", \"max\"}");
    if (!get_number(c, o, "samples", jpath, true, &n) || !get_number(c, o, "median", jpath, false, &e->median) ||
        !get_number(c, o, "p90", jpath, false, &e->p90) || !get_number(c, o, "max", jpath, false, &e->max))
        return false;
    bool ok = n == floor(n) && n < 1e9 && (n == 0 || (e->median >= 0 && e->p90 >= 0 && e->max >= 0));
    if (!ok)
        return bad(c, jpath, "a whole number of samples and non-negative errors (-1 only with 0 samples)");
    e->n = (int)n; /* after the range check: a larger number does not fit an int */
    return true;
}

/* A class name: a full-screen kind's name, or forward/MODE or ring/MODE (MODE: [a-z0-9_-]+). */
static bool class_name_valid(const char *name)
{
    for (int k = 0; k < COST_KINDS; k++) {
        size_t n = strlen(k_kind_names[k]);
        if (strncmp(name, k_kind_names[k], n) != 0)
            continue;
        if (k != COST_KIND_FORWARD && k != COST_KIND_RING)
            return name[n] == '\0';
        if (name[n] != '/' || !name[n + 1] || strlen(name) >= COST_CLASS_NAME_MAX)
            return false;
        return strspn(name + n + 1, "abcdefghijklmnopqrstuvwxyz0123456789_-") == strlen(name + n + 1);
    }
    return false;
}

static bool parse_class(parse_ctx *c, const cJSON *cls, const char *at, cost_fit *f)
{
    char cat[160];
    if (!cJSON_IsObject(cls))
        return bad(c, at, "an object");
    snprintf(cat, sizeof cat, "%s.coefficients_ms", at);
    const cJSON *co = cJSON_GetObjectItemCaseSensitive(cls, "coefficients_ms");
    if (!cJSON_IsObject(co))
        return bad(c, cat, "an object of per_primitive, per_invocation, per_byte and per_stage");
    for (int j = 0; j < COST_TERMS; j++) {
        if (!get_number(c, co, k_coef_keys[j], cat, true, &f->coef[j]))
            return false;
        /* No stage costs a second per unit: a larger coefficient is not a measurement, and it would
         * make predictions overflow to infinity. */
        if (f->coef[j] > COST_MAX_COEF_MS) {
            char jpath[200];
            snprintf(jpath, sizeof jpath, "%s.%s", cat, k_coef_keys[j]);
            return bad(c, jpath, "at most 1000 ms per unit");
        }
    }
    f->fitted = true;
    return get_error(c, cls, "fit_error", at, &f->fit) && get_error(c, cls, "held_out_error", at, &f->held);
}

static bool parse_classes(parse_ctx *c, const cJSON *root, cost_model *m)
{
    const cJSON *classes = cJSON_GetObjectItemCaseSensitive(root, "classes");
    if (!cJSON_IsObject(classes) || !classes->child)
        return bad(c, "classes", "an object with at least one stage class");
    for (const cJSON *k = classes->child; k; k = k->next) {
        char at[96];
        snprintf(at, sizeof at, "classes.%.80s", k->string);
        if (!class_name_valid(k->string))
            return bad(c, at, "a stage class: taa, composite, fullscreen, or forward/MODE or ring/MODE with an "
                              "alpha mode");
        if (cost_model_find(m, k->string) >= 0)
            return bad(c, at, "each class once");
        if (m->count == COST_MAX_CLASSES)
            return bad(c, at, "at most 48 classes (COST_MAX_CLASSES)");
        cost_fit *f = &m->cls[m->count++];
        snprintf(f->name, sizeof f->name, "%s", k->string);
        if (!parse_class(c, k, at, f))
            return false;
    }
    return true;
}

static bool parse_root(parse_ctx *c, const cJSON *root, cost_model *m)
{
    double version = 0;
    char fmt[64];
    if (!cJSON_IsObject(root))
        return bad(c, "(top level)", "a JSON object (a cost model written by fovsim bench --calibrate)");
    if (!get_string(c, root, "format", fmt, sizeof fmt) || strcmp(fmt, "fovsim cost model") != 0)
        return bad(c, "format", "\"fovsim cost model\"");
    if (!get_number(c, root, "version", "", true, &version) || version != 1)
        return bad(c, "version", "1");
    if (!get_string(c, root, "renderer", m->renderer, sizeof m->renderer) ||
        !get_string(c, root, "time_source", m->time_source, sizeof m->time_source))
        return false;
    if (strcmp(m->time_source, COST_TIME_WALL) != 0 && strcmp(m->time_source, COST_TIME_GL) != 0)
        return bad(c, "time_source", "\"" COST_TIME_WALL "\" or \"" COST_TIME_GL "\"");
    if (!get_number(c, root, "bound_held_out_p90", "", true, &m->bound))
        return false;
    return parse_classes(c, root, m);
}

fs_status cost_model_parse(const char *text, const char *path, cost_model *m, char *err, size_t cap)
{
    memset(m, 0, sizeof *m);
    parse_ctx c = {path, err, cap};
    cJSON *root = cJSON_Parse(text);
    bool ok = root ? parse_root(&c, root, m) : bad(&c, "(top level)", "valid JSON");
    cJSON_Delete(root);
    return ok ? FS_OK : FS_ERR_USAGE;
}

fs_status cost_model_load(const char *path, const char *renderer, cost_model *m)
{
    char *text = NULL, err[512], over[128];
    size_t size = 0;
    fs_status st = file_read_all(path, 1 << 20, "a cost model", FS_ERR_USAGE, &text, &size);
    if (st != FS_OK)
        return st;
    st = cost_model_parse(text, path, m, err, sizeof err);
    free(text);
    if (st != FS_OK)
        log_error("--cost-model %s", err);
    else if (strcmp(m->renderer, renderer) != 0) {
        log_error("--cost-model %s: fitted on renderer '%s', this run draws with '%s' (calibrate this device with "
                  "fovsim bench --calibrate)", path, m->renderer, renderer);
        st = FS_ERR_USAGE;
    } else if (cost_model_over_bound(m, over, sizeof over) > 0) {
        log_error("--cost-model %s: class %s: held-out p90 relative error over the model's bound of %.0f %% (or not "
                  "checked on held-out samples); its predictions are not used", path, over, m->bound * 100.0);
        st = FS_ERR_USAGE;
    }
    return st;
}
