/* dispatch.c: a parsed command line (cli.h's run_desc) to the command that runs it. sweep, merge
 * and check parse their own options (d->own). */
#include "commands/commands.h"


#include "core/log.h"
#include "gl/gl_device.h"
#include "view/view.h"

fs_status command_run(const run_desc *d)
{
    log_set_verbose(d->verbose);
    switch (d->cmd) {
    case CMD_HELP: cli_print_help(d->help_for); return FS_OK;
    case CMD_VERSION: printf("fovsim %s\n", FOVSIM_VERSION); return FS_OK;
    case CMD_LIST_GPUS: gl_device_list(); return FS_OK;
    case CMD_PLAN: return cmd_plan(d);
    case CMD_RENDER: return cmd_render(d);
    case CMD_DEMO: return cmd_demo(d);
    case CMD_BENCH: return d->bench.accuracy ? cmd_bench_accuracy(d) : d->bench.calibrate ? cmd_bench_calibrate(d) : cmd_bench(d);
    case CMD_REFERENCE: return cmd_reference(d);
    case CMD_COMPARE: return cmd_compare(d);
    case CMD_VIEW: return view_run(d);
    case CMD_SWEEP: return cmd_sweep(d->own.argc, d->own.argv);
    case CMD_MERGE: return cmd_merge(d->own.argc, d->own.argv);
    case CMD_CHECK: return cmd_check(d->own.argc, d->own.argv);
    case CMD_COUNT:
    case CMD_NONE: break;
    }
    return FS_ERR_INTERNAL;
}
