/* grid_video.c: see grid_video.h. */
#include "output/grid_video.h"

#include <dirent.h>
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/log.h"
#include "core/spawn.h"
#include "output/out_path.h"
#include "output/png_write.h"

#define PREVIEW_MAX_WIDTH 640 /* the previews are box-filtered down to at most this width */

struct grid_video {
    char dir[PATH_MAX];
    double fps;
    bool want_video, previews, failed;
    int given, step;   /* frames given so far; a preview every step-th of them */
    int width, height; /* the first frame's */
    int pid, fd;       /* ffmpeg, its stdin; fd -1 when not running */
    char tmp[PATH_MAX + 64], tmp_base[PATH_MAX + 72];
    unsigned char *rgb; /* one rgb24 frame */
    uint8_t *lut;
    struct sigaction old_pipe; /* SIGPIPE's action before ffmpeg started (restored at the end) */
    bool pipe_saved;
};

static void path_in(const grid_video *v, const char *name, char *out, size_t n)
{
    snprintf(out, n, "%s/%s", v->dir, name);
}

/* Removes DIR/preview/frame.*.png and the folder (an earlier run's). */
static void remove_previews(const char *dir)
{
    char pd[PATH_MAX + 16], f[PATH_MAX + 300];
    snprintf(pd, sizeof pd, "%s/preview", dir);
    DIR *dh = opendir(pd);
    if (!dh)
        return;
    for (struct dirent *e; (e = readdir(dh));)
        if (out_path_sequence_index(e->d_name, "frame", ".png") >= 0) {
            snprintf(f, sizeof f, "%s/%s", pd, e->d_name);
            unlink(f);
        }
    closedir(dh);
    rmdir(pd);
}

grid_video *grid_video_begin(const grid_video_desc *d)
{
    grid_video *v = calloc(1, sizeof *v);
    if (!v)
        return NULL;
    snprintf(v->dir, sizeof v->dir, "%s", d->dir);
    v->fps = d->fps;
    v->fd = -1;
    char p[PATH_MAX + 32], exe[PATH_MAX];
    path_in(v, "video.mp4", p, sizeof p);
    unlink(p);
    remove_previews(v->dir);
    v->want_video = d->video && spawn_find("ffmpeg", exe, sizeof exe);
    if (d->video && !v->want_video)
        printf("video: ffmpeg is not installed, so no %s/video.mp4 (apt install ffmpeg); report.html shows "
               "previews of the frames instead\n", v->dir);
    v->previews = !v->want_video && d->previews > 0;
    v->step = d->previews > 0 && d->frames > d->previews ? (d->frames + d->previews - 1) / d->previews : 1;
    return v;
}

/* ffmpeg reading rgb24 frames of the grid's size on stdin, writing the temporary MP4 in dir. */
static fs_status start_ffmpeg(grid_video *v)
{
    char mp4[PATH_MAX + 32], size[32], fps[32];
    path_in(v, "video.mp4", mp4, sizeof mp4);
    if (!out_path_temp_name(mp4, v->tmp, sizeof v->tmp)) {
        log_error("%s: the path is too long", mp4);
        return FS_ERR_IO;
    }
    const char *base = strrchr(v->tmp, '/') ? strrchr(v->tmp, '/') + 1 : v->tmp;
    snprintf(v->tmp_base, sizeof v->tmp_base, "./%s", base);
    snprintf(size, sizeof size, "%dx%d", v->width, v->height);
    snprintf(fps, sizeof fps, "%.9g", v->fps);
    /* Pad to even sizes (yuv420p), BT.709 matrix, tagged with the sRGB transfer the frames have. */
    char *argv[] = {"ffmpeg", "-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24",
                    "-video_size", size, "-framerate", fps, "-i", "pipe:0", "-vf",
                    "pad=ceil(iw/2)*2:ceil(ih/2)*2,scale=out_color_matrix=bt709:out_range=tv,format=yuv420p",
                    "-c:v", "libx264", "-preset", "veryfast", "-crf", "20", "-pix_fmt", "yuv420p",
                    "-color_primaries", "bt709", "-color_trc", "iec61966-2-1", "-colorspace", "bt709",
                    "-movflags", "+faststart", "-f", "mp4", v->tmp_base, NULL};
    /* A dead ffmpeg must make write() fail (EPIPE), not end fovsim. */
    struct sigaction ign = {.sa_handler = SIG_IGN};
    v->pipe_saved = sigaction(SIGPIPE, &ign, &v->old_pipe) == 0;
    int rc = spawn_start_writer(argv, &(spawn_opts){.dir = v->dir, .output = "ffmpeg.log"}, &v->pid, &v->fd);
    if (rc != 0) {
        log_error("%s: cannot run ffmpeg: %s", mp4, rc == SPAWN_NOT_FOUND ? "not found" : strerror(errno));
        v->fd = -1;
        return FS_ERR_IO;
    }
    return FS_OK;
}

static bool write_all(int fd, const unsigned char *p, size_t n)
{
    while (n) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return false;
        p += w;
        n -= (size_t)w;
    }
    return true;
}

/* The LUT level of linear l: what lrintf(clamp(l, 0, 1) * 65535) gives, NaN and infinities 0. Adding
 * and taking away 2^23 rounds a float in [0, 2^23) to an integer in the current rounding mode (to
 * nearest, ties to even, as lrintf), with no call. */
static inline int lut_level(float l)
{
    const float big = 8388608.0f; /* 2^23: from here up, floats are integers */
    if (!(l > 0.0f))
        return 0; /* also NaN, -Inf */
    if (!(l < 1.0f))
        return l <= FLT_MAX ? GRID_VIDEO_LUT - 1 : 0; /* +Inf as 0, like NaN */
    float x = l * (float)(GRID_VIDEO_LUT - 1);
    return (int)((x + big) - big);
}

void grid_video_to_rgb24(const float *const rgb[3], size_t n, const uint8_t *lut, unsigned char *out)
{
    const float *r = rgb[0], *g = rgb[1], *b = rgb[2];
    for (size_t i = 0; i < n; i++) {
        out[3 * i] = lut[lut_level(r[i])];
        out[3 * i + 1] = lut[lut_level(g[i])];
        out[3 * i + 2] = lut[lut_level(b[i])];
    }
}

static fs_status video_frame(grid_video *v, const float *const rgb[3])
{
    if (!v->lut) {
        v->lut = malloc(GRID_VIDEO_LUT);
        v->rgb = malloc((size_t)v->width * (size_t)v->height * 3);
        if (!v->lut || !v->rgb)
            return FS_ERR_NOMEM;
        for (int i = 0; i < GRID_VIDEO_LUT; i++)
            v->lut[i] = (uint8_t)png_srgb_quantise((float)i / (GRID_VIDEO_LUT - 1), 8);
        fs_status st = start_ffmpeg(v);
        if (st != FS_OK)
            return st;
    }
    size_t n = (size_t)v->width * (size_t)v->height;
    grid_video_to_rgb24(rgb, n, v->lut, v->rgb);
    if (!write_all(v->fd, v->rgb, n * 3)) {
        log_error("%s/video.mp4: ffmpeg stopped reading its frames: %s (see %s/ffmpeg.log)", v->dir, strerror(errno),
                  v->dir);
        return FS_ERR_IO;
    }
    return FS_OK;
}

/* The grid box-filtered (in linear light) to at most PREVIEW_MAX_WIDTH wide, as an 8-bit PNG. */
static fs_status preview_frame(grid_video *v, int index, const float *const rgb[3])
{
    int f = (v->width + PREVIEW_MAX_WIDTH - 1) / PREVIEW_MAX_WIDTH;
    int pw = v->width / f, ph = v->height / f;
    if (pw < 1 || ph < 1)
        pw = ph = 1, f = 1;
    float *buf = malloc(sizeof(float) * 3 * (size_t)pw * (size_t)ph);
    if (!buf)
        return FS_ERR_NOMEM;
    size_t pn = (size_t)pw * (size_t)ph;
    for (int y = 0; y < ph; y++)
        for (int x = 0; x < pw; x++)
            for (int c = 0; c < 3; c++) {
                double s = 0;
                for (int j = 0; j < f; j++)
                    for (int i = 0; i < f; i++) {
                        float l = rgb[c][(size_t)(y * f + j) * (size_t)v->width + (size_t)(x * f + i)];
                        s += isfinite(l) ? l : 0.0;
                    }
                buf[(size_t)c * pn + (size_t)y * (size_t)pw + (size_t)x] = (float)(s / (f * f));
            }
    char pd[PATH_MAX + 16], p[PATH_MAX + 48];
    snprintf(pd, sizeof pd, "%s/preview", v->dir);
    if (mkdir(pd, 0755) != 0 && errno != EEXIST) {
        log_error("%s: cannot create: %s", pd, strerror(errno));
        free(buf);
        return FS_ERR_IO;
    }
    snprintf(p, sizeof p, "%s/frame.%04d.png", pd, index);
    const float *planes[3] = {buf, buf + pn, buf + 2 * pn};
    fs_status st = png_write_srgb(p, pw, ph, planes, 8);
    free(buf);
    return st;
}

fs_status grid_video_frame(grid_video *v, int index, const exr_image *grid)
{
    if (v->failed)
        return FS_OK; /* said once; the run's other outputs go on */
    const float *rgb[3] = {exr_image_channel(grid, "R"), exr_image_channel(grid, "G"), exr_image_channel(grid, "B")};
    if (!rgb[0] || !rgb[1] || !rgb[2])
        return FS_ERR_INTERNAL;
    if (!v->width) {
        v->width = grid->width;
        v->height = grid->height;
    } else if (grid->width != v->width || grid->height != v->height) {
        return FS_ERR_INTERNAL;
    }
    bool preview = v->previews && v->given++ % v->step == 0;
    fs_status st = v->want_video ? video_frame(v, rgb) : preview ? preview_frame(v, index, rgb) : FS_OK;
    if (st == FS_ERR_IO && v->want_video) {
        v->failed = true; /* the video fails at the end; the frames and metrics do not */
        st = FS_OK;
    }
    return st;
}

fs_status grid_video_end(grid_video *v, bool ok)
{
    if (!v)
        return FS_OK;
    fs_status st = FS_OK;
    if (v->fd >= 0) {
        close(v->fd);
        int rc = spawn_wait(v->pid);
        char mp4[PATH_MAX + 32], log[PATH_MAX + 32];
        path_in(v, "video.mp4", mp4, sizeof mp4);
        path_in(v, "ffmpeg.log", log, sizeof log);
        if (ok && !v->failed && rc == 0 && rename(v->tmp, mp4) == 0) {
            unlink(log); /* kept only when ffmpeg failed */
        } else {
            unlink(v->tmp);
            if (ok && !v->failed && rc != 0)
                log_error("%s: ffmpeg failed with status %d (see %s)", mp4, rc, log);
            else if (ok && !v->failed)
                log_error("%s: cannot rename %s: %s", mp4, v->tmp, strerror(errno));
            st = ok ? FS_ERR_IO : FS_OK;
        }
    }
    if (ok && v->failed)
        st = FS_ERR_IO;
    if (v->pipe_saved)
        sigaction(SIGPIPE, &v->old_pipe, NULL);
    if (!ok && v->previews)
        remove_previews(v->dir);
    free(v->rgb);
    free(v->lut);
    free(v);
    return st;
}

bool grid_video_has_video(const char *dir)
{
    char p[PATH_MAX + 32];
    snprintf(p, sizeof p, "%s/video.mp4", dir);
    struct stat sb;
    return stat(p, &sb) == 0 && S_ISREG(sb.st_mode);
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

int grid_video_previews(const char *dir, int *idx, int cap)
{
    char pd[PATH_MAX + 16];
    snprintf(pd, sizeof pd, "%s/preview", dir);
    DIR *dh = opendir(pd);
    if (!dh)
        return 0;
    int n = 0;
    for (struct dirent *e; (e = readdir(dh));) {
        long k = out_path_sequence_index(e->d_name, "frame", ".png");
        if (k >= 0 && k <= INT_MAX) {
            if (n < cap)
                idx[n] = (int)k;
            n++;
        }
    }
    closedir(dh);
    qsort(idx, (size_t)(n < cap ? n : cap), sizeof *idx, cmp_int);
    return n;
}
