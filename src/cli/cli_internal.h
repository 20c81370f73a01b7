/* cli_internal.h: the option table shared by cli.c (parsing), cli_help.c (--help) and
 * cli_options.c (the table itself). docs/design-notes.md, "The command line from one table". */
#ifndef FOVSIM_CLI_INTERNAL_H
#define FOVSIM_CLI_INTERNAL_H

#include <stddef.h>

#include "cli/cli.h"

/* Where an option applies: one bit per command, and two bits for a command with a switch that
 * widens what it accepts (bench --accuracy takes the reference's options, compare --first-frame
 * takes --warmup). */
#define ON(c) (1u << (c))
#define CTX_BENCH_ACCURACY (1u << 20)
#define CTX_COMPARE_CHUNK (1u << 21)
#define CMDS_DRAWING (ON(CMD_RENDER) | ON(CMD_PLAN) | ON(CMD_DEMO) | ON(CMD_BENCH) | ON(CMD_REFERENCE) | \
                      ON(CMD_COMPARE) | ON(CMD_VIEW) | CTX_BENCH_ACCURACY | CTX_COMPARE_CHUNK)
/* The runs whose frames come from session_frame, where a recording's head motion is replayed. */
#define CMDS_HEAD (ON(CMD_RENDER) | ON(CMD_COMPARE) | ON(CMD_DEMO) | CTX_BENCH_ACCURACY | CTX_COMPARE_CHUNK)
#define CMDS_REFERENCE (ON(CMD_REFERENCE) | ON(CMD_COMPARE) | ON(CMD_DEMO) | CTX_BENCH_ACCURACY)
#define CMDS_RUN_FOLDER (ON(CMD_RENDER) | ON(CMD_REFERENCE) | ON(CMD_COMPARE) | ON(CMD_DEMO) | CTX_COMPARE_CHUNK)

typedef enum cli_arg {
    ARG_FLAG,   /* no value: sets a bool */
    ARG_INT,    /* an integer in [lo, hi] */
    ARG_FLOAT,  /* a number in (lo, hi], [lo, hi] with OPT_LO_CLOSED, as the 32-bit float it is used as */
    ARG_STRING, /* kept as given */
    ARG_CHOICE, /* one of `choices`: "expected a, b or c, got 'V'" */
    ARG_CUSTOM, /* its own setter */
} cli_arg;

enum {
    OPT_LO_CLOSED = 1 << 0, /* ARG_FLOAT: lo itself is allowed */
    OPT_RECORDED = 1 << 1,  /* written into the run record (run_record.c): it changes what a run writes */
    OPT_MACHINE = 1 << 2,   /* of the machine that runs it: fovsim check passes it on, never stores it */
    OPT_HELP_ONLY = 1 << 3, /* a second help line of the option above, for other commands */
};

typedef struct cli_choice {
    const char *name;
    int value;
} cli_choice;

struct cli_option;
/* A setter: parses `v` into d; on error one line and false. */
typedef bool (*cli_setter)(const struct cli_option *o, run_desc *d, const char *v);

typedef struct cli_option {
    const char *name;           /* "--taa-blend" */
    cli_arg arg;
    unsigned cmds;              /* ON(CMD_...) | CTX_...: where it applies (and is listed by --help) */
    const char *metavar;        /* "W" in the help line, NULL for a flag */
    const char *help;           /* help text; '\n' starts an indented line; {builtins} and {modes} are
                                 * the lists of built-in scenes and alpha modes */
    size_t field, size;         /* offsetof and sizeof the run_desc member it sets */
    double lo, hi;              /* ARG_INT, ARG_FLOAT: the range */
    const cli_choice *choices;  /* ARG_CHOICE: {name, value}..., {NULL} */
    cli_setter set;             /* ARG_CUSTOM */
    size_t given;               /* offsetof a bool set whenever the option is given, 0 for none */
    unsigned flags;             /* OPT_* */
    const char *misuse;         /* the line printed when it is given where it does not apply */
} cli_option;

extern const cli_option k_cli_options[];
extern const size_t k_cli_option_count;

/* The option's first row by name, or NULL. */
const cli_option *cli_option_find(const char *name);
/* The CTX bits a run of d->cmd (with its switches) has; for --help of `cmd` (d NULL), all of
 * cmd's. */
unsigned cli_context(command cmd, const run_desc *d);

/* The commands and their one-line summaries, as `fovsim --help` lists them. */
void cli_print_commands(void);

/* A number used as a 32-bit float, in (lo, hi] or [lo, hi] with lo_closed, and normal or 0 as
 * that float (cli_values.c); else one line naming `opt` and `expected` (NULL: the range). */
bool cli_parse_float_in(const char *opt, const char *v, float lo, bool lo_closed, float hi, float *out,
                        const char *expected);

#endif
