/* spawn.c: see spawn.h. */
#include "core/spawn.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static bool executable(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISREG(sb.st_mode) && access(path, X_OK) == 0;
}

bool spawn_find(const char *prog, char *out, size_t n)
{
    if (!prog[0])
        return false;
    if (strchr(prog, '/')) {
        int l = snprintf(out, n, "%s", prog);
        return l >= 0 && (size_t)l < n && executable(out);
    }
    const char *path = getenv("PATH");
    if (!path)
        path = "/usr/local/bin:/usr/bin:/bin";
    for (const char *p = path;; p++) {
        size_t len = strcspn(p, ":");
        /* An empty PATH entry is the current folder. */
        int l = len ? snprintf(out, n, "%.*s/%s", (int)len, p, prog) : snprintf(out, n, "./%s", prog);
        if (l >= 0 && (size_t)l < n && executable(out))
            return true;
        p += len;
        if (!*p)
            return false;
    }
}

/* In the child: only async-signal-safe calls (the parent may have threads). A failure writes errno
 * into `report` (close-on-exec, so a successful exec closes it empty). */
static void child(const char *exe, char *const argv[], const spawn_opts *o, int report, int in)
{
    int fd = -1;
    if (in >= 0) { /* spawn_start_writer: the pipe becomes stdin (dup2 drops close-on-exec) */
        struct sigaction sa = {.sa_handler = SIG_DFL};
        if (dup2(in, STDIN_FILENO) < 0 || sigaction(SIGPIPE, &sa, NULL) != 0)
            goto fail;
    }
    if (o && o->dir && chdir(o->dir) != 0)
        goto fail;
    if (o && (o->output || o->quiet)) {
        fd = o->output ? open(o->output, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644)
                       : open("/dev/null", O_WRONLY | O_CLOEXEC);
        if (fd < 0 || dup2(fd, STDOUT_FILENO) < 0 || dup2(fd, STDERR_FILENO) < 0)
            goto fail;
    }
    execv(exe, argv);
fail:;
    int e = errno;
    ssize_t w = write(report, &e, sizeof e);
    (void)w;
    _exit(127);
}

/* pipe() with both ends close-on-exec. */
static int pipe_cloexec(int fd[2])
{
    if (pipe(fd) != 0)
        return -1;
    fcntl(fd[0], F_SETFD, FD_CLOEXEC);
    fcntl(fd[1], F_SETFD, FD_CLOEXEC);
    return 0;
}

/* Forks the child of exe (stdin the descriptor `in`, or the parent's when -1) and waits until it
 * has exec'd: 0 with *pid, or SPAWN_FAILED with errno the fork's or the child's (a child that
 * failed before exec is reaped). */
static int start(const char *exe, char *const argv[], const spawn_opts *o, int in, pid_t *pid)
{
    int report[2];
    if (pipe_cloexec(report) != 0)
        return SPAWN_FAILED;
    fflush(NULL);
    pid_t p = fork();
    if (p == 0)
        child(exe, argv, o, report[1], in);
    int e = errno;
    close(report[1]);
    if (p < 0) {
        close(report[0]);
        errno = e;
        return SPAWN_FAILED;
    }
    /* The child writes its errno into the pipe only when it fails before exec; a successful exec
     * closes the pipe empty. */
    int child_errno = 0;
    ssize_t got;
    while ((got = read(report[0], &child_errno, sizeof child_errno)) < 0 && errno == EINTR)
        ;
    close(report[0]);
    if (got == (ssize_t)sizeof child_errno) {
        spawn_wait((int)p);
        errno = child_errno;
        return SPAWN_FAILED;
    }
    *pid = p;
    return 0;
}

int spawn_run(char *const argv[], const spawn_opts *o)
{
    char exe[4096];
    if (!spawn_find(argv[0], exe, sizeof exe))
        return SPAWN_NOT_FOUND;
    pid_t pid;
    if (start(exe, argv, o, -1, &pid) != 0)
        return SPAWN_FAILED;
    return spawn_wait((int)pid);
}

int spawn_start_writer(char *const argv[], const spawn_opts *o, int *pid, int *in_fd)
{
    char exe[4096];
    if (!spawn_find(argv[0], exe, sizeof exe))
        return SPAWN_NOT_FOUND;
    int data[2];
    if (pipe_cloexec(data) != 0)
        return SPAWN_FAILED;
    pid_t p;
    int st = start(exe, argv, o, data[0], &p);
    int e = errno;
    close(data[0]);
    if (st != 0) {
        close(data[1]);
        errno = e;
        return SPAWN_FAILED;
    }
    *pid = (int)p;
    *in_fd = data[1];
    return 0;
}

int spawn_wait(int pid)
{
    int ws;
    while (waitpid((pid_t)pid, &ws, 0) < 0)
        if (errno != EINTR)
            return SPAWN_FAILED;
    return WIFEXITED(ws) ? WEXITSTATUS(ws) : 128 + (WIFSIGNALED(ws) ? WTERMSIG(ws) : 0);
}

bool spawn_path_arg(const char *path, char *out, size_t n)
{
    int l = snprintf(out, n, "%s%s", path[0] == '-' ? "./" : "", path);
    return l >= 0 && (size_t)l < n;
}

void shell_quote(sbuf *b, const char *s)
{
    sb_append(b, "'", 1);
    for (const char *q; (q = strchr(s, '\'')); s = q + 1) {
        sb_append(b, s, (size_t)(q - s));
        sb_append(b, "'\\''", 4);
    }
    sb_puts(b, s);
    sb_append(b, "'", 1);
}
