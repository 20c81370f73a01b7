/* test_view.c: `fovsim view` end to end, under Xvfb (Mesa's GLX on llvmpipe), driven by --script:
 * the window shows the scene (not blank, and exactly the frame encoded to sRGB), the ring overlay
 * follows the scripted gaze, the recorded trace round-trips through the gaze loader, the viewer's
 * frame equals `fovsim render`'s for the same gaze and settings (TAA on, replaying the recorded
 * trace), the split screen shows the two modes' frames, a resized window letterboxes the frame and
 * still maps the cursor to the right pixel, a viewer killed mid-recording leaves a
 * valid trace, and bad scripts / no X server fail with one line and their exit status.
 *
 * Skipped (exit 77, with a message) only where no X server can be started: xvfb-run is missing or
 * Xvfb does not start. scripts/setup.sh installs xvfb, so on CI it runs. */
#include <math.h>
#include <stdbool.h>
#include <sys/wait.h>

#include "fov/fov_ring.h"
#include "gaze/gaze.h"
#include "output/exr_write.h"
#include "test.h"

#define W 160
#define H 90
#define RINGS "10:1:0,25:1/2:0,*:1/4:0"
#define XVFB "xvfb-run -a -s '-screen 0 1280x1024x24'"

static char g_dir[1100];
static const char *g_bin;

/* Runs a shell command; its exit status (-1 if it did not exit). Output goes to `log` (appended). */
static int sh(const char *cmd, const char *log)
{
    char full[4096];
    snprintf(full, sizeof full, "%s >>'%s' 2>&1", cmd, log);
    int ws = system(full);
    return ws != -1 && WIFEXITED(ws) ? WEXITSTATUS(ws) : -1;
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static void dump(const char *path)
{
    FILE *f = fopen(path, "r");
    char line[512];
    while (f && fgets(line, sizeof line, f))
        fprintf(stderr, "  | %s", line);
    if (f)
        fclose(f);
}

static const char *p(const char *rel)
{
    static char buf[8][1300];
    static int k;
    k = (k + 1) & 7;
    snprintf(buf[k], sizeof buf[k], "%s/%s", g_dir, rel);
    return buf[k];
}

static bool read_exr(const char *path, exr_image *img)
{
    if (exr_read_file(path, img) == FS_OK)
        return true;
    fprintf(stderr, "cannot read %s\n", path);
    return false;
}

/* Largest |a - b| over the render channels, or INFINITY when one is missing or sizes differ.
 * `prefix_b` selects a layer of b ("" for the main channels, "hashed." ...). */
static double max_diff(const exr_image *a, const char *prefix_a, const exr_image *b, const char *prefix_b)
{
    static const char *const ch[] = {"R", "G", "B", "A", "coverage"};
    if (a->width != b->width || a->height != b->height)
        return INFINITY;
    double m = 0;
    for (int c = 0; c < 5; c++) {
        char na[64], nb[64];
        snprintf(na, sizeof na, "%s%s", prefix_a, ch[c]);
        snprintf(nb, sizeof nb, "%s%s", prefix_b, ch[c]);
        const float *pa = exr_image_channel(a, na), *pb = exr_image_channel(b, nb);
        if (!pa || !pb)
            return INFINITY;
        for (int i = 0; i < a->width * a->height; i++)
            m = fmax(m, fabs((double)pa[i] - (double)pb[i]));
    }
    return m;
}

static float srgb_encode(float v)
{
    v = fminf(fmaxf(v, 0.0f), 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
}

/* The window (8-bit, as shown) against the frame's linear RGB encoded to sRGB, over columns
 * [x0, x1): largest difference in 8-bit steps. */
static double window_vs_frame(const exr_image *win, const exr_image *frame, const char *prefix, int x0, int x1)
{
    if (win->width != W || win->height != H)
        return INFINITY;
    double m = 0;
    for (int c = 0; c < 3; c++) {
        const char *ch = (const char *[]){"R", "G", "B"}[c];
        char n[64];
        snprintf(n, sizeof n, "%s%s", prefix, ch);
        /* By name: a file read back lists its channels sorted, not in the order written. */
        const float *f = exr_image_channel(frame, n), *w = exr_image_channel(win, ch);
        if (!f || !w)
            return INFINITY;
        for (int y = 0; y < H; y++)
            for (int x = x0; x < x1; x++)
                m = fmax(m, fabs(255.0 * srgb_encode(f[y * W + x]) - 255.0 * w[y * W + x]));
    }
    return m;
}

static bool is_magenta(const exr_image *img, int x, int y)
{
    const float *r = exr_image_channel(img, "R"), *g = exr_image_channel(img, "G"), *b = exr_image_channel(img, "B");
    int i = y * img->width + x;
    return r && g && b && r[i] == 1.0f && g[i] == 0.0f && b[i] == 1.0f;
}

/* The overlay of a capture: the gaze marker's centre lands on the gaze pixel, and every ring-border
 * pixel (yellow) lies at a ring radius (10 or 25 degrees) from that gaze. */
static void check_overlay(const char *path, float gx, float gy)
{
    exr_image img;
    if (!read_exr(path, &img)) {
        CHECK(false);
        return;
    }
    int cx = -1, cy = -1, centres = 0;
    for (int y = 1; y < H - 1; y++)
        for (int x = 1; x < W - 1; x++)
            if (is_magenta(&img, x, y) && is_magenta(&img, x - 1, y) && is_magenta(&img, x + 1, y) &&
                is_magenta(&img, x, y - 1) && is_magenta(&img, x, y + 1)) {
                cx = x;
                cy = y;
                centres++;
            }
    int ex = (int)floorf(gx * W), ey = (int)floorf(gy * H);
    fprintf(stderr, "%s: marker at (%d, %d), gaze pixel (%d, %d)\n", path, cx, cy, ex, ey);
    CHECK(centres == 1 && cx == ex && cy == ey);
    const exr_attr *hfov = exr_image_attr(&img, "fovsim:hfov_deg");
    display_desc d = {W, H, hfov ? hfov->f[0] : 90.0f, 0.0f, 0.0f};
    const float *r = exr_image_channel(&img, "R"), *g = exr_image_channel(&img, "G"), *b = exr_image_channel(&img, "B");
    int border = 0, off = 0;
    double px_deg = 1.0 / (double)fov_pixels_per_degree(&d); /* at the centre; larger nowhere on screen */
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int i = y * W + x;
            if (!(r[i] == 1.0f && fabsf(g[i] - 0.9f) < 1e-3f && fabsf(b[i] - 0.1f) < 1e-3f))
                continue;
            border++;
            float e = fov_eccentricity_deg(&d, gx * W, gy * H, (float)x + 0.5f, (float)y + 0.5f);
            off += fminf(fabsf(e - 10.0f), fabsf(e - 25.0f)) > 1.5 * px_deg;
        }
    fprintf(stderr, "%s: %d ring-border pixels, %d not at a ring radius from the gaze\n", path, border, off);
    CHECK(border > 50 && off == 0);
    exr_image_free(&img);
}

TEST(viewer_matches_render_and_follows_the_gaze)
{
    const char *log = p("view.log");
    write_file(p("s.txt"), "# the viewer test's script (docs/viewer.md)\n"
                           "frame 0\n"
                           "move 0.25 0.40\n"
                           "key R            # record the gaze from frame 0\n"
                           "frame 2\n"
                           "move 0.30 0.45\n"
                           "frame 4\n"
                           "capture          # TAA on, no overlay: compared with render\n"
                           "frame 5\n"
                           "key O            # ring overlay on\n"
                           "capture\n"
                           "frame 6\n"
                           "move 0.70 0.60\n"
                           "capture          # the overlay moved with the gaze\n"
                           "frame 7\n"
                           "key D            # ring LOD on (the frame says so in its header)\n"
                           "capture\n"
                           "leave            # recorded as invalid (the gaze holds)\n"
                           "frame 8\n"
                           "quit             # while recording: the trace must stay valid\n");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, XVFB " '%s' view --builtin forest --width %d --height %d --rings '%s' --record '%s' "
             "--script '%s' --quiet", g_bin, W, H, RINGS, p("rec/trace.csv"), p("s.txt"));
    int rc = sh(cmd, log);
    CHECK(rc == 0);
    if (rc != 0) {
        dump(log);
        return;
    }

    /* The recorded trace: 9 frames at 24 fps, the scripted gaze, the last two frames invalid. */
    gaze_trace t;
    CHECK(gaze_load(p("rec/trace.csv"), &(gaze_load_desc){0}, &t) == FS_OK);
    CHECK(t.count == 9 && t.valid_count == 7 && t.format == GAZE_FORMAT_CSV);
    static const float want[9][2] = {{0.25f, 0.4f}, {0.25f, 0.4f}, {0.3f, 0.45f}, {0.3f, 0.45f}, {0.3f, 0.45f},
                                     {0.3f, 0.45f}, {0.7f, 0.6f}, {0.7f, 0.6f}, {0.7f, 0.6f}};
    for (int i = 0; i < t.count && i < 9; i++) {
        CHECK(t.samples[i].t == (double)((float)i / 24.0f));
        CHECK(t.samples[i].x == want[i][0] && t.samples[i].y == want[i][1]);
        CHECK(t.samples[i].valid == (i < 7));
    }
    gaze_free(&t);

    /* The same frame from the headless renderer, replaying the recorded trace. */
    snprintf(cmd, sizeof cmd, "'%s' render --builtin forest --width %d --height %d --rings '%s' --gaze '%s' "
             "--frames 5 --out '%s' --quiet", g_bin, W, H, RINGS, p("rec/trace.csv"), p("render"));
    CHECK(sh(cmd, log) == 0);
    exr_image view, ref, win;
    if (read_exr(p("rec/trace.capture.0004.exr"), &view) && read_exr(p("render/frame.0004.exr"), &ref)) {
        double d = max_diff(&view, "", &ref, "");
        fprintf(stderr, "viewer vs render, frame 4 (TAA on, 5 frames of history): max difference %g\n", d);
        /* Same GL, shaders, plan, frames and gaze: identical here; the tolerance is one half-float
         * step at 1, for a driver that schedules a reduction differently. */
        CHECK(d <= 1e-3);
        const exr_attr *fr = exr_image_attr(&view, "fovsim:frame"), *mode = exr_image_attr(&view, "fovsim:alpha_mode");
        CHECK(fr && fr->i == 4 && mode && !strcmp(mode->s, "traditional"));
        CHECK(exr_image_attr(&view, "fovsim:renderer") && exr_image_attr(&view, "fovsim:rings"));
        exr_image_free(&view);
        exr_image_free(&ref);
    } else {
        CHECK(false);
    }

    /* The window showed the scene: not one colour, and exactly the frame encoded to sRGB (the
     * window is the display size, so the blit copies pixels 1:1). */
    if (read_exr(p("rec/trace.window.0004.exr"), &win) && read_exr(p("rec/trace.capture.0004.exr"), &view)) {
        const float *green = exr_image_channel(&win, "G");
        double mean = 0, var = 0;
        for (int i = 0; green && i < W * H; i++)
            mean += green[i] / (W * H);
        for (int i = 0; green && i < W * H; i++)
            var += (green[i] - mean) * (green[i] - mean) / (W * H);
        fprintf(stderr, "window: green mean %.3f, standard deviation %.3f\n", mean, sqrt(var));
        CHECK(sqrt(var) > 0.05);
        const exr_attr *how = exr_image_attr(&win, "fovsim:view");
        bool srgb = how && strstr(how->s, "sRGB");
        CHECK(srgb); /* Mesa's GLX offers sRGB-capable visuals */
        double d = srgb ? window_vs_frame(&win, &view, "", 0, W) : INFINITY;
        fprintf(stderr, "window vs sRGB(frame): max difference %.2f / 255\n", d);
        CHECK(d <= 1.5); /* rounding of the 8-bit encode, and of the half-float frame */
        exr_image_free(&win);
        exr_image_free(&view);
    } else {
        CHECK(false);
    }

    check_overlay(p("rec/trace.capture.0005.exr"), 0.30f, 0.45f);
    check_overlay(p("rec/trace.capture.0006.exr"), 0.70f, 0.60f);

    /* D: ring LOD with the default schedule (the run gave no --ring-lod), named in the header. */
    exr_image six = {0}, seven = {0};
    CHECK(exr_read_part(p("rec/trace.capture.0006.exr"), 0, &six) == FS_OK);
    CHECK(exr_read_part(p("rec/trace.capture.0007.exr"), 0, &seven) == FS_OK);
    const exr_attr *lod = exr_image_attr(&seven, "fovsim:ring_lod_u");
    fprintf(stderr, "capture 7 (after D): fovsim:ring_lod_u %s\n", lod ? lod->s : "(none)");
    CHECK(!exr_image_attr(&six, "fovsim:ring_lod_u") && lod && strchr(lod->s, ','));
    exr_image_free(&six);
    exr_image_free(&seven);
}

/* An hmd display: the window shows both eyes side by side, and the capture (a multi-view EXR) holds
 * each eye as render draws it (docs/hmd.md "Two eyes"). */
TEST(hmd_view_shows_both_eyes)
{
    const char *log = p("hmd.log");
    write_file(p("hmd.txt"), "frame 0\nmove 0.5 0.5\ncapture\nquit\n");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, XVFB " '%s' view --builtin fence --display hmd:eyenavgs,width=64 --rings off --taa off "
             "--record '%s' --script '%s' --quiet", g_bin, p("hmd/s.csv"), p("hmd.txt"));
    int rc = sh(cmd, log);
    CHECK(rc == 0);
    snprintf(cmd, sizeof cmd, "'%s' render --builtin fence --display hmd:eyenavgs,width=64 --rings off --taa off "
             "--frames 1 --out '%s' --quiet", g_bin, p("hmd/render"));
    CHECK(sh(cmd, log) == 0);
    exr_image cap, ren, win;
    if (rc != 0 || !read_exr(p("hmd/s.capture.0000.exr"), &cap)) {
        dump(log);
        return;
    }
    if (read_exr(p("hmd/render/frame.0000.exr"), &ren) && read_exr(p("hmd/s.window.0000.exr"), &win)) {
        double dl = max_diff(&cap, "", &ren, ""), dr = max_diff(&cap, "right.", &ren, "right.");
        double eyes = max_diff(&ren, "", &ren, "right.");
        fprintf(stderr, "hmd view: left eye vs render %g, right eye vs render %g (the eyes differ by %g); window %dx%d\n",
                dl, dr, eyes, win.width, win.height);
        CHECK(dl <= 1e-3 && dr <= 1e-3 && eyes > 0.1);
        CHECK(win.width == 2 * ren.width && win.height == ren.height);
        exr_image_free(&ren);
        exr_image_free(&win);
    }
    exr_image_free(&cap);
}

TEST(split_screen_shows_two_modes)
{
    const char *log = p("split.log");
    write_file(p("split.txt"), "frame 0\nmove 0.5 0.5\ncapture\nquit\n");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, XVFB " '%s' view --builtin fence --width %d --height %d --rings off --taa off "
             "--split traditional,hashed --record '%s' --script '%s' --quiet", g_bin, W, H, p("split/s.csv"),
             p("split.txt"));
    int rc = sh(cmd, log);
    CHECK(rc == 0);
    for (int m = 0; m < 2 && rc == 0; m++) {
        snprintf(cmd, sizeof cmd, "'%s' render --builtin fence --width %d --height %d --rings off --taa off --alpha %s "
                 "--frames 1 --out '%s' --quiet", g_bin, W, H, m ? "hashed" : "traditional",
                 p(m ? "split/hashed" : "split/traditional"));
        CHECK(sh(cmd, log) == 0);
    }
    if (rc != 0) {
        dump(log);
        return;
    }
    exr_image cap, trad, hashed, win;
    if (read_exr(p("split/s.capture.0000.exr"), &cap) && read_exr(p("split/traditional/frame.0000.exr"), &trad) &&
        read_exr(p("split/hashed/frame.0000.exr"), &hashed) && read_exr(p("split/s.window.0000.exr"), &win)) {
        double dt = max_diff(&cap, "", &trad, ""), dh = max_diff(&cap, "hashed.", &hashed, "");
        double differ = max_diff(&trad, "", &hashed, "");
        fprintf(stderr, "split: traditional layer vs render %g, hashed layer vs render %g (modes differ by %g)\n", dt,
                dh, differ);
        CHECK(dt <= 1e-3 && dh <= 1e-3 && differ > 0.1);
        /* Left half of the window: traditional; right half: hashed (the column between is the
         * divider line). */
        double l = window_vs_frame(&win, &trad, "", 0, W / 2), r = window_vs_frame(&win, &hashed, "", W / 2 + 1, W);
        fprintf(stderr, "split window: left vs traditional %.2f, right vs hashed %.2f (/ 255)\n", l, r);
        CHECK(l <= 1.5 && r <= 1.5);
        exr_image_free(&cap);
        exr_image_free(&trad);
        exr_image_free(&hashed);
        exr_image_free(&win);
    } else {
        CHECK(false);
    }
}

/* A resized window letterboxes the frame, and the cursor (window pixels) still maps to the display
 * pixel under it. */
TEST(resized_window_letterboxes_and_maps_the_cursor)
{
    const char *log = p("resize.log");
    /* 320x240 holds the 160x90 frame at 2x: 320x180 with 30-pixel bars above and below. Window
     * pixel (80, 120) is display pixel (40, 45), i.e. gaze (0.25, 0.5). */
    write_file(p("resize.txt"), "frame 0\nresize 320 240\nframe 1\nmove 80px 120px\nkey O\ncapture\nquit\n");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, XVFB " '%s' view --builtin forest --width %d --height %d --rings '%s' --taa off "
             "--record '%s' --script '%s' --quiet", g_bin, W, H, RINGS, p("resize/r.csv"), p("resize.txt"));
    int rc = sh(cmd, log);
    CHECK(rc == 0);
    if (rc != 0) {
        dump(log);
        return;
    }
    check_overlay(p("resize/r.capture.0001.exr"), 0.25f, 0.5f);
    exr_image win;
    if (read_exr(p("resize/r.window.0001.exr"), &win)) {
        fprintf(stderr, "resized window: %dx%d\n", win.width, win.height);
        CHECK(win.width == 320 && win.height == 240);
        const float *g = exr_image_channel(&win, "G");
        double bars = 0, image = 0;
        for (int y = 0; g && y < win.height; y++)
            for (int x = 0; x < win.width; x++) {
                bool bar = y < 30 || y >= 210;
                bars = fmax(bars, bar ? g[y * win.width + x] : 0.0);
                image += bar ? 0.0 : g[y * win.width + x] / (320.0 * 180.0);
            }
        fprintf(stderr, "resized window: bars max %.3f, image mean %.3f\n", bars, image);
        CHECK(g && bars == 0.0 && image > 0.2);
        exr_image_free(&win);
    } else {
        CHECK(false);
    }
}

TEST(killed_mid_recording_leaves_a_valid_trace)
{
    const char *log = p("kill.log");
    /* No quit: after the script the viewer runs on interactively (24 fps), recording, until it is
     * killed outright (no chance to close anything). */
    write_file(p("kill.txt"), "frame 0\nmove 0.6 0.3\nkey R\n");
    char cmd[2048];
    /* Killed once the trace holds three samples (polled, at most 30 s: a loaded machine or a
     * sanitizer build starts the viewer slowly), not after a fixed time. */
    snprintf(cmd, sizeof cmd, XVFB " sh -c \"'%s' view --builtin fence --width 64 --height 36 --record '%s' "
             "--script '%s' --quiet & v=\\$!; n=0; c=0; while [ \\$n -lt 300 ] && [ \\${c:-0} -lt 3 ]; do "
             "sleep 0.1; n=\\$((n+1)); c=\\$(grep -c '^[0-9]' '%s' 2>/dev/null); done; "
             "kill -KILL \\$v; wait \\$v; exit 0\"", g_bin, p("kill/k.csv"), p("kill.txt"), p("kill/k.csv"));
    CHECK(sh(cmd, log) == 0);
    gaze_trace t;
    fs_status st = gaze_load(p("kill/k.csv"), &(gaze_load_desc){0}, &t);
    CHECK(st == FS_OK);
    if (st == FS_OK) {
        fprintf(stderr, "killed after %d recorded frames (%.2f s)\n", t.count, t.duration);
        CHECK(t.count >= 2 && t.samples[0].x == 0.6f && t.samples[0].y == 0.3f);
        gaze_free(&t);
    } else {
        dump(log);
    }
}

TEST(bad_input_fails_with_one_line)
{
    /* A bad script is refused before any window opens: no X server needed. */
    write_file(p("bad.txt"), "frame 0\nmove 0.5 0.5\nmove 80 45\n");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "'%s' view --builtin fence --script '%s' 2>'%s'", g_bin, p("bad.txt"), p("bad.err"));
    int ws = system(cmd);
    CHECK(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 2);
    snprintf(cmd, sizeof cmd, "test $(wc -l <'%s') -eq 1 && grep -q 'bad.txt:3: expected' '%s'", p("bad.err"),
             p("bad.err"));
    CHECK(system(cmd) == 0);
    /* No X server: exit status 7 (no OpenGL context), one line saying what to do. */
    snprintf(cmd, sizeof cmd, "env -u DISPLAY -u WAYLAND_DISPLAY '%s' view --builtin fence --width 64 --height 36 "
             "2>'%s' >/dev/null", g_bin, p("nox.err"));
    ws = system(cmd);
    CHECK(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 7);
    snprintf(cmd, sizeof cmd, "test $(wc -l <'%s') -eq 1 && grep -q 'xvfb-run' '%s'", p("nox.err"), p("nox.err"));
    CHECK(system(cmd) == 0);
}

int main(void)
{
    g_bin = getenv("FOVSIM_BIN");
    if (!g_bin) {
        fprintf(stderr, "FOVSIM_BIN is not set (ctest sets it)\n");
        return 1;
    }
    snprintf(g_dir, sizeof g_dir, "%s/view", test_out_dir());
    char cmd[2400];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", g_dir, g_dir);
    if (system(cmd) != 0)
        return 1;
    if (system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        fprintf(stderr, "SKIP: xvfb-run is not installed, so no X server can be started for the viewer "
                        "(scripts/setup.sh installs the Debian packages xvfb and xauth)\n");
        return 77;
    }
    if (sh(XVFB " true", p("xvfb.log")) != 0) {
        fprintf(stderr, "SKIP: Xvfb cannot start here, so the viewer cannot be tested:\n");
        dump(p("xvfb.log"));
        return 77;
    }
    RUN(viewer_matches_render_and_follows_the_gaze);
    RUN(split_screen_shows_two_modes);
    RUN(hmd_view_shows_both_eyes);
    RUN(resized_window_letterboxes_and_maps_the_cursor);
    RUN(killed_mid_recording_leaves_a_valid_trace);
    RUN(bad_input_fails_with_one_line);
    return test_summary();
}
