/* spawn.h: the one way fovsim starts another program (gnuplot, python3, sbatch): an argv array,
 * never a shell, so a path or a value read from a file is one argument and nothing in it runs. The
 * program is looked up on PATH once, in the parent, so what a caller checks for is what it runs. */
#ifndef FOVSIM_SPAWN_H
#define FOVSIM_SPAWN_H

#include <stdbool.h>
#include <stddef.h>

#include "core/strbuf.h"

/* spawn_run's results other than an exit status (0..255) or 128 + a signal number. */
#define SPAWN_NOT_FOUND (-2) /* no executable of that name on PATH (or at that path) */
#define SPAWN_FAILED (-1)    /* it could not be started (fork, chdir, a redirection, exec); errno says why */

typedef struct spawn_opts {
    const char *dir;    /* the child's working folder (NULL: the caller's) */
    const char *output; /* stdout and stderr into this file (created or truncated; relative to dir) */
    bool quiet;         /* stdout and stderr to /dev/null (output unset) */
} spawn_opts;

/* The executable `prog` is: itself when it holds a '/', else the first match on PATH. False when
 * there is none (or the result does not fit in n). */
bool spawn_find(const char *prog, char *out, size_t n);
/* Runs argv (argv[0] looked up as spawn_find does) without a shell and waits for it. o may be NULL. */
int spawn_run(char *const argv[], const spawn_opts *o);
/* Starts argv (looked up as spawn_find does) without a shell, its stdin the read end of a new pipe,
 * and does not wait: *pid is the child, *in_fd the pipe's write end (close-on-exec, so no later
 * child holds it open; closing it is the child's end of input). The child starts with SIGPIPE at
 * its default; the caller should ignore SIGPIPE (a child that dies makes write fail with EPIPE).
 * Returns 0, SPAWN_NOT_FOUND or SPAWN_FAILED (errno says why). Wait for it with spawn_wait. */
int spawn_start_writer(char *const argv[], const spawn_opts *o, int *pid, int *in_fd);
/* Waits for a child of spawn_start_writer: its exit status, 128 + a signal, or SPAWN_FAILED. */
int spawn_wait(int pid);
/* `path` as a program's argument that cannot be read as an option: "./" before one that starts
 * with '-'. out: n bytes; false when it does not fit. */
bool spawn_path_arg(const char *path, char *out, size_t n);
/* Appends `s` single-quoted for a POSIX shell (for commands fovsim prints or writes into job
 * scripts for the user; fovsim itself never runs a shell). */
void shell_quote(sbuf *b, const char *s);

#endif
