/* render.c: `fovsim render`: the frames of one configuration as EXR files (--resume redraws only
 * what is missing, and the TAA history it needs). Everything that can fail on bad input (scene,
 * plan, GL context, shaders) is done before the output directory is touched, so a bad run leaves
 * nothing behind. */
#include "commands/commands.h"

#include <stdio.h>

#include "core/log.h"
#include "core/progress.h"
#include "gl/gl_device.h"
#include "fov/fov_ring.h"
#include "passes/renderer.h"
#include "session/session.h"
#include "session/run_record.h"
#include "commands/eyes.h"

/* The frames a run must draw: from `start` (where the TAA history of the first missing frame
 * begins) to the last missing one; frames kept by --resume in between are drawn again without
 * being written when the history needs them, skipped when it does not (TAA off). */
typedef struct draw_range {
    int start, end; /* [start, end) */
    bool redraw_kept;
} draw_range;

static draw_range frames_to_draw(const run_folder *rf, const session *s, float fps, bool history)
{
    int first = -1, last = -1;
    for (int i = 0; i < rf->frames; i++)
        if (!rf->kept[i]) {
            first = first < 0 ? i : first;
            last = i;
        }
    if (first < 0)
        return (draw_range){0, 0, false};
    int start = history ? run_history_start(&s->sc, first, fps, s->pl.width, s->pl.height) : first;
    return (draw_range){start, last + 1, history};
}

static fs_status render_run(const run_desc *d, int *frames_out)
{
    session s;
    fs_status st = session_begin(d, &s, true);
    if (st != FS_OK)
        return st;
    const char *out = d->out_dir ? d->out_dir : "out/render";
    int frames = session_frame_count(d, &s.sc);
    *frames_out = frames;
    run_folder rf = {0};
    /* a killed run's litter, another configuration's output, --resume (README "Output folders") */
    st = run_folder_open(&rf, out, d, &s, frames);
    exr_writer *w = st == FS_OK ? exr_writer_create(&(exr_writer_desc){.compression = d->compression}) : NULL;
    if (st == FS_OK && !w)
        st = FS_ERR_NOMEM;
    draw_range dr = st == FS_OK ? frames_to_draw(&rf, &s, d->fps, s.pl.taa) : (draw_range){0, 0, false};
    session_catch_sigint();
    progress pr = progress_begin("frame", dr.end - dr.start, d->quiet, d->progress_interval);
    double t0 = time_now(), redrawn_s = 0;
    int done = 0, redrawn = 0;
    for (int i = dr.start; i < dr.end && st == FS_OK; i++) {
        if (session_interrupted()) {
            st = FS_ERR_INTERRUPTED;
            break;
        }
        if (rf.kept[i] && !dr.redraw_kept)
            continue;
        double a = time_now();
        frame_record fr = session_frame(&s, i, (float)i / d->fps, i > 0 ? (float)(i - 1) / d->fps : -1.0f);
        exr_image img;
        st = renderer_draw(s.r, &fr);
        if (st == FS_OK)
            st = renderer_read(s.r, &img);
        if (st != FS_OK)
            break;
        if (rf.kept[i]) {
            exr_image_free(&img);
            redrawn++;
            redrawn_s += time_now() - a;
        } else {
            session_frame_attrs(&img, &s, &fr);
            char path[1200];
            snprintf(path, sizeof path, "%s/%s.%04d.exr", out, d->name, i);
            st = exr_writer_submit(w, path, &img);
            done += st == FS_OK;
        }
        progress_update(&pr, i + 1 - dr.start);
    }
    if (w) {
        fs_status wst = exr_writer_finish(w);
        if (st == FS_OK)
            st = wst;
    }
    if (st == FS_OK)
        st = run_folder_complete(&rf);
    progress_end(&pr);
    double el = time_now() - t0;
    if (st == FS_OK) {
        char rings[256];
        plan_foveation_format(&s.pl, rings, sizeof rings);
        printf("wrote %d frame%s (%dx%d, alpha %s, %s%s) to %s/%s.####.exr in %.1f s (%.2f fps) on %s\n",
               done, done == 1 ? "" : "s", s.pl.width, s.pl.height, alpha_mode_name(s.pl.global_mode),
               s.pl.vrs ? "" : "rings ", rings, out, d->name, el,
               el > 0 ? (done + redrawn) / el : 0.0, gl_device_renderer());
        run_folder_print_resume(&rf, redrawn, redrawn_s);
    } else if (st == FS_ERR_INTERRUPTED) {
        log_error("interrupted after %d complete frames in %s (no partial frame was left; --resume continues)",
                  done + rf.kept_count, out);
    } else if (done > 0) {
        /* The failing write already printed the one error line; this is context for --verbose. */
        log_info("RENDER: stopped; frames written before the failure in %s are complete, no partial frame was left", out);
    }
    run_folder_close(&rf);
    session_end(&s);
    return st;
}

/* An hmd display: one run per eye into OUT/eye-left/ and OUT/eye-right/ (each a run folder of its
 * own: its record, --resume), then each frame's eyes joined into OUT/NAME.####.exr, one multi-view
 * EXR (docs/hmd.md "Two eyes"). */
static fs_status render_eyes(const run_desc *d)
{
    const char *out = d->out_dir ? d->out_dir : "out/render";
    int frames = 0;
    fs_status st = FS_OK;
    for (int e = 1; e <= 2 && st == FS_OK; e++) {
        char sub[1200];
        run_desc de = eyes_run_desc(d, out, e, sub, sizeof sub);
        st = render_run(&de, &frames);
    }
    if (st == FS_OK)
        st = eyes_join_frames(out, d->name, 0, frames, d->compression, 0);
    if (st == FS_OK && !d->quiet)
        printf("joined both eyes of %d frame%s into %s/%s.####.exr (multi-view: left, right)\n", frames,
               frames == 1 ? "" : "s", out, d->name);
    return st;
}

fs_status cmd_render(const run_desc *d)
{
    bool hmd = false;
    fs_status st = d->eye_run ? FS_OK : session_display_is_hmd(d, &hmd);
    if (st != FS_OK)
        return st;
    int frames;
    return hmd ? render_eyes(d) : render_run(d, &frames);
}
