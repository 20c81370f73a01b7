/* run_record.h: the record of what wrote an output folder, and --resume / --replace (docs/design.md
 * "Outputs"; README "Output folders").
 *
 * render, reference, compare and demo write into DIR (--out) a text file, DIR/fovsim-run.txt:
 * one "key: value" line per setting that changes what the run writes (the command, --name, every
 * option that reaches a pixel, the scene's and the gaze trace's content hashes, the executable's
 * hash, the GL renderer), then "---", then how many frames it draws and whether it finished. It is
 * written (atomically) before the first frame and rewritten with "complete: yes" after the last.
 *
 * At the start of a run, the folder's record decides:
 *   - no record and no frames of --name: a new folder;
 *   - the same configuration: the earlier frames are removed and every frame is drawn, or, with
 *     --resume, the complete frames are kept (run_folder.kept) and only the others are drawn;
 *   - another configuration, or frames that no record describes (an older fovsim's, or not
 *     fovsim's): the run refuses with one line naming the first setting that differs, unless
 *     --replace, which removes the earlier run's frames first.
 * metrics.csv, summary.json and fvvdp/ are written only by a compare that finishes; they are
 * removed at the start of every run, so a folder holds them only when its last run completed. */
#ifndef FOVSIM_RUN_RECORD_H
#define FOVSIM_RUN_RECORD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "cli/cli.h"
#include "session/session.h"

#define RUN_RECORD_FILE "fovsim-run.txt"
/* The folder's lock (README "Output folders", one writer at a time): a run holds an exclusive flock(2) on DIR/fovsim-run.lock
 * from before it reads the record until after its last file, so a second run into DIR (--replace
 * and --resume included, and a sweep task run twice) is refused, or waits with --wait-lock,
 * instead of mixing its frames with the first's. The file names the holder ("pid P on host H,
 * fovsim render, since T") for the refusal message; it is removed by its holder at the end (a
 * killed run leaves it, unlocked, and the next run takes it). The record itself cannot carry the
 * lock: it is replaced by rename, and a lock belongs to one file, not to a name. */
#define RUN_LOCK_FILE "fovsim-run.lock"

/* The configuration text of a run (the part of the record above "---"), malloc'd into *out.
 * FS_ERR_IO when the executable cannot be read to hash it (never in practice: /proc/self/exe). */
fs_status run_record_describe(const run_desc *d, const session *s, char **out);
/* The slow parts of a description (the executable's hash, read once per process, and the scene's
 * and the gaze trace's content), computed once for many runs of one scene and trace: a sweep
 * describes each of its tasks with run_record_describe_hashed (sweep.c, "the state of a task"). */
typedef struct run_record_hashes {
    uint64_t exe, scene_content, scene_settings, gaze;
} run_record_hashes;
fs_status run_record_hashes_of(const session *s, run_record_hashes *h);
fs_status run_record_describe_hashed(const run_desc *d, const session *s, const run_record_hashes *h, char **out);
/* DIR's record: its configuration part into *config (malloc'd; NULL when DIR has no record), its
 * frame count (-1 when absent) and whether it says complete (either may be NULL). FS_ERR_IO with
 * one line when it cannot be read or is not fovsim's record (a FIFO, a folder, too long). */
fs_status run_record_read(const char *dir, char **config, int *frames, bool *complete);
/* The first setting in which configuration texts `now` and `there` differ, as
 * "key: 'value now' now, 'value there' there", into out. */
void run_record_difference(const char *now, const char *there, char *out, size_t cap);

typedef struct run_folder {
    char dir[1024];
    char name[256];
    char *config;  /* this run's configuration text (owned) */
    int frames;    /* frames this run draws */
    bool *kept;    /* per frame: a complete frame of the same configuration kept by --resume */
    int kept_count;
    bool written, completed; /* the record, "complete: no" / "complete: yes" */
    int lock_fd;             /* DIR/fovsim-run.lock, held while locked */
    bool locked;
} run_folder;

/* Prepares DIR for a run of `frames` frames named d->name: describes the run's configuration
 * (run_record_describe), creates DIR, removes stale temporary files, checks the record as above
 * (d->resume, d->replace), removes what the run replaces and writes the record ("complete: no").
 * First it takes the folder's lock (RUN_LOCK_FILE), waiting up to d->wait_lock seconds for
 * another run holding it; FS_ERR_BUSY with one line naming that run when it is still held.
 * FS_ERR_USAGE with one line when the folder holds another configuration's output and --replace
 * was not given; FS_ERR_IO when it cannot be made, tidied or the record cannot be written.
 * f->kept lists the frames --resume keeps. run_folder_close after any result. */
fs_status run_folder_open(run_folder *f, const char *dir, const run_desc *d, const session *s, int frames);
/* Rewrites the record with "complete: yes" (after the last frame and file of the run). */
fs_status run_folder_complete(run_folder *f);
/* Frees f and releases the lock. A run that did not complete and left no frame of its own removes
 * its record too. */
void run_folder_close(run_folder *f);
/* Prints the line that says what a resume kept and what redrawing kept frames for the TAA
 * history cost (nothing when no frame was kept). */
void run_folder_print_resume(const run_folder *rf, int redrawn, double redrawn_s);

/* The frame the TAA history of frame `first` starts from: the last frame at or before it whose
 * history is reset (frame 0, or a frame just after a camera cut). Resuming at `first` redraws
 * from there without writing, so its history equals an uninterrupted run's. */
int run_history_start(const scene *sc, int first, float fps, int width, int height);

#endif
