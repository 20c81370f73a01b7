/* The viewer's pure-C parts: key bindings, --script parsing (good scripts and the mistakes a test
 * author makes), the gaze recorder (a recording round-trips through the gaze loader, and is valid
 * after every frame, i.e. when the window closes mid-recording), and the view CLI options. */
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "core/log.h"
#include "gaze/gaze.h"
#include "test.h"
#include "view/gaze_record.h"
#include "view/view_input.h"

static fs_status parse_script(const char *text, view_script *s)
{
    return view_script_parse(text, (long)strlen(text), "s.txt", s);
}

TEST(keys_have_actions)
{
    CHECK(view_key_action("A") == VIEW_ACT_ALPHA_NEXT);
    CHECK(view_key_action("a") == VIEW_ACT_ALPHA_NEXT);
    CHECK(view_key_action("LEFT_BRACKET") == VIEW_ACT_BIAS_DOWN);
    CHECK(view_key_action("RIGHT_BRACKET") == VIEW_ACT_BIAS_UP);
    CHECK(view_key_action("ESCAPE") == VIEW_ACT_QUIT && view_key_action("Q") == VIEW_ACT_QUIT);
    CHECK(view_key_action("RIGHT") == VIEW_ACT_STEP && view_key_action("N") == VIEW_ACT_STEP);
    CHECK(view_key_action("D") == VIEW_ACT_RING_LOD && view_key_action("d") == VIEW_ACT_RING_LOD);
    CHECK(view_key_action("Z") == VIEW_ACT_NONE);
    CHECK(view_key_action("") == VIEW_ACT_NONE);
    CHECK(strstr(view_key_help(), "TAA") != NULL);
}

TEST(script_parses)
{
    view_script s;
    const char *text = "# a test\n"
                       "move 0.25 0.5   # before any frame: frame 0\n"
                       "\n"
                       "frame 3\n"
                       "  key r\n"
                       "move 40px 30.5px\r\n"
                       "capture\n"
                       "frame 3\n"
                       "leave\n"
                       "resize 320 240\n"
                       "frame 10\n"
                       "quit"; /* no final newline */
    CHECK(parse_script(text, &s) == FS_OK);
    CHECK(s.count == 7);
    if (s.count == 7) {
        CHECK(s.events[0].frame == 0 && s.events[0].kind == VIEW_EV_MOVE && s.events[0].line == 2);
        CHECK_NEAR(s.events[0].x, 0.25, 0);
        CHECK_NEAR(s.events[0].y, 0.5, 0);
        CHECK(s.events[1].frame == 3 && s.events[1].kind == VIEW_EV_KEY && !strcmp(s.events[1].key, "R"));
        CHECK(s.events[2].kind == VIEW_EV_MOVE_PX && s.events[2].x == 40.0f && s.events[2].y == 30.5f);
        CHECK(s.events[3].kind == VIEW_EV_CAPTURE && s.events[3].frame == 3);
        CHECK(s.events[4].kind == VIEW_EV_LEAVE && s.events[4].frame == 3);
        CHECK(s.events[5].kind == VIEW_EV_RESIZE && s.events[5].x == 320.0f && s.events[5].y == 240.0f);
        CHECK(s.events[6].kind == VIEW_EV_QUIT && s.events[6].frame == 10 && s.events[6].line == 12);
    }
    view_script_free(&s);
    view_script_free(&s); /* no-op on a freed script */
    CHECK(parse_script("", &s) == FS_OK && s.count == 0);
    view_script_free(&s);
}

TEST(script_errors)
{
    static const char *const bad[] = {
        "frame\n",                 /* no number */
        "frame -1\n",              /* negative */
        "frame 2x\n",              /* not a number */
        "frame 5\nframe 4\n",      /* backwards */
        "move 0.5\n",              /* one coordinate */
        "move 1.5 0.5\n",          /* normalised out of range (forgot px?) */
        "move 40px 0.5\n",         /* mixed units */
        "move 40pt 30pt\n",        /* unknown unit */
        "move nan 0.5\n",          /* not finite */
        "key\n",                   /* no key */
        "key Z\n",                 /* a key with no binding */
        "capture now\n",           /* extra argument */
        "quit 1\n",
        "jump 3\n",                /* unknown event */
        "move 0.1 0.2 0.3 0.4\n",  /* too many fields */
        "resize 8 8\n",            /* too small */
        "resize 640\n",            /* one dimension */
        "resize 640x480 1\n",      /* not a number */
    };
    log_set_quiet_errors(true);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        view_script s;
        fs_status st = parse_script(bad[i], &s);
        if (st != FS_ERR_USAGE)
            fprintf(stderr, "accepted: %s", bad[i]);
        CHECK(st == FS_ERR_USAGE);
        CHECK(s.events == NULL && s.count == 0);
    }
    char longline[400];
    memset(longline, ' ', sizeof longline - 1);
    longline[sizeof longline - 1] = '\0';
    view_script s;
    CHECK(parse_script(longline, &s) == FS_ERR_USAGE);
    CHECK(view_script_load("/nonexistent/script.txt", &s) == FS_ERR_IO);
    log_set_quiet_errors(false);
}

TEST(recording_round_trips_and_is_valid_after_every_frame)
{
    char path[1100];
    snprintf(path, sizeof path, "%s/view_rec.csv", test_out_dir());
    remove(path);
    gaze_recorder r;
    gaze_recorder_begin(&r, path, "fovsim view recording: test\nsecond comment line");
    CHECK(gaze_recorder_is_open(&r));
    CHECK(access(path, F_OK) != 0); /* nothing on disk before the first sample */
    const float xs[6] = {0.25f, 0.3f, 0.1f, 0.9f, 0.95f, 1.0f / 3.0f}, ys[6] = {0.4f, 0.45f, 0.7f, 0.05f, 0.5f, 2.0f / 3.0f};
    const bool valid[6] = {true, true, false, true, true, true};
    for (int i = 0; i < 6; i++) {
        CHECK(gaze_recorder_add(&r, (double)((float)i / 24.0f), xs[i], ys[i], valid[i]) == FS_OK);
        /* While recording, the file as it stands is a valid trace (a window closed now keeps it). */
        gaze_trace t;
        CHECK(gaze_load(path, &(gaze_load_desc){0}, &t) == FS_OK);
        CHECK(t.count == i + 1 && t.format == GAZE_FORMAT_CSV);
        gaze_free(&t);
    }
    CHECK(gaze_recorder_add(&r, 0.0, 0.5f, 0.5f, true) == FS_OK); /* time not increasing: dropped */
    CHECK(r.samples == 6);
    CHECK(gaze_recorder_end(&r) == FS_OK);
    CHECK(!gaze_recorder_is_open(&r));
    CHECK(gaze_recorder_add(&r, 1.0, 0.5f, 0.5f, true) == FS_OK && r.samples == 6); /* closed: ignored */

    gaze_trace t;
    CHECK(gaze_load(path, &(gaze_load_desc){0}, &t) == FS_OK);
    CHECK(t.count == 6 && t.valid_count == 5);
    for (int i = 0; i < t.count && i < 6; i++) {
        /* Written with 9 significant digits: exactly the floats that went in. */
        CHECK(t.samples[i].t == (double)((float)i / 24.0f));
        CHECK(t.samples[i].valid == valid[i]);
        if (valid[i])
            CHECK(t.samples[i].x == xs[i] && t.samples[i].y == ys[i]);
        /* Resampled at the frame's time (as render does), a frame gets its own gaze back; the
         * invalid one holds the gaze before it. */
        gaze_point g = gaze_at(&t, (float)i / 24.0f, NULL);
        CHECK(g.x == xs[valid[i] ? i : i - 1] && g.y == ys[valid[i] ? i : i - 1]);
    }
    gaze_free(&t);
    /* No temporary file is left next to it. */
    char cmd[1300];
    snprintf(cmd, sizeof cmd, "ls -a '%s' | grep -q 'view_rec.csv.tmp'", test_out_dir());
    CHECK(system(cmd) != 0);
}

TEST(recording_to_a_missing_directory_fails_cleanly)
{
    gaze_recorder r;
    gaze_recorder_begin(&r, "/nonexistent/dir/rec.csv", NULL);
    log_set_quiet_errors(true);
    CHECK(gaze_recorder_add(&r, 0.0, 0.5f, 0.5f, true) == FS_ERR_IO);
    log_set_quiet_errors(false);
    CHECK(!gaze_recorder_is_open(&r));
    CHECK(gaze_recorder_end(&r) == FS_OK);
}


int main(void)
{
    RUN(keys_have_actions);
    RUN(script_parses);
    RUN(script_errors);
    RUN(recording_round_trips_and_is_valid_after_every_frame);
    RUN(recording_to_a_missing_directory_fails_cleanly);
    return test_summary();
}
