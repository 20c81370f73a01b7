/* sweep_manifest.c: a sweep's manifest (sweep_manifest.h). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "commands/sweep_manifest.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/config.h"
#include "core/file_read.h"
#include "core/hash.h"
#include "core/log.h"
#include "output/out_path.h"
#include "gaze/gaze_tracker.h"
#include "scene/scene.h"

#define MANIFEST_MAX_BYTES (1 << 20)

/* >>messages */

static fs_status bad(const sweep_manifest *m, const char *jpath, const char *fmt, ...) FS_PRINTF(3, 4);
static fs_status bad(const sweep_manifest *m, const char *jpath, const char *fmt, ...)
{
    char msg[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    log_error("%s: %s: %s", m->path, jpath, msg);
    return FS_ERR_USAGE;
}

/* >>paths */

/* Copies s into out[n] when it fits; false (out unchanged) when not. */
static bool put(char *out, size_t n, const char *s)
{
    size_t l = strlen(s);
    if (l >= n)
        return false;
    memcpy(out, s, l + 1);
    return true;
}

/* `p` relative to `dir` (unless absolute), made absolute and, when it exists, resolved. False
 * when the result does not fit in out[n]. */
static bool absolute(const char *dir, const char *p, char *out, size_t n)
{
    char joined[2 * PATH_MAX + 2], real[PATH_MAX];
    size_t dl = strlen(dir), pl = strlen(p);
    if (p[0] == '/' || dl + 1 + pl >= sizeof joined)
        return put(out, n, p) && p[0] == '/';
    memcpy(joined, dir, dl);
    joined[dl] = '/';
    memcpy(joined + dl + 1, p, pl + 1);
    return put(out, n, realpath(joined, real) ? real : joined);
}

static bool is_builtin_scene(const char *name)
{
    const char *list = scene_builtin_list();
    size_t l = strlen(name);
    for (const char *p = strstr(list, name); p; p = strstr(p + 1, name))
        if ((p == list || p[-1] == ' ') && (p[l] == ' ' || p[l] == '\0'))
            return true;
    return false;
}

/* >>lists */

/* A list of non-empty strings at obj[key]: an array, or one string. Absent or []: *count = 0. */
static fs_status strings(const sweep_manifest *m, const cJSON *obj, const char *key, const char **out, int *count)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    *count = 0;
    if (!v)
        return FS_OK;
    if (cJSON_IsString(v)) {
        out[(*count)++] = v->valuestring;
        return v->valuestring[0] ? FS_OK : bad(m, key, "expected a non-empty string");
    }
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) > SWEEP_MAX_LIST)
        return bad(m, key, "expected an array of at most %d strings", SWEEP_MAX_LIST);
    int i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        if (!cJSON_IsString(e) || !e->valuestring[0])
            return bad(m, key, "[%d]: expected a non-empty string", i);
        out[(*count)++] = e->valuestring;
    }
    return FS_OK;
}

static fs_status integer(const sweep_manifest *m, const cJSON *obj, const char *key, const char *jpath, int lo, int hi,
                         int *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v)
        return FS_OK;
    if (!cJSON_IsNumber(v) || v->valuedouble != (double)(long long)v->valuedouble || v->valuedouble < lo ||
        v->valuedouble > hi)
        return bad(m, jpath, "expected an integer in [%d, %d]", lo, hi);
    *out = (int)v->valuedouble;
    return FS_OK;
}

static fs_status text(const sweep_manifest *m, const cJSON *obj, const char *key, const char *jpath, char *out,
                      size_t n)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v)
        return FS_OK;
    if (!cJSON_IsString(v) || !v->valuestring[0] || strlen(v->valuestring) >= n || strchr(v->valuestring, '\n'))
        return bad(m, jpath, "expected a one-line string of 1 to %zu characters", n - 1);
    snprintf(out, n, "%s", v->valuestring);
    return FS_OK;
}

/* Every key of obj is one of `allowed` (NULL-terminated). */
static fs_status known_keys(const sweep_manifest *m, const cJSON *obj, const char *where, const char *const *allowed)
{
    for (const cJSON *c = obj->child; c; c = c->next) {
        bool ok = false;
        for (int i = 0; allowed[i]; i++)
            ok = ok || !strcmp(c->string, allowed[i]);
        if (!ok) {
            char list[512] = "", jp[256];
            for (int i = 0; allowed[i]; i++)
                snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? ", " : "", allowed[i]);
            snprintf(jp, sizeof jp, "%s%s%s", where, where[0] ? "." : "", c->string);
            return bad(m, jp, "unknown key (expected one of: %s)", list);
        }
    }
    return FS_OK;
}

/* >>load */

static char *dup_or_null(const char *s, bool *oom)
{
    char *d = s ? strdup(s) : NULL;
    *oom = *oom || (s && !d);
    return d;
}

/* What parse's phases share: the manifest being filled, the document, the manifest's folder
 * (relative paths resolve against it), the first failure (each phase does nothing once st is not
 * FS_OK, but for the defaults it sets) and whether a copy ran out of memory. */
typedef struct mparse {
    sweep_manifest *m;
    const cJSON *root;
    const char *dir;
    fs_status st;
    bool oom;
} mparse;

/* scenes: built-in names or files */
static void parse_scenes(mparse *p)
{
    sweep_manifest *m = p->m;
    const char *list[SWEEP_MAX_LIST];
    int n = 0;
    char abs_path[PATH_MAX];
    if (p->st == FS_OK && (p->st = strings(m, p->root, "scenes", list, &n)) == FS_OK && n == 0)
        p->st = bad(m, "scenes", "expected an array of scene files or built-in names (%s)", scene_builtin_list());
    for (int i = 0; i < n && p->st == FS_OK; i++) {
        const char *s = list[i];
        if (!strncmp(s, "builtin:", 8) || (is_builtin_scene(s) && !strchr(s, '/'))) {
            char b[128];
            snprintf(b, sizeof b, "builtin:%s", strncmp(s, "builtin:", 8) ? s : s + 8);
            if (!is_builtin_scene(b + 8))
                p->st = bad(m, "scenes", "[%d]: '%s': no such built-in scene (%s)", i, s, scene_builtin_list());
            m->scenes[m->nscenes++] = dup_or_null(b, &p->oom);
            continue;
        }
        if (!absolute(p->dir, s, abs_path, sizeof abs_path)) {
            p->st = bad(m, "scenes", "[%d]: the path is too long", i);
            break;
        }
        struct stat sb;
        int rc = stat(abs_path, &sb);
        if (rc != 0 || !S_ISREG(sb.st_mode))
            p->st = bad(m, "scenes", "[%d]: %s: expected a scene file or built-in name (%s): %s", i, abs_path,
                        scene_builtin_list(), rc != 0 ? strerror(errno) : "not a regular file");
        m->scenes[m->nscenes++] = dup_or_null(abs_path, &p->oom);
    }
}

/* gaze: "centre", builtin:NAME or files; default the centre */
static void parse_gaze(mparse *p)
{
    sweep_manifest *m = p->m;
    const char *list[SWEEP_MAX_LIST];
    int n = 0;
    char abs_path[PATH_MAX];
    if (p->st == FS_OK && (p->st = strings(m, p->root, "gaze", list, &n)) == FS_OK && n == 0)
        m->gaze[m->ngaze++] = NULL;
    for (int i = 0; i < n && p->st == FS_OK; i++) {
        const char *g = list[i];
        if (!strcmp(g, "centre") || !strcmp(g, "center")) {
            m->gaze[m->ngaze++] = NULL;
            continue;
        }
        if (!strncmp(g, "builtin:", 8)) {
            m->gaze[m->ngaze++] = dup_or_null(g, &p->oom); /* the task's gaze loader says if it is unknown */
            continue;
        }
        if (!absolute(p->dir, g, abs_path, sizeof abs_path)) {
            p->st = bad(m, "gaze", "[%d]: the path is too long", i);
            break;
        }
        if (access(abs_path, R_OK) != 0)
            p->st = bad(m, "gaze", "[%d]: %s: expected a readable gaze trace, builtin:NAME or \"centre\": %s", i,
                        abs_path, strerror(errno));
        m->gaze[m->ngaze++] = dup_or_null(abs_path, &p->oom);
    }
}

/* modes, compared together in every task; ring layouts ("vrs": VRS foveation, docs/cluster.md) and
 * TAA settings: the task's compare checks each ring value */
static void parse_modes_rings_taa(mparse *p)
{
    sweep_manifest *m = p->m;
    const char *list[SWEEP_MAX_LIST];
    int n = 0;
    if (p->st == FS_OK && (p->st = strings(m, p->root, "modes", list, &n)) == FS_OK && n == 0) {
        list[0] = "traditional", list[1] = "hashed";
        n = 2;
    }
    for (int i = 0; i < n && p->st == FS_OK; i++) {
        if (alpha_mode_parse(list[i]) == ALPHA_MODE_DEFAULT && strcmp(list[i], "all") != 0)
            p->st = bad(m, "modes", "[%d]: '%s': expected an alpha mode (%s) or all", i, list[i], alpha_mode_list());
        snprintf(m->modes + strlen(m->modes), sizeof m->modes - strlen(m->modes), "%s%s", i ? "," : "", list[i]);
    }
    if (p->st == FS_OK && (p->st = strings(m, p->root, "rings", list, &n)) == FS_OK && n == 0)
        list[0] = "default", n = 1;
    for (int i = 0; i < n && p->st == FS_OK; i++)
        m->rings[m->nrings++] = dup_or_null(list[i], &p->oom);
    if (p->st == FS_OK && (p->st = strings(m, p->root, "taa", list, &n)) == FS_OK && n == 0)
        list[0] = "default", n = 1;
    if (p->st == FS_OK && n > 3)
        p->st = bad(m, "taa", "expected at most 3 of \"on\", \"off\", \"default\"");
    for (int i = 0; i < n && p->st == FS_OK; i++) {
        static const char *const k_taa[] = {"default", "on", "off"};
        int k = 0;
        while (k < 3 && strcmp(list[i], k_taa[k]) != 0)
            k++;
        if (k == 3)
            p->st = bad(m, "taa", "[%d]: '%s': expected \"on\", \"off\" or \"default\" (the scene's)", i, list[i]);
        else
            m->taa[m->ntaa++] = k_taa[k];
    }
}

/* >>the eye tracker's axes */

static const struct {
    const char *key, *option, *label;
    double hi; /* numbers in [0, hi]; 0: names of a loss policy */
} k_tracker_axes[SWEEP_TRACKER_AXES] = {
    {"gaze_latency", "--gaze-latency", "lat", GAZE_TRACKER_MAX_LATENCY_MS},
    {"gaze_rate", "--gaze-rate", "rate", GAZE_TRACKER_MAX_RATE_HZ},
    {"gaze_noise", "--gaze-noise", "noise", GAZE_TRACKER_MAX_NOISE_DEG},
    {"gaze_loss", "--gaze-loss", "loss", 0},
};

const char *sweep_tracker_key(int a)
{
    return k_tracker_axes[a].key;
}

const char *sweep_tracker_option(int a)
{
    return k_tracker_axes[a].option;
}

const char *sweep_tracker_label(int a)
{
    return k_tracker_axes[a].label;
}

const char *sweep_tracker_value(const sweep_manifest *m, int t, int a)
{
    for (int b = SWEEP_TRACKER_AXES - 1; b > a; b--)
        t /= m->ntracker_axis[b];
    return m->tracker[a][t % m->ntracker_axis[a]];
}

/* One value of axis a, as its option takes it; else NULL after one line. */
static char *tracker_value(mparse *p, int a, const cJSON *v, int i)
{
    char buf[32], path[48];
    snprintf(path, sizeof path, "%s[%d]", k_tracker_axes[a].key, i);
    if (k_tracker_axes[a].hi == 0) {
        if (!cJSON_IsString(v) || gaze_loss_parse(v->valuestring) == GAZE_LOSS_COUNT) {
            p->st = bad(p->m, path, "expected \"hold\", \"centre\" or \"full\"");
            return NULL;
        }
        return dup_or_null(v->valuestring, &p->oom);
    }
    if (!cJSON_IsNumber(v) || !(v->valuedouble >= 0 && v->valuedouble <= k_tracker_axes[a].hi)) {
        p->st = bad(p->m, path, "expected a number in [0, %g]", k_tracker_axes[a].hi);
        return NULL;
    }
    snprintf(buf, sizeof buf, "%.9g", v->valuedouble);
    return dup_or_null(buf, &p->oom);
}

/* gaze_latency, gaze_rate, gaze_noise, gaze_loss: a value or a list each (absent: the scene's);
 * gaze_seed: one integer for every task */
static void parse_tracker(mparse *p)
{
    sweep_manifest *m = p->m;
    m->ntracker = 1;
    for (int a = 0; a < SWEEP_TRACKER_AXES && p->st == FS_OK; a++) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(p->root, k_tracker_axes[a].key);
        int n = 0;
        if (v && cJSON_IsArray(v) && (cJSON_GetArraySize(v) < 1 || cJSON_GetArraySize(v) > SWEEP_MAX_LIST))
            p->st = bad(m, k_tracker_axes[a].key, "expected a value or a list of 1 to %d values", SWEEP_MAX_LIST);
        for (const cJSON *e = v && cJSON_IsArray(v) ? v->child : v; e && p->st == FS_OK;
             e = cJSON_IsArray(v) ? e->next : NULL, n++)
            m->tracker[a][n] = tracker_value(p, a, e, n);
        m->has_tracker = m->has_tracker || n > 0;
        m->ntracker_axis[a] = n > 0 ? n : 1; /* absent: one entry, NULL */
        m->ntracker *= m->ntracker_axis[a];
    }
    int seed = -1;
    if (p->st == FS_OK)
        p->st = integer(m, p->root, "gaze_seed", "gaze_seed", 0, 2147483647, &seed);
    if (seed >= 0) {
        snprintf(m->gaze_seed, sizeof m->gaze_seed, "%d", seed);
        m->has_tracker = true;
    }
    if (p->st == FS_OK && m->ntracker > SWEEP_MAX_LIST)
        p->st = bad(m, "gaze_latency", "the tracker axes make %d combinations, more than %d", m->ntracker,
                    SWEEP_MAX_LIST);
}

/* display and sequence; the reference */
static void parse_display_reference(mparse *p)
{
    static const char *const k_ref[] = {"kind", "supersample", "samples", NULL};
    sweep_manifest *m = p->m;
    const cJSON *root = p->root;
    if (p->st == FS_OK)
        p->st = integer(m, root, "width", "width", 1, 16384, &m->width);
    if (p->st == FS_OK)
        p->st = integer(m, root, "height", "height", 1, 16384, &m->height);
    if (p->st == FS_OK && (m->width > 0) != (m->height > 0))
        p->st = bad(m, m->width ? "height" : "width", "expected width and height together, or neither");
    if (p->st == FS_OK)
        p->st = integer(m, root, "frames", "frames", 1, MAX_FRAMES, &m->frames);
    const cJSON *fps = cJSON_GetObjectItemCaseSensitive(root, "fps");
    if (p->st == FS_OK && fps) {
        if (!cJSON_IsNumber(fps) || !(fps->valuedouble >= FPS_MIN && fps->valuedouble <= FPS_MAX))
            p->st = bad(m, "fps", "expected a number in [0.001, 1000]");
        else
            m->fps = fps->valuedouble;
    }
    const cJSON *ref = cJSON_GetObjectItemCaseSensitive(root, "reference");
    if (p->st == FS_OK && ref && !cJSON_IsObject(ref))
        p->st = bad(m, "reference", "expected an object with kind, supersample, samples");
    if (p->st == FS_OK && ref)
        p->st = known_keys(m, ref, "reference", k_ref);
    if (p->st == FS_OK && ref)
        p->st = text(m, ref, "kind", "reference.kind", m->reference, sizeof m->reference);
    if (p->st == FS_OK && m->reference[0] && strcmp(m->reference, "exact") && strcmp(m->reference, "stochastic"))
        p->st = bad(m, "reference.kind", "expected \"exact\" or \"stochastic\", got '%s'", m->reference);
    if (p->st == FS_OK && ref)
        p->st = integer(m, ref, "supersample", "reference.supersample", 1, 16, &m->supersample);
    if (p->st == FS_OK && ref)
        p->st = integer(m, ref, "samples", "reference.samples", 2, 4096, &m->samples);
}

/* chunks, and the chunks a sweep found (written into its copies; not for people to write) */
static void parse_chunks(mparse *p)
{
    sweep_manifest *m = p->m;
    const cJSON *root = p->root;
    if (p->st == FS_OK)
        p->st = integer(m, root, "chunk_frames", "chunk_frames", 1, MAX_FRAMES, &m->chunk_frames);
    m->warmup = SWEEP_DEFAULT_WARMUP;
    if (p->st == FS_OK)
        p->st = integer(m, root, "warmup", "warmup", 0, MAX_FRAMES, &m->warmup);
    const cJSON *cs = cJSON_GetObjectItemCaseSensitive(root, "chunk_starts");
    if (p->st == FS_OK && cs && m->chunk_frames && (!cJSON_IsArray(cs) || cJSON_GetArraySize(cs) != m->nscenes))
        p->st = bad(m, "chunk_starts", "expected one array per scene (written by fovsim sweep; remove it)");
    int si = 0;
    for (const cJSON *e = cs && m->chunk_frames ? cs->child : NULL; e && p->st == FS_OK; e = e->next, si++) {
        int len = cJSON_GetArraySize(e), prev = -1;
        if (!cJSON_IsArray(e) || len < 2 || !(m->chunks[si] = malloc(sizeof(int) * (size_t)len))) {
            p->st = bad(m, "chunk_starts", "[%d]: expected increasing frame numbers (written by fovsim sweep)", si);
            break;
        }
        int j = 0;
        for (const cJSON *f = e->child; f; f = f->next, j++) {
            if (!cJSON_IsNumber(f) || f->valuedouble <= prev || f->valuedouble > MAX_FRAMES) {
                p->st = bad(m, "chunk_starts", "[%d][%d]: expected increasing frame numbers (written by fovsim sweep)",
                            si, j);
                break;
            }
            prev = m->chunks[si][j] = (int)f->valuedouble;
        }
        m->nchunks[si] = len - 1;
    }
}

/* further compare options; Slurm */
static void parse_options_slurm(mparse *p)
{
    static const char *const k_slurm[] = {"cpus_per_task", "mem", "time", "partition", "max_running", "extra", NULL};
    sweep_manifest *m = p->m;
    const char *list[SWEEP_MAX_LIST];
    int n = 0;
    if (p->st == FS_OK && (p->st = strings(m, p->root, "options", list, &n)) == FS_OK)
        for (int i = 0; i < n; i++)
            m->options[m->noptions++] = dup_or_null(list[i], &p->oom);
    m->slurm.cpus_per_task = 2;
    const cJSON *sl = cJSON_GetObjectItemCaseSensitive(p->root, "slurm");
    if (p->st == FS_OK && sl && !cJSON_IsObject(sl))
        p->st = bad(m, "slurm", "expected an object");
    if (p->st == FS_OK && sl)
        p->st = known_keys(m, sl, "slurm", k_slurm);
    if (p->st == FS_OK && sl)
        p->st = integer(m, sl, "cpus_per_task", "slurm.cpus_per_task", 1, 4096, &m->slurm.cpus_per_task);
    if (p->st == FS_OK && sl)
        p->st = integer(m, sl, "max_running", "slurm.max_running", 1, 100000, &m->slurm.max_running);
    if (p->st == FS_OK && sl)
        p->st = text(m, sl, "mem", "slurm.mem", m->slurm.mem, sizeof m->slurm.mem);
    if (p->st == FS_OK && sl)
        p->st = text(m, sl, "time", "slurm.time", m->slurm.time, sizeof m->slurm.time);
    if (p->st == FS_OK && sl)
        p->st = text(m, sl, "partition", "slurm.partition", m->slurm.partition, sizeof m->slurm.partition);
    if (p->st == FS_OK && sl && (p->st = strings(m, sl, "extra", list, &n)) == FS_OK) {
        if (n > 16)
            p->st = bad(m, "slurm.extra", "expected at most 16 lines");
        for (int i = 0; i < n && p->st == FS_OK; i++) {
            if (strchr(list[i], '\n') || list[i][0] != '-')
                p->st = bad(m, "slurm.extra", "[%d]: expected one sbatch option such as \"--account=lab\"", i);
            m->slurm.extra[m->slurm.nextra++] = dup_or_null(list[i], &p->oom);
        }
    }
}

/* The command line's settings win. */
static void apply_overrides(sweep_manifest *m, const sweep_overrides *ov)
{
    if (ov->chunk_frames && ov->chunk_frames != m->chunk_frames) {
        for (int i = 0; i < m->nscenes; i++) { /* found for another length: found again */
            free(m->chunks[i]);
            m->chunks[i] = NULL;
        }
        m->chunk_frames = ov->chunk_frames;
    }
    if (ov->warmup >= 0)
        m->warmup = ov->warmup;
    if (ov->cpus_per_task)
        m->slurm.cpus_per_task = ov->cpus_per_task;
    if (ov->max_running)
        m->slurm.max_running = ov->max_running;
    if (ov->mem)
        snprintf(m->slurm.mem, sizeof m->slurm.mem, "%s", ov->mem);
    if (ov->time)
        snprintf(m->slurm.time, sizeof m->slurm.time, "%s", ov->time);
    if (ov->partition)
        snprintf(m->slurm.partition, sizeof m->slurm.partition, "%s", ov->partition);
}

/* The sweep's folder (--out, else "out", else out/sweep/NAME) and its cache, made absolute. */
static void parse_out_cache(mparse *p, const sweep_overrides *ov)
{
    sweep_manifest *m = p->m;
    char out[PATH_MAX] = "";
    if (p->st == FS_OK)
        p->st = text(m, p->root, "out", "out", out, sizeof out);
    bool fits;
    char cwd[PATH_MAX];
    if (!getcwd(cwd, sizeof cwd))
        snprintf(cwd, sizeof cwd, ".");
    if (ov->out) {
        fits = absolute(cwd, ov->out, m->out, sizeof m->out);
    } else if (out[0]) {
        fits = absolute(p->dir, out, m->out, sizeof m->out);
    } else {
        const char *b = strrchr(m->path, '/') ? strrchr(m->path, '/') + 1 : m->path;
        char rel[128] = "out/sweep/";
        size_t l = strlen(rel), bl = strcspn(b, ".");
        bl = bl < sizeof rel - l - 1 ? bl : sizeof rel - l - 1;
        memcpy(rel + l, b, bl);
        rel[l + bl] = '\0';
        fits = absolute(cwd, rel, m->out, sizeof m->out);
    }
    if (p->st == FS_OK && !fits)
        p->st = bad(m, "out", "the sweep's folder, made absolute, is longer than %zu characters", sizeof m->out - 1);
    char cache[PATH_MAX] = "";
    if (p->st == FS_OK)
        p->st = text(m, p->root, "cache", "cache", cache, sizeof cache);
    if (cache[0])
        fits = absolute(p->dir, cache, m->cache, sizeof m->cache);
    else
        fits = strlen(m->out) + 6 < sizeof m->cache && (strcat(strcpy(m->cache, m->out), "/cache"), true);
    if (p->st == FS_OK && !fits)
        p->st = bad(m, "cache", "the cache folder, made absolute, is longer than %zu characters", sizeof m->cache - 1);
}

static fs_status parse(sweep_manifest *m, const cJSON *root, const char *dir, const sweep_overrides *ov)
{
    static const char *const k_top[] = {"scenes", "gaze", "modes", "rings", "taa", "width", "height", "fps",
                                        "frames", "reference", "cache", "chunk_frames", "warmup", "options",
                                        "slurm", "out", "chunk_starts", "gaze_latency", "gaze_rate",
                                        "gaze_noise", "gaze_loss", "gaze_seed", NULL};
    if (!cJSON_IsObject(root))
        return bad(m, "(top level)", "expected an object");
    mparse p = {.m = m, .root = root, .dir = dir};
    p.st = known_keys(m, root, "", k_top);
    parse_scenes(&p);
    parse_gaze(&p);
    parse_modes_rings_taa(&p);
    parse_tracker(&p);
    parse_display_reference(&p);
    parse_chunks(&p);
    parse_options_slurm(&p);
    apply_overrides(m, ov);
    parse_out_cache(&p, ov);
    if (p.oom)
        return FS_ERR_NOMEM;
    return p.st;
}

/* The manifest as loaded, with absolute paths and every default written out. */
static char *normalised(const sweep_manifest *m)
{
    cJSON *o = cJSON_CreateObject(), *a;
    a = cJSON_AddArrayToObject(o, "scenes");
    for (int i = 0; i < m->nscenes; i++)
        cJSON_AddItemToArray(a, cJSON_CreateString(m->scenes[i]));
    a = cJSON_AddArrayToObject(o, "gaze");
    for (int i = 0; i < m->ngaze; i++)
        cJSON_AddItemToArray(a, cJSON_CreateString(m->gaze[i] ? m->gaze[i] : "centre"));
    a = cJSON_AddArrayToObject(o, "modes");
    char modes[sizeof m->modes];
    snprintf(modes, sizeof modes, "%s", m->modes);
    for (char *save = NULL, *t = strtok_r(modes, ",", &save); t; t = strtok_r(NULL, ",", &save))
        cJSON_AddItemToArray(a, cJSON_CreateString(t));
    a = cJSON_AddArrayToObject(o, "rings");
    for (int i = 0; i < m->nrings; i++)
        cJSON_AddItemToArray(a, cJSON_CreateString(m->rings[i]));
    a = cJSON_AddArrayToObject(o, "taa");
    for (int i = 0; i < m->ntaa; i++)
        cJSON_AddItemToArray(a, cJSON_CreateString(m->taa[i]));
    for (int x = 0; x < SWEEP_TRACKER_AXES; x++) { /* only those given: manifests without stay as they were */
        if (!m->tracker[x][0])
            continue;
        a = cJSON_AddArrayToObject(o, k_tracker_axes[x].key);
        for (int i = 0; i < m->ntracker_axis[x]; i++)
            cJSON_AddItemToArray(a, k_tracker_axes[x].hi == 0 ? cJSON_CreateString(m->tracker[x][i])
                                                              : cJSON_CreateNumber(atof(m->tracker[x][i])));
    }
    if (m->gaze_seed[0])
        cJSON_AddNumberToObject(o, "gaze_seed", atoi(m->gaze_seed));
    if (m->width) {
        cJSON_AddNumberToObject(o, "width", m->width);
        cJSON_AddNumberToObject(o, "height", m->height);
    }
    if (m->fps > 0)
        cJSON_AddNumberToObject(o, "fps", m->fps);
    if (m->frames)
        cJSON_AddNumberToObject(o, "frames", m->frames);
    cJSON *r = cJSON_AddObjectToObject(o, "reference");
    if (m->reference[0])
        cJSON_AddStringToObject(r, "kind", m->reference);
    if (m->supersample)
        cJSON_AddNumberToObject(r, "supersample", m->supersample);
    if (m->samples)
        cJSON_AddNumberToObject(r, "samples", m->samples);
    cJSON_AddStringToObject(o, "cache", m->cache);
    if (m->chunk_frames)
        cJSON_AddNumberToObject(o, "chunk_frames", m->chunk_frames);
    cJSON_AddNumberToObject(o, "warmup", m->warmup);
    a = cJSON_AddArrayToObject(o, "options");
    for (int i = 0; i < m->noptions; i++)
        cJSON_AddItemToArray(a, cJSON_CreateString(m->options[i]));
    cJSON *s = cJSON_AddObjectToObject(o, "slurm");
    cJSON_AddNumberToObject(s, "cpus_per_task", m->slurm.cpus_per_task);
    if (m->slurm.max_running)
        cJSON_AddNumberToObject(s, "max_running", m->slurm.max_running);
    if (m->slurm.mem[0])
        cJSON_AddStringToObject(s, "mem", m->slurm.mem);
    if (m->slurm.time[0])
        cJSON_AddStringToObject(s, "time", m->slurm.time);
    if (m->slurm.partition[0])
        cJSON_AddStringToObject(s, "partition", m->slurm.partition);
    a = cJSON_AddArrayToObject(s, "extra");
    for (int i = 0; i < m->slurm.nextra; i++)
        cJSON_AddItemToArray(a, cJSON_CreateString(m->slurm.extra[i]));
    if (m->chunk_frames) {
        a = cJSON_AddArrayToObject(o, "chunk_starts");
        for (int i = 0; i < m->nscenes; i++)
            cJSON_AddItemToArray(a, cJSON_CreateIntArray(m->chunks[i], m->chunks[i] ? m->nchunks[i] + 1 : 0));
    }
    cJSON_AddStringToObject(o, "out", m->out);
    char *text = cJSON_Print(o);
    cJSON_Delete(o);
    return text;
}

fs_status sweep_manifest_write(sweep_manifest *m)
{
    char *text = normalised(m);
    if (!text)
        return FS_ERR_NOMEM;
    size_t len = strlen(text);
    char *withnl = realloc(text, len + 2);
    if (!withnl) {
        free(text);
        return FS_ERR_NOMEM;
    }
    text = withnl;
    memcpy(text + len, "\n", 2);
    uint64_t h = hash_str(HASH_FNV_INIT, text);
    char logs[PATH_MAX + 16], latest[PATH_MAX + 32];
    snprintf(logs, sizeof logs, "%s/logs", m->out);
    snprintf(latest, sizeof latest, "%s/manifest.json", m->out);
    snprintf(m->frozen, sizeof m->frozen, "%s/manifest-%08" PRIx32 ".json", m->out, (uint32_t)(h ^ (h >> 32)));
    fs_status st = file_make_dirs(logs);
    struct stat sb;
    if (st == FS_OK && stat(m->frozen, &sb) != 0)
        st = out_write_atomic(m->frozen, text);
    if (st == FS_OK)
        st = out_write_atomic(latest, text);
    free(text);
    return st;
}

fs_status sweep_manifest_load(const char *path, const sweep_overrides *ov, sweep_manifest *m)
{
    memset(m, 0, sizeof *m);
    snprintf(m->path, sizeof m->path, "%s", path);
    char *buf = NULL;
    size_t size = 0;
    fs_status st = file_read_all(path, MANIFEST_MAX_BYTES, "a sweep manifest", FS_ERR_USAGE, &buf, &size);
    if (st != FS_OK)
        return st;
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(buf, size + 1, &end, true); /* with the NUL */
    if (!root) {
        size_t off = end ? (size_t)(end - buf) : 0;
        int line = 1, col = 1;
        for (size_t i = 0; i < off && i < size; i++)
            buf[i] == '\n' ? (line++, col = 1) : col++;
        log_error("%s:%d:%d: not valid JSON", path, line, col);
        free(buf);
        return FS_ERR_USAGE;
    }
    char dir[PATH_MAX], real[PATH_MAX];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash)
        *slash = '\0';
    else
        snprintf(dir, sizeof dir, ".");
    if (realpath(dir, real))
        snprintf(dir, sizeof dir, "%s", real);
    st = parse(m, root, dir, ov);
    cJSON_Delete(root);
    free(buf);
    snprintf(m->frozen, sizeof m->frozen, "%s", m->path);
    return st;
}

fs_status sweep_manifest_load_dir(const char *sweep_dir, sweep_manifest *m)
{
    memset(m, 0, sizeof *m);
    char path[PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/manifest.json", sweep_dir);
    if (access(path, R_OK) != 0) {
        log_error("%s: cannot read: %s (is %s a sweep's folder?)", path, strerror(errno), sweep_dir);
        return FS_ERR_IO;
    }
    /* The folder as given, not the "out" it was written with: a sweep's folder may be moved. */
    return sweep_manifest_load(path, &(sweep_overrides){.out = sweep_dir, .warmup = -1}, m);
}

void sweep_manifest_free(sweep_manifest *m)
{
    for (int i = 0; i < m->nscenes; i++)
        free(m->scenes[i]);
    for (int i = 0; i < m->ngaze; i++)
        free(m->gaze[i]);
    for (int i = 0; i < m->nrings; i++)
        free(m->rings[i]);
    for (int a = 0; a < SWEEP_TRACKER_AXES; a++)
        for (int i = 0; i < m->ntracker_axis[a]; i++)
            free(m->tracker[a][i]);
    for (int i = 0; i < m->noptions; i++)
        free(m->options[i]);
    for (int i = 0; i < m->slurm.nextra; i++)
        free(m->slurm.extra[i]);
    for (int i = 0; i < m->nscenes; i++)
        free(m->chunks[i]);
    free(m->tasks);
    memset(m, 0, sizeof *m);
}

/* >>a task's compare */

int sweep_task_options(const sweep_manifest *m, const sweep_task *k, char **argv, int cap)
{
    int n = 0;
    bool oom = false;
#define ARG(...)                                                                                                       \
    do {                                                                                                               \
        char b_[PATH_MAX + 64];                                                                                        \
        snprintf(b_, sizeof b_, __VA_ARGS__);                                                                          \
        if (n < cap - 3)                                                                                               \
            oom = oom || !(argv[n++] = strdup(b_));                                                                    \
        else                                                                                                           \
            oom = true;                                                                                                \
    } while (0)
    ARG("%s", m->scenes[k->scene]);
    if (m->gaze[k->gaze]) {
        ARG("--gaze");
        ARG("%s", m->gaze[k->gaze]);
    }
    ARG("--modes");
    ARG("%s", m->modes);
    if (strcmp(m->rings[k->rings], "vrs") == 0) { /* VRS foveation, beside the ring layouts */
        ARG("--foveation");
        ARG("vrs");
    } else if (strcmp(m->rings[k->rings], "default") != 0) {
        ARG("--rings");
        ARG("%s", m->rings[k->rings]);
    }
    if (strcmp(m->taa[k->taa], "default") != 0) {
        ARG("--taa");
        ARG("%s", m->taa[k->taa]);
    }
    for (int a = 0; a < SWEEP_TRACKER_AXES; a++)
        if (sweep_tracker_value(m, k->tracker, a)) {
            ARG("%s", k_tracker_axes[a].option);
            ARG("%s", sweep_tracker_value(m, k->tracker, a));
        }
    if (m->gaze_seed[0]) {
        ARG("--gaze-seed");
        ARG("%s", m->gaze_seed);
    }
    if (m->width) {
        ARG("--width");
        ARG("%d", m->width);
        ARG("--height");
        ARG("%d", m->height);
    }
    if (m->fps > 0) {
        ARG("--fps");
        ARG("%.9g", m->fps);
    }
    if (k->end > 0 && (k->first > 0 || m->chunk_frames)) {
        ARG("--frames");
        ARG("%d", k->end);
        if (k->first > 0) {
            ARG("--first-frame");
            ARG("%d", k->first);
            ARG("--warmup");
            ARG("%d", m->warmup);
        }
    } else if (m->frames) {
        ARG("--frames");
        ARG("%d", m->frames);
    }
    if (m->reference[0]) {
        ARG("--reference");
        ARG("%s", m->reference);
    }
    if (m->supersample) {
        ARG("--supersample");
        ARG("%d", m->supersample);
    }
    if (m->samples) {
        ARG("--samples");
        ARG("%d", m->samples);
    }
    ARG("--cache");
    ARG("%s", m->cache);
    ARG("--out");
    ARG("%.*s/tasks/%.*s", 700, m->out, 199, k->name);
    for (int i = 0; i < m->noptions; i++)
        ARG("%s", m->options[i]);
#undef ARG
    argv[n] = NULL;
    if (oom) {
        sweep_task_options_free(argv, n);
        log_error("a task's command line: out of memory, or more than %d arguments", cap - 3);
        return -1;
    }
    return n;
}

void sweep_task_options_free(char **argv, int argc)
{
    for (int i = 0; i < argc; i++)
        free(argv[i]);
}
