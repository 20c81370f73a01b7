/* replay_main.c: runs files through a fuzz target's LLVMFuzzerTestOneInput without libFuzzer.
 *
 * Usage: fuzz_replay_<name> DIR_OR_FILE...   (ctest: the seed corpus and the saved regressions)
 * Every regular file in each folder (sorted by name, dot files skipped; not recursive) or each file
 * named is read and passed once. A crash, a sanitizer report or a broken FUZZ_CHECK ends the process,
 * so the test fails; the line before it names the file. Exit status 1 when no file at all was run (a
 * mistyped folder must not pass), 2 when a folder or file cannot be read. Prints how many it ran.
 *
 * Built with any compiler (gcc in the normal and the sanitizer build); libFuzzer's own main is used
 * instead in build-fuzz.
 */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fuzz_common.h"

static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        perror(path);
        return -1;
    }
    size_t cap = 4096, n = 0;
    unsigned char *buf = malloc(cap);
    for (;;) {
        if (!buf)
            break;
        n += fread(buf + n, 1, cap - n, f);
        if (n < cap)
            break;
        unsigned char *bigger = realloc(buf, cap * 2);
        if (!bigger) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = bigger;
        cap *= 2;
    }
    int bad = ferror(f);
    fclose(f);
    if (!buf || bad) {
        fprintf(stderr, "%s: cannot read\n", path);
        free(buf);
        return -1;
    }
    /* An exactly sized copy, so reading one byte past the input is caught as under libFuzzer. */
    unsigned char *data = malloc(n ? n : 1);
    if (!data) {
        free(buf);
        return -1;
    }
    memcpy(data, buf, n);
    free(buf);
    fprintf(stderr, "replay: %s (%zu bytes)\n", path, n);
    LLVMFuzzerTestOneInput(data, n);
    free(data);
    return 0;
}

static int cmp_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Runs every regular file of `dir`; returns how many, or -1 on an error. */
static int run_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) {
        perror(dir);
        return -1;
    }
    char **names = NULL;
    size_t count = 0, cap = 0;
    struct dirent *e;
    int status = 0;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        if (count == cap) {
            cap = cap ? cap * 2 : 64;
            char **more = realloc(names, cap * sizeof *names);
            if (!more) {
                status = -1;
                break;
            }
            names = more;
        }
        size_t len = strlen(dir) + strlen(e->d_name) + 2;
        if (!(names[count] = malloc(len))) {
            status = -1;
            break;
        }
        snprintf(names[count++], len, "%s/%s", dir, e->d_name);
    }
    closedir(d);
    if (count > 1)
        qsort(names, count, sizeof *names, cmp_names);
    int ran = 0;
    for (size_t i = 0; i < count; i++) {
        struct stat sb;
        if (status == 0 && stat(names[i], &sb) == 0 && S_ISREG(sb.st_mode)) {
            if (run_file(names[i]) != 0)
                status = -1;
            else
                ran++;
        }
        free(names[i]);
    }
    free(names);
    return status != 0 ? -1 : ran;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s DIR_OR_FILE...\n", argv[0]);
        return 2;
    }
    int total = 0;
    for (int i = 1; i < argc; i++) {
        struct stat sb;
        if (stat(argv[i], &sb) != 0) {
            perror(argv[i]);
            return 2;
        }
        int ran = S_ISDIR(sb.st_mode) ? run_dir(argv[i]) : run_file(argv[i]) == 0 ? 1 : -1;
        if (ran < 0)
            return 2;
        printf("%s: %d file%s\n", argv[i], ran, ran == 1 ? "" : "s");
        total += ran;
    }
    printf("replayed %d file%s without a crash\n", total, total == 1 ? "" : "s");
    if (total == 0) {
        fprintf(stderr, "no input file found: nothing was tested\n");
        return 1;
    }
    return 0;
}
