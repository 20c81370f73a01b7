/* test_out_path.c: output path lengths are checked with the arguments (src/output/out_path.c,
 * README "Exit status"), and the longest --name accepted really fits a file name. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <dirent.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli/cli.h"
#include "core/log.h"
#include "output/exr_write.h"
#include "output/out_path.h"
#include "test.h"

static char *repeat(char *buf, char c, int n)
{
    memset(buf, c, (size_t)n);
    buf[n] = '\0';
    return buf;
}

TEST(name_limit)
{
    char name[400], why[512];
    /* The temporary name adds 67 characters:
     * . name .99999.exr .tmp. <host, 32> . 4194304 . 4294967295 */
    CHECK(out_path_temp_overhead() == 67);
    CHECK(out_path_name_max() == 188);
    CHECK(out_path_check("out", repeat(name, 'a', 188), NULL, why, sizeof why));
    CHECK(!out_path_check("out", repeat(name, 'a', 189), NULL, why, sizeof why));
    CHECK(strstr(why, "--name") && strstr(why, "(189 characters)") && strstr(why, "at most 188"));
    CHECK(strlen(why) < 300); /* the long value is not echoed whole */
    CHECK(!out_path_check(NULL, repeat(name, 'a', 250), NULL, why, sizeof why));
}

TEST(dir_limits)
{
    char dir[2100], why[512];
    CHECK(out_path_check(repeat(dir, 'd', 255), "frame", NULL, why, sizeof why));
    CHECK(!out_path_check(repeat(dir, 'd', 256), "frame", NULL, why, sizeof why));
    CHECK(strstr(why, "--out") && strstr(why, "component of 256"));
    /* 1023 characters in short components: fine alone, too long with a long name. */
    for (int i = 0; i < 1023; i++)
        dir[i] = i % 2 ? '/' : 'd';
    dir[1023] = '\0';
    CHECK(out_path_check(dir, "frame", NULL, why, sizeof why));
    char name[300];
    CHECK(!out_path_check(dir, repeat(name, 'n', 150), NULL, why, sizeof why));
    CHECK(strstr(why, "--out and --name"));
    dir[1023] = 'd';
    dir[1024] = '\0';
    CHECK(!out_path_check(dir, "frame", NULL, why, sizeof why));
    CHECK(strstr(why, "1 to 1023"));
    CHECK(!out_path_check("", "frame", NULL, why, sizeof why));
    /* The cache directory. */
    CHECK(out_path_check(NULL, NULL, repeat(dir, 'c', 200), why, sizeof why));
    dir[0] = '\0';
    for (int i = 0; i < 900; i++)
        dir[i] = i % 2 ? '/' : 'c';
    dir[900] = '\0';
    CHECK(!out_path_check(NULL, NULL, dir, why, sizeof why) && strstr(why, "--cache"));
}

TEST(cli_refuses_before_running)
{
    char name[300];
    run_desc d;
    char *argv[] = {"fovsim", "render", "--name", name, NULL};
    repeat(name, 'x', 250);
    log_set_quiet_errors(true);
    CHECK(cli_parse(4, argv, &d) == FS_ERR_USAGE);
    log_set_quiet_errors(false);
    repeat(name, 'x', 188);
    CHECK(cli_parse(4, argv, &d) == FS_OK);
}

/* The longest accepted name, with the longest frame number, written for real through the atomic
 * writer: its temporary name fits. */
TEST(longest_name_writes)
{
    char dir[1100], path[1500], name[300];
    snprintf(dir, sizeof dir, "%s/out_path", test_out_dir());
    mkdir(dir, 0777);
    snprintf(path, sizeof path, "%s/%s.99999.exr", dir, repeat(name, 'm', out_path_name_max()));
    exr_image img;
    CHECK(exr_image_init(&img, 4, 4));
    CHECK(exr_image_add_channel(&img, "R") != NULL);
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_OK);
    struct stat sb;
    CHECK(stat(path, &sb) == 0);
    unlink(path);
    exr_image_free(&img);
}

TEST(temp_pid_parsing)
{
    /* The old format (fovsim before names carried the host): no host. */
    CHECK(out_path_temp_pid(".frame.0003.exr.tmp.4242.7") == 4242);
    CHECK(out_path_temp_pid(".metrics.csv.tmp.17") == 17);
    CHECK(out_path_temp_pid("summary.json.tmp.99") == 99);
    CHECK(out_path_temp_pid(".a.tmp.b.exr.tmp.5.0") == 5);
    CHECK(out_path_temp_pid("frame.0003.exr") == 0);
    CHECK(out_path_temp_pid(".frame.tmp.") == 0);
    CHECK(out_path_temp_pid(".frame.tmp.12x") == 0);
    CHECK(out_path_temp_pid(".frame.tmp.12.") == 0);
    CHECK(out_path_temp_pid(".frame.tmp.0") == 0);
    CHECK(out_path_temp_pid(".frame.tmp.1234567890123") == 0);
    CHECK(out_path_temp_pid(".tmp.5") == 0 || out_path_temp_pid(".tmp.5") == 5);
    out_temp_name t;
    CHECK(out_path_temp_parse(".frame.0003.exr.tmp.4242.7", &t) && t.pid == 4242 && t.host[0] == '\0');
    CHECK(out_path_temp_parse(".metrics.csv.tmp.17", &t) && t.pid == 17 && t.host[0] == '\0');
    /* With the host: `.tmp.<host>.<pid>.<n>`. */
    CHECK(out_path_temp_parse(".frame.0003.exr.tmp.node-07.4242.7", &t) && t.pid == 4242 && !strcmp(t.host, "node-07"));
    CHECK(out_path_temp_parse(".ref-0123456789abcdef.exr.tmp.N1.5.0", &t) && t.pid == 5 && !strcmp(t.host, "N1"));
    CHECK(out_path_temp_parse(".f.exr.tmp.123.45.6", &t) && t.pid == 45 && !strcmp(t.host, "123")); /* digits only */
    CHECK(out_path_temp_parse(".f.exr.tmp.tmp.45.6", &t) && t.pid == 45 && !strcmp(t.host, "tmp"));
    CHECK(out_path_temp_parse(".a.tmp.b.exr.tmp.h.5.0", &t) && t.pid == 5 && !strcmp(t.host, "h"));
    CHECK(!out_path_temp_parse(".f.exr.tmp.host.45", &t)); /* a host needs <n> */
    CHECK(!out_path_temp_parse(".f.exr.tmp.ho_st.45.6", &t));                  /* not a host's characters */
    CHECK(!out_path_temp_parse(".f.exr.tmp.host.0.6", &t));
    CHECK(!out_path_temp_parse(".f.exr.tmp.host.45.", &t));
    CHECK(!out_path_temp_parse(".f.exr.tmp..45.6", &t));
    CHECK(!out_path_temp_parse(".f.exr.tmp.aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa.45.6", &t)); /* 33 characters */
    CHECK(out_path_temp_parse(".f.exr.tmp.aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa.45.6", &t) && strlen(t.host) == 32);
}

/* This host's name in temporary names, and the names the helper makes: parsed back to this host
 * and pid, <n> new every time, the directory kept, the base hidden. */
TEST(temp_name_helper)
{
    char host[OUT_PATH_HOST_MAX + 1], a[300], b[300];
    out_path_host(host);
    CHECK(host[0] && strlen(host) <= OUT_PATH_HOST_MAX);
    for (const char *p = host; *p; p++)
        CHECK((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '-');
    CHECK(out_path_temp_name("some/dir/frame.0001.exr", a, sizeof a));
    CHECK(out_path_temp_name("some/dir/frame.0001.exr", b, sizeof b));
    CHECK(strcmp(a, b) != 0);
    CHECK(!strncmp(a, "some/dir/.frame.0001.exr.tmp.", 29));
    out_temp_name t;
    CHECK(out_path_temp_parse(strrchr(a, '/') + 1, &t) && t.pid == (long)getpid() && !strcmp(t.host, host));
    CHECK(out_path_temp_name("x.csv", a, sizeof a) && !strncmp(a, ".x.csv.tmp.", 11));
    /* The longest: every part at its maximum fits what out_path_temp_overhead counts. */
    char name[300], path[400];
    snprintf(path, sizeof path, "%s.99999.exr", repeat(name, 'n', out_path_name_max()));
    CHECK(out_path_temp_name(path, a, sizeof a));
    CHECK((int)strlen(a) <= out_path_name_max() + out_path_temp_overhead() && strlen(a) <= 255);
    CHECK(!out_path_temp_name(path, a, 40)); /* does not fit: false */
}

static void touch(const char *dir, const char *name)
{
    char p[1400];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "w");
    if (f)
        fclose(f);
}

static bool exists(const char *dir, const char *name)
{
    char p[1400];
    struct stat sb;
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return lstat(p, &sb) == 0;
}

/* A pid that no longer exists: a child that has exited and been reaped. */
static long dead_pid(void)
{
    pid_t pid = fork();
    if (pid == 0)
        _exit(0);
    int status;
    waitpid(pid, &status, 0);
    return (long)pid;
}

TEST(stale_temps_and_old_frames_removed)
{
    char dir[1100], cmd[2300], name[1300];
    snprintf(dir, sizeof dir, "%s/out_path_tidy", test_out_dir());
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", dir, dir);
    CHECK(system(cmd) == 0);
    long dead = dead_pid(), live = (long)getppid();
    snprintf(name, sizeof name, ".frame.0003.exr.tmp.%ld.0", dead);
    touch(dir, name);
    snprintf(name, sizeof name, ".metrics.csv.tmp.%ld", dead);
    touch(dir, name);
    snprintf(name, sizeof name, ".frame.0004.exr.tmp.%ld.3", live); /* another run, still going */
    touch(dir, name);
    snprintf(name, sizeof name, ".frame.0005.exr.tmp.%ld.1", (long)getpid()); /* our own */
    touch(dir, name);
    snprintf(name, sizeof name, "%s/.dir.tmp.%ld", dir, dead); /* not a regular file */
    CHECK(mkdir(name, 0755) == 0);
    touch(dir, "frame.0000.exr");
    touch(dir, "frame.0011.exr");
    touch(dir, "frame.100000.exr");
    touch(dir, "frame.001.exr");      /* 3 digits: not fovsim's */
    touch(dir, "frame.0001.exr.bak"); /* not a frame */
    touch(dir, "frames.0001.exr");    /* another name */
    touch(dir, "frame.0001.0002.exr");
    touch(dir, "notes.txt");

    CHECK(out_dir_remove_stale_temps(dir) == 2);
    snprintf(name, sizeof name, ".metrics.csv.tmp.%ld", dead);
    CHECK(!exists(dir, name));
    snprintf(name, sizeof name, ".frame.0003.exr.tmp.%ld.0", dead);
    CHECK(!exists(dir, name));
    snprintf(name, sizeof name, ".frame.0004.exr.tmp.%ld.3", live);
    CHECK(exists(dir, name));
    snprintf(name, sizeof name, ".frame.0005.exr.tmp.%ld.1", (long)getpid());
    CHECK(exists(dir, name));
    snprintf(name, sizeof name, ".dir.tmp.%ld", dead);
    CHECK(exists(dir, name));

    int removed = -1;
    CHECK(out_dir_remove_sequence(dir, "frame", 0, &removed) == FS_OK && removed == 3);
    CHECK(!exists(dir, "frame.0000.exr") && !exists(dir, "frame.0011.exr") && !exists(dir, "frame.100000.exr"));
    CHECK(exists(dir, "frame.001.exr") && exists(dir, "frame.0001.exr.bak") && exists(dir, "frames.0001.exr") &&
          exists(dir, "frame.0001.0002.exr") && exists(dir, "notes.txt"));
    /* From an index on (--resume with fewer frames), and whether a sequence is there. */
    CHECK(!out_dir_has_sequence(dir, "frame"));
    touch(dir, "frame.0002.exr");
    touch(dir, "frame.0005.exr");
    touch(dir, "frame.0007.exr");
    CHECK(out_dir_has_sequence(dir, "frame") && !out_dir_has_sequence(dir, "other"));
    CHECK(out_dir_remove_sequence(dir, "frame", 5, &removed) == FS_OK && removed == 2);
    CHECK(exists(dir, "frame.0002.exr") && !exists(dir, "frame.0005.exr") && !exists(dir, "frame.0007.exr"));
    CHECK(out_path_frame_index("frame.0042.exr", "frame") == 42 && out_path_frame_index("frame.042.exr", "frame") == -1);
    CHECK(out_path_frame_index("frame.1234567890.exr", "frame") == -1); /* more than 9 digits */
    CHECK(out_dir_remove_stale_temps("/nonexistent/fovsim") == 0);
    CHECK(out_dir_remove_sequence("/nonexistent/fovsim", "frame", 0, &removed) == FS_OK && removed == 0);
}

/* Sets a file's modification time `age` seconds back. */
static bool age_file(const char *dir, const char *name, long age)
{
    char p[1400];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    struct timespec ts[2];
    clock_gettime(CLOCK_REALTIME, &ts[0]);
    ts[0].tv_sec -= age;
    ts[1] = ts[0];
    return utimensat(AT_FDCWD, p, ts, 0) == 0;
}

/* docs/reference.md "A cache on shared storage": a shared cache (NFS, Lustre) is written by runs on many machines. A temporary name
 * carries the host: only this host's temporaries of dead processes are removed at once; another
 * host's pids mean nothing here, so its temporaries are kept (its run may still be writing them)
 * until they are older than OUT_PATH_TEMP_MAX_AGE_S, what a run killed there leaves. */
TEST(stale_temps_of_other_hosts)
{
    char dir[1100], cmd[2300], name[1300], host[OUT_PATH_HOST_MAX + 1];
    snprintf(dir, sizeof dir, "%s/out_path_hosts", test_out_dir());
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", dir, dir);
    CHECK(system(cmd) == 0);
    out_path_host(host);
    /* Another host's name: this one with a character changed (still a valid host). */
    char other[OUT_PATH_HOST_MAX + 1];
    snprintf(other, sizeof other, "%s", host);
    other[0] = other[0] == 'x' ? 'y' : 'x';
    long dead = dead_pid(), live = (long)getppid();
    char here_dead[300], here_live[300], here_self[300], there_dead[300], there_live[300], there_old[300],
        here_live_old[300], old_format_old[300], there_young[300];
    snprintf(here_dead, sizeof here_dead, ".ref-00112233aabbccdd.exr.tmp.%s.%ld.0", host, dead);
    snprintf(here_live, sizeof here_live, ".ref-00112233aabbccdd.exr.tmp.%s.%ld.1", host, live);
    snprintf(here_self, sizeof here_self, ".ref-00112233aabbccdd.exr.tmp.%s.%ld.2", host, (long)getpid());
    snprintf(there_dead, sizeof there_dead, ".ref-00112233aabbccdd.exr.tmp.%s.%ld.3", other, dead);
    snprintf(there_live, sizeof there_live, ".ref-00112233aabbccdd.exr.tmp.%s.%ld.4", other, live);
    snprintf(there_old, sizeof there_old, ".ref-00112233aabbccdd.exr.tmp.%s.%ld.5", other, live);
    snprintf(there_young, sizeof there_young, ".ref-00112233aabbccdd.exr.tmp.%s.%ld.6", other, dead);
    snprintf(here_live_old, sizeof here_live_old, ".ref-00112233aabbccdd.exr.tmp.%s.%ld.7", host, live);
    snprintf(old_format_old, sizeof old_format_old, ".metrics.csv.tmp.%ld", live);
    const char *all[] = {here_dead, here_live, here_self, there_dead, there_live, there_old, there_young,
                         here_live_old, old_format_old};
    for (size_t i = 0; i < sizeof all / sizeof *all; i++)
        touch(dir, all[i]);
    /* Older than the limit: removed whatever the host and pid; just under it: kept. */
    CHECK(age_file(dir, there_old, OUT_PATH_TEMP_MAX_AGE_S + 3600));
    CHECK(age_file(dir, here_live_old, OUT_PATH_TEMP_MAX_AGE_S + 60));
    CHECK(age_file(dir, old_format_old, 3L * OUT_PATH_TEMP_MAX_AGE_S));
    CHECK(age_file(dir, there_young, OUT_PATH_TEMP_MAX_AGE_S - 3600));
    /* A directory with an old temporary name: never removed. */
    snprintf(name, sizeof name, "%s/.d.tmp.%s.%ld.9", dir, other, dead);
    CHECK(mkdir(name, 0755) == 0);
    CHECK(age_file(dir, strrchr(name, '/') + 1, 2L * OUT_PATH_TEMP_MAX_AGE_S));

    CHECK(out_dir_remove_stale_temps(dir) == 4);
    CHECK(!exists(dir, here_dead));      /* this host, process gone */
    CHECK(exists(dir, here_live));       /* this host, process alive */
    CHECK(exists(dir, here_self));       /* our own */
    CHECK(exists(dir, there_dead));      /* another host: its pid means nothing here */
    CHECK(exists(dir, there_live));
    CHECK(exists(dir, there_young));     /* another host, 23 h old */
    CHECK(!exists(dir, there_old));      /* another host, 25 h old */
    CHECK(!exists(dir, here_live_old));  /* old: the pid has been reused */
    CHECK(!exists(dir, old_format_old)); /* the old format, old */
    CHECK(exists(dir, strrchr(name, '/') + 1));
    CHECK(out_dir_remove_stale_temps(dir) == 0);
}

int main(void)
{
    RUN(name_limit);
    RUN(dir_limits);
    RUN(cli_refuses_before_running);
    RUN(longest_name_writes);
    RUN(temp_pid_parsing);
    RUN(temp_name_helper);
    RUN(stale_temps_and_old_frames_removed);
    RUN(stale_temps_of_other_hosts);
    return test_summary();
}
