/* fuzz_common.h: what the fuzz targets of tests/fuzz share.
 *
 * Each target (fuzz_<name>.c) defines LLVMFuzzerTestOneInput and nothing else of libFuzzer's, so
 * the same file links against libFuzzer (clang, FOVSIM_FUZZ=ON: build-fuzz/fuzz_<name>) and against
 * replay_main.c (any compiler: the ctest `fuzz_replay_<name>` runs the seed corpus and the saved
 * regressions through it in every build).
 *
 * What it does NOT do: decide what is a bug. A crash, a sanitizer report, a leak, or a broken
 * invariant (FUZZ_CHECK, which aborts) is one; every error status fovsim returns is fine.
 */
#ifndef FOVSIM_FUZZ_COMMON_H
#define FOVSIM_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Once per process (every target calls it first). fovsim's error and warning lines stay on, so the
 * code that formats and escapes them runs on fuzzed text too; run.sh sends them to /dev/null with
 * libFuzzer's -close_fd_mask=2 (libFuzzer's and the sanitizers' own reports still show), and a
 * reproduction shows them. FOVSIM_FUZZ_QUIET=1 turns them off (log_set_quiet_errors). */
void fuzz_init(void);

/* This process's scratch folder: <base>/fovsim-fuzz.<pid>, base = $FOVSIM_FUZZ_TMP, else /dev/shm,
 * else $TMPDIR, else /tmp. Created on first use (after removing the folders of fovsim-fuzz
 * processes that no longer exist, which a crash leaves behind) and removed at exit. Never NULL:
 * aborts when no folder can be made. */
const char *fuzz_tmp_dir(void);

/* Writes data to <fuzz_tmp_dir()>/<name> (replacing it); returns the path (static storage, valid
 * until the next call). Aborts on a write error (a full /dev/shm is not an input's fault). */
const char *fuzz_write_tmp(const char *name, const void *data, size_t size);

/* A broken invariant: prints it and aborts, so libFuzzer (and the replay) report a crash. */
#define FUZZ_CHECK(c) ((c) ? (void)0 : fuzz_check_fail(#c, __FILE__, __LINE__))
void fuzz_check_fail(const char *expr, const char *file, int line);

#endif
