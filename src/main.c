/* main.c: fovsim entry point: parse the command line, run it, map the result to an exit status. */
#include <malloc.h>
#include <stdlib.h>

#include "cli/cli.h"
#include "commands/commands.h"

/* The frame loop allocates nothing of its own that lives shorter than the session, but Mesa's
 * llvmpipe does: each draw's binned scene takes 64 KiB data blocks from malloc and frees them at
 * the flush. With glibc's defaults (trim threshold and top pad of 128 KiB) every frame then grows
 * the heap with brk and hands it back, and the kernel zero-fills the pages again on the next
 * frame: 43 brk calls and about 1 600 minor page faults per foveated draw of the forest at
 * 1280x720 (`strace -f -c -e trace=brk` and `/usr/bin/time` of `fovsim bench forest --taa off`,
 * 8 frames minus 2), 15-20 % of the frame's CPU time, most of it in the kernel. Keeping up to
 * 256 MiB of freed heap, growing it 64 MiB at a time and serving blocks up to 32 MiB (a
 * 1280x720 read-back frame) from the heap rather than from fresh mmaps makes the steady-state
 * frame fault-free: about 75 faults per draw. The memory is reused, not leaked: the heap stays
 * as large as the largest frame needed. docs/benchmarks.md, "Allocator churn".
 * FOVSIM_MALLOC_DEFAULTS=1 keeps glibc's defaults, to measure the difference. */
static void tune_allocator(void)
{
    if (getenv("FOVSIM_MALLOC_DEFAULTS"))
        return;
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    mallopt(M_TOP_PAD, 64 << 20);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
}

int main(int argc, char **argv)
{
    tune_allocator();
    run_desc d;
    fs_status st = cli_parse(argc, argv, &d);
    if (st == FS_OK)
        st = command_run(&d);
    return fs_status_exit_code(st);
}
