/* look_hints.h: the "look at it" lines compare and demo print when a run has finished. */
#ifndef FOVSIM_LOOK_HINTS_H
#define FOVSIM_LOOK_HINTS_H

typedef struct look_hints_desc {
    const char *out;   /* the output folder */
    const char *name;  /* the frames' prefix (--name): DIR/<name>.<frame:04d>.exr */
    int first_frame;   /* the first frame written (--first-frame) */
    const char *mode;  /* a mode of the run, for the layer example */
    const char *video; /* the video's file name in the ffmpeg example ("demo.mp4") */
    float fps;
} look_hints_desc;

/* Prints, to stdout, how to look at a finished compare or demo folder: DIR/report.html first
 * when the run wrote one, then oiiotool and ffmpeg commands (shell-quoted paths). The commands are
 * README.md's "Look at the frames" recipes, which tests/cli/test_docs.sh runs. */
void look_hints_print(const look_hints_desc *h);

#endif
