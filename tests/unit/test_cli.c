/* Command-line parsing: defaults, every option, and the errors a user will make. */
#include <string.h>

#include "cli.h"
#include "core/log.h"
#include "test.h"

static fs_status parse(run_desc *d, const char *line)
{
    char buf[512], *argv[32];
    int argc = 0;
    snprintf(buf, sizeof buf, "%s", line);
    for (char *t = strtok(buf, " "); t && argc < 31; t = strtok(NULL, " "))
        argv[argc++] = t;
    argv[argc] = NULL;
    return cli_parse(argc, argv, d);
}

TEST(defaults)
{
    run_desc d;
    CHECK(parse(&d, "fovsim render") == FS_OK);
    CHECK(d.cmd == CMD_RENDER);
    CHECK(strcmp(d.builtin, "forest") == 0);
    CHECK(d.scene_path == NULL);
    CHECK(d.frames == 0 && d.fps == 24.0f && d.gpu == -1 && d.alpha == ALPHA_MODE_DEFAULT);
    CHECK(strcmp(d.name, "frame") == 0);
    CHECK(parse(&d, "fovsim") == FS_OK && d.cmd == CMD_HELP);
    CHECK(parse(&d, "fovsim --version") == FS_OK && d.cmd == CMD_VERSION);
    CHECK(parse(&d, "fovsim render --help") == FS_OK && d.cmd == CMD_HELP && d.help_for == CMD_RENDER);
    CHECK(parse(&d, "fovsim demo") == FS_OK && d.cmd == CMD_DEMO);
}

TEST(options)
{
    run_desc d;
    CHECK(parse(&d, "fovsim render --scene a.json --frames 12 --fps=30 --out o --width 320 --height 180 "
                    "--alpha traditional --gpu 1 --quiet --compression none --name f") == FS_OK);
    CHECK(strcmp(d.scene_path, "a.json") == 0 && d.builtin == NULL);
    CHECK(d.frames == 12 && d.fps == 30.0f && strcmp(d.out_dir, "o") == 0);
    CHECK(d.width == 320 && d.height == 180 && d.alpha == ALPHA_MODE_TRADITIONAL && d.gpu == 1);
    CHECK(d.quiet && d.compression == EXR_COMPRESS_NONE && strcmp(d.name, "f") == 0);
    CHECK(parse(&d, "fovsim bench --builtin fence --warmup 2 --markdown x.md") == FS_OK);
    CHECK(d.warmup == 2 && strcmp(d.markdown, "x.md") == 0 && strcmp(d.builtin, "fence") == 0);
    /* A positional scene: a path, or a built-in name. */
    CHECK(parse(&d, "fovsim plan scenes/x.json") == FS_OK && strcmp(d.scene_path, "scenes/x.json") == 0 && !d.builtin);
    CHECK(parse(&d, "fovsim plan plant.glb --alpha traditional") == FS_OK && strcmp(d.scene_path, "plant.glb") == 0);
    CHECK(parse(&d, "fovsim render fence --frames 2") == FS_OK && strcmp(d.builtin, "fence") == 0 && !d.scene_path);
}

TEST(bad_arguments)
{
    static const char *const bad[] = {
        "fovsim rendr",                         /* unknown command */
        "fovsim render --frame 3",              /* unknown option */
        "fovsim render --frames",               /* missing value */
        "fovsim render --frames 0",             /* out of range */
        "fovsim render --frames 3x",            /* not a number */
        "fovsim render --fps -1",
        "fovsim render --fps nan",
        "fovsim render --width 320",            /* width without height */
        "fovsim render --width 8 --height 8",   /* too small */
        "fovsim render --alpha hashd",
        "fovsim render --scene a --builtin b",
        "fovsim render --compression lz4",
        "fovsim render --name a/b",
        "fovsim render a.json b.json",          /* two scenes */
        "fovsim render a.json --builtin fence", /* a scene twice */
        "fovsim demo forest",                   /* demo takes no scene */
        "fovsim demo --builtin fence",
        "fovsim render --quiet=1",
        "fovsim render --quiet --verbose",
        "fovsim render --gpu -2",
    };
    log_set_quiet_errors(true);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        run_desc d;
        fs_status s = parse(&d, bad[i]);
        if (s != FS_ERR_USAGE)
            fprintf(stderr, "accepted: %s\n", bad[i]);
        CHECK(s == FS_ERR_USAGE);
    }
    log_set_quiet_errors(false);
    CHECK(fs_status_exit_code(FS_ERR_USAGE) == 2);
    CHECK(fs_status_exit_code(FS_OK) == 0);
}

TEST(exit_codes_are_distinct)
{
    for (int a = 0; a < FS_STATUS_COUNT; a++)
        for (int b = a + 1; b < FS_STATUS_COUNT; b++)
            CHECK(fs_status_exit_code((fs_status)a) != fs_status_exit_code((fs_status)b));
}

int main(void)
{
    RUN(defaults);
    RUN(options);
    RUN(bad_arguments);
    RUN(exit_codes_are_distinct);
    return test_summary();
}
