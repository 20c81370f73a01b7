/* run_record.c: the record of what wrote an output folder, --resume and --replace (run_record.h). */
#include "session/run_record.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/file.h>
#include <time.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/config.h"
#include "core/file_read.h"
#include "core/hash.h"
#include "core/log.h"
#include "core/strbuf.h"
#include "gl/gl_device.h"
#include "output/exr_write.h"
#include "output/out_path.h"
#include "frame/frame.h"
#include "session/session.h"

/* Which options the record holds is the option table's OPT_RECORDED flag (cli_options.c): a row
 * with it is written into the configuration below, one without it changes nothing a run writes.
 * A new run_desc field usually changes the struct's size, which stops the build here until its
 * option's row says which (LP64 only: the size is the ABI's; a bool that fits into padding slips
 * through, so read the table when adding one). */
#if defined(__x86_64__) || defined(__aarch64__)
_Static_assert(sizeof(run_desc) == 928, "run_desc changed: give the new option its row in cli_options.c (OPT_RECORDED "
                                        "or not) and write the recorded ones below, then update this size");
#endif

#define RECORD_MAX 16384
#define SEPARATOR "---\n"

/* >>describe */

/* What scene_content_hash (the geometry, materials and images, which the reference cache keys)
 * leaves out but a frame depends on: the camera path, the light and sky, the display, and the
 * scene's own defaults for the options ("alpha", "taa", "rings", "ring_lod") and the materials'
 * alpha LOD clamps. */
static uint64_t scene_settings_hash(const scene *sc)
{
    uint64_t h = hash_u64(HASH_FNV_INIT, (uint64_t)sc->camera.count);
    for (int i = 0; i < sc->camera.count; i++) {
        const camera_key *k = &sc->camera.keys[i];
        float v[8] = {k->time, k->position.x, k->position.y, k->position.z, k->target.x, k->target.y, k->target.z,
                      k->hfov_deg};
        h = hash_u64(hash_floats(h, v, 8), k->cut);
    }
    const light_desc *l = &sc->light;
    float lv[12] = {l->direction.x, l->direction.y, l->direction.z, l->color.x, l->color.y, l->color.z,
                    l->ambient.x, l->ambient.y, l->ambient.z, l->sky.x, l->sky.y, l->sky.z};
    h = hash_floats(h, lv, 12);
    h = hash_u64(hash_u64(h, (uint64_t)sc->display.width), (uint64_t)sc->display.height);
    h = hash_floats(h, &sc->display.hfov_deg, 1);
    if (sc->display_kind == DISPLAY_HMD) { /* only then: planar scenes hash as before */
        char disp[512];
        hmd_format(&sc->hmd, disp, sizeof disp);
        h = hash_str(h, disp);
    }
    h = hash_u64(h, (uint64_t)sc->alpha_mode);
    float tv[3] = {sc->taa.blend, sc->taa.gamma, sc->taa.sparse};
    h = hash_floats(hash_u64(hash_u64(h, sc->taa.given), sc->taa.off), tv, 3);
    h = hash_u64(h, (uint64_t)sc->taa.jitter_length);
    /* Materials' "alpha_lod_max" (only those that have one: other scenes hash as before). */
    for (int a = 0; a < sc->asset_count; a++)
        for (int m = 0; m < sc->assets[a].material_count; m++)
            if (sc->assets[a].materials[m].has_alpha_lod_max)
                h = hash_floats(hash_u64(h, ((uint64_t)a << 32) | (uint64_t)m), &sc->assets[a].materials[m].alpha_lod_max, 1);
    h = hash_str(hash_str(h, sc->rings), sc->ring_lod);
    /* The VRS keys only when given: other scenes hash as before. */
    if (sc->foveation != FOVEATION_UNSET || sc->vrs[0] || sc->vrs_tile)
        h = hash_u64(hash_str(hash_u64(h, (uint64_t)sc->foveation), sc->vrs), (uint64_t)sc->vrs_tile);
    return h;
}

/* FNV-1a of the running executable: a rebuilt fovsim may draw other pixels under the same version.
 * Hashed once per process (a sweep describes thousands of tasks); /proc/self/exe is the running
 * file even when a rebuild has replaced it on disk. */
static bool executable_hash(uint64_t *out)
{
    static uint64_t cached;
    static bool have;
    if (have) {
        *out = cached;
        return true;
    }
    FILE *f = fopen("/proc/self/exe", "rb");
    if (!f)
        return false;
    uint64_t h = HASH_FNV_INIT;
    unsigned char buf[1 << 16];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0)
        h = hash_bytes(h, buf, n);
    bool ok = !ferror(f);
    fclose(f);
    *out = cached = h;
    have = ok;
    return ok;
}

static uint64_t gaze_hash(const gaze_trace *g)
{
    uint64_t h = hash_u64(HASH_FNV_INIT, (uint64_t)g->count);
    for (int i = 0; i < g->count; i++) {
        const gaze_sample *s = &g->samples[i];
        float v[3] = {s->x, s->y, s->confidence};
        h = hash_bytes(h, &s->t, sizeof s->t);
        h = hash_floats(h, v, 3);
        h = hash_u64(h, s->valid);
    }
    h = hash_u64(h, (uint64_t)g->screen_w);
    return hash_u64(h, (uint64_t)g->screen_h);
}

/* A head recording's poses (both eyes: time, position, orientations) and its scene settings. */
static uint64_t head_hash(const pose_trace *t)
{
    uint64_t h = hash_u64(HASH_FNV_INIT, (uint64_t)t->count);
    for (int e = 0; e < 2; e++)
        for (int i = 0; i < t->count; i++) {
            const pose_sample *s = &t->eye[e][i];
            double v[11] = {s->t, s->pos.x, s->pos.y, s->pos.z, s->head.x, s->head.y, s->head.z, s->head.w,
                            s->gaze.x, s->gaze.y, s->gaze.z};
            h = hash_bytes(hash_bytes(h, v, sizeof v), &s->gaze.w, sizeof s->gaze.w);
        }
    double sc[8] = {t->scene.tilt.x, t->scene.tilt.y, t->scene.tilt.z, t->scene.tilt.w, t->scene.scale,
                    t->scene.initial.x, t->scene.initial.y, t->scene.initial.z};
    return hash_bytes(h, sc, sizeof sc);
}

static const char *or_default(const char *s)
{
    return s ? s : "default";
}

fs_status run_record_hashes_of(const session *s, run_record_hashes *h)
{
    if (!executable_hash(&h->exe)) {
        log_error("/proc/self/exe: cannot read the executable to record which fovsim wrote the output: %s",
                  strerror(errno));
        return FS_ERR_IO;
    }
    h->scene_content = scene_content_hash(&s->sc);
    h->scene_settings = scene_settings_hash(&s->sc);
    h->gaze = s->gaze.count > 0 ? gaze_hash(&s->gaze) : 0;
    return FS_OK;
}

fs_status run_record_describe(const run_desc *d, const session *s, char **out)
{
    *out = NULL;
    run_record_hashes h;
    fs_status st = run_record_hashes_of(s, &h);
    return st == FS_OK ? run_record_describe_hashed(d, s, &h, out) : st;
}

fs_status run_record_describe_hashed(const run_desc *d, const session *s, const run_record_hashes *h, char **out)
{
    *out = NULL;
    static const char *const k_cmd[] = {[CMD_RENDER] = "render", [CMD_REFERENCE] = "reference",
                                        [CMD_COMPARE] = "compare", [CMD_DEMO] = "demo"};
    static const char *const k_compress[] = {"zip", "none", "piz"};
    const uint64_t exe = h->exe;
    sbuf t = {0};
    const bool is_ref = d->cmd == CMD_REFERENCE, has_ref = is_ref || d->cmd == CMD_COMPARE || d->cmd == CMD_DEMO;
    sb_printf(&t, "command: %s\n", (size_t)d->cmd < sizeof k_cmd / sizeof k_cmd[0] && k_cmd[d->cmd] ? k_cmd[d->cmd] : "?");
    sb_printf(&t, "name: %s\n", d->name);
    sb_printf(&t, "fovsim: %s, executable %016" PRIx64 "\n", FOVSIM_VERSION, exe);
    sb_printf(&t, "renderer: %s\n", gl_device_renderer());
    sb_printf(&t, "scene: %s, content %016" PRIx64 ", settings %016" PRIx64 "\n", s->sc.path,
        h->scene_content, h->scene_settings);
    if (s->gaze.count > 0)
        sb_printf(&t, "gaze: %s, format %d, eye %d, samples %d, content %016" PRIx64 "\n", s->gaze.path,
            (int)d->gaze_format, (int)d->eye, s->gaze.count, h->gaze);
    else
        sb_printf(&t, "gaze: centre fixation\n");
    sb_printf(&t, "size: %dx%d\n", s->pl.width, s->pl.height);
    if (d->display) { /* absent when not given: older folders stay valid */
        char disp[512] = "planar";
        if (d->display_kind == DISPLAY_HMD)
            hmd_format(&d->display_hmd, disp, sizeof disp);
        sb_printf(&t, "display: %s\n", disp);
    }
    sb_printf(&t, "fps: %.9g\n", d->fps);
    sb_printf(&t, "compression: %s\n", k_compress[d->compression]);
    if (!is_ref) {
        if (d->bench_mode_count > 0) {
            sb_printf(&t, "%s", "modes:");
            for (int m = 0; m < d->bench_mode_count; m++)
                sb_printf(&t, " %s", alpha_mode_name(d->bench_modes[m]));
            sb_printf(&t, "%s", "\n");
        } else {
            sb_printf(&t, "alpha: %s\n", d->alpha == ALPHA_MODE_DEFAULT ? "default" : alpha_mode_name(d->alpha));
        }
        sb_printf(&t, "rings: %s\n", or_default(d->rings));
        sb_printf(&t, "ring lod: %s\n", or_default(d->ring_lod));
        if (d->foveation != FOVEATION_UNSET || d->vrs || d->vrs_tile) /* absent when not given: older folders stay valid */
            sb_printf(&t, "foveation: %s, vrs: %s, vrs tile: %d\n", foveation_kind_name(d->foveation), or_default(d->vrs),
                d->vrs_tile);
        sb_printf(&t, "overlay: %d, debug channels: %d\n", d->overlay, d->debug_channels);
        sb_printf(&t, "hash: scale %.9g, kind %d, aniso %d, fade %s, fade n %.9g, offset %s\n", d->hash_scale, d->hash_kind,
            d->hash_aniso, d->no_fade ? "off" : "on", d->fade_n, d->no_hash_offset ? "off" : "on");
        sb_printf(&t, "a2c sharpen: %d\n", d->a2c_sharpen);
        if (d->alpha_lod != ALPHA_LOD_CLAMP_UNSET) /* absent when not given: folders written before the option stay valid */
        {
            if (d->alpha_lod == ALPHA_LOD_CLAMP_OFF)
                sb_printf(&t, "alpha lod max: off\n");
            else
                sb_printf(&t, "alpha lod max: %.9g\n", d->alpha_lod_max);
        }
        sb_printf(&t, "taa: %d, blend %.9g, gamma %.9g, sparse %.9g, jitter %d, neighbourhood %d, history %d, nan %d\n",
            d->taa.mode, d->taa.blend, d->taa.gamma, d->taa.sparse, d->taa.jitter_length, d->taa.neighbourhood, d->taa.history,
            d->taa.nan);
        sb_printf(&t, "object motion: %s, ring cull: %s, composite: %s, disocclusion: %s\n",
            d->taa.no_object_motion ? "off" : "on", d->no_ring_cull ? "off" : "on",
            d->composite_per_pixel ? "per-pixel" : "tiled", d->taa.no_disocclusion ? "off" : "on");
    }
    if (has_ref)
        sb_printf(&t, "reference: kind %d, supersample %d, samples %d, memory %d MB\n", d->ref.kind, d->ref.supersample,
            d->ref.samples, d->ref.memory_mb);
    if (d->cmd == CMD_COMPARE || d->cmd == CMD_DEMO)
        sb_printf(&t, "fvvdp export: %d\n", d->compare.export_fvvdp);
    if (d->compare.no_grid_annotate) /* absent when on: folders written before the option stay valid */
        sb_printf(&t, "grid annotation: off\n");
    gaze_tracker_desc td = gaze_tracker_merge(&d->tracker, &s->sc.tracker);
    if (!gaze_tracker_is_ideal(&td) || td.seed != 0) { /* absent without one: folders written before stay valid */
        char tr[160];
        gaze_tracker_format(&td, tr, sizeof tr);
        sb_printf(&t, "gaze tracker: %s\n", tr);
    }
    gaze_place_desc gp = gaze_place_merge(&d->place, &s->sc.gaze_place);
    if (gp.map != GAZE_MAP_ANGLE || gp.screen.kind != GAZE_SCREEN_NONE) { /* absent by default, as above */
        char scr[64];
        gaze_screen_format(&gp.screen, scr, sizeof scr);
        sb_printf(&t, "gaze map: %s, screen %s\n", gaze_map_name(gp.map), scr[0] ? scr : "from the file");
    }
    if (s->head.count > 0 || d->head_path || d->head_place_set) { /* absent without: folders written before stay valid */
        bool on = s->head.count > 0;
        const pose_place *hp = on ? &s->head_place : &d->head_place;
        sb_printf(&t, "head: %s, content %016" PRIx64 ", place %.9g,%.9g,%.9g yaw %.9g scale %.9g\n",
                  on ? s->head.path : d->head_path ? d->head_path : "none", on ? head_hash(&s->head) : 0, hp->pos.x,
                  hp->pos.y, hp->pos.z, hp->yaw_deg, hp->scale);
    }
    if (d->eye_run) /* an hmd display's eye (absent otherwise) */
        sb_printf(&t, "eye: %s\n", d->eye_run == 1 ? "left" : "right");
    if (d->compare.first_frame)
        sb_printf(&t, "chunk: from frame %d, warm-up %d\n", d->compare.first_frame, d->bench.warmup_set ? d->bench.warmup : -1);
    /* Not recorded (no OPT_RECORDED in cli_options.c), because they change nothing a run writes:
     * frames (the record's second part), out_dir (the folder itself), builtin/scene_path and
     * asset_root (the scene's content is), the machine's options (OPT_MACHINE), the limits, resume
     * and replace, run_fvvdp (runs after the frames) and the options of other commands. */
    if (t.oom) {
        free(t.p);
        return FS_ERR_NOMEM;
    }
    *out = t.p;
    return FS_OK;
}

/* >>the record file */

static void record_path(const run_folder *f, char *out, size_t cap)
{
    snprintf(out, cap, "%s/%s", f->dir, RUN_RECORD_FILE);
}

/* Writes the record atomically (a reader sees the old one or the new one). */
static fs_status write_record(const run_folder *f, bool complete)
{
    char path[1200];
    record_path(f, path, sizeof path);
    size_t cap = strlen(f->config) + 256;
    char *text = malloc(cap);
    if (!text)
        return FS_ERR_NOMEM;
    snprintf(text, cap, "# the configuration that wrote this folder (fovsim, README \"Output folders\")\n%s" SEPARATOR
             "frames: %d\ncomplete: %s\n", f->config, f->frames, complete ? "yes" : "no");
    fs_status st = out_write_atomic(path, text);
    free(text);
    return st;
}

/* The earlier record's configuration part into *out (malloc'd; NULL when there is none). */
static fs_status read_record(const run_folder *f, char **out)
{
    return run_record_read(f->dir, out, NULL, NULL);
}

/* The value of `key` in a configuration text, into out ("" when absent). */
static void value_of(const char *config, const char *key, char *out, size_t cap);

fs_status run_record_read(const char *dir, char **out, int *frames, bool *complete)
{
    *out = NULL;
    if (frames)
        *frames = -1;
    if (complete)
        *complete = false;
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, RUN_RECORD_FILE);
    struct stat sb;
    if (lstat(path, &sb) != 0)
        return errno == ENOENT ? FS_OK : (log_error("%s: cannot read: %s", path, strerror(errno)), FS_ERR_IO);
    if (!S_ISREG(sb.st_mode) || sb.st_size > RECORD_MAX) {
        log_error("%s: expected fovsim's record of this folder (a text file of at most %d bytes); move it away or "
                  "choose another --out", path, RECORD_MAX);
        return FS_ERR_IO;
    }
    FILE *in = fopen(path, "rb");
    char *buf = in ? calloc(1, (size_t)sb.st_size + 1) : NULL;
    size_t n = buf ? fread(buf, 1, (size_t)sb.st_size, in) : 0;
    if (in)
        fclose(in);
    if (!buf || n != (size_t)sb.st_size) {
        log_error("%s: cannot read: %s", path, buf ? "short read" : in ? "out of memory" : strerror(errno));
        free(buf);
        return FS_ERR_IO;
    }
    /* Drop the comment line and everything from the separator on. */
    char *body = buf[0] == '#' ? strchr(buf, '\n') : buf;
    body = body ? body + (buf[0] == '#') : buf + n;
    char *sep = strstr(body, "\n" SEPARATOR);
    if (sep) { /* the state part: "frames: N", "complete: yes" */
        char v[32];
        value_of(sep + 1 + strlen(SEPARATOR), "frames", v, sizeof v);
        if (frames && v[0])
            *frames = atoi(v);
        value_of(sep + 1 + strlen(SEPARATOR), "complete", v, sizeof v);
        if (complete)
            *complete = !strcmp(v, "yes");
        sep[1] = '\0';
    }
    memmove(buf, body, strlen(body) + 1);
    *out = buf;
    return FS_OK;
}

static void value_of(const char *config, const char *key, char *out, size_t cap)
{
    size_t kl = strlen(key);
    out[0] = '\0';
    for (const char *l = config; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL)
        if (!strncmp(l, key, kl) && l[kl] == ':' && l[kl + 1] == ' ') {
            const char *v = l + kl + 2;
            snprintf(out, cap, "%.*s", (int)strcspn(v, "\n"), v);
            return;
        }
}

/* The first key of `a` whose value in `b` differs, into out; false when there is none. */
static bool differing_key(const char *a, const char *b, bool a_is_now, char *out, size_t cap)
{
    for (const char *l = a; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
        int len = (int)strcspn(l, "\n"), kl = (int)strcspn(l, ":");
        char key[64], va[200], vb[200];
        snprintf(key, sizeof key, "%.*s", kl < len ? kl : len, l);
        value_of(a, key, va, sizeof va);
        value_of(b, key, vb, sizeof vb);
        if (strcmp(va, vb) != 0) {
            const char *now = a_is_now ? va : vb, *there = a_is_now ? vb : va;
            snprintf(out, cap, "%s: '%s' now, '%s' there", key, now[0] ? now : "(none)", there[0] ? there : "(none)");
            return true;
        }
    }
    return false;
}

void run_record_difference(const char *a, const char *b, char *out, size_t cap)
{
    /* Both ways: a line only the earlier record has (a chunk's warm-up, say) is a difference too. */
    if (!differing_key(a, b, true, out, cap) && !differing_key(b, a, false, out, cap))
        snprintf(out, cap, "a setting this fovsim does not record");
}

/* >>frames */

static bool frame_path(const run_folder *f, const char *name, int i, char *out, size_t cap)
{
    return snprintf(out, cap, "%s/%s.%04d.exr", f->dir, name, i) < (int)cap;
}

/* Whether frame i is complete: it reads back whole and says it is frame i. Frames reach their
 * final name only by rename after a complete write, so this fails only for damaged files. */
static bool frame_complete(const run_folder *f, int i)
{
    char path[1200];
    struct stat sb;
    if (!frame_path(f, f->name, i, path, sizeof path) || lstat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
        return false;
    exr_image img;
    log_set_quiet_errors(true);
    bool ok = exr_read_file(path, &img) == FS_OK;
    log_set_quiet_errors(false);
    if (!ok) {
        log_warn("%s: cannot be read back; it is drawn again", path);
        return false;
    }
    const exr_attr *a = exr_image_attr(&img, "fovsim:frame");
    ok = a && a->type == FS_EXR_ATTR_INT && a->i == i;
    exr_image_free(&img);
    if (!ok)
        log_warn("%s: does not say it is frame %d; it is drawn again", path, i);
    return ok;
}

/* >>the files only a finished compare writes */

static fs_status remove_file(const char *path)
{
    struct stat sb;
    if (lstat(path, &sb) != 0 || S_ISDIR(sb.st_mode))
        return FS_OK;
    if (unlink(path) != 0) {
        log_error("%s: cannot remove the output of an earlier run: %s", path, strerror(errno));
        return FS_ERR_IO;
    }
    return FS_OK;
}

/* DIR/fvvdp/: the files fvvdp_export writes (fvvdp_export.h) and its sequences' PNGs. Anything
 * else the user put there stays, and so does the folder then. */
static fs_status remove_fvvdp(const char *dir)
{
    static const char *const k_files[] = {"fixation.csv", "display.json", "run_fvvdp.py", "results.json"};
    char fv[1100];
    snprintf(fv, sizeof fv, "%s/fvvdp", dir);
    DIR *d = opendir(fv);
    if (!d)
        return FS_OK;
    fs_status st = FS_OK;
    struct dirent *e;
    while (st == FS_OK && (e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        char p[1400];
        snprintf(p, sizeof p, "%s/%s", fv, e->d_name);
        struct stat sb;
        if (lstat(p, &sb) != 0)
            continue;
        if (S_ISREG(sb.st_mode)) {
            for (size_t k = 0; k < sizeof k_files / sizeof k_files[0]; k++)
                if (!strcmp(e->d_name, k_files[k]))
                    st = remove_file(p);
            continue;
        }
        if (!S_ISDIR(sb.st_mode))
            continue;
        DIR *sd = opendir(p);
        struct dirent *x;
        while (sd && st == FS_OK && (x = readdir(sd)) != NULL) {
            if (out_path_sequence_index(x->d_name, e->d_name, ".png") >= 0) { /* <seq>/<seq>.NNNN.png */
                char q[1700];
                snprintf(q, sizeof q, "%s/%s", p, x->d_name);
                st = remove_file(q);
            }
        }
        if (sd)
            closedir(sd);
        rmdir(p); /* only when empty */
    }
    closedir(d);
    rmdir(fv);
    return st;
}

static fs_status remove_compare_outputs(const char *dir)
{
    char p[1100];
    snprintf(p, sizeof p, "%s/metrics.csv", dir);
    fs_status st = remove_file(p);
    snprintf(p, sizeof p, "%s/summary.json", dir);
    if (st == FS_OK)
        st = remove_file(p);
    return st == FS_OK ? remove_fvvdp(dir) : st;
}

/* >>the lock */

/* What the lock file names: its first line, printable ASCII only, at most 200 bytes. */
static void lock_holder(int fd, char *out, size_t cap)
{
    char buf[256];
    ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
    size_t k = 0;
    for (ssize_t i = 0; i < n && buf[i] != '\n' && k + 1 < cap && k < 200; i++)
        out[k++] = buf[i] >= 0x20 && buf[i] < 0x7f ? buf[i] : '?';
    out[k] = '\0';
    if (k == 0)
        snprintf(out, cap, "not named yet in %s", RUN_LOCK_FILE);
}

static double monotonic_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Takes DIR/fovsim-run.lock (run_record.h), waiting up to wait_s seconds, polling 5 times a
 * second (a blocking flock could not be bounded or interrupted). A lock taken on a file that its
 * holder removed meanwhile is no lock: the name is opened again until the file locked is the one
 * the name leads to. */
static fs_status lock_folder(run_folder *f, const run_desc *d, int wait_s)
{
    static const char *const k_cmd[] = {[CMD_RENDER] = "render", [CMD_REFERENCE] = "reference",
                                        [CMD_COMPARE] = "compare", [CMD_DEMO] = "demo"};
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", f->dir, RUN_LOCK_FILE);
    const double t0 = monotonic_s();
    bool said = false;
    for (;;) {
        int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
        if (fd < 0) {
            log_error("%s: cannot open the folder's lock: %s", path, strerror(errno));
            return FS_ERR_IO;
        }
        struct stat a, b;
        if (fstat(fd, &a) != 0 || !S_ISREG(a.st_mode)) {
            log_error("%s: expected fovsim's lock of this folder (a regular file); move it away or choose another "
                      "--out", path);
            close(fd);
            return FS_ERR_IO;
        }
        if (flock(fd, LOCK_EX | LOCK_NB) == 0) {
            if (stat(path, &b) != 0 || a.st_dev != b.st_dev || a.st_ino != b.st_ino) {
                close(fd); /* removed by the run that held it: take the new one */
                continue;
            }
            char host[256] = "", when[64] = "";
            gethostname(host, sizeof host - 1);
            time_t now = time(NULL);
            struct tm tm;
            strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S UTC", gmtime_r(&now, &tm));
            char text[600];
            int n = snprintf(text, sizeof text, "pid %ld on host %.200s, fovsim %s, since %s\n", (long)getpid(), host,
                             (size_t)d->cmd < sizeof k_cmd / sizeof k_cmd[0] && k_cmd[d->cmd] ? k_cmd[d->cmd] : "?",
                             when);
            /* Only a message depends on it: a failed write leaves "not named yet". */
            if (ftruncate(fd, 0) != 0 || pwrite(fd, text, (size_t)n, 0) != n)
                log_info("%s: cannot write who holds the lock: %s", path, strerror(errno));
            f->lock_fd = fd;
            f->locked = true;
            return FS_OK;
        }
        int e = errno;
        char who[256];
        lock_holder(fd, who, sizeof who);
        close(fd);
        if (e != EWOULDBLOCK && e != EAGAIN && e != EINTR) {
            log_error("%s: cannot lock the folder: %s", path, strerror(e));
            return FS_ERR_IO;
        }
        double waited = monotonic_s() - t0;
        if (waited >= wait_s) {
            if (wait_s > 0)
                log_error("%s: another run is still writing this folder after %d s (%s); --out chooses another folder",
                          f->dir, wait_s, who);
            else
                log_error("%s: another run is writing this folder (%s); --wait-lock S waits for it, --out chooses "
                          "another folder", f->dir, who);
            return FS_ERR_BUSY;
        }
        if (!said) {
            log_warn("%s: another run is writing this folder (%s); waiting up to %d s for it to end", f->dir, who,
                     wait_s);
            said = true;
        }
        if (session_interrupted())
            return FS_ERR_INTERRUPTED;
        nanosleep(&(struct timespec){0, 200 * 1000 * 1000}, NULL);
    }
}

static void unlock_folder(run_folder *f)
{
    if (!f->locked)
        return;
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", f->dir, RUN_LOCK_FILE);
    unlink(path); /* while still held: a waiter that opened it sees it gone and opens the name again */
    close(f->lock_fd);
    f->locked = false;
}

/* >>open */

fs_status run_folder_open(run_folder *f, const char *dir, const run_desc *d, const session *s, int frames)
{
    memset(f, 0, sizeof *f);
    snprintf(f->dir, sizeof f->dir, "%s", dir);
    snprintf(f->name, sizeof f->name, "%s", d->name);
    f->frames = frames;
    fs_status st = run_record_describe(d, s, &f->config);
    if (st != FS_OK)
        return st;
    const char *config = f->config;
    f->kept = calloc((size_t)frames, sizeof *f->kept);
    if (!f->kept)
        return FS_ERR_NOMEM;
    st = file_make_dirs(dir);
    if (st == FS_OK)
        st = lock_folder(f, d, d->wait_lock);
    if (st != FS_OK)
        return st;
    out_dir_remove_stale_temps(dir);
    char *prior = NULL;
    st = read_record(f, &prior);
    if (st != FS_OK)
        return st;
    bool same = prior && !strcmp(prior, config);
    char prior_name[256] = "";
    if (prior)
        value_of(prior, "name", prior_name, sizeof prior_name);
    if (!d->replace && prior && !same) {
        char why[600];
        run_record_difference(config, prior, why, sizeof why);
        log_error("%s: holds the output of another configuration (%s); --replace replaces it, --out chooses another "
                  "folder", dir, why);
        st = FS_ERR_USAGE;
    } else if (!d->replace && !prior && out_dir_has_sequence(f->dir, d->name)) {
        log_error("%s: holds frames %s.####.exr that no %s describes (an older fovsim's, or not fovsim's); "
                  "--replace replaces them, --out chooses another folder", dir, d->name, RUN_RECORD_FILE);
        st = FS_ERR_USAGE;
    }
    /* Keep (--resume, same configuration) or remove the frames of the earlier run. */
    if (st == FS_OK && same && d->resume) {
        for (int i = 0; i < frames; i++)
            f->kept_count += f->kept[i] = frame_complete(f, i);
        st = out_dir_remove_sequence(dir, d->name, frames, NULL);
    } else if (st == FS_OK) {
        if (d->resume)
            log_info("OUTPUT: nothing to resume in %s; every frame is drawn", dir);
        if (prior_name[0] && strcmp(prior_name, d->name) != 0)
            st = out_dir_remove_sequence(dir, prior_name, 0, NULL);
        if (st == FS_OK)
            st = out_dir_remove_sequence(dir, d->name, 0, NULL);
    }
    free(prior);
    if (st == FS_OK)
        st = remove_compare_outputs(dir);
    if (st == FS_OK)
        st = write_record(f, false);
    f->written = st == FS_OK;
    return st;
}

fs_status run_folder_complete(run_folder *f)
{
    fs_status st = write_record(f, true);
    f->completed = st == FS_OK;
    return st;
}

void run_folder_close(run_folder *f)
{
    /* A run that stopped before its first frame leaves no record either: nothing to resume. */
    if (f->written && !f->completed && !out_dir_has_sequence(f->dir, f->name)) {
        char path[1200];
        record_path(f, path, sizeof path);
        unlink(path);
    }
    unlock_folder(f);
    free(f->config);
    free(f->kept);
    memset(f, 0, sizeof *f);
}

int run_history_start(const scene *sc, int first, float fps, int width, int height)
{
    for (int i = first; i > 0; i--) {
        frame_record fr = frame_record_at(sc, i, (float)i / fps, (float)(i - 1) / fps, width, height);
        if (fr.cut)
            return i;
    }
    return 0;
}

/* The line that says what a resume kept and what it cost. */
void run_folder_print_resume(const run_folder *rf, int redrawn, double redrawn_s)
{
    if (rf->kept_count == 0)
        return;
    printf("resumed: kept %d complete frame%s of the earlier run", rf->kept_count, rf->kept_count == 1 ? "" : "s");
    if (redrawn)
        printf("; drew %d of them again without writing them, for the TAA history of the next (%.1f s)", redrawn,
               redrawn_s);
    printf("\n");
}
