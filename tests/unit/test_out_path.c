/* test_out_path.c: output path lengths are checked with the arguments (src/output/out_path.c,
 * issue 17 defect 8), and the longest --name accepted really fits a file name. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
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

int main(void)
{
    RUN(name_limit);
    RUN(dir_limits);
    RUN(cli_refuses_before_running);
    RUN(longest_name_writes);
    return test_summary();
}
