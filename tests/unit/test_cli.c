/* Command-line parsing: defaults, every option, and the errors a user will make. */
#include <string.h>

#include <stdlib.h>

#include "cli/cli.h"
#include "cli/cli_internal.h"
#include "core/log.h"
#include "session/run_record.h"
#include "session/session.h"
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
    CHECK(parse(&d, "fovsim render fence --wait-lock 30 --replace --fps 0.001") == FS_OK);
    CHECK(d.wait_lock == 30 && d.replace && d.fps == 0.001f);
    CHECK(parse(&d, "fovsim bench --builtin fence --warmup 2 --markdown x.md") == FS_OK);
    CHECK(d.bench.warmup == 2 && strcmp(d.bench.markdown, "x.md") == 0 && strcmp(d.builtin, "fence") == 0);
    /* A positional scene: a path, or a built-in name. */
    CHECK(parse(&d, "fovsim plan scenes/x.json") == FS_OK && strcmp(d.scene_path, "scenes/x.json") == 0 && !d.builtin);
    CHECK(parse(&d, "fovsim plan plant.glb --alpha traditional") == FS_OK && strcmp(d.scene_path, "plant.glb") == 0);
    CHECK(parse(&d, "fovsim render fence --frames 2") == FS_OK && strcmp(d.builtin, "fence") == 0 && !d.scene_path);
    /* the eye tracker: each option says it was given (0 included), so it wins over the scene's */
    CHECK(parse(&d, "fovsim compare --gaze-latency 0 --gaze-rate 90 --gaze-noise 0.5 --gaze-seed 9 --gaze-loss full") ==
          FS_OK);
    CHECK(d.tracker.latency_set && d.tracker.desc.latency_ms == 0.0f && d.tracker.rate_set &&
          d.tracker.desc.rate_hz == 90.0f && d.tracker.desc.noise_deg == 0.5f && d.tracker.desc.seed == 9 &&
          d.tracker.desc.loss == GAZE_LOSS_FULL && d.tracker.loss_set);
    CHECK(parse(&d, "fovsim render") == FS_OK && !d.tracker.latency_set && gaze_tracker_is_ideal(&d.tracker.desc));
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
        /* in range as a double, 0 or denormal as the float they are used as (README "Limits", numbers) */
        "fovsim render --fps 1e-300",
        "fovsim render --fps 0.0001",           /* below FPS_MIN */
        "fovsim render --taa-blend 1e-300",
        "fovsim render --hash-scale 1e-40",
        "fovsim render --taa-sparse 1e-300",
        "fovsim render --wait-lock 0",          /* at least a second (without it: no wait) */
        "fovsim render --wait-lock 86401",      /* at most a day: never unbounded */
        "fovsim plan --wait-lock 5",            /* only for commands that write a run folder */
        "fovsim render --gaze-latency -1",
        "fovsim render --gaze-latency 10001",
        "fovsim render --gaze-rate -90",
        "fovsim render --gaze-noise 31",
        "fovsim render --gaze-seed -1",
        "fovsim render --gaze-loss blink",
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

TEST(view_cli)
{
    run_desc d;
    CHECK(parse(&d, "fovsim view") == FS_OK && d.cmd == CMD_VIEW && !strcmp(d.builtin, "forest"));
    CHECK(d.view.script == NULL && d.view.record == NULL && d.view.split[0] == ALPHA_MODE_DEFAULT);
    CHECK(parse(&d, "fovsim view fence --script s.txt --record out/r.csv --split traditional,hashed --taa off "
                        "--rings off --width 160 --height 90 --gaze builtin:pursuit") == FS_OK);
    CHECK(!strcmp(d.builtin, "fence") && !strcmp(d.view.script, "s.txt") && !strcmp(d.view.record, "out/r.csv"));
    CHECK(d.view.split[0] == ALPHA_MODE_TRADITIONAL && d.view.split[1] == ALPHA_MODE_HASHED && d.taa.mode == 0);
    CHECK(parse(&d, "fovsim view --help") == FS_OK && d.cmd == CMD_HELP && d.help_for == CMD_VIEW);
    CHECK(parse(&d, "fovsim help view") == FS_OK && d.help_for == CMD_VIEW);
    log_set_quiet_errors(true);
    CHECK(parse(&d, "fovsim view --split hashed") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim view --split hashed,hashed") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim view --split hashed,nope") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim view --split hashed,a2c --alpha castano") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim view --frames 3") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim view --out o") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim view --name n") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim view --gpu 0") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim render --script s.txt") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim render --record r.csv") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim bench --split a2c,hashed") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim view --script") == FS_ERR_USAGE);
    log_set_quiet_errors(false);
}

TEST(reference_and_compare_options)
{
    run_desc d;
    log_set_quiet_errors(true);
    CHECK(parse(&d, "fovsim compare fence --modes traditional,castano --samples 8 --supersample 2 --cache /tmp/c") == FS_OK);
    CHECK(d.cmd == CMD_COMPARE && d.bench_mode_count == 2 && d.ref.samples == 8 && d.ref.supersample == 2);
    CHECK(!strcmp(d.ref.cache_dir, "/tmp/c") && !strcmp(d.name, "compare"));
    CHECK(parse(&d, "fovsim reference forest --no-cache") == FS_OK && d.ref.no_cache && !strcmp(d.name, "reference"));
    CHECK(parse(&d, "fovsim bench forest --accuracy --samples 4") == FS_OK && d.bench.accuracy && d.ref.samples == 4);
    CHECK(parse(&d, "fovsim reference --samples 3") == FS_ERR_USAGE);      /* odd: no two halves */
    CHECK(parse(&d, "fovsim reference --samples 0") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim reference --supersample 17") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim compare --cache x --no-cache") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim render --samples 8") == FS_ERR_USAGE);         /* no reference in render */
    CHECK(parse(&d, "fovsim bench --samples 8") == FS_ERR_USAGE);          /* only with --accuracy */
    CHECK(parse(&d, "fovsim render --accuracy") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim compare --alpha hashed") == FS_ERR_USAGE);     /* compare takes --modes */
    CHECK(parse(&d, "fovsim reference --alpha hashed") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim render --modes all") == FS_ERR_USAGE);
    log_set_quiet_errors(false);
}


/* A value of option o that differs from its default in `def`, as text for cli_apply_option. */
static const char *other_value(const cli_option *o, const run_desc *def, char *buf, size_t n)
{
    static const struct {
        const char *name, *value;
    } k_custom[] = {{"--builtin", "fence"}, {"--name", "n"}, {"--asset-root", "dir"}, {"--alpha", "hashed"},
                    {"--alpha-lod-max", "2"}, {"--taa-sparse", "0.5"}, {"--rings", "off"}, {"--samples", "8"},
                    {"--gaze-format", "csv"}, {"--gaze-latency", "50"}, {"--split", "traditional,hashed"},
                    {"--modes", "hashed"}, {"--gaze-screen", "520x290@600"}, {"--vrs", "10:1x1,*:4x4"},
                    {"--foveation", "vrs"}, {"--display", "hmd:eyenavgs"},
                    {"--head-place", "1,2,3"}};
    const char *field = (const char *)def + o->field;
    switch (o->arg) {
    case ARG_FLAG: return NULL;
    case ARG_STRING: return "x";
    case ARG_INT: snprintf(buf, n, "%d", (int)o->hi); return buf;
    case ARG_FLOAT: snprintf(buf, n, "%g", o->hi); return buf;
    case ARG_CHOICE:
        for (const cli_choice *c = o->choices; c->name; c++)
            if (c->value != (o->size == sizeof(bool) ? (int)*(const bool *)field : *(const int *)field))
                return c->name;
        return "?";
    case ARG_CUSTOM:
        for (size_t k = 0; k < sizeof k_custom / sizeof k_custom[0]; k++)
            if (!strcmp(o->name, k_custom[k].name))
                return k_custom[k].value;
        return "?";
    }
    return "?";
}

/* The option table's OPT_RECORDED flag is what the run record holds: every recorded option
 * changes the record's configuration, every other option leaves it as it is. */
TEST(recorded_options_are_the_run_records)
{
    session s;
    memset(&s, 0, sizeof s);
    CHECK(scene_load_builtin("fence", &s.sc) == FS_OK);
    gaze_sample one = {.x = 0.5f, .y = 0.5f, .valid = true};
    s.gaze.samples = &one;
    s.gaze.count = 1;
    snprintf(s.gaze.path, sizeof s.gaze.path, "g.csv");
    s.pl.width = 64;
    s.pl.height = 64;
    run_desc base;
    cli_begin(&base, CMD_COMPARE);
    base.name = "compare";
    base.compare.first_frame = 1; /* --warmup is recorded with it */
    char *ref = NULL;
    CHECK(run_record_describe(&base, &s, &ref) == FS_OK);
    for (size_t i = 0; ref && i < k_cli_option_count; i++) {
        const cli_option *o = &k_cli_options[i];
        /* Help-only rows set nothing; --width and --height reach the record as the plan's size. */
        if ((o->flags & OPT_HELP_ONLY) || !strcmp(o->name, "--width") || !strcmp(o->name, "--height"))
            continue;
        run_desc d = base;
        char buf[32], *text = NULL;
        CHECK(cli_apply_option(&d, o->name, other_value(o, &base, buf, sizeof buf)) == FS_OK);
        CHECK(run_record_describe(&d, &s, &text) == FS_OK);
        bool changed = text && strcmp(text, ref) != 0, recorded = (o->flags & OPT_RECORDED) != 0;
        if (changed != recorded)
            fprintf(stderr, "%s: %s in cli_options.c, but %s the run record\n", o->name,
                    recorded ? "OPT_RECORDED" : "not OPT_RECORDED", changed ? "changes" : "does not change");
        CHECK(changed == recorded);
        free(text);
    }
    free(ref);
    scene_free(&s.sc);
}

/* A run built from parts, as fovsim check and sweep build compare's: the same table and checks. */
/* --gaze-latency: one latency anywhere, a list (a latency study) for compare and demo only. */
TEST(gaze_latency_lists)
{
    run_desc d;
    CHECK(parse(&d, "fovsim compare --gaze-latency 0,20,50.5 --out /tmp/fovsim-lat") == FS_OK);
    CHECK(d.gaze_latency_count == 3 && d.gaze_latencies[2] == 50.5f && d.tracker.latency_set &&
          d.tracker.desc.latency_ms == 0.0f);
    CHECK(parse(&d, "fovsim render --gaze-latency 80 --out /tmp/fovsim-lat") == FS_OK);
    CHECK(d.gaze_latency_count == 1 && d.tracker.desc.latency_ms == 80.0f);
    log_set_quiet_errors(true);
    CHECK(parse(&d, "fovsim render --gaze-latency 0,80 --out /tmp/fovsim-lat") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim bench --gaze-latency 0,80") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim compare --gaze-latency 20,20") == FS_ERR_USAGE);   /* twice */
    CHECK(parse(&d, "fovsim compare --gaze-latency 20,,50") == FS_ERR_USAGE);  /* empty item */
    CHECK(parse(&d, "fovsim compare --gaze-latency 20,") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim compare --gaze-latency 0,-5") == FS_ERR_USAGE);    /* out of range */
    CHECK(parse(&d, "fovsim compare --gaze-latency 0,20001") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim compare --gaze-latency 0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16") == FS_ERR_USAGE);
    CHECK(parse(&d, "fovsim compare --gaze-latency 0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15") == FS_OK);
    log_set_quiet_errors(false);
}

TEST(run_from_parts)
{
    run_desc d;
    char *opts[] = {"fence", "--modes", "traditional,hashed", "--rings=10:1:0,*:1/4:0", "--taa", "off"};
    cli_begin(&d, CMD_COMPARE);
    CHECK(cli_parse_args(&d, 6, opts) == FS_OK);
    CHECK(cli_apply_option(&d, "--out", "/tmp/fovsim-parts") == FS_OK);
    CHECK(cli_apply_option(&d, "--replace", NULL) == FS_OK);
    CHECK(cli_finish(&d) == FS_OK);
    CHECK(d.cmd == CMD_COMPARE && !strcmp(d.builtin, "fence") && d.bench_mode_count == 2 && d.replace);
    CHECK(d.taa.mode == TAA_SWITCH_OFF && !strcmp(d.name, "compare") && !strcmp(d.out_dir, "/tmp/fovsim-parts"));
    CHECK(d.rings_layout.kind == FOV_LAYOUT_EXPLICIT && d.rings_layout.count == 2);
    CHECK(!strcmp(cli_command_name(CMD_COMPARE), "compare"));
    bool takes = false;
    CHECK(cli_machine_option("--gpu", &takes) && takes && !strcmp(cli_machine_option("--cache=x", &takes), "--cache"));
    CHECK(!takes && !cli_machine_option("--rings", NULL) && cli_machine_option("--quiet", NULL));
    log_set_quiet_errors(true);
    cli_begin(&d, CMD_COMPARE);
    CHECK(cli_apply_option(&d, "--replace", "1") == FS_ERR_USAGE);      /* a flag takes no value */
    CHECK(cli_apply_option(&d, "--out", NULL) == FS_ERR_USAGE);         /* expected a value */
    CHECK(cli_apply_option(&d, "--nope", "1") == FS_ERR_USAGE);
    CHECK(cli_apply_option(&d, "--rings", "10:1:0,5:1/2:0,*:1/4:0") == FS_ERR_USAGE); /* checked when given */
    CHECK(cli_apply_option(&d, "--alpha", "hashed") == FS_OK && cli_finish(&d) == FS_ERR_USAGE); /* compare: --modes */
    log_set_quiet_errors(false);
}

int main(void)
{
    RUN(gaze_latency_lists);
    RUN(run_from_parts);
    RUN(recorded_options_are_the_run_records);
    RUN(view_cli);
    RUN(reference_and_compare_options);
    RUN(defaults);
    RUN(options);
    RUN(bad_arguments);
    RUN(exit_codes_are_distinct);
    return test_summary();
}
