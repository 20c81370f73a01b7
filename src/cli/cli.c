/* cli.c: argv -> run_desc through the option table (cli_options.c): the command, the options and
 * the positional scene, then the checks across options. */
#include "cli/cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli_internal.h"
#include "core/config.h"
#include "core/log.h"
#include "core/progress.h"
#include "output/out_path.h"

/* >>values */

/* One of the names: "OPT: expected a, b or c, got 'V'" otherwise. */
static bool parse_choice(const char *opt, const char *v, const cli_choice *c, int *out)
{
    int n = 0;
    for (; c[n].name; n++)
        if (!strcmp(v, c[n].name)) {
            *out = c[n].value;
            return true;
        }
    char names[256] = "";
    for (int i = 0; i < n; i++)
        snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i == 0 ? "" : i == n - 1 ? " or " : ", ",
                 c[i].name);
    log_error("%s: expected %s, got '%s'", opt, names, v);
    return false;
}

/* Stores an int or bool into the field of the given size. */
static void store_int(run_desc *d, const cli_option *o, int v)
{
    char *p = (char *)d + o->field;
    if (o->size == sizeof(bool))
        *(bool *)p = v != 0;
    else
        *(int *)p = v;
}

static bool set_value(run_desc *d, const cli_option *o, const char *v)
{
    char *p = (char *)d + o->field;
    int k = 0;
    switch (o->arg) {
    case ARG_FLAG: *(bool *)p = true; return true;
    case ARG_STRING: *(const char **)p = v; return true;
    case ARG_INT: return cli_parse_int(o->name, v, (int)o->lo, (int)o->hi, (int *)p);
    case ARG_FLOAT:
        return cli_parse_float_in(o->name, v, (float)o->lo, (o->flags & OPT_LO_CLOSED) != 0, (float)o->hi, (float *)p,
                                  NULL);
    case ARG_CHOICE:
        if (!parse_choice(o->name, v, o->choices, &k))
            return false;
        store_int(d, o, k);
        return true;
    case ARG_CUSTOM: return o->set(o, d, v);
    }
    return false;
}

/* >>commands */

static const struct {
    const char *name;
    command cmd;
    const char *summary;
} k_commands[] = {
    {"render", CMD_RENDER, "render a scene to an EXR sequence"},
    {"plan", CMD_PLAN, "print the passes and shader variants a scene needs"},
    {"demo", CMD_DEMO, "render the built-in forest to ./out/demo/ (no arguments needed)"},
    {"bench", CMD_BENCH, "time a scene: median and spread of frame and pass times"},
    {"reference", CMD_REFERENCE, "render the ground truth (supersampled, exact alpha compositing; cached)"},
    {"compare", CMD_COMPARE, "render alpha modes side by side against the reference, with metrics"},
    {"view", CMD_VIEW, "interactive window: the mouse is the gaze (GLFW, OpenGL 4.5)"},
    {"sweep", CMD_SWEEP, "run scenes x gaze traces x configurations: here, as a jobs file or on Slurm"},
    {"merge", CMD_MERGE, "gather a sweep's metrics into one CSV, summary and plot"},
    {"check", CMD_CHECK, "regression test: record a compare run as a baseline, or check one against it"},
};
#define COMMAND_COUNT (sizeof k_commands / sizeof k_commands[0])

/* sweep, merge and check parse their own options (commands.h). */
static bool has_own_options(command c)
{
    return c == CMD_SWEEP || c == CMD_MERGE || c == CMD_CHECK;
}

const char *cli_command_name(command cmd)
{
    for (size_t k = 0; k < COMMAND_COUNT; k++)
        if (k_commands[k].cmd == cmd)
            return k_commands[k].name;
    return "";
}

void cli_print_commands(void)
{
    for (size_t i = 0; i < COMMAND_COUNT; i++)
        printf("  %-10s %s\n", k_commands[i].name, k_commands[i].summary);
}

/* >>options */

void cli_begin(run_desc *d, command cmd)
{
    memset(d, 0, sizeof *d);
    d->cmd = cmd;
    d->gpu = -1;
    d->hash_kind = HASH_CHOICE_DEFAULT;
    d->taa.mode = TAA_SWITCH_SCENE;
    d->fps = 24.0f;
    d->bench.warmup = 5;
    d->progress_interval = (float)PROGRESS_INTERVAL_DEFAULT;
}

static fs_status apply(run_desc *d, const cli_option *o, const char *value)
{
    if (o->arg == ARG_FLAG && value) {
        log_error("%s takes no value", o->name);
        return FS_ERR_USAGE;
    }
    if (o->given)
        *(bool *)((char *)d + o->given) = true;
    return set_value(d, o, value) ? FS_OK : FS_ERR_USAGE;
}

static fs_status unknown_option(const run_desc *d, const char *name)
{
    const char *c = cli_command_name(d->cmd);
    log_error("fovsim %s: unknown option '%s' (see fovsim %s --help)", c, name, c);
    return FS_ERR_USAGE;
}

fs_status cli_apply_option(run_desc *d, const char *name, const char *value)
{
    if (d->cmd == CMD_HELP)
        return FS_OK;
    const cli_option *o = cli_option_find(name);
    if (!o)
        return unknown_option(d, name);
    if (o->arg != ARG_FLAG && !value) {
        log_error("%s: expected a value", name);
        return FS_ERR_USAGE;
    }
    return apply(d, o, value);
}

/* One positional argument: the scene (`fovsim plan scenes/x.json`, `fovsim render fence`). */
static fs_status positional(run_desc *d, const char *a)
{
    const char *c = cli_command_name(d->cmd);
    if (d->cmd == CMD_DEMO || d->scene_path || d->builtin || a[0] == '-') {
        log_error("fovsim %s: unexpected argument '%s' (see fovsim %s --help)", c, a, c);
        return FS_ERR_USAGE;
    }
    /* A built-in's name is the built-in even where a file or folder of that name is in the
     * current folder (as in sweep manifests; ./fence is the file): a folder `fence` hid it.
     * Another word without '/' or '.' that names no file is taken for a built-in name, so
     * that scene_load_builtin lists the known ones. */
    if (!strncmp(a, "builtin:", 8))
        d->builtin = a + 8; /* as fovsim prints a built-in scene's path */
    else if (!strchr(a, '/') && !strchr(a, '.') && (scene_is_builtin(a) || access(a, F_OK) != 0))
        d->builtin = a;
    else
        d->scene_path = a;
    return FS_OK;
}

fs_status cli_parse_args(run_desc *d, int argc, char *const *args)
{
    for (int i = 0; i < argc && d->cmd != CMD_HELP; i++) {
        const char *a = args[i], *eq = strchr(a, '=');
        if (strncmp(a, "--", 2) != 0) {
            fs_status st = positional(d, a);
            if (st != FS_OK)
                return st;
            continue;
        }
        char opt[64];
        size_t len = eq ? (size_t)(eq - a) : strlen(a);
        if (len >= sizeof opt) /* longer than any option: named whole in the message */
            return unknown_option(d, a);
        snprintf(opt, sizeof opt, "%.*s", (int)len, a);
        if (!strcmp(opt, "--help")) {
            d->help_for = d->cmd;
            d->cmd = CMD_HELP;
            return FS_OK;
        }
        const cli_option *o = cli_option_find(opt);
        if (!o)
            return unknown_option(d, opt);
        const char *val = eq ? eq + 1 : NULL;
        if (o->arg != ARG_FLAG && !val) {
            if (i + 1 >= argc) {
                log_error("%s: expected a value", opt);
                return FS_ERR_USAGE;
            }
            val = args[++i];
        }
        fs_status st = apply(d, o, val);
        if (st != FS_OK)
            return st;
    }
    return FS_OK;
}

/* >>checks across options */

/* Whether an option was given: its field differs from the default, or its `given` flag is set
 * (`--format text` and `--first-frame 0` are the defaults, and accepted anywhere). */
static bool used(const run_desc *d, const run_desc *def, const cli_option *o)
{
    return (o->given && *(const bool *)((const char *)d + o->given)) ||
           memcmp((const char *)d + o->field, (const char *)def + o->field, o->size) != 0;
}

/* Every option given where it does not apply: its table row's line. */
static fs_status check_applies(const run_desc *d)
{
    run_desc def;
    cli_begin(&def, d->cmd);
    unsigned ctx = cli_context(d->cmd, d);
    for (size_t i = 0; i < k_cli_option_count; i++) {
        const cli_option *o = &k_cli_options[i];
        if ((o->flags & OPT_HELP_ONLY) || !o->misuse || !used(d, &def, o))
            continue;
        unsigned cmds = 0; /* over its rows: a second help row widens where it applies */
        for (size_t k = 0; k < k_cli_option_count; k++)
            if (!strcmp(k_cli_options[k].name, o->name))
                cmds |= k_cli_options[k].cmds;
        if (!(cmds & ctx)) {
            log_error("%s", o->misuse);
            return FS_ERR_USAGE;
        }
    }
    return FS_OK;
}

#define REFUSE(...)                                                                                                    \
    do {                                                                                                               \
        log_error(__VA_ARGS__);                                                                                        \
        return FS_ERR_USAGE;                                                                                           \
    } while (0)

fs_status cli_finish(run_desc *d)
{
    if (d->cmd == CMD_HELP)
        return FS_OK;
    const char *c = cli_command_name(d->cmd);
    if (d->scene_path && d->builtin)
        REFUSE("--scene and --builtin: give one of them, not both");
    if (d->cmd == CMD_DEMO && (d->scene_path || d->builtin))
        REFUSE("fovsim demo always renders the built-in forest; use fovsim render --scene/--builtin for others");
    if ((d->width > 0) != (d->height > 0))
        REFUSE("--width and --height: give both or neither");
    if (d->no_fade && d->fade_n > 0.0f)
        REFUSE("--no-fade and --fade-n: give one of them, not both");
    if (check_applies(d) != FS_OK)
        return FS_ERR_USAGE;
    d->compare.export_fvvdp |= d->compare.run_fvvdp; /* running it needs its inputs */
    if (d->ref.cache_dir && d->ref.no_cache)
        REFUSE("--cache and --no-cache: give one of them, not both");
    if (d->alpha != ALPHA_MODE_DEFAULT && (d->cmd == CMD_REFERENCE || d->cmd == CMD_COMPARE))
        REFUSE("fovsim %s: --alpha does not apply (%s)", c,
               d->cmd == CMD_REFERENCE ? "the reference tests alpha stochastically" : "give the modes with --modes");
    if ((d->gaze_format != GAZE_FORMAT_AUTO || d->eye != GAZE_EYE_AUTO) && !d->gaze_path)
        REFUSE("--gaze-format and --eye describe a --gaze trace; give --gaze FILE");
    if (d->head_place_set && (!d->head_path ? !d->gaze_path : !strcmp(d->head_path, "off")))
        REFUSE("--head-place places a head recording: give --head FILE (or a --gaze recording with head poses)");
    if (d->gaze_latency_count > 1 && d->cmd != CMD_COMPARE && d->cmd != CMD_DEMO)
        REFUSE("--gaze-latency: a list of latencies is a latency study, which fovsim compare and demo run; fovsim %s "
               "takes one latency", c);
    if (d->view.split[0] && d->alpha)
        REFUSE("--split and --alpha: give one of them, not both (--split A,B sets the left-hand mode)");
    if (d->compare.first_frame && d->frames && d->compare.first_frame >= d->frames)
        REFUSE("--first-frame %d: expected less than --frames %d", d->compare.first_frame, d->frames);
    if (d->resume && d->replace)
        REFUSE("--resume and --replace: give one of them, not both (--resume keeps the folder's frames, --replace "
               "removes them)");
    if (d->bench.calibrate && d->bench.accuracy)
        REFUSE("--calibrate and --accuracy: give one of them, not both (--accuracy --cost-model FILE uses a model)");
    if (d->cmd == CMD_BENCH && d->bench.cost_model && !d->bench.calibrate && !d->bench.accuracy)
        REFUSE("--cost-model: fovsim bench --calibrate writes the model, bench --accuracy, compare and demo predict "
               "with it; plain bench does neither");
    if (d->bench.cost == ACC_COST_MODEL && !d->bench.cost_model)
        REFUSE("--cost model: give the model with --cost-model FILE");
    if (d->foveation_count > 1 && d->cmd != CMD_COMPARE)
        REFUSE("--foveation: a list of foveations is a foveation study, which fovsim compare runs; fovsim %s takes one",
               c);
    if (d->foveation_count > 1 && d->gaze_latency_count > 1)
        REFUSE("--foveation and --gaze-latency: a study of one of them at a time (give one foveation or one latency)");
    if (d->foveation == FOVEATION_OFF && d->foveation_count == 1 && d->rings && d->rings_layout.kind != FOV_LAYOUT_OFF)
        REFUSE("--foveation off and --rings %s: give one of them (--foveation off is --rings off)", d->rings);
    bool listed_vrs = d->foveation == FOVEATION_VRS;
    for (int i = 0; i < d->foveation_count; i++)
        listed_vrs |= d->foveations[i] == FOVEATION_VRS;
    if ((d->vrs || d->vrs_tile) && d->foveation != FOVEATION_UNSET && !listed_vrs)
        REFUSE("--vrs and --vrs-tile shape VRS foveation: not with --foveation %s", foveation_kind_name(d->foveation));
    if (d->foveation == FOVEATION_VRS && !RUN_TAKES_VRS(d))
        REFUSE("fovsim %s --foveation vrs: %s", c, VRS_NOT_BUILT);
    if (d->quiet && d->verbose)
        REFUSE("--quiet and --verbose: give one of them, not both");
    if (!d->builtin && !d->scene_path)
        d->builtin = "forest";
    if (!d->name)
        d->name = d->cmd == CMD_REFERENCE ? "reference" : d->cmd == CMD_COMPARE || d->cmd == CMD_DEMO ? "compare" : "frame";
    /* Output paths that cannot be written fail here, not after the frames are drawn. */
    char why[512];
    if (!out_path_check(d->out_dir, d->name, d->ref.cache_dir, why, sizeof why))
        REFUSE("%s", why);
    return FS_OK;
}

fs_status cli_parse(int argc, char **argv, run_desc *d)
{
    cli_begin(d, CMD_NONE);
    if (argc < 2) {
        d->cmd = CMD_HELP;
        return FS_OK;
    }
    const char *c = argv[1];
    if (!strcmp(c, "--help") || !strcmp(c, "-h") || !strcmp(c, "help")) {
        d->cmd = CMD_HELP;
        if (argc > 2)
            for (size_t k = 0; k < COMMAND_COUNT; k++)
                if (!strcmp(argv[2], k_commands[k].name) && !has_own_options(k_commands[k].cmd))
                    d->help_for = k_commands[k].cmd;
        return FS_OK;
    }
    if (!strcmp(c, "--version")) {
        d->cmd = CMD_VERSION;
        return FS_OK;
    }
    if (!strcmp(c, "--list-gpus")) {
        d->cmd = CMD_LIST_GPUS;
        return FS_OK;
    }
    for (size_t k = 0; k < COMMAND_COUNT; k++)
        if (!strcmp(c, k_commands[k].name))
            d->cmd = k_commands[k].cmd;
    if (d->cmd == CMD_NONE) {
        char names[256] = "";
        for (size_t k = 0; k < COMMAND_COUNT; k++)
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", k ? ", " : "", k_commands[k].name);
        log_error("unknown command '%s' (commands: %s; see fovsim --help)", c, names);
        return FS_ERR_USAGE;
    }
    if (has_own_options(d->cmd)) {
        d->own.argc = argc;
        d->own.argv = argv;
        return FS_OK;
    }
    fs_status st = cli_parse_args(d, argc - 2, argv + 2);
    return st == FS_OK ? cli_finish(d) : st;
}
