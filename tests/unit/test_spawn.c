/* test_spawn.c: spawn_start_writer (src/core/spawn.c): the child reads what is written into the
 * pipe, its exit status comes back through spawn_wait, the write end is close-on-exec (no other
 * child keeps the reader from seeing the end of input), a missing program is SPAWN_NOT_FOUND, and
 * html_escape (src/output/svg_chart.c), which report.html relies on. */
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/spawn.h"
#include "output/svg_chart.h"
#include "test.h"

static char g_dir[64];

TEST(writer_child_reads_the_pipe)
{
    int pid = 0, fd = -1;
    char *argv[] = {"cat", NULL};
    CHECK(spawn_start_writer(argv, &(spawn_opts){.dir = g_dir, .output = "cat.out"}, &pid, &fd) == 0);
    CHECK(pid > 0 && fd >= 0);
    CHECK((fcntl(fd, F_GETFD) & FD_CLOEXEC) != 0);
    /* Another child started meanwhile must not hold the pipe open (cat would never end). */
    char *t[] = {"true", NULL};
    CHECK(spawn_run(t, NULL) == 0);
    const char msg[] = "frames\n";
    CHECK(write(fd, msg, sizeof msg - 1) == (ssize_t)(sizeof msg - 1));
    close(fd);
    CHECK(spawn_wait(pid) == 0);
    char path[128], buf[64] = "";
    snprintf(path, sizeof path, "%s/cat.out", g_dir);
    FILE *f = fopen(path, "r");
    CHECK(f != NULL);
    if (f) {
        CHECK(fgets(buf, sizeof buf, f) != NULL);
        fclose(f);
    }
    CHECK(strcmp(buf, msg) == 0);
    unlink(path);
}

TEST(writer_status_and_missing_program)
{
    int pid = 0, fd = -1;
    char *argv[] = {"sh", "-c", "exit 3", NULL};
    CHECK(spawn_start_writer(argv, NULL, &pid, &fd) == 0);
    close(fd);
    CHECK(spawn_wait(pid) == 3);
    char *none[] = {"fovsim-no-such-program", NULL};
    CHECK(spawn_start_writer(none, NULL, &pid, &fd) == SPAWN_NOT_FOUND);
    char *bad_dir[] = {"cat", NULL};
    CHECK(spawn_start_writer(bad_dir, &(spawn_opts){.dir = "/nonexistent/fovsim"}, &pid, &fd) == SPAWN_FAILED);
}

TEST(writer_to_a_dead_child_gets_epipe)
{
    int pid = 0, fd = -1;
    char *argv[] = {"true", NULL};
    CHECK(spawn_start_writer(argv, NULL, &pid, &fd) == 0);
    CHECK(spawn_wait(pid) == 0);
    char buf[4096] = {0};
    CHECK(write(fd, buf, sizeof buf) < 0); /* SIGPIPE is ignored in main */
    close(fd);
}

TEST(html_escape_escapes_markup)
{
    sbuf b = {0};
    html_escape(&b, "a<b>&\"c'");
    CHECK(b.p && strcmp(b.p, "a&lt;b&gt;&amp;&quot;c&#39;") == 0);
    free(b.p);
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN);
    snprintf(g_dir, sizeof g_dir, "/tmp/fovsim_test_spawn.XXXXXX");
    if (!mkdtemp(g_dir))
        return 1;
    RUN(writer_child_reads_the_pipe);
    RUN(writer_status_and_missing_program);
    RUN(writer_to_a_dead_child_gets_epipe);
    RUN(html_escape_escapes_markup);
    rmdir(g_dir);
    return test_summary();
}
