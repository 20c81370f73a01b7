/* test_out_path.c: output path lengths are checked with the arguments (src/output/out_path.c,
 * issue 17 defect 8), and the longest --name accepted really fits a file name. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <dirent.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"
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
    /* The temporary name adds 34 characters: . name .99999.exr .tmp. 4194304 . 4294967295 */
    CHECK(out_path_temp_overhead() == 34);
    CHECK(out_path_name_max() == 221);
    CHECK(out_path_check("out", repeat(name, 'a', 221), NULL, why, sizeof why));
    CHECK(!out_path_check("out", repeat(name, 'a', 222), NULL, why, sizeof why));
    CHECK(strstr(why, "--name") && strstr(why, "(222 characters)") && strstr(why, "at most 221"));
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
    CHECK(!out_path_check(dir, repeat(name, 'n', 200), NULL, why, sizeof why));
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
    repeat(name, 'x', 221);
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

int main(void)
{
    RUN(name_limit);
    RUN(dir_limits);
    RUN(cli_refuses_before_running);
    RUN(longest_name_writes);
    RUN(temp_pid_parsing);
    RUN(stale_temps_and_old_frames_removed);
    return test_summary();
}
