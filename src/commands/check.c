/* check.c: `fovsim check` (check.h): options, the baseline's check.json, and running compare
 * in-process into the baseline or the next folder. The comparison itself is in check_judge.c, its
 * report in check_report.c, and the metrics' names and tolerances, which all three read, in
 * check_tol.c; none of those calls back into this file. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "commands/check.h"

#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli/cli.h"
#include "core/file_read.h"
#include "core/log.h"
#include "output/out_path.h"
#include "commands/commands.h"
#include "session/run_record.h"

#define CHECK_FILE "check.json"
#define CHECK_FORMAT 1          /* check.json's "fovsim_check": the layout of this file */
#define CHECK_REPORT_LINES 20   /* failures listed on stdout */
#define CHECK_MAX_FILE (1 << 20)

/* >>help */

static void check_help(void)
{
    printf("usage: fovsim check --record DIR [SCENE] [compare's options] [--tol-METRIC SPEC ...]\n"
           "       fovsim check --baseline DIR [--out NEXT] [--junit FILE] [--tol-METRIC SPEC ...]\n\n"
           "Regression tests of the renderer (docs/check.md). --record runs fovsim compare with the options\n"
           "given into DIR, the baseline: its frames (EXR), metrics.csv, summary.json, fovsim-run.txt and\n"
           "check.json (the command line, the options, the fovsim version and the tolerances).\n"
           "--baseline runs the baseline's own options again into NEXT (default DIR-next; replaced by every\n"
           "check) and compares, per frame, mode and ring, the metrics (coverage ratio, RMSE, alpha RMSE,\n"
           "FLIP, temporal error) and the pixels of every mode and of the reference. It prints what is outside\n"
           "its tolerance, writes NEXT/diff.NNNN.exr for every failing frame and NEXT/check.json (the\n"
           "verdict and every failure), and exits 1 on a regression.\n\n"
           "options:\n"
           "  --record DIR        run compare with the options that follow and keep the result as a baseline\n"
           "                      (a baseline already in DIR is replaced)\n"
           "  --baseline DIR      check against the baseline in DIR; compare's options are refused (the\n"
           "                      baseline holds them: record a new one to change them)\n"
           "  --out NEXT          --baseline: where this run's output goes (default DIR-next)\n"
           "  --junit FILE        --baseline: also write the result as JUnit XML, one testcase per frame and\n"
           "                      image (each mode, the reference) and one for the run\n"
           "  --tol-coverage SPEC     |coverage ratio change| (default 0.05; rings whose reference holds\n"
           "                      under 4 ring texels of coverage are left to the pixel checks)\n"
           "  --tol-rmse SPEC     growth of RMSE against the reference (default 0.01)\n"
           "  --tol-alpha-rmse SPEC   growth of alpha RMSE against the band-limited reference (default 0.01)\n"
           "  --tol-flip SPEC     growth of mean LDR-FLIP (default 0.01)\n"
           "  --tol-temporal SPEC growth of the temporal error (default 0.01)\n"
           "  --tol-pixel SPEC    largest |difference| of the means of 2x2 ring-texel blocks of R, G, B, A or\n"
           "                      coverage, of each mode and the reference (default 0.75)\n"
           "  --tol-pixel-rmse SPEC   RMSE of the pixels (R, G, B, A, coverage) per ring (default 0.05)\n"
           "  --tol-time RATIO    median frame time over the baseline's, per mode (default off: timing is\n"
           "                      not reproducible across machines)\n"
           "                      SPEC: VALUE for every ring, RING=VALUE (rings from 0, innermost first),\n"
           "                      all=VALUE (the whole display), comma-separated; VALUE a number or off.\n"
           "                      Given with --record they are stored in the baseline; with --baseline they\n"
           "                      override it for this run.\n"
           "  --gpu N, --cache DIR, --no-cache, --wait-lock S, --quiet, --progress-interval S, --verbose,\n"
           "  --gl-debug          as for compare, with either;\n"
           "                      not stored in the baseline (--verbose also prints compare's table)\n"
           "  --replace           --record: write into a DIR another configuration wrote (a baseline there\n"
           "                      is replaced without it)\n\n"
           "Paths in the options (a scene or gaze file) are read from the current directory when the check\n"
           "runs: run --record and --baseline from the same folder (the repository root in CI).\n\n"
           "exit status: 0 within tolerance, 1 a regression, 2 bad arguments or a bad DIR/check.json (the\n"
           "             message names the JSON path), 6 a baseline file missing or damaged, and compare's\n"
           "             other statuses (3 bad scene, 5 bad gaze trace, 7 no OpenGL, 130 interrupted, ...)\n");
}

/* >>options */

typedef struct check_opts {
    const char *record, *baseline, *out, *junit;
    const char *pass[CHECK_MAX_ARGS]; /* --record: compare's options, stored in the baseline */
    int npass;
    const char *env[16];              /* --gpu, --cache, ...: given to compare, not stored */
    int nenv;
    bool replace, verbose;
    check_tols tol_cli;               /* the --tol-* given */
    bool tol_set[CHECK_METRIC_COUNT];
} check_opts;

/* "--opt=value" or "--opt value": the value, or NULL (one line printed). */
static const char *value_of(int argc, char **argv, int *i, const char *eq)
{
    if (eq)
        return eq + 1;
    if (*i + 1 >= argc) {
        log_error("%s: expected a value", argv[*i]);
        return NULL;
    }
    return argv[++*i];
}

static fs_status parse_options(int argc, char **argv, check_opts *o, bool *help)
{
    memset(o, 0, sizeof *o);
    check_tols_default(&o->tol_cli);
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i], *eq = strncmp(a, "--", 2) ? NULL : strchr(a, '=');
        char opt[64];
        snprintf(opt, sizeof opt, "%.*s", eq ? (int)(eq - a) : (int)strlen(a), a);
        check_metric m = check_metric_of_option(opt);
        bool takes = false;
        const char **slot = !strcmp(opt, "--record") ? &o->record : !strcmp(opt, "--baseline") ? &o->baseline
                            : !strcmp(opt, "--out") ? &o->out : !strcmp(opt, "--junit") ? &o->junit : NULL;
        if (!strcmp(opt, "--help") || !strcmp(opt, "-h")) {
            *help = true;
            return FS_OK;
        } else if (slot) {
            if (*slot) {
                log_error("fovsim check: %s given twice", opt);
                return FS_ERR_USAGE;
            }
            if (!(*slot = value_of(argc, argv, &i, eq)))
                return FS_ERR_USAGE;
            if (!**slot) {
                log_error("%s: expected a path, got ''", opt);
                return FS_ERR_USAGE;
            }
        } else if (m < CHECK_METRIC_COUNT) {
            const char *v = value_of(argc, argv, &i, eq);
            char err[256];
            if (!v)
                return FS_ERR_USAGE;
            if (m == CHECK_TIME && strchr(v, '=')) {
                log_error("%s: '%s': expected one ratio for every mode (frame times are not per ring)", opt, v);
                return FS_ERR_USAGE;
            }
            if (!check_tol_apply(&o->tol_cli.t[m], v, err, sizeof err)) {
                log_error("%s: %s", opt, err);
                return FS_ERR_USAGE;
            }
            o->tol_set[m] = true;
        } else if (!strcmp(opt, "--replace")) {
            o->replace = true;
        } else if (cli_machine_option(a, &takes)) { /* given to compare, not stored */
            o->verbose |= !strcmp(opt, "--verbose");
            o->env[o->nenv++] = a;
            if (takes && !(o->env[o->nenv++] = value_of(argc, argv, &i, eq)))
                return FS_ERR_USAGE;
        } else if (o->npass < CHECK_MAX_ARGS) {
            o->pass[o->npass++] = a;
        } else {
            log_error("fovsim check: more than %d options for compare", CHECK_MAX_ARGS);
            return FS_ERR_USAGE;
        }
        if (o->nenv > 12) {
            log_error("fovsim check: %s given too often", opt);
            return FS_ERR_USAGE;
        }
    }
    if (!o->record == !o->baseline) {
        log_error("fovsim check: give --record DIR (record a baseline) or --baseline DIR (check against one)%s",
                  o->record ? ", not both" : " (see fovsim check --help)");
        return FS_ERR_USAGE;
    }
    if (o->baseline && o->npass) {
        log_error("fovsim check --baseline: '%s' would change what the baseline recorded: a check runs the "
                  "options in %s/%s; record a new baseline (fovsim check --record DIR ...) to change them",
                  o->pass[0], o->baseline, CHECK_FILE);
        return FS_ERR_USAGE;
    }
    if (o->record && (o->out || o->junit)) {
        log_error("fovsim check --record: %s is an option of --baseline (the baseline goes to DIR)",
                  o->out ? "--out" : "--junit");
        return FS_ERR_USAGE;
    }
    if (o->baseline && o->replace) {
        log_error("fovsim check --baseline: --replace is an option of --record (a check replaces its own NEXT folder)");
        return FS_ERR_USAGE;
    }
    for (int k = 0; k < o->npass; k++) {
        static const char *const own[] = {"--name", "--resume"}; /* (--out and --replace are check's) */
        for (size_t q = 0; q < sizeof own / sizeof own[0]; q++) {
            size_t l = strlen(own[q]);
            if (!strncmp(o->pass[k], own[q], l) && (o->pass[k][l] == '\0' || o->pass[k][l] == '=')) {
                log_error("fovsim check --record: %s does not apply (the baseline is DIR, its frames are "
                          "compare.NNNN.exr and a baseline is always drawn whole)", own[q]);
                return FS_ERR_USAGE;
            }
        }
    }
    return FS_OK;
}

/* >>check.json */

/* The tolerances as an object of SPEC strings, one per metric. */
static cJSON *tols_json(const check_tols *t)
{
    cJSON *o = cJSON_CreateObject();
    for (int m = 0; o && m < CHECK_METRIC_COUNT; m++) {
        char spec[512];
        check_tol_format(&t->t[m], spec, sizeof spec);
        cJSON_AddStringToObject(o, check_metric_name((check_metric)m), spec);
    }
    return o;
}

static fs_status bad_json(const char *path, const char *jpath, const char *what)
{
    log_error("%s: %s: %s", path, jpath, what);
    return FS_ERR_USAGE;
}

/* Reads DIR/check.json. *root owns the strings put into argv. Missing file: FS_ERR_IO with one line
 * (unless `quiet`); a bad file: FS_ERR_USAGE naming the JSON path. */
static fs_status read_check_json(const char *dir, cJSON **root, bool quiet)
{
    char path[PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/%s", dir, CHECK_FILE);
    *root = NULL;
    if (access(path, F_OK) != 0) {
        if (!quiet)
            log_error("%s: cannot open: %s (%s is not a baseline of fovsim check: record one with fovsim check "
                      "--record %s [SCENE] [options])", path, strerror(errno), dir, dir);
        return FS_ERR_IO;
    }
    char *text = NULL;
    size_t size = 0;
    if (quiet)
        log_set_quiet_errors(true);
    fs_status st = file_read_all(path, CHECK_MAX_FILE, "a baseline's check.json", FS_ERR_USAGE, &text, &size);
    if (quiet)
        log_set_quiet_errors(false);
    if (st != FS_OK)
        return st;
    const char *end = NULL;
    *root = cJSON_ParseWithLengthOpts(text, size + 1, &end, true);
    if (!*root) {
        size_t off = end ? (size_t)(end - text) : 0;
        int line = 1, col = 1;
        for (size_t i = 0; i < off && i < size; i++)
            text[i] == '\n' ? (line++, col = 1) : col++;
        if (!quiet)
            log_error("%s:%d:%d: not valid JSON (a damaged baseline: record it again)", path, line, col);
        st = FS_ERR_USAGE;
    }
    free(text);
    return st;
}

/* The role of DIR/check.json ("baseline", "next"), or "" when there is none or it is not ours. */
static void check_role(const char *dir, char *out, size_t n)
{
    cJSON *root;
    out[0] = '\0';
    if (read_check_json(dir, &root, true) == FS_OK) {
        const cJSON *r = cJSON_GetObjectItemCaseSensitive(root, "role");
        if (cJSON_IsString(r))
            snprintf(out, n, "%s", r->valuestring);
    }
    cJSON_Delete(root);
}

/* The options `fovsim check --record` never writes into compare_argv: the machine's (passed to
 * compare, not stored; OPT_MACHINE in cli_options.c), check's own, and those a baseline refuses.
 * The option's name when `arg` is one ("--cache" for "--cache=DIR" too), else NULL. */
static const char *never_stored(const char *arg)
{
    static const char *const k_never[] = {"--out", "--replace", "--resume", "--name", "--help", "--record",
                                          "--baseline", "--junit"};
    const char *machine = cli_machine_option(arg, NULL);
    if (machine)
        return machine;
    for (size_t k = 0; k < sizeof k_never / sizeof k_never[0]; k++) {
        size_t l = strlen(k_never[k]);
        if (!strncmp(arg, k_never[k], l) && (arg[l] == '\0' || arg[l] == '='))
            return k_never[k];
    }
    char opt[64];
    snprintf(opt, sizeof opt, "%.*s", (int)strcspn(arg, "="), arg);
    check_metric m = check_metric_of_option(opt);
    return m < CHECK_METRIC_COUNT ? check_metric_option(m) : NULL;
}

static const char *never_stored_why(const char *opt)
{
    if (cli_machine_option(opt, NULL))
        return "an option of the machine that runs the check";
    if (!strncmp(opt, "--tol-", 6))
        return "tolerances are stored under \"tolerances\"";
    return "an option of fovsim check itself, or one a baseline refuses";
}

fs_status check_baseline_parse(const char *dir, const cJSON *root, const char **argv, int *argc, check_tols *t,
                               const char **version)
{
    static const char *const keys[] = {"fovsim_check", "role", "fovsim", "argv", "compare_argv", "tolerances"};
    char path[PATH_MAX + 32], jp[96];
    snprintf(path, sizeof path, "%s/%s", dir, CHECK_FILE);
    if (!cJSON_IsObject(root))
        return bad_json(path, "(top level)", "expected an object");
    for (const cJSON *c = root->child; c; c = c->next) {
        bool known = false;
        for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
            known = known || !strcmp(c->string, keys[k]);
        if (!known)
            return bad_json(path, c->string, "unknown key (expected fovsim_check, role, fovsim, argv, compare_argv, "
                            "tolerances)");
    }
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(root, "fovsim_check"),
                *role = cJSON_GetObjectItemCaseSensitive(root, "role"),
                *ver = cJSON_GetObjectItemCaseSensitive(root, "fovsim"),
                *ca = cJSON_GetObjectItemCaseSensitive(root, "compare_argv"),
                *tol = cJSON_GetObjectItemCaseSensitive(root, "tolerances");
    if (!cJSON_IsNumber(f) || f->valuedouble != CHECK_FORMAT)
        return bad_json(path, "fovsim_check", "expected 1 (the format of this file; written by another fovsim?)");
    if (!cJSON_IsString(role) || strcmp(role->valuestring, "baseline") != 0)
        return bad_json(path, "role", cJSON_IsString(role) && !strcmp(role->valuestring, "next")
                                          ? "'next': this folder is what a check ran, not a baseline"
                                          : "expected \"baseline\"");
    if (!cJSON_IsString(ver))
        return bad_json(path, "fovsim", "expected the version string of the fovsim that recorded it");
    *version = ver->valuestring;
    if (!cJSON_IsArray(ca) || cJSON_GetArraySize(ca) < 1 || cJSON_GetArraySize(ca) > CHECK_MAX_ARGS)
        return bad_json(path, "compare_argv", "expected an array of 1 to 256 strings, \"compare\" first");
    *argc = 0;
    for (const cJSON *e = ca->child; e; e = e->next) {
        snprintf(jp, sizeof jp, "compare_argv[%d]", *argc);
        if (!cJSON_IsString(e) || (*argc == 0 && strcmp(e->valuestring, "compare") != 0))
            return bad_json(path, jp, *argc ? "expected a string" : "expected \"compare\"");
        /* A baseline holds compare's options that shape the run; --record keeps the machine's
         * (--cache, --gpu, ...) and check's own out of it, so one here was not written by fovsim
         * and is refused rather than obeyed (docs/check.md). */
        const char *never = never_stored(e->valuestring);
        if (*argc > 0 && never) {
            char why[200];
            snprintf(why, sizeof why, "'%s' is never stored in a baseline (%s); give it to fovsim check, or record "
                     "the baseline again", never, never_stored_why(never));
            return bad_json(path, jp, why);
        }
        argv[(*argc)++] = e->valuestring;
    }
    check_tols_default(t);
    if (tol && !cJSON_IsObject(tol))
        return bad_json(path, "tolerances", "expected an object of SPEC strings per metric");
    for (const cJSON *c = tol ? tol->child : NULL; c; c = c->next) {
        int m = 0;
        while (m < CHECK_METRIC_COUNT && strcmp(c->string, check_metric_name((check_metric)m)) != 0)
            m++;
        char err[300];
        snprintf(jp, sizeof jp, "tolerances.%.60s", c->string);
        if (m == CHECK_METRIC_COUNT)
            return bad_json(path, jp, "not a metric of fovsim check (coverage_ratio, rmse, alpha_rmse, flip, "
                            "temporal_error, pixel_2x2, pixel_rmse, frame_time_ratio)");
        if (!cJSON_IsString(c) || !check_tol_apply(&t->t[m], c->valuestring, err, sizeof err))
            return bad_json(path, jp, cJSON_IsString(c) ? err : "expected a SPEC string (\"0.05\", \"0.05,3=0.1\")");
    }
    return FS_OK;
}

/* Writes DIR/check.json atomically. */
static fs_status write_check_json(const char *dir, cJSON *root)
{
    char path[PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/%s", dir, CHECK_FILE);
    char *text = cJSON_Print(root);
    if (!text)
        return FS_ERR_NOMEM;
    size_t l = strlen(text);
    char *withnl = malloc(l + 2);
    fs_status st = FS_ERR_NOMEM;
    if (withnl) {
        memcpy(withnl, text, l);
        memcpy(withnl + l, "\n", 2);
        st = out_write_atomic(path, withnl);
    }
    free(withnl);
    cJSON_free(text);
    return st;
}

static cJSON *string_array(const char *const *v, int n)
{
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; a && i < n; i++)
        cJSON_AddItemToArray(a, cJSON_CreateString(v[i]));
    return a;
}

/* >>running compare */

/* A compare run from the options `opts` ("compare" first), the machine's (o->env), --out `out`
 * (and --replace), through the CLI's own table (messages prefixed with `context`). */
static fs_status compare_prepare(run_desc *d, const char *const *opts, int nopts, const check_opts *o,
                                 const char *out, bool replace, const char *context)
{
    log_set_context(context);
    cli_begin(d, CMD_COMPARE);
    fs_status st = cli_parse_args(d, nopts - 1, (char *const *)opts + 1);
    if (st == FS_OK)
        st = cli_parse_args(d, o->nenv, (char *const *)o->env);
    if (st == FS_OK)
        st = cli_apply_option(d, "--out", out);
    if (st == FS_OK && replace)
        st = cli_apply_option(d, "--replace", NULL);
    if (st == FS_OK)
        st = cli_finish(d);
    log_set_context(NULL);
    if (st == FS_OK && (d->cmd != CMD_COMPARE || strcmp(d->name, "compare") != 0 || d->resume)) {
        log_error("%s--help, --name and --resume are not options of a baseline", context ? context : "");
        st = FS_ERR_USAGE;
    }
    return st;
}

/* Runs compare, with its table on stdout only when `table`. */
static fs_status compare_run_quiet(const run_desc *d, bool table)
{
    fflush(stdout);
    int saved = table ? -1 : dup(STDOUT_FILENO), devnull = saved >= 0 ? open("/dev/null", O_WRONLY) : -1;
    if (devnull >= 0) {
        dup2(devnull, STDOUT_FILENO);
        close(devnull);
    }
    fs_status st = cmd_compare(d);
    fflush(stdout);
    if (saved >= 0) {
        dup2(saved, STDOUT_FILENO);
        close(saved);
    }
    return st;
}

/* Removes DIR/diff.NNNN.exr (an earlier check's; every check writes its own). */
static void remove_old_diffs(const char *dir)
{
    DIR *dp = opendir(dir);
    for (struct dirent *e; dp && (e = readdir(dp));) {
        if (strncmp(e->d_name, "diff.", 5) != 0)
            continue;
        size_t digits = strspn(e->d_name + 5, "0123456789");
        if (digits >= 4 && !strcmp(e->d_name + 5 + digits, ".exr")) {
            char path[PATH_MAX + 300];
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            unlink(path);
        }
    }
    if (dp)
        closedir(dp);
}

/* `dir` without trailing slashes into out. */
static void trim_dir(const char *dir, char *out, size_t n)
{
    snprintf(out, n, "%s", dir);
    for (size_t l = strlen(out); l > 1 && out[l - 1] == '/'; l--)
        out[l - 1] = '\0';
}

/* The keys of the configuration lines (above "---") that differ between the two folders' run
 * records, e.g. "scene, fovsim": what changed since the baseline. "" when none (or unreadable). */
static void record_diff(const char *base, const char *next, char *out, size_t cap)
{
    char *t[2] = {NULL, NULL};
    for (int i = 0; i < 2; i++) {
        char path[1300];
        size_t size;
        snprintf(path, sizeof path, "%s/%s", i ? next : base, RUN_RECORD_FILE);
        log_set_quiet_errors(true);
        file_read_all(path, 1 << 20, "a run record", FS_ERR_IO, &t[i], &size);
        log_set_quiet_errors(false);
    }
    out[0] = '\0';
    for (char *l = t[0]; l && t[1] && *l && strncmp(l, "---", 3) != 0; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
        size_t len = strcspn(l, "\n"), key = strcspn(l, ":");
        if (l[0] == '#' || key >= len || !strncmp(l, "name:", 5))
            continue;
        bool same = false; /* the same line anywhere in the other record's configuration */
        for (char *m = t[1]; m && *m && strncmp(m, "---", 3) != 0; m = strchr(m, '\n') ? strchr(m, '\n') + 1 : NULL)
            same = same || (strcspn(m, "\n") == len && !strncmp(l, m, len));
        if (!same && strlen(out) + key + 3 < cap)
            snprintf(out + strlen(out), cap - strlen(out), "%s%.*s", out[0] ? ", " : "", (int)key, l);
    }
    free(t[0]);
    free(t[1]);
}

/* >>record */

static fs_status record(int argc, char **argv, const check_opts *o)
{
    char dir[PATH_MAX], role[32];
    trim_dir(o->record, dir, sizeof dir);
    const char *opts[CHECK_MAX_ARGS + 1];
    opts[0] = "compare";
    memcpy(opts + 1, o->pass, sizeof *opts * (size_t)o->npass);
    check_role(dir, role, sizeof role);
    bool replacing = !strcmp(role, "baseline"); /* recording again replaces the baseline */
    run_desc *c = malloc(sizeof *c);
    if (!c)
        return FS_ERR_NOMEM;
    fs_status st = compare_prepare(c, opts, o->npass + 1, o, dir, replacing || o->replace, NULL);
    char path[PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/%s", dir, CHECK_FILE);
    if (st == FS_OK && replacing && unlink(path) != 0) { /* a failed recording leaves no baseline */
        log_error("%s: cannot remove the old baseline's file: %s", path, strerror(errno));
        st = FS_ERR_IO;
    }
    if (st == FS_OK)
        st = compare_run_quiet(c, true);
    free(c);
    if (st != FS_OK)
        return st;
    cJSON *root = cJSON_CreateObject();
    const char *full[CHECK_MAX_ARGS + 64];
    int n = 0;
    full[n++] = "fovsim";
    for (int i = 1; i < argc && n < CHECK_MAX_ARGS + 63; i++)
        full[n++] = argv[i];
    bool ok = root && cJSON_AddNumberToObject(root, "fovsim_check", CHECK_FORMAT) &&
              cJSON_AddStringToObject(root, "role", "baseline") &&
              cJSON_AddStringToObject(root, "fovsim", FOVSIM_VERSION);
    cJSON *a = ok ? string_array(full, n) : NULL, *ca = a ? string_array(opts, o->npass + 1) : NULL,
          *t = ca ? tols_json(&o->tol_cli) : NULL;
    if (a)
        cJSON_AddItemToObject(root, "argv", a);
    if (ca)
        cJSON_AddItemToObject(root, "compare_argv", ca);
    if (t)
        cJSON_AddItemToObject(root, "tolerances", t);
    st = t ? write_check_json(dir, root) : FS_ERR_NOMEM;
    cJSON_Delete(root);
    if (st == FS_OK)
        printf("\nrecorded the baseline %s (%s); check against it with: fovsim check --baseline %s\n", dir, CHECK_FILE,
               dir);
    return st;
}

/* >>baseline */

static fs_status check_against(const check_opts *o)
{
    char dir[PATH_MAX], next[PATH_MAX], role[32];
    trim_dir(o->baseline, dir, sizeof dir);
    if (o->out)
        trim_dir(o->out, next, sizeof next);
    else
        snprintf(next, sizeof next, "%.*s-next", (int)sizeof next - 6, dir);
    char rd[PATH_MAX], rn[PATH_MAX];
    if (!strcmp(dir, next) || (realpath(dir, rd) && realpath(next, rn) && !strcmp(rd, rn))) {
        log_error("--out %s: the baseline's own folder; a check writes its run elsewhere (default %s-next)", next, dir);
        return FS_ERR_USAGE;
    }
    if (o->junit) {
        char jd[PATH_MAX];
        snprintf(jd, sizeof jd, "%s", o->junit);
        char *slash = strrchr(jd, '/');
        const char *parent = slash ? (slash == jd ? "/" : (*slash = '\0', jd)) : ".";
        struct stat sb;
        if (stat(parent, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
            log_error("--junit %s: the folder %s does not exist", o->junit, parent);
            return FS_ERR_USAGE;
        }
    }
    cJSON *root = NULL;
    fs_status st = read_check_json(dir, &root, false);
    const char *opts[CHECK_MAX_ARGS], *version = "";
    int nopts = 0;
    check_tols tols;
    if (st == FS_OK)
        st = check_baseline_parse(dir, root, opts, &nopts, &tols, &version);
    for (int m = 0; m < CHECK_METRIC_COUNT; m++)
        if (o->tol_set[m]) /* the options given now override the baseline's, metric by metric */
            tols.t[m] = o->tol_cli.t[m];
    /* NEXT is check's own: the default folder, or one an earlier check wrote; its earlier run (of
     * another fovsim executable, or of changed content) is replaced. */
    check_role(next, role, sizeof role);
    bool ours = !o->out || !strcmp(role, "next");
    if (st == FS_OK && !strcmp(role, "baseline")) {
        log_error("--out %s: holds a baseline of fovsim check; a check writes its run elsewhere", next);
        st = FS_ERR_USAGE;
    }
    char context[PATH_MAX + 64];
    snprintf(context, sizeof context, "%s/%s: compare_argv: ", dir, CHECK_FILE);
    run_desc *c = st == FS_OK ? malloc(sizeof *c) : NULL;
    if (st == FS_OK && !c)
        st = FS_ERR_NOMEM;
    if (st == FS_OK)
        st = compare_prepare(c, opts, nopts, o, next, ours, context);
    if (st == FS_OK) /* a damaged baseline fails before anything is drawn */
        st = check_baseline_validate(dir);
    if (st == FS_OK && strcmp(version, FOVSIM_VERSION) != 0)
        printf("the baseline was recorded by fovsim %s; this is fovsim %s\n", version, FOVSIM_VERSION);
    if (st == FS_OK && !strcmp(role, "next")) { /* no earlier verdict stands beside this run's frames */
        cJSON *mark = cJSON_CreateObject();
        if (mark && cJSON_AddNumberToObject(mark, "fovsim_check", CHECK_FORMAT) &&
            cJSON_AddStringToObject(mark, "role", "next") && cJSON_AddStringToObject(mark, "baseline", dir) &&
            cJSON_AddStringToObject(mark, "verdict", "incomplete"))
            st = write_check_json(next, mark);
        cJSON_Delete(mark);
    }
    if (st == FS_OK && o->junit && unlink(o->junit) != 0 && errno != ENOENT) {
        log_error("--junit %s: cannot replace: %s", o->junit, strerror(errno));
        st = FS_ERR_IO;
    }
    if (st == FS_OK) {
        printf("fovsim check: running the baseline's options into %s\n", next);
        st = compare_run_quiet(c, o->verbose);
    }
    free(c);
    check_verdict v = {0};
    if (st == FS_OK) {
        remove_old_diffs(next);
        st = check_judge(&(check_judge_desc){.baseline = dir, .next = next, .label = strrchr(dir, '/') ?
                                             strrchr(dir, '/') + 1 : dir, .tols = &tols, .junit = o->junit,
                                             .max_lines = CHECK_REPORT_LINES}, &v);
    }
    if (st == FS_OK) {
        char diff[512];
        record_diff(dir, next, diff, sizeof diff);
        printf("what differs from the baseline's run (%s): %s\n", RUN_RECORD_FILE,
               diff[0] ? diff : "nothing (the same options, scene, gaze, fovsim executable and renderer)");
        if (o->junit)
            printf("JUnit: %s\n", o->junit);
    }
    if (st == FS_OK) {
        cJSON *res = cJSON_CreateObject(), *fails = cJSON_Parse(v.failures_json);
        bool ok = res && fails && cJSON_AddNumberToObject(res, "fovsim_check", CHECK_FORMAT) &&
                  cJSON_AddStringToObject(res, "role", "next") && cJSON_AddStringToObject(res, "baseline", dir) &&
                  cJSON_AddStringToObject(res, "fovsim", FOVSIM_VERSION) &&
                  cJSON_AddStringToObject(res, "baseline_fovsim", version) &&
                  cJSON_AddStringToObject(res, "verdict", v.failed_values ? "regression" : "pass") &&
                  cJSON_AddNumberToObject(res, "values", v.values) &&
                  cJSON_AddNumberToObject(res, "failed_values", v.failed_values) &&
                  cJSON_AddNumberToObject(res, "cases", v.cases) &&
                  cJSON_AddNumberToObject(res, "failed_cases", v.failed_cases);
        cJSON *t = ok ? tols_json(&tols) : NULL;
        if (t)
            cJSON_AddItemToObject(res, "tolerances", t);
        if (t)
            cJSON_AddItemToObject(res, "failures", fails);
        else
            cJSON_Delete(fails);
        st = t ? write_check_json(next, res) : FS_ERR_NOMEM;
        cJSON_Delete(res);
    }
    free(v.failures_json);
    cJSON_Delete(root);
    return st == FS_OK && v.failed_values ? FS_REGRESSION : st;
}

fs_status cmd_check(int argc, char **argv)
{
    check_opts o;
    bool help = false;
    fs_status st = parse_options(argc, argv, &o, &help);
    if (st != FS_OK || help) {
        if (help)
            check_help();
        return st;
    }
    log_set_verbose(o.verbose);
    return o.record ? record(argc, argv, &o) : check_against(&o);
}
