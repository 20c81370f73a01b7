/* main.c: fovsim entry point: parse the command line, run it, map the result to an exit status. */
#include "cli.h"
#include "run.h"

int main(int argc, char **argv)
{
    run_desc d;
    fs_status st = cli_parse(argc, argv, &d);
    if (st == FS_OK)
        st = run(&d);
    return fs_status_exit_code(st);
}
