/* sweep.c: `fovsim sweep MANIFEST` (docs/cluster.md); `fovsim merge SWEEP_DIR` is merge.c.
 *
 * A manifest (JSON) names scenes, gaze traces, alpha modes, ring layouts, TAA settings, the
 * display and the reference; the sweep is the product of scenes x traces x ring layouts x TAA
 * settings (x frame chunks with --chunk-frames), each task one `fovsim compare` of every mode into
 * SWEEP/tasks/<a name derived from its parameters>/. The task list is run by the same binary in
 * three ways: a jobs file (one shell command per line, for GNU parallel or any farm), a Slurm array
 * script (sbatch), or --local N processes here. Every way runs `fovsim sweep MANIFEST --task I`,
 * which skips a task whose folder's record says complete (run_record.h) and redraws one that is
 * not, so running the list again resumes it. `fovsim merge` gathers the tasks' metrics.
 *
 * What a sweep writes, all under SWEEP (the manifest's "out", or --out):
 *   manifest.json           the manifest with absolute paths (what merge reads)
 *   manifest-<hash>.json    the same, under a name of its content: the jobs and the Slurm script
 *                           read this one, so editing the manifest never changes a running task
 *   tasks/<task>/           each task's compare output (frames, metrics.csv, summary.json, record)
 *   logs/                   each task's output (task-NNNN.log; Slurm: slurm-<job>_<index>.out/.err)
 *   jobs.txt, sweep.sbatch  with --jobs-file / --slurm
 *   metrics.csv, summary.json, accuracy.csv, accuracy.png   by merge */
#include "commands/commands.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <signal.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli/cli.h"
#include "core/config.h"
#include "core/file_read.h"
#include "core/grow.h"
#include "core/hash.h"
#include "core/log.h"
#include "core/spawn.h"
#include "core/progress.h"
#include "core/strbuf.h"
#include "output/out_path.h"
#include "fov/fov_ring.h"
#include "session/run_record.h"
#include "frame/frame.h"
#include "reference/reference.h"
#include "session/session.h"
#include "commands/sweep_manifest.h"

/* >>task list */

/* A file or folder name from `s`: letters, digits, '-' and '_' kept, the rest '_', at most n - 1. */
static void slug(const char *s, char *out, size_t n)
{
    size_t k = 0;
    for (; *s && k + 1 < n; s++)
        out[k++] = (*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') || *s == '-' ||
                           *s == '_'
                       ? *s
                       : '_';
    out[k] = '\0';
}

/* A scene's or trace's short name: "builtin:forest" -> forest, "/a/b/p01.csv" -> p01. */
static void short_name(const char *s, char *out, size_t n)
{
    if (!s) {
        snprintf(out, n, "centre");
        return;
    }
    const char *b = strncmp(s, "builtin:", 8) == 0 ? s + 8 : strrchr(s, '/') ? strrchr(s, '/') + 1 : s;
    char tmp[128];
    snprintf(tmp, sizeof tmp, "%s", b);
    char *dot = strrchr(tmp, '.');
    if (dot && dot != tmp)
        *dot = '\0';
    slug(tmp, out, n > 41 ? 41 : n);
}

/* The chunks of a sequence of `frames` frames: each boundary `chunk` frames after the last, moved
 * to a camera cut within a quarter chunk of it (the history starts afresh there: no warm-up needed).
 * starts[0..*count) and the end, starts[*count] = frames. */
static fs_status chunk_bounds(const scene *sc, int frames, float fps, int chunk, int width, int height, int **starts,
                              int *count)
{
    /* A boundary moved back to a cut makes its chunk as short as chunk - chunk/4 frames. */
    int cap = frames / (chunk - chunk / 4) + 2;
    int *b = malloc(sizeof(int) * (size_t)cap);
    if (!b)
        return FS_ERR_NOMEM;
    int n = 0;
    b[n++] = 0;
    for (int nominal = chunk; nominal < frames; nominal = b[n - 1] + chunk) {
        int best = -1, reach = chunk / 4;
        for (int c = nominal - reach; c <= nominal + reach; c++) {
            if (c <= b[n - 1] || c >= frames)
                continue;
            frame_record fr = frame_record_at(sc, c, (float)c / fps, (float)(c - 1) / fps, width, height);
            if (fr.cut && (best < 0 || abs(c - nominal) < abs(best - nominal)))
                best = c;
        }
        best = best < 0 ? nominal : best;
        if (best > b[n - 1])
            b[n++] = best;
    }
    b[n] = frames;
    *starts = b;
    *count = n;
    return FS_OK;
}

/* Task k's compare run: its options through the CLI's table (cli.h), then --replace and --quiet
 * when asked. `opts` (sweep_task_options, freed by the caller after the run) holds the strings. */
static fs_status task_desc(const sweep_manifest *m, const sweep_task *k, char **opts, int *n, run_desc *d,
                           bool replace, bool quiet)
{
    *n = sweep_task_options(m, k, opts, SWEEP_MAX_ARGS);
    if (*n < 0)
        return FS_ERR_NOMEM;
    cli_begin(d, CMD_COMPARE);
    fs_status st = cli_parse_args(d, *n, opts);
    if (st == FS_OK && replace)
        st = cli_apply_option(d, "--replace", NULL);
    if (st == FS_OK && quiet)
        st = cli_apply_option(d, "--quiet", NULL);
    /* A task's report.html is for a look at one task; the merged report is the sweep's. Previews
     * at every task would fill a cluster's disk: none unless the manifest's options ask. */
    if (st == FS_OK && !d->compare.previews_set)
        st = cli_apply_option(d, "--previews", "0");
    if (st == FS_OK)
        st = cli_finish(d);
    /* A foveation study writes a folder per foveation, not the task's: a sweep's are its "rings" axis. */
    if (st == FS_OK && d->foveation_count > 1) {
        log_error("options: --foveation with a list is a foveation study of its own; in a sweep give them as the "
                  "\"rings\" axis, e.g. [\"default\", \"vrs\"] (docs/cluster.md)");
        st = FS_ERR_USAGE;
    }
    /* A latency study writes a folder per latency, not the task's: a sweep's latencies are its axis. */
    if (st == FS_OK && d->gaze_latency_count > 1) {
        log_error("options: --gaze-latency with a list is a latency study of its own; in a sweep give the latencies "
                  "as the \"gaze_latency\" axis (docs/latency.md)");
        st = FS_ERR_USAGE;
    }
    return st;
}

/* Tracker combination e in a task's name (".lat-50.loss-full", the axes given only, so names
 * without a tracker stay as they were), hashed into *h; returns the characters written. */
static int tracker_name(const sweep_manifest *m, int e, uint64_t *h, char *out, size_t n)
{
    int o = 0;
    for (int a = 0; a < SWEEP_TRACKER_AXES; a++) {
        const char *v = sweep_tracker_value(m, e, a);
        if (!v)
            continue;
        char sv[24];
        slug(v, sv, sizeof sv);
        *h = hash_str(hash_str(*h, sweep_tracker_key(a)), v);
        int w = snprintf(out + o, n - (size_t)o, ".%s-%s", sweep_tracker_label(a), sv);
        o += w > 0 && (size_t)(o + w) < n ? w : 0;
    }
    return o;
}

/* The task list: scenes x traces x ring layouts x TAA settings x tracker combinations x chunks, in
 * that nesting. */
fs_status sweep_build_tasks(sweep_manifest *m)
{
    int per_chunk = m->ngaze * m->nrings * m->ntaa * m->ntracker; /* a scene's tasks per chunk */
    int cap = 0;
    m->tasks = NULL;
    m->ntasks = 0;
    fs_status st = FS_OK;
    for (int s = 0; s < m->nscenes && st == FS_OK; s++) {
        int frames = m->frames;
        if (m->chunk_frames > 0 && !m->chunks[s]) {
            /* The scene's length and cuts, with the options the tasks use (asset root, size). */
            scene sc;
            run_desc d;
            char *opts[SWEEP_MAX_ARGS];
            int n;
            st = task_desc(m, &(sweep_task){.scene = s}, opts, &n, &d, false, false);
            if (st == FS_OK)
                st = session_load_scene(&d, &sc);
            if (st == FS_OK) {
                frames = session_frame_count(&d, &sc);
                int w = d.width ? d.width : sc.display.width, h = d.height ? d.height : sc.display.height;
                st = chunk_bounds(&sc, frames, d.fps, m->chunk_frames, w, h, &m->chunks[s], &m->nchunks[s]);
                scene_free(&sc);
            }
            sweep_task_options_free(opts, n > 0 ? n : 0);
            if (st != FS_OK)
                break;
        }
        const int *starts = m->chunk_frames > 0 ? m->chunks[s] : NULL;
        int nchunks = starts ? m->nchunks[s] : 1;
        if (!FS_GROW_INT(m->tasks, cap, m->ntasks + per_chunk * nchunks)) {
            st = FS_ERR_NOMEM;
            break;
        }
        for (int g = 0; g < m->ngaze; g++)
            for (int r = 0; r < m->nrings; r++)
                for (int t = 0; t < m->ntaa; t++)
                    for (int ec = 0; ec < m->ntracker * nchunks; ec++) { /* tracker settings x chunks */
                        int e = ec / nchunks, c = ec % nchunks;
                        sweep_task *k = &m->tasks[m->ntasks++];
                        *k = (sweep_task){.scene = s, .gaze = g, .rings = r, .taa = t, .tracker = e,
                                          .first = starts ? starts[c] : 0,
                                          .end = starts ? starts[c + 1] : frames};
                        char sn[48], gn[48], rn[48];
                        short_name(m->scenes[s], sn, sizeof sn);
                        short_name(m->gaze[g], gn, sizeof gn);
                        slug(m->rings[r], rn, 24);
                        /* The parameters in full, hashed: two scenes named alike in two folders differ. */
                        uint64_t h = hash_str(HASH_FNV_INIT, m->scenes[s]);
                        h = hash_str(h, m->gaze[g] ? m->gaze[g] : "centre");
                        h = hash_str(h, m->rings[r]);
                        h = hash_str(h, m->taa[t]);
                        h = hash_u64(hash_u64(h, (uint64_t)k->first), (uint64_t)k->end);
                        int o = snprintf(k->name, sizeof k->name, "%s.%s.rings-%s.taa-%s", sn, gn, rn, m->taa[t]);
                        o += tracker_name(m, e, &h, k->name + o, sizeof k->name - (size_t)o);
                        if (starts)
                            o += snprintf(k->name + o, sizeof k->name - (size_t)o, ".f%05d-%05d", k->first,
                                          k->end - 1);
                        snprintf(k->name + o, sizeof k->name - (size_t)o, ".%08" PRIx32, (uint32_t)(h ^ (h >> 32)));
                    }
    }
    if (st == FS_OK && m->ntasks == 0) {
        log_error("%s: the sweep has no task", m->path);
        st = FS_ERR_USAGE;
    }
    return st;
}

/* >>the state of a task */

void sweep_task_dir(const sweep_manifest *m, const sweep_task *k, char *out, size_t n)
{
    snprintf(out, n, "%s/tasks/%s", m->out, k->name);
}

/* What describing a task needs, kept between calls: the tasks are built scene by scene and trace
 * by trace, so a sweep loads each scene once and each trace once per scene. */
struct sweep_ident {
    int scene, gaze, width, height; /* what sc and gz hold (-1: nothing) */
    scene sc;
    gaze_trace gz;
    run_record_hashes h;
};

sweep_ident *sweep_ident_new(void)
{
    sweep_ident *id = calloc(1, sizeof *id);
    if (id)
        id->scene = id->gaze = -1;
    return id;
}

void sweep_ident_free(sweep_ident *id)
{
    if (!id)
        return;
    if (id->scene >= 0)
        scene_free(&id->sc);
    gaze_free(&id->gz);
    free(id);
}

/* Removes the "key: ..." line from a configuration text, in place. */
static void drop_line(char *text, const char *key)
{
    size_t kl = strlen(key);
    for (char *l = text; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL)
        if (!strncmp(l, key, kl) && l[kl] == ':') {
            char *next = strchr(l, '\n');
            memmove(l, next ? next + 1 : l + strlen(l), strlen(next ? next + 1 : l + strlen(l)) + 1);
            return;
        }
}

/* Loads task k's scene into id unless it holds it. */
static fs_status ident_scene(sweep_ident *id, const sweep_task *k, const run_desc *d)
{
    if (id->scene == k->scene)
        return FS_OK;
    if (id->scene >= 0)
        scene_free(&id->sc);
    id->scene = id->gaze = -1;
    fs_status st = session_load_scene(d, &id->sc);
    if (st == FS_OK)
        id->scene = k->scene;
    return st;
}

/* Loads task k's trace, placed on the plan's display as session_begin places it, unless id holds
 * it, and hashes the scene and the trace (run_record.h). */
static fs_status ident_trace(sweep_ident *id, const sweep_task *k, const run_desc *d, const plan *pl)
{
    if (id->gaze == k->gaze && id->width == pl->width && id->height == pl->height)
        return FS_OK;
    gaze_free(&id->gz);
    memset(&id->gz, 0, sizeof id->gz);
    id->gaze = -1;
    fs_status st = FS_OK;
    if (d->gaze_path)
        st = gaze_load(d->gaze_path, &(gaze_load_desc){.format = d->gaze_format, .eye = d->eye}, &id->gz);
    if (st == FS_OK && d->gaze_path) {
        gaze_place_desc pd = gaze_place_merge(&d->place, &id->sc.gaze_place);
        display_desc at = display_resized(&id->sc.display, pl->width, pl->height);
        gaze_place(&id->gz, &pd, &at);
    }
    session s = {.sc = id->sc, .pl = *pl, .gaze = id->gz};
    if (st == FS_OK && (st = run_record_hashes_of(&s, &id->h)) == FS_OK) {
        id->gaze = k->gaze;
        id->width = pl->width;
        id->height = pl->height;
    }
    return st;
}

fs_status sweep_task_describe(const sweep_manifest *m, const sweep_task *k, sweep_ident *id, char **config,
                              int *frames)
{
    *config = NULL;
    char *opts[SWEEP_MAX_ARGS];
    int n;
    run_desc d;
    plan pl;
    fs_status st = task_desc(m, k, opts, &n, &d, false, false);
    if (st == FS_OK)
        st = ident_scene(id, k, &d);
    if (st == FS_OK)
        st = session_build_plan(&d, &id->sc, &pl);
    if (st == FS_OK)
        st = ident_trace(id, k, &d, &pl);
    if (st == FS_OK) {
        session s = {.sc = id->sc, .pl = pl, .gaze = id->gz};
        st = run_record_describe_hashed(&d, &s, &id->h, config);
        *frames = session_frame_count(&d, &id->sc);
    }
    /* The renderer is the machine's (the one that lists or merges a sweep may have no GL), not
     * the task's: not part of its identity (docs/cluster.md "When a task is done"). */
    if (*config)
        drop_line(*config, "renderer");
    sweep_task_options_free(opts, n > 0 ? n : 0);
    return st;
}

/* The value of a "key: value" line of a configuration text into out ("" when absent). */
static void line_value(const char *text, const char *key, char *out, size_t n)
{
    size_t kl = strlen(key);
    out[0] = '\0';
    for (const char *l = text; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL)
        if (!strncmp(l, key, kl) && l[kl] == ':' && l[kl + 1] == ' ') {
            snprintf(out, n, "%.*s", (int)strcspn(l + kl + 2, "\n"), l + kl + 2);
            return;
        }
}

/* Done when its folder's record says complete (compare writes it last, after metrics and summary)
 * and holds the configuration the task would write now; stale when it holds another. */
fs_status sweep_task_status(const sweep_manifest *m, const sweep_task *k, sweep_ident *id, bool any_executable,
                            sweep_task_check *c)
{
    char dir[PATH_MAX + 300];
    sweep_task_dir(m, k, dir, sizeof dir);
    char *there = NULL, *now = NULL;
    int there_frames, now_frames = 0;
    bool complete;
    c->why[0] = c->exe[0] = '\0';
    log_set_quiet_errors(true);
    fs_status st = run_record_read(dir, &there, &there_frames, &complete);
    log_set_quiet_errors(false);
    if (st != FS_OK) { /* not fovsim's record (a FIFO there must not hang --list): the task's run says */
        c->state = TASK_INCOMPLETE;
        return FS_OK;
    }
    c->state = !there ? TASK_TODO : !complete ? TASK_INCOMPLETE : TASK_DONE;
    if (c->state == TASK_DONE)
        st = sweep_task_describe(m, k, id, &now, &now_frames);
    if (st == FS_OK && c->state == TASK_DONE) {
        line_value(there, "fovsim", c->exe, sizeof c->exe);
        drop_line(there, "renderer");
        if (any_executable) {
            drop_line(there, "fovsim");
            drop_line(now, "fovsim");
        }
        if (strcmp(now, there) != 0) {
            c->state = TASK_STALE;
            run_record_difference(now, there, c->why, sizeof c->why);
        } else if (now_frames != there_frames) {
            c->state = TASK_STALE;
            snprintf(c->why, sizeof c->why, "frames: '%d' now, '%d' there", now_frames, there_frames);
        }
    }
    free(there);
    free(now);
    return st;
}

static const char *const k_state_names[] = {"todo", "incomplete", "done", "stale"};

/* Every task's options through the CLI's table (its ring layout included), its scene, trace and
 * plan, the checks compare makes before drawing, before anything is written or submitted: a bad
 * scene file or option fails the sweep at once, not task by task on a cluster. Each scene and
 * trace is loaded once (sweep_ident). Messages say which task. */
static fs_status check_tasks(const sweep_manifest *m, sweep_ident *id)
{
    fs_status st = FS_OK;
    for (int i = 0; i < m->ntasks && st == FS_OK; i++) {
        const sweep_task *k = &m->tasks[i];
        char context[420];
        snprintf(context, sizeof context, "%.150s: task %d (%.200s): ", m->path, i, k->name);
        log_set_context(context);
        char *config = NULL;
        int frames;
        st = sweep_task_describe(m, k, id, &config, &frames);
        free(config);
    }
    log_set_context(NULL);
    return st;
}

/* >>running one task (--task I) */

static fs_status run_task(const sweep_manifest *m, int index, sweep_ident *id, bool quiet)
{
    const sweep_task *k = &m->tasks[index];
    sweep_task_check c;
    fs_status st = sweep_task_status(m, k, id, false, &c);
    if (st != FS_OK)
        return st;
    if (c.state == TASK_DONE) {
        printf("task %d (%s): complete, skipped\n", index, k->name);
        return FS_OK;
    }
    if (c.state == TASK_STALE) /* drawn again: --replace below */
        printf("task %d (%s): its folder holds another configuration (%s); drawing it again\n", index, k->name,
               c.why);
    char dir[PATH_MAX + 300];
    sweep_task_dir(m, k, dir, sizeof dir);
    printf("task %d (%s) -> %s\n", index, k->name, dir);
    fflush(stdout);
    char *opts[SWEEP_MAX_ARGS];
    int n;
    run_desc d;
    /* --replace: an incomplete folder of this task (a killed run), or a stale one, is drawn anew */
    st = task_desc(m, k, opts, &n, &d, true, quiet);
    if (st == FS_OK) {
        log_set_verbose(d.verbose);
        st = cmd_compare(&d);
    }
    sweep_task_options_free(opts, n > 0 ? n : 0);
    return st;
}

/* >>reference jobs (--reference-task G) */

/* A task's reference frames depend on its scene, its frames (the chunk), the size and the
 * reference settings, not on its gaze trace, ring layout, TAA or tracker (reference.h); the size
 * and settings are the manifest's, one for all tasks. So the sweep plans one reference job per
 * distinct (scene, chunk): it draws those frames into the shared cache before the group's compare
 * tasks run (a Slurm dependency; the first jobs of --local and of a jobs file), and the tasks read
 * them from there. The cache's lock per entry (reference.c) keeps a task that starts early from
 * drawing a frame a reference job is drawing. */
typedef struct ref_plan {
    int n;
    int *first_task; /* group g's first task, whose options the reference job uses */
    int *group;      /* task i's group */
} ref_plan;

static void ref_plan_free(ref_plan *rp)
{
    free(rp->first_task);
    free(rp->group);
    *rp = (ref_plan){0};
}

static fs_status ref_plan_build(const sweep_manifest *m, ref_plan *rp)
{
    *rp = (ref_plan){.first_task = malloc(sizeof(int) * (size_t)m->ntasks),
                     .group = malloc(sizeof(int) * (size_t)m->ntasks)};
    if (!rp->first_task || !rp->group) {
        ref_plan_free(rp);
        return FS_ERR_NOMEM;
    }
    for (int i = 0; i < m->ntasks; i++) {
        const sweep_task *k = &m->tasks[i];
        int g = rp->n - 1; /* a scene's tasks are consecutive: its groups are the last ones */
        for (; g >= 0 && m->tasks[rp->first_task[g]].scene == k->scene; g--)
            if (m->tasks[rp->first_task[g]].first == k->first && m->tasks[rp->first_task[g]].end == k->end)
                break;
        if (g < 0 || m->tasks[rp->first_task[g]].scene != k->scene) {
            g = rp->n++;
            rp->first_task[g] = i;
        }
        rp->group[i] = g;
    }
    return FS_OK;
}

/* Whether task i has work: not complete, or complete with another configuration (stale: drawn again,
 * said unless quiet, counted in *stale). */
static bool task_todo(const sweep_manifest *m, int i, sweep_ident *id, bool quiet, int *stale)
{
    sweep_task_check c;
    if (sweep_task_status(m, &m->tasks[i], id, false, &c) != FS_OK)
        c.state = TASK_INCOMPLETE; /* cannot happen (check_tasks described every task): the task says */
    if (c.state == TASK_STALE) {
        if (!quiet)
            printf("task %d (%s): its folder holds another configuration (%s); drawing it again\n", i,
                   m->tasks[i].name, c.why);
        ++*stale;
    }
    return c.state != TASK_DONE;
}

/* Which reference jobs and tasks have work: todo[g] for reference job g (a task of its group has
 * work), todo[rp->n + i] for task i (task_todo); *ntasks_todo counts the tasks, *stale the stale
 * ones. NULL: no memory. */
static bool *todo_flags(const sweep_manifest *m, const ref_plan *rp, sweep_ident *id, bool quiet, int *ntasks_todo,
                        int *stale)
{
    bool *t = calloc((size_t)(rp->n + m->ntasks), sizeof *t);
    *ntasks_todo = *stale = 0;
    for (int i = 0; t && i < m->ntasks; i++) {
        bool todo = task_todo(m, i, id, quiet, stale);
        t[rp->n + i] = todo;
        t[rp->group[i]] = t[rp->group[i]] || todo;
        *ntasks_todo += todo;
    }
    return t;
}

/* Draws reference job g's frames into the cache: the frames its tasks measure, and the one
 * before a chunk, whose reference compare draws too (for the frame-to-frame change). */
static fs_status reference_frames(const run_desc *d, session *s, reference *rf, int *drawn, int *cached)
{
    int frames = session_frame_count(d, &s->sc);
    int from = d->compare.first_frame > 0 ? d->compare.first_frame - 1 : 0;
    fs_status st = FS_OK;
    for (int i = from; i < frames && st == FS_OK; i++) {
        if (session_interrupted())
            return FS_ERR_INTERRUPTED;
        frame_record fr = session_frame(s, i, (float)i / d->fps, i > 0 ? (float)(i - 1) / d->fps : -1.0f);
        exr_image img;
        reference_info info;
        st = reference_frame(rf, &fr, &img, &info);
        if (st == FS_OK) {
            *drawn += !info.cached;
            *cached += info.cached;
            exr_image_free(&img);
        }
    }
    return st;
}

static fs_status run_reference_task(const sweep_manifest *m, const ref_plan *rp, int g, bool quiet)
{
    const sweep_task *k = &m->tasks[rp->first_task[g]];
    char *opts[SWEEP_MAX_ARGS];
    int n;
    run_desc d;
    fs_status st = task_desc(m, k, opts, &n, &d, false, quiet);
    char buf[1024];
    const char *cache = st == FS_OK ? session_cache_dir(&d, buf, sizeof buf) : NULL;
    if (st == FS_OK && !cache) {
        printf("reference job %d: the tasks have no reference cache (--no-cache): nothing to draw ahead\n", g);
        sweep_task_options_free(opts, n > 0 ? n : 0);
        return FS_OK;
    }
    session s;
    if (st == FS_OK) {
        log_set_verbose(d.verbose);
        st = session_begin(&d, &s, false);
    }
    if (st == FS_OK) {
        ref_progress prog = {.pr = progress_begin("reference pass", 1, true, d.progress_interval)};
        reference *rf = session_reference(&d, &s, &prog, &st);
        int drawn = 0, cached = 0;
        session_catch_sigint();
        if (rf)
            st = reference_frames(&d, &s, rf, &drawn, &cached);
        if (st == FS_OK)
            printf("reference job %d (the tasks of %s): %d frame%s drawn, %d from the cache, into %s\n", g, k->name,
                   drawn, drawn == 1 ? "" : "s", cached, cache);
        progress_end(&prog.pr);
        reference_destroy(rf);
        session_end(&s);
    }
    sweep_task_options_free(opts, n > 0 ? n : 0);
    return st;
}

/* >>shell quoting (shell_quote, core/spawn.h) */

/* Whether `s`, bound for a line of a jobs file or a Slurm script (`what` names it), holds no control
 * character: quoting keeps everything else one word, but a line break would end the line (GNU
 * parallel runs each line as its own command; a #SBATCH directive would end there). */
static bool script_safe(const char *what, const char *s)
{
    for (const unsigned char *p = (const unsigned char *)s; *p; p++)
        if (*p < 0x20 || *p == 0x7f) {
            log_error("%s '%s': a control character (a line break?) cannot go into a jobs file or Slurm script; "
                      "use another name", what, s);
            return false;
        }
    return true;
}

/* Every path and manifest value written into the jobs file or the Slurm script is script_safe. */
static fs_status scripts_safe(const sweep_manifest *m, const char *exe, bool slurm)
{
    bool ok = script_safe("the sweep's folder", m->out) && script_safe("the sweep's manifest", m->frozen) &&
              script_safe("fovsim's path", exe);
    if (slurm) {
        ok = ok && script_safe("slurm.mem", m->slurm.mem) && script_safe("slurm.time", m->slurm.time) &&
             script_safe("slurm.partition", m->slurm.partition);
        for (int i = 0; i < m->slurm.nextra && ok; i++)
            ok = script_safe("slurm.extra", m->slurm.extra[i]);
    }
    return ok ? FS_OK : FS_ERR_USAGE;
}

/* The command that runs task I (or with `ref`, reference job I), as a shell line, appended to out. */
static void job_command(const sweep_manifest *m, const char *exe, bool ref, const char *i_expr, sbuf *out)
{
    shell_quote(out, exe);
    sb_puts(out, " sweep ");
    shell_quote(out, m->frozen);
    sb_puts(out, ref ? " --reference-task " : " --task ");
    sb_puts(out, i_expr);
}

/* >>--list */

static fs_status list_tasks(const sweep_manifest *m, sweep_ident *id)
{
    int state_count[4] = {0};
    char trackers[48] = "";
    if (m->has_tracker)
        snprintf(trackers, sizeof trackers, " x %d tracker setting%s", m->ntracker, m->ntracker == 1 ? "" : "s");
    printf("%d task%s (%d scene%s x %d trace%s x %d ring layout%s x %d TAA setting%s%s%s), modes %s, in %s/tasks/\n",
           m->ntasks, m->ntasks == 1 ? "" : "s", m->nscenes, m->nscenes == 1 ? "" : "s", m->ngaze,
           m->ngaze == 1 ? "" : "s", m->nrings, m->nrings == 1 ? "" : "s", m->ntaa, m->ntaa == 1 ? "" : "s",
           trackers, m->chunk_frames ? " x frame chunks" : "", m->modes, m->out);
    for (int i = 0; i < m->ntasks; i++) {
        const sweep_task *k = &m->tasks[i];
        sweep_task_check c;
        fs_status st = sweep_task_status(m, k, id, false, &c);
        if (st != FS_OK)
            return st;
        sweep_task_state s = c.state;
        state_count[s]++;
        char *opts[SWEEP_MAX_ARGS];
        int n = sweep_task_options(m, k, opts, SWEEP_MAX_ARGS);
        sbuf cmd = {0};
        shell_quote(&cmd, "fovsim");
        sb_puts(&cmd, " ");
        shell_quote(&cmd, "compare");
        for (int a = 0; a < n; a++) {
            sb_puts(&cmd, " ");
            shell_quote(&cmd, opts[a]);
        }
        sweep_task_options_free(opts, n > 0 ? n : 0);
        printf("%4d  %-10s %s\n      %s\n", i, k_state_names[s], k->name, cmd.p ? cmd.p : "");
        if (s == TASK_STALE)
            printf("      (its folder holds another configuration: %s)\n", c.why);
        free(cmd.p);
    }
    printf("%d done, %d incomplete, %d to do", state_count[TASK_DONE], state_count[TASK_INCOMPLETE],
           state_count[TASK_TODO]);
    if (state_count[TASK_STALE])
        printf(", %d stale (complete, but with another configuration: the sweep draws them again)",
               state_count[TASK_STALE]);
    printf("\n");
    return FS_OK;
}

/* >>--jobs-file */

/* The reference jobs' lines come first, so that a farm that starts the lines in order (GNU
 * parallel) starts them before the tasks; a task that starts while its reference job draws waits
 * for the cache's entries (reference.c). */
/* One line of the jobs file: task (or with `ref`, reference job) i with its log. llvmpipe draws
 * with the job's share of the cores (cpus_per_task), not every core: eight jobs at once must not
 * each start a thread per core. A value set by the user wins. */
static void job_line(const sweep_manifest *m, const char *exe, bool ref, int i, sbuf *t)
{
    char idx[16], lp[PATH_MAX + 64];
    snprintf(idx, sizeof idx, "%d", i);
    snprintf(lp, sizeof lp, "%s/logs/%s-%04d.log", m->out, ref ? "ref" : "task", i);
    sb_printf(t, "LP_NUM_THREADS=${LP_NUM_THREADS:-%d} ", m->slurm.cpus_per_task);
    job_command(m, exe, ref, idx, t);
    sb_puts(t, " >");
    shell_quote(t, lp);
    sb_puts(t, " 2>&1\n");
}

static fs_status write_jobs(const sweep_manifest *m, const ref_plan *rp, const char *exe, const char *path)
{
    if (scripts_safe(m, exe, false) != FS_OK)
        return FS_ERR_USAGE;
    sbuf t = {0};
    for (int g = 0; g < rp->n; g++) /* the reference jobs first */
        job_line(m, exe, true, g, &t);
    for (int i = 0; i < m->ntasks; i++)
        job_line(m, exe, false, i, &t);
    if (t.oom) {
        free(t.p);
        return FS_ERR_NOMEM;
    }
    fs_status st = out_write_atomic(path, t.p ? t.p : "");
    free(t.p);
    if (st == FS_OK) {
        long cores = sysconf(_SC_NPROCESSORS_ONLN), per = m->slurm.cpus_per_task;
        printf("wrote %d commands to %s (%d reference job%s, then one line per task; %ld cores each: "
               "LP_NUM_THREADS; a completed task is skipped, so running the file again resumes it)\n"
               "  e.g.: parallel --jobs %ld --joblog %s/joblog --resume-failed < %s\n",
               rp->n + m->ntasks, path, rp->n, rp->n == 1 ? "" : "s", per, cores / per > 1 ? cores / per : 1, m->out,
               path);
    }
    return st;
}

/* >>--slurm */

#define SWEEP_MAX_ARRAY_DEFAULT 1001 /* Slurm's default MaxArraySize */

/* The sweep's array jobs: its reference jobs, then its tasks, each list cut into arrays of at most
 * MaxArraySize indices (Slurm refuses an index of MaxArraySize or more), each array's index plus
 * its offset being the reference job's or task's number. */
typedef struct slurm_part {
    bool ref;          /* reference jobs (--reference-task), else tasks */
    int offset, count; /* items [offset, offset + count) */
    char script[PATH_MAX + 64];
} slurm_part;

typedef struct slurm_plan {
    int max_array;          /* indices per array: MaxArraySize */
    int nref;               /* reference jobs */
    const char *max_from;   /* where that came from, for people */
    char job_name[128];     /* the tasks'; the reference jobs' is it + "-ref" */
    slurm_part *parts;
    int nparts;
} slurm_plan;

/* Runs argv (no shell) with its stdout and stderr into a temporary file of the sweep's logs/,
 * read back into out (n bytes at most); returns spawn_run's result. */
static int run_capture(const sweep_manifest *m, char *const argv[], char *out, size_t n)
{
    char tmp[PATH_MAX + 64];
    snprintf(tmp, sizeof tmp, "%s/logs/.slurm-command.%ld", m->out, (long)getpid());
    fflush(stdout);
    int rc = spawn_run(argv, &(spawn_opts){.output = tmp});
    out[0] = '\0';
    FILE *f = fopen(tmp, "r");
    if (f) {
        size_t r = fread(out, 1, n - 1, f);
        out[r] = '\0';
        fclose(f);
    }
    unlink(tmp);
    return rc;
}

/* MaxArraySize: --max-array-size, else the cluster's (scontrol show config), else Slurm's
 * default. A login node that cannot reach the controller gets the default, said so. */
static void slurm_max_array(const sweep_manifest *m, int option, slurm_plan *sp)
{
    sp->max_array = SWEEP_MAX_ARRAY_DEFAULT;
    sp->max_from = "Slurm's default; scontrol show config did not say";
    if (option > 0) {
        sp->max_array = option;
        sp->max_from = "--max-array-size";
        return;
    }
    static char out[65536];
    char *argv[] = {"scontrol", "show", "config", NULL};
    if (run_capture(m, argv, out, sizeof out) != 0)
        return;
    const char *p = strstr(out, "\nMaxArraySize");
    const char *eq = p ? strchr(p, '=') : NULL;
    long v = eq ? strtol(eq + 1, NULL, 10) : 0;
    if (v >= 1 && v <= INT_MAX) {
        sp->max_array = (int)v;
        sp->max_from = "scontrol show config";
    }
}

/* The job name: --job-name, else "fovsim-" and the manifest's file name (without .json), so that
 * two sweeps tell apart in squeue and sacct. */
static void slurm_job_name(const sweep_manifest *m, const char *option, slurm_plan *sp)
{
    if (option) {
        snprintf(sp->job_name, sizeof sp->job_name, "%s", option);
        return;
    }
    const char *b = strrchr(m->path, '/') ? strrchr(m->path, '/') + 1 : m->path;
    char base[64], sl[64];
    snprintf(base, sizeof base, "%.63s", b);
    char *dot = strrchr(base, '.');
    if (dot && dot != base)
        *dot = '\0';
    slug(base, sl, sizeof sl);
    snprintf(sp->job_name, sizeof sp->job_name, "fovsim-%s", sl);
}

/* The parts and their scripts' paths: DIR/references.sbatch and DIR/sweep.sbatch, or
 * references-P.sbatch and sweep-P.sbatch when a list needs more than one array. */
static fs_status slurm_parts(const sweep_manifest *m, int nref, slurm_plan *sp)
{
    sp->nref = nref;
    int nr = (nref + sp->max_array - 1) / sp->max_array, nt = (m->ntasks + sp->max_array - 1) / sp->max_array;
    sp->parts = calloc((size_t)(nr + nt), sizeof *sp->parts);
    if (!sp->parts)
        return FS_ERR_NOMEM;
    for (int p = 0; p < nr + nt; p++) {
        slurm_part *q = &sp->parts[p];
        q->ref = p < nr;
        int k = q->ref ? p : p - nr, total = q->ref ? nref : m->ntasks, nk = q->ref ? nr : nt;
        q->offset = k * sp->max_array;
        q->count = total - q->offset < sp->max_array ? total - q->offset : sp->max_array;
        const char *what = q->ref ? "references" : "sweep";
        if (nk == 1)
            snprintf(q->script, sizeof q->script, "%s/%s.sbatch", m->out, what);
        else
            snprintf(q->script, sizeof q->script, "%s/%s-%d.sbatch", m->out, what, k);
    }
    sp->nparts = nr + nt;
    return FS_OK;
}

/* The #SBATCH lines of the manifest's resources, then its "extra" lines (after fovsim's own, so
 * that one of them, --no-requeue say, has the last word). */
static void sbatch_resources(const sweep_manifest *m, sbuf *t)
{
    sb_printf(t, "#SBATCH --cpus-per-task=%d\n", m->slurm.cpus_per_task);
    if (m->slurm.mem[0])
        sb_printf(t, "#SBATCH --mem=%s\n", m->slurm.mem);
    if (m->slurm.time[0])
        sb_printf(t, "#SBATCH --time=%s\n", m->slurm.time);
    if (m->slurm.partition[0])
        sb_printf(t, "#SBATCH --partition=%s\n", m->slurm.partition);
    sb_puts(t, "#SBATCH --requeue\n#SBATCH --open-mode=append\n");
    for (int i = 0; i < m->slurm.nextra; i++)
        sb_printf(t, "#SBATCH %s\n", m->slurm.extra[i]);
}

/* Part q's script. --requeue: a task ended by a node failure or preemption runs again (it resumes
 * its folder); --open-mode=append: the requeued run's output goes after the first attempt's in
 * the same log (the job and index, %A_%a, stay the same). */
static void sbatch_text(const sweep_manifest *m, const slurm_plan *sp, const slurm_part *q, const char *exe, sbuf *t)
{
    const char *kind = q->ref ? "reference job" : "task";
    sb_printf(t, "#!/bin/bash\n# fovsim sweep: %ss %d to %d of %d, one per array index", kind, q->offset,
              q->offset + q->count - 1, q->ref ? sp->nref : m->ntasks);
    if (q->offset)
        sb_printf(t, " (the index plus %d)", q->offset);
    sb_printf(t, "; fovsim sweep --list shows the tasks.\n# %s, so submitting again resumes the sweep. "
              "`fovsim sweep MANIFEST --slurm --submit`\n# submits every script of the sweep, the reference jobs "
              "first and the tasks after them (docs/cluster.md).\n",
              q->ref ? "A frame in the cache is not drawn again" : "A completed task is skipped");
    sb_printf(t, "#SBATCH --job-name=%s%s\n#SBATCH --array=0-%d", sp->job_name, q->ref ? "-ref" : "", q->count - 1);
    if (m->slurm.max_running > 0)
        sb_printf(t, "%%%d", m->slurm.max_running);
    sb_puts(t, "\n");
    sbatch_resources(m, t);
    const char *log = q->ref ? "ref" : "slurm";
    sb_printf(t, "#SBATCH --output=%s/logs/%s-%%A_%%a.out\n"
              "#SBATCH --error=%s/logs/%s-%%A_%%a.err\n"
              "# llvmpipe draws with as many threads as the task has cores\n"
              "export LP_NUM_THREADS=${LP_NUM_THREADS:-${SLURM_CPUS_PER_TASK:-1}}\nexec ",
              m->out, log, m->out, log);
    char idx[64] = "\"$SLURM_ARRAY_TASK_ID\"";
    if (q->offset)
        snprintf(idx, sizeof idx, "\"$((SLURM_ARRAY_TASK_ID + %d))\"", q->offset);
    job_command(m, exe, q->ref, idx, t);
    sb_puts(t, "\n");
}

/* Scripts an earlier --slurm wrote that this one does not (a list split differently then): gone,
 * so that no stale array is submitted by hand. `what`: "sweep" or "references"; nk: its parts. */
static void remove_stale_scripts(const sweep_manifest *m, const char *what, int nk)
{
    char path[PATH_MAX + 64];
    if (nk > 1) {
        snprintf(path, sizeof path, "%s/%s.sbatch", m->out, what);
        unlink(path);
    }
    for (int k = nk > 1 ? nk : 0;; k++) {
        snprintf(path, sizeof path, "%s/%s-%d.sbatch", m->out, what, k);
        if (unlink(path) != 0)
            break;
    }
}

static fs_status write_sbatch(const sweep_manifest *m, const slurm_plan *sp, const char *exe)
{
    if (scripts_safe(m, exe, true) != FS_OK || !script_safe("--job-name", sp->job_name))
        return FS_ERR_USAGE;
    fs_status st = FS_OK;
    for (int p = 0; p < sp->nparts && st == FS_OK; p++) {
        sbuf t = {0};
        sbatch_text(m, sp, &sp->parts[p], exe, &t);
        st = t.oom ? FS_ERR_NOMEM : out_write_atomic(sp->parts[p].script, t.p);
        free(t.p);
        if (st == FS_OK && chmod(sp->parts[p].script, 0755) != 0)
            log_warn("%s: cannot make it executable: %s", sp->parts[p].script, strerror(errno));
    }
    int nref_parts = 0;
    while (nref_parts < sp->nparts && sp->parts[nref_parts].ref)
        nref_parts++;
    if (st == FS_OK) {
        remove_stale_scripts(m, "references", nref_parts);
        remove_stale_scripts(m, "sweep", sp->nparts - nref_parts);
    }
    return st;
}
/* >>--submit */

/* The array spec of part q's items with work ("0-3,7,9-12", indices of the array, not of the
 * sweep), appended to t; returns how many. */
static int array_spec(const slurm_part *q, const bool *todo, int nref, sbuf *t)
{
    const bool *w = todo + (q->ref ? 0 : nref) + q->offset;
    int n = 0;
    for (int j = 0; j < q->count; j++) {
        if (!w[j])
            continue;
        int e = j;
        while (e + 1 < q->count && w[e + 1])
            e++;
        sb_printf(t, "%s%d", n ? "," : "", j);
        if (e > j)
            sb_printf(t, "-%d", e);
        n += e - j + 1;
        j = e;
    }
    return n;
}

/* sbatch of part q with the array spec given on the command line (it overrides the script's) and,
 * for tasks, the dependency on the reference jobs (`deps`: "--dependency=afterok:ID:ID", or
 * empty): a failed reference job cancels the tasks that wait for it. *id: the job's id. */
static fs_status submit_part(const sweep_manifest *m, const slurm_part *q, const char *spec, const char *deps,
                             long *id)
{
    sbuf arr = {0};
    sb_printf(&arr, "--array=%s", spec);
    if (m->slurm.max_running > 0)
        sb_printf(&arr, "%%%d", m->slurm.max_running);
    if (arr.oom) {
        free(arr.p);
        return FS_ERR_NOMEM;
    }
    char *argv[8] = {"sbatch", "--parsable", arr.p};
    int a = 3;
    if (deps && deps[0]) {
        argv[a++] = (char *)deps;
        argv[a++] = "--kill-on-invalid-dep=yes";
    }
    argv[a++] = (char *)q->script;
    char out[4096];
    int rc = run_capture(m, argv, out, sizeof out);
    free(arr.p);
    char *line = out; /* the id: the line that starts with a digit ("123" or "123;cluster") */
    while (*line && !(*line >= '0' && *line <= '9'))
        line = strchr(line, '\n') ? strchr(line, '\n') + 1 : line + strlen(line);
    *id = strtol(line, NULL, 10);
    out[strcspn(out, "\n")] = '\0';
    if (rc < 0) {
        log_error("sbatch: cannot run it (is Slurm's client installed and on PATH?); the script is %s", q->script);
        return FS_ERR_IO;
    }
    if (rc != 0 || *id <= 0) {
        log_error("sbatch %s: exit status %d: %.300s", q->script, rc, out);
        return FS_ERR_INCOMPLETE;
    }
    return FS_OK;
}

/* Until none of the jobs is in the queue (squeue lists pending, running and requeued ones; a job
 * it does not know has ended and been purged), asking once a second. */
static void wait_jobs(const sweep_manifest *m, const long *ids, int n)
{
    char out[4096], job[24];
    char *argv[] = {"squeue", "-h", "-o", "%i", "-j", job, NULL};
    for (int i = 0; i < n; i++) {
        snprintf(job, sizeof job, "%ld", ids[i]);
        while (run_capture(m, argv, out, sizeof out) == 0 && out[strspn(out, " \n")])
            sleep(1);
    }
}

/* The tasks submitted (todo) that are still not complete after the jobs ended. */
static int tasks_left(const sweep_manifest *m, const bool *todo, int nref, sweep_ident *id)
{
    int left = 0, stale = 0;
    for (int i = 0; i < m->ntasks; i++)
        left += todo[nref + i] && task_todo(m, i, id, true, &stale);
    return left;
}

/* Submits every part, only the indices of unfinished tasks (and of the reference jobs of their
 * groups), the reference jobs first and the tasks with a dependency on them; with `wait`, waits
 * for all and fails when a submitted task did not complete. */
static fs_status submit(const sweep_manifest *m, const ref_plan *rp, const slurm_plan *sp, sweep_ident *id, bool wait)
{
    int ntodo, stale;
    bool *todo = todo_flags(m, rp, id, false, &ntodo, &stale);
    long *ids = calloc((size_t)sp->nparts, sizeof *ids);
    if (!todo || !ids) {
        free(todo);
        free(ids);
        return FS_ERR_NOMEM;
    }
    printf("%d of %d tasks complete, skipped; submitting %d\n", m->ntasks - ntodo, m->ntasks, ntodo);
    sbuf deps = {0};
    int nids = 0;
    fs_status st = FS_OK;
    for (int p = 0; p < sp->nparts && st == FS_OK && ntodo > 0; p++) {
        const slurm_part *q = &sp->parts[p];
        sbuf spec = {0};
        int n = array_spec(q, todo, rp->n, &spec);
        if (n > 0 && spec.oom)
            st = FS_ERR_NOMEM;
        else if (n > 0)
            st = submit_part(m, q, spec.p, q->ref ? NULL : deps.p, &ids[nids]);
        if (n > 0 && st == FS_OK) {
            printf("submitted batch job %ld: %s, %d %s%s (--array=%.100s%s)\n", ids[nids], q->script, n,
                   q->ref ? "reference job" : "task", n == 1 ? "" : "s", spec.p, strlen(spec.p) > 100 ? "..." : "");
            if (q->ref)
                sb_printf(&deps, "%s%ld", deps.len ? ":" : "--dependency=afterok:", ids[nids]);
            st = deps.oom ? FS_ERR_NOMEM : st;
            nids++;
        }
        free(spec.p);
    }
    if (st != FS_OK && nids > 0)
        log_error("%d array job%s submitted before that one stay in the queue (scancel them, or submit again: "
                  "what they complete is skipped)", nids, nids == 1 ? " was" : "s were");
    if (st == FS_OK && wait && nids > 0) {
        wait_jobs(m, ids, nids);
        int left = tasks_left(m, todo, rp->n, id);
        if (left > 0) {
            log_error("%d of the %d submitted tasks did not complete (fovsim merge %s lists them; logs in %s/logs)",
                      left, ntodo, m->out, m->out);
            st = FS_ERR_INCOMPLETE;
        }
    }
    free(deps.p);
    free(todo);
    free(ids);
    return st;
}

/* >>--local N */

/* SIGINT or SIGTERM stops the sweep: no new task starts, the signal is passed on to every running
 * task (which stops as it would by itself: SIGINT after its current frame, SIGTERM at once; either
 * way its folder resumes), and the sweep waits for them before it exits 130. The handler itself
 * forwards, so a signal that arrives while the loop is blocked in waitpid() is not lost; the
 * signals are blocked between fork() and recording the child's pid, so no task escapes it. */
static volatile sig_atomic_t g_stop;
static volatile sig_atomic_t g_stop_signal;
static pid_t *volatile g_children; /* the running tasks' pids (0: free slot) */
static volatile sig_atomic_t g_nchildren;

static void on_stop_signal(int sig)
{
    int saved = errno;
    g_stop = 1;
    g_stop_signal = sig;
    pid_t *kids = g_children;
    for (int i = 0; kids && i < g_nchildren; i++)
        if (kids[i] > 0)
            kill(kids[i], sig);
    errno = saved;
}

static void stop_signals(sigset_t *set)
{
    sigemptyset(set);
    sigaddset(set, SIGINT);
    sigaddset(set, SIGTERM);
}

/* A finished reference job (ok or not): only a failure says something. */
static void reference_job_ended(const sweep_manifest *m, int g, bool ok, int ws)
{
    if (!ok)
        log_error("reference job %d failed with exit status %d; see %s/logs/ref-%04d.log", g,
                  WIFEXITED(ws) ? WEXITSTATUS(ws) : 128 + WTERMSIG(ws), m->out, g);
}

/* The reference jobs of unfinished tasks run first (items 0 .. rp->n - 1), then the tasks (items
 * rp->n ..): a task that starts while its reference job draws waits for the cache's entries
 * (reference.c) instead of drawing them too. */
static fs_status run_local(const sweep_manifest *m, const ref_plan *rp, sweep_ident *id, const char *exe, int jobs,
                           bool quiet)
{
    pid_t *pids = calloc((size_t)jobs, sizeof *pids);
    int *which = calloc((size_t)jobs, sizeof *which);
    double *started = calloc((size_t)jobs, sizeof *started);
    int ntodo, stale;
    bool *work = todo_flags(m, rp, id, quiet, &ntodo, &stale);
    if (!pids || !which || !started || !work) {
        free(pids);
        free(which);
        free(started);
        free(work);
        return FS_ERR_NOMEM;
    }
    /* Each task's llvmpipe gets its share of the cores, unless the user set it. */
    char threads[24];
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    snprintf(threads, sizeof threads, "%ld", cores / jobs > 1 ? cores / jobs : 1);
    setenv("LP_NUM_THREADS", threads, 0);
    sigset_t stop_set, old_mask;
    stop_signals(&stop_set);
    g_children = pids;
    g_nchildren = jobs;
    struct sigaction sa, old_int, old_term;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaddset(&sa.sa_mask, SIGINT);
    sigaddset(&sa.sa_mask, SIGTERM);
    sa.sa_flags = 0; /* no SA_RESTART: waitpid returns EINTR */
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
    int next = 0, running = 0, finished = 0, failed = 0, skipped = 0, stopped = 0;
    int todo = m->ntasks, nitems = rp->n + m->ntasks;
    struct timespec ts;
    while ((next < nitems && !g_stop) || running > 0) {
        while (running < jobs && next < nitems && !g_stop) {
            int i = next++;
            bool ref = i < rp->n;
            if (!work[i]) {
                skipped += !ref;
                todo -= !ref;
                continue;
            }
            char idx[16], log[PATH_MAX + 64];
            snprintf(idx, sizeof idx, "%d", ref ? i : i - rp->n);
            snprintf(log, sizeof log, "%s/logs/%s-%04d.log", m->out, ref ? "ref" : "task", ref ? i : i - rp->n);
            int slot = 0;
            while (pids[slot])
                slot++;
            fflush(stdout);
            sigprocmask(SIG_BLOCK, &stop_set, &old_mask);
            if (g_stop) { /* a signal came since the loop's test */
                sigprocmask(SIG_SETMASK, &old_mask, NULL);
                break;
            }
            pid_t pid = fork();
            if (pid == 0) {
                signal(SIGINT, SIG_DFL); /* the task installs its own */
                signal(SIGTERM, SIG_DFL);
                sigprocmask(SIG_SETMASK, &old_mask, NULL);
                FILE *f = freopen(log, "w", stdout);
                if (!f || dup2(fileno(stdout), STDERR_FILENO) < 0)
                    _exit(126);
                char *argv[] = {(char *)exe, "sweep", (char *)m->frozen, ref ? "--reference-task" : "--task", idx,
                                "--quiet", NULL};
                execv(exe, argv);
                _exit(127);
            }
            if (pid < 0) {
                int err = errno;
                sigprocmask(SIG_SETMASK, &old_mask, NULL);
                log_error("cannot start a task: %s", strerror(err));
                g_stop = 1;
                break;
            }
            pids[slot] = pid;
            sigprocmask(SIG_SETMASK, &old_mask, NULL);
            clock_gettime(CLOCK_MONOTONIC, &ts);
            which[slot] = i;
            started[slot] = (double)ts.tv_sec + ts.tv_nsec * 1e-9;
            running++;
        }
        if (running == 0)
            break;
        int ws;
        pid_t pid = waitpid(-1, &ws, 0);
        if (pid < 0) {
            if (errno == EINTR)
                continue;
            break;
        }
        int slot = 0;
        while (slot < jobs && pids[slot] != pid)
            slot++;
        if (slot == jobs)
            continue;
        pids[slot] = 0; /* (a signal between waitpid and here is sent to a reaped pid: harmless) */
        running--;
        clock_gettime(CLOCK_MONOTONIC, &ts);
        double el = (double)ts.tv_sec + ts.tv_nsec * 1e-9 - started[slot];
        bool ok = WIFEXITED(ws) && WEXITSTATUS(ws) == 0;
        if (!ok && g_stop) { /* stopped by the forwarded signal: the one "interrupted" line says it */
            stopped++;
            continue;
        }
        failed += !ok;
        if (which[slot] < rp->n) {
            reference_job_ended(m, which[slot], ok, ws);
            continue;
        }
        finished++;
        int t = which[slot] - rp->n;
        const sweep_task *k = &m->tasks[t];
        if (ok && !quiet)
            printf("[%d/%d] task %d (%s) done in %.1f s\n", finished, todo, t, k->name, el);
        else if (!ok)
            log_error("task %d (%s) failed with exit status %d after %.1f s; see %s/logs/task-%04d.log", t, k->name,
                      WIFEXITED(ws) ? WEXITSTATUS(ws) : 128 + WTERMSIG(ws), el, m->out, t);
        fflush(stdout);
    }
    sigaction(SIGINT, &old_int, NULL);
    sigaction(SIGTERM, &old_term, NULL);
    g_children = NULL;
    g_nchildren = 0;
    free(pids);
    free(which);
    free(started);
    free(work);
    if (g_stop) {
        log_error("interrupted%s: %d of %d tasks finished, %d stopped; run the sweep again to resume",
                  g_stop_signal == SIGTERM ? " (SIGTERM)" : g_stop_signal == SIGINT ? " (SIGINT)" : "", finished,
                  todo, stopped);
        return FS_ERR_INTERRUPTED;
    }
    char stale_note[64] = "";
    if (stale)
        snprintf(stale_note, sizeof stale_note, " (%d of them stale: another configuration)", stale);
    printf("%d task%s run%s, %d already complete, %d failed; fovsim merge %s gathers the metrics\n", finished,
           finished == 1 ? "" : "s", stale_note, skipped, failed, m->out);
    return failed ? FS_ERR_INCOMPLETE : FS_OK;
}

/* >>the command */

static void sweep_help(void)
{
    printf("usage: fovsim sweep MANIFEST.json [--list | --local N | --jobs-file FILE | --slurm [--submit [--wait]]]\n"
           "                    [--out DIR] [--chunk-frames N [--warmup W]] [--cpus-per-task N] [--mem M]\n"
           "                    [--time T] [--partition P] [--max-running M] [--job-name NAME]\n"
           "                    [--max-array-size N]\n\n"
           "Runs the product of the manifest's scenes, gaze traces, ring layouts and TAA settings (and frame\n"
           "chunks), each task one fovsim compare of the manifest's modes into DIR/tasks/<task>/. The same\n"
           "task list runs three ways; a completed task is skipped, so running it again resumes it. Then\n"
           "`fovsim merge DIR` gathers the metrics. Manifest format and cluster use: docs/cluster.md.\n\n"
           "  --list              the tasks, their state (todo, incomplete, done, stale) and commands (default)\n"
           "  --local N           run the tasks here, N at a time (each with its share of the cores)\n"
           "  --jobs-file FILE    one shell command per task, for GNU parallel or any farm\n"
           "  --slurm             write DIR/references.sbatch and DIR/sweep.sbatch, Slurm array jobs of the\n"
           "                      reference jobs and the tasks (several scripts past MaxArraySize)\n"
           "  --submit            with --slurm: submit the unfinished ones, the tasks after the reference\n"
           "                      jobs (afterok); --wait: wait for them to end\n"
           "  --job-name NAME     with --slurm: the jobs' name (default fovsim-<manifest name>; the\n"
           "                      reference jobs' is NAME-ref)\n"
           "  --max-array-size N  with --slurm: indices per array job (default: MaxArraySize from scontrol\n"
           "                      show config, else 1001); a longer task list is split into several arrays\n"
           "  --task I            run task I (what the three ways call)\n"
           "  --reference-task G  draw reference job G's frames into the cache (the three ways run these\n"
           "                      first: one per scene and chunk, so each reference frame is drawn once)\n"
           "  --out DIR           the sweep's folder (default: the manifest's \"out\", else\n"
           "                      out/sweep/<manifest name>)\n"
           "  --chunk-frames N    split each sequence into chunks of about N frames (moved to a camera cut\n"
           "                      within N/4); each chunk draws up to --warmup W earlier frames (default %d)\n"
           "                      for the TAA history without writing them\n"
           "  --cpus-per-task N, --mem M, --time T, --partition P, --max-running M   Slurm resources\n"
           "                      (default: the manifest's \"slurm\" object; cpus 2)\n"
           "  --quiet             no per-task lines\n",
           SWEEP_DEFAULT_WARMUP);
}

typedef enum sweep_action { ACT_LIST, ACT_LOCAL, ACT_JOBS, ACT_SLURM, ACT_TASK, ACT_REFERENCE } sweep_action;

/* --slurm: the scripts (DIR/references*.sbatch, DIR/sweep*.sbatch), then with --submit the jobs. */
static fs_status slurm_action(const sweep_manifest *m, const ref_plan *rp, sweep_ident *id, const char *exe,
                              const char *job_name, int max_array, bool submit_it, bool wait)
{
    slurm_plan sp = {0};
    slurm_job_name(m, job_name, &sp);
    slurm_max_array(m, max_array, &sp);
    fs_status st = slurm_parts(m, rp->n, &sp);
    if (st == FS_OK)
        st = write_sbatch(m, &sp, exe);
    if (st == FS_OK) {
        printf("wrote %d Slurm script%s in %s (job name %s, arrays of at most %d indices: MaxArraySize from %s):\n",
               sp.nparts, sp.nparts == 1 ? "" : "s", m->out, sp.job_name, sp.max_array, sp.max_from);
        for (int p = 0; p < sp.nparts; p++)
            printf("  %s: %s %d to %d, %d core%s each\n", sp.parts[p].script,
                   sp.parts[p].ref ? "reference jobs" : "tasks", sp.parts[p].offset,
                   sp.parts[p].offset + sp.parts[p].count - 1, m->slurm.cpus_per_task,
                   m->slurm.cpus_per_task == 1 ? "" : "s");
        if (!submit_it)
            printf("submit them with --submit (the reference jobs first, the tasks after them: docs/cluster.md)\n");
    }
    if (st == FS_OK && submit_it)
        st = submit(m, rp, &sp, id, wait);
    free(sp.parts);
    return st;
}

fs_status cmd_sweep(int argc, char **argv)
{
    const char *manifest = NULL, *jobs_file = NULL, *job_name = NULL;
    int max_array = 0;
    sweep_overrides ov = {.warmup = -1};
    sweep_action act = ACT_LIST;
    int jobs = 1, task = -1;
    bool submit_it = false, wait = false, quiet = false;
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        bool ok = true, takes = true;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            sweep_help();
            return FS_OK;
        } else if (!strcmp(a, "--list")) {
            act = ACT_LIST, takes = false;
        } else if (!strcmp(a, "--local")) {
            act = ACT_LOCAL, ok = v && cli_parse_int(a, v, 1, 256, &jobs);
        } else if (!strcmp(a, "--jobs-file")) {
            act = ACT_JOBS, jobs_file = v, ok = v != NULL;
        } else if (!strcmp(a, "--slurm")) {
            act = ACT_SLURM, takes = false;
        } else if (!strcmp(a, "--submit")) {
            submit_it = true, takes = false;
        } else if (!strcmp(a, "--wait")) {
            wait = true, takes = false;
        } else if (!strcmp(a, "--quiet")) {
            quiet = true, takes = false;
        } else if (!strcmp(a, "--task")) {
            act = ACT_TASK, ok = v && cli_parse_int(a, v, 0, INT_MAX, &task);
        } else if (!strcmp(a, "--reference-task")) {
            act = ACT_REFERENCE, ok = v && cli_parse_int(a, v, 0, INT_MAX, &task);
        } else if (!strcmp(a, "--job-name")) {
            job_name = v, ok = v != NULL;
        } else if (!strcmp(a, "--max-array-size")) {
            ok = v && cli_parse_int(a, v, 1, INT_MAX, &max_array);
        } else if (!strcmp(a, "--out")) {
            ov.out = v, ok = v != NULL;
        } else if (!strcmp(a, "--chunk-frames")) {
            ok = v && cli_parse_int(a, v, 1, MAX_FRAMES, &ov.chunk_frames);
        } else if (!strcmp(a, "--warmup")) {
            ok = v && cli_parse_int(a, v, 0, MAX_FRAMES, &ov.warmup);
        } else if (!strcmp(a, "--cpus-per-task")) {
            ok = v && cli_parse_int(a, v, 1, 4096, &ov.cpus_per_task);
        } else if (!strcmp(a, "--max-running")) {
            ok = v && cli_parse_int(a, v, 1, 100000, &ov.max_running);
        } else if (!strcmp(a, "--mem")) {
            ov.mem = v, ok = v != NULL;
        } else if (!strcmp(a, "--time")) {
            ov.time = v, ok = v != NULL;
        } else if (!strcmp(a, "--partition")) {
            ov.partition = v, ok = v != NULL;
        } else if (a[0] != '-' && !manifest) {
            manifest = a, takes = false;
        } else {
            log_error("fovsim sweep: unexpected argument '%s' (see fovsim sweep --help)", a);
            return FS_ERR_USAGE;
        }
        if (!ok) {
            if (!v)
                log_error("%s: expected a value", a);
            return FS_ERR_USAGE;
        }
        i += takes;
    }
    if (!manifest) {
        log_error("fovsim sweep: expected a manifest file (see fovsim sweep --help)");
        return FS_ERR_USAGE;
    }
    if (job_name && (!job_name[0] || strspn(job_name, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                      "0123456789-_.") != strlen(job_name))) {
        /* an #SBATCH line ends its value at a blank */
        log_error("--job-name '%s': expected letters, digits, '-', '_' or '.'", job_name);
        return FS_ERR_USAGE;
    }
    if ((job_name || max_array) && act != ACT_SLURM) {
        log_error("--job-name and --max-array-size go with --slurm");
        return FS_ERR_USAGE;
    }
    if ((submit_it || wait) && act != ACT_SLURM) {
        log_error("--submit and --wait go with --slurm");
        return FS_ERR_USAGE;
    }
    if (wait && !submit_it) {
        log_error("--wait goes with --submit (it waits for the submitted array)");
        return FS_ERR_USAGE;
    }
    char exe[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0) {
        log_error("/proc/self/exe: cannot find this program's path: %s", strerror(errno));
        return FS_ERR_IO;
    }
    exe[n] = '\0';
    sweep_manifest m;
    sweep_ident *id = sweep_ident_new();
    fs_status st = id ? sweep_manifest_load(manifest, &ov, &m) : FS_ERR_NOMEM;
    if (!id)
        memset(&m, 0, sizeof m);
    if (st == FS_OK)
        st = sweep_build_tasks(&m);
    if (st == FS_OK && (act == ACT_JOBS || act == ACT_SLURM)) /* before anything is written */
        st = scripts_safe(&m, exe, act == ACT_SLURM);
    bool one = act == ACT_TASK || act == ACT_REFERENCE;
    if (st == FS_OK && !one) /* every scene, trace and option, before anything is written */
        st = check_tasks(&m, id);
    if (st == FS_OK && !one)
        st = sweep_manifest_write(&m);
    ref_plan rp = {0};
    if (st == FS_OK)
        st = ref_plan_build(&m, &rp);
    if (st == FS_OK && act == ACT_TASK && task >= m.ntasks) {
        log_error("--task %d: the sweep has %d tasks (0 to %d)", task, m.ntasks, m.ntasks - 1);
        st = FS_ERR_USAGE;
    }
    if (st == FS_OK && act == ACT_REFERENCE && task >= rp.n) {
        log_error("--reference-task %d: the sweep has %d reference jobs (0 to %d)", task, rp.n, rp.n - 1);
        st = FS_ERR_USAGE;
    }
    if (st == FS_OK) {
        switch (act) {
        case ACT_LIST: st = list_tasks(&m, id); break;
        case ACT_TASK: st = run_task(&m, task, id, quiet); break;
        case ACT_REFERENCE: st = run_reference_task(&m, &rp, task, quiet); break;
        case ACT_JOBS: st = write_jobs(&m, &rp, exe, jobs_file); break;
        case ACT_LOCAL: st = run_local(&m, &rp, id, exe, jobs, quiet); break;
        case ACT_SLURM: st = slurm_action(&m, &rp, id, exe, job_name, max_array, submit_it, wait); break;
        }
    }
    ref_plan_free(&rp);
    sweep_ident_free(id);
    sweep_manifest_free(&m);
    return st;
}
