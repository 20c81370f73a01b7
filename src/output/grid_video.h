/* grid_video.h: the pictures of a comparison for people: an MP4 of the grid (part 0 of each
 * comparison EXR, as the run built it) encoded by the `ffmpeg` program, or, without one, small PNG
 * previews of it (DIR/preview/frame.NNNN.png, at most --previews of them, evenly spaced over the
 * frames: a long run or a sweep's many tasks do not fill the disk) for report.html's frame scrubber
 * (docs/compare.md "Video and report page").
 *
 * The video: the linear grid is encoded to sRGB 8 bit (png_srgb_quantise's curve) and piped as raw
 * rgb24 frames into ffmpeg (spawn_start_writer: no shell), which pads it to an even size and
 * writes H.264 (libx264), yuv420p, tagged sRGB, at the run's frame rate, to a temporary name in
 * DIR renamed to DIR/video.mp4 when ffmpeg succeeds; a failed or interrupted encoding leaves no
 * video.mp4 (its messages stay in DIR/ffmpeg.log). No ffmpeg library is linked. */
#ifndef FOVSIM_GRID_VIDEO_H
#define FOVSIM_GRID_VIDEO_H

#include <stdbool.h>

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "output/exr_write.h"

typedef struct grid_video grid_video;

typedef struct grid_video_desc {
    const char *dir; /* the run's folder */
    double fps;
    bool video;      /* --video on: encode video.mp4 when ffmpeg is installed (else previews) */
    int frames;      /* how many frames grid_video_frame will be given */
    int previews;    /* --previews: at most this many previews, evenly spaced, first frame first; 0 none */
} grid_video_desc;

/* Removes the outputs of an earlier run (video.mp4, preview/), then says (one line) when the video
 * was asked for but ffmpeg is not installed. NULL only when out of memory. */
grid_video *grid_video_begin(const grid_video_desc *d);
/* Frame `index` (frames are given in order): the R, G, B planes of `grid` (part 0). The size is
 * the first frame's; a later frame of another size is an FS_ERR_INTERNAL. */
fs_status grid_video_frame(grid_video *v, int index, const exr_image *grid);
/* Ends it: with ok, waits for ffmpeg and renames the video into place (a failure: one line naming
 * ffmpeg.log, FS_ERR_IO); without, stops and removes what was begun. Frees v (NULL: nothing). */
fs_status grid_video_end(grid_video *v, bool ok);
/* n linear pixels of planes rgb as rgb24 (interleaved) into out: each value clamped to [0, 1]
 * (NaN and infinities as 0), stepped to the nearest of 65536 levels (ties to even) and looked up
 * in lut (GRID_VIDEO_LUT entries, the sRGB 8-bit value of each level). Written without libm calls
 * (one call per value was a third of the video's cost); the same bytes as the plain formula
 * (test_png_write checks it). */
#define GRID_VIDEO_LUT 65536
void grid_video_to_rgb24(const float *const rgb[3], size_t n, const uint8_t *lut, unsigned char *out);
/* Whether the run's folder holds the video, or the previews. */
bool grid_video_has_video(const char *dir);
/* The frame indices of the previews in DIR/preview/ (frame.NNNN.png), sorted, into idx (at most
 * cap); returns how many there are (may exceed cap), 0 for none. */
int grid_video_previews(const char *dir, int *idx, int cap);

#endif
