/* scene_json_values.c: the JSON value readers of the scene-file parser (see
 * scene_json_internal.h): JSON paths, unknown and duplicate keys, numbers in ranges, booleans,
 * strings, 3-vectors and alpha modes, each failure one log_error line naming the document and the
 * JSON path. */
#include "scene/scene_json_internal.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* >>context */

fs_status jfail(const jctx *c, const char *path, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (path && path[0])
        log_error("%s: %s: %s", c->file, path, msg);
    else
        log_error("%s: %s", c->file, msg);
    return FS_ERR_SCENE;
}

/* Appends `src` to the path in buf (length *len), truncating at n - 1 characters. */
static void path_cat(char *buf, size_t n, size_t *len, const char *src)
{
    size_t k = strlen(src);
    if (k > n - 1 - *len)
        k = n - 1 - *len;
    memcpy(buf + *len, src, k);
    *len += k;
    buf[*len] = '\0';
}

/* "parent.key" (or "key" at the top level). */
const char *jkey_path(char *buf, size_t n, const char *parent, const char *key)
{
    size_t len = 0;
    buf[0] = '\0';
    if (parent && parent[0]) {
        path_cat(buf, n, &len, parent);
        path_cat(buf, n, &len, ".");
    }
    path_cat(buf, n, &len, key);
    return buf;
}

/* "parent[i]". */
const char *jidx_path(char *buf, size_t n, const char *parent, int i)
{
    char idx[16];
    size_t len = 0;
    snprintf(idx, sizeof idx, "[%d]", i);
    buf[0] = '\0';
    path_cat(buf, n, &len, parent);
    path_cat(buf, n, &len, idx);
    return buf;
}

/* What a value is, for "got ..." in messages: numbers and booleans by value, the rest by type. */
const char *jgot(const cJSON *it, char *buf, size_t n)
{
    if (!it)
        return "nothing";
    if (cJSON_IsNumber(it)) {
        snprintf(buf, n, "%.9g", it->valuedouble);
        return buf;
    }
    if (cJSON_IsTrue(it))
        return "true";
    if (cJSON_IsFalse(it))
        return "false";
    if (cJSON_IsNull(it))
        return "null";
    if (cJSON_IsString(it))
        return "a string";
    if (cJSON_IsArray(it)) {
        snprintf(buf, n, "an array of %d element%s", cJSON_GetArraySize(it),
                 cJSON_GetArraySize(it) == 1 ? "" : "s");
        return buf;
    }
    if (cJSON_IsObject(it))
        return "an object";
    return "an invalid value";
}

/* Checks that `obj` is an object whose keys are all in `allowed` (NULL-terminated), once each. */
fs_status jkeys(const jctx *c, const cJSON *obj, const char *path, const char *const *allowed)
{
    char got[64], kp[256];
    if (!cJSON_IsObject(obj))
        return jfail(c, path, "expected an object, got %s", jgot(obj, got, sizeof got));
    for (const cJSON *ch = obj->child; ch; ch = ch->next) {
        bool ok = false;
        for (int i = 0; allowed[i]; i++)
            ok = ok || strcmp(ch->string, allowed[i]) == 0;
        if (!ok) {
            char list[512] = "";
            for (int i = 0; allowed[i]; i++) {
                size_t l = strlen(list);
                snprintf(list + l, sizeof list - l, "%s%s", i ? ", " : "", allowed[i]);
            }
            return jfail(c, jkey_path(kp, sizeof kp, path, ch->string),
                         "unknown key (expected one of: %s)", list);
        }
        for (const cJSON *prev = obj->child; prev != ch; prev = prev->next)
            if (strcmp(prev->string, ch->string) == 0)
                return jfail(c, jkey_path(kp, sizeof kp, path, ch->string), "duplicate key");
    }
    return FS_OK;
}

/* >>numbers */

static void nrange_describe(nrange r, char *buf, size_t n)
{
    const char *kind = r.pow2 ? "a power of two" : r.integer ? "an integer" : "a number";
    bool has_lo = isfinite(r.lo), has_hi = isfinite(r.hi);
    if (has_lo && has_hi)
        snprintf(buf, n, "%s in %c%.9g, %.9g%c", kind, r.lo_open ? '(' : '[', r.lo, r.hi,
                 r.hi_open ? ')' : ']');
    else if (has_lo)
        snprintf(buf, n, "%s %s %.9g", kind, r.lo_open ? ">" : ">=", r.lo);
    else if (has_hi)
        snprintf(buf, n, "%s %s %.9g", kind, r.hi_open ? "<" : "<=", r.hi);
    else
        snprintf(buf, n, "%s", kind);
}

static bool nrange_holds(nrange r, double v)
{
    if (!isfinite(v))
        return false;
    if (r.lo_open ? !(v > r.lo) : !(v >= r.lo))
        return false;
    if (r.hi_open ? !(v < r.hi) : !(v <= r.hi))
        return false;
    if ((r.integer || r.pow2) && v != floor(v))
        return false;
    if (r.pow2) {
        double f = frexp(v, &(int){0});
        if (f != 0.5)
            return false;
    }
    return true;
}

fs_status jnum(const jctx *c, const cJSON *it, const char *path, nrange r, double *out)
{
    char want[128], got[64];
    if (!cJSON_IsNumber(it) || !nrange_holds(r, it->valuedouble)) {
        nrange_describe(r, want, sizeof want);
        if (cJSON_IsNumber(it) && !isfinite(it->valuedouble))
            return jfail(c, path, "expected a finite number, got %s", jgot(it, got, sizeof got));
        return jfail(c, path, "expected %s, got %s", want, jgot(it, got, sizeof got));
    }
    *out = it->valuedouble;
    return FS_OK;
}

fs_status jfloat(const jctx *c, const cJSON *it, const char *path, nrange r, float *out)
{
    double v;
    fs_status s = jnum(c, it, path, r, &v);
    if (s == FS_OK) {
        /* Range-checked again as the float it is used as (README "Limits", numbers): 1e-300 is > 0 as a
         * double but 0 as a float, which readers take for "the default". */
        float f = (float)v;
        if (!isfinite(f))
            return jfail(c, path, "expected a number that fits a float, got %.9g", v);
        bool tiny = v != 0.0 && (f == 0.0f || !isnormal(f)); /* 0 or denormal as a float: not what was written */
        if (!nrange_holds(r, (double)f) || tiny) {
            char want[128];
            nrange_describe(r, want, sizeof want);
            return jfail(c, path, "expected %s, got %.9g (%s)", want, v,
                         tiny ? "too small for the 32-bit float it is used as"
                                                   : "out of range as the 32-bit float it is used as");
        }
        *out = f;
    }
    return s;
}

fs_status jint(const jctx *c, const cJSON *it, const char *path, int lo, int hi, int *out)
{
    nrange r = {lo, hi, false, false, true, false};
    double v;
    fs_status s = jnum(c, it, path, r, &v);
    if (s == FS_OK)
        *out = (int)v;
    return s;
}

fs_status jbool(const jctx *c, const cJSON *it, const char *path, bool *out)
{
    char got[64];
    if (!cJSON_IsBool(it))
        return jfail(c, path, "expected true or false, got %s", jgot(it, got, sizeof got));
    *out = cJSON_IsTrue(it);
    return FS_OK;
}

fs_status jstring(const jctx *c, const cJSON *it, const char *path, const char **out)
{
    char got[64];
    if (!cJSON_IsString(it) || !it->valuestring)
        return jfail(c, path, "expected a string, got %s", jgot(it, got, sizeof got));
    *out = it->valuestring;
    return FS_OK;
}

/* An array of exactly 3 numbers, each in r. */
fs_status jvec3(const jctx *c, const cJSON *it, const char *path, nrange r, vec3 *out)
{
    char got[64], ep[256];
    if (!cJSON_IsArray(it) || cJSON_GetArraySize(it) != 3)
        return jfail(c, path, "expected 3 numbers, got %s", jgot(it, got, sizeof got));
    float v[3];
    for (int i = 0; i < 3; i++) {
        fs_status s = jfloat(c, cJSON_GetArrayItem(it, i), jidx_path(ep, sizeof ep, path, i), r, &v[i]);
        if (s != FS_OK)
            return s;
    }
    *out = v3(v[0], v[1], v[2]);
    return FS_OK;
}

fs_status jmode(const jctx *c, const cJSON *it, const char *path, alpha_mode *out)
{
    const char *name;
    fs_status s = jstring(c, it, path, &name);
    if (s != FS_OK)
        return s;
    alpha_mode m = alpha_mode_parse(name);
    if (m == ALPHA_MODE_DEFAULT)
        return jfail(c, path, "unknown alpha mode \"%s\" (modes are: %s)", name, alpha_mode_list());
    *out = m;
    return FS_OK;
}

/* >>optional members */

/* The member `key` of obj (NULL when absent) and, when present, its path "parent.key" in buf. */
static const cJSON *member(const cJSON *obj, const char *parent, const char *key, char *buf, size_t n)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (it)
        jkey_path(buf, n, parent, key);
    return it;
}

fs_status jopt_num(const jctx *c, const cJSON *obj, const char *parent, const char *key, nrange r, double *out)
{
    char kp[JPATH_MAX];
    const cJSON *it = member(obj, parent, key, kp, sizeof kp);
    return it ? jnum(c, it, kp, r, out) : FS_OK;
}

fs_status jopt_float(const jctx *c, const cJSON *obj, const char *parent, const char *key, nrange r, float *out)
{
    char kp[JPATH_MAX];
    const cJSON *it = member(obj, parent, key, kp, sizeof kp);
    return it ? jfloat(c, it, kp, r, out) : FS_OK;
}

fs_status jopt_int(const jctx *c, const cJSON *obj, const char *parent, const char *key, int lo, int hi, int *out)
{
    char kp[JPATH_MAX];
    const cJSON *it = member(obj, parent, key, kp, sizeof kp);
    return it ? jint(c, it, kp, lo, hi, out) : FS_OK;
}

fs_status jopt_bool(const jctx *c, const cJSON *obj, const char *parent, const char *key, bool *out)
{
    char kp[JPATH_MAX];
    const cJSON *it = member(obj, parent, key, kp, sizeof kp);
    return it ? jbool(c, it, kp, out) : FS_OK;
}

fs_status jopt_vec3(const jctx *c, const cJSON *obj, const char *parent, const char *key, nrange r, vec3 *out)
{
    char kp[JPATH_MAX];
    const cJSON *it = member(obj, parent, key, kp, sizeof kp);
    return it ? jvec3(c, it, kp, r, out) : FS_OK;
}

fs_status jopt_mode(const jctx *c, const cJSON *obj, const char *parent, const char *key, alpha_mode *out)
{
    char kp[JPATH_MAX];
    const cJSON *it = member(obj, parent, key, kp, sizeof kp);
    return it ? jmode(c, it, kp, out) : FS_OK;
}

fs_status jopt_comment(const jctx *c, const cJSON *obj, const char *parent)
{
    const char *str;
    char kp[JPATH_MAX];
    const cJSON *it = member(obj, parent, "comment", kp, sizeof kp);
    return it ? jstring(c, it, kp, &str) : FS_OK;
}
