/* status.h: result codes shared by every module, and the process exit status each maps to.
 *
 * Readers and loaders return an fs_status; main() turns it into the exit status, so each class of
 * failure gets a distinct, documented exit code (README "Exit status"). The message that goes with
 * a failure is printed where the failure is found (log_error), in one line naming file, line or
 * JSON path. This header does not print anything itself.
 */
#ifndef FOVSIM_STATUS_H
#define FOVSIM_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

/* X(name, exit status, short description) */
#define FS_STATUS_TABLE(X)                                                  \
    X(FS_OK,            0, "ok")                                            \
    X(FS_ERR_USAGE,     2, "bad command-line arguments")                    \
    X(FS_ERR_SCENE,     3, "bad scene file")                                \
    X(FS_ERR_ASSET,     4, "bad or unsupported glTF asset")                 \
    X(FS_ERR_GAZE,      5, "bad gaze trace")                                \
    X(FS_ERR_IO,        6, "cannot read or write a file")                   \
    X(FS_ERR_GL,        7, "no usable OpenGL 4.5 context")                  \
    X(FS_ERR_SHADER,    8, "shader failed to compile or link")              \
    X(FS_ERR_NOMEM,     9, "out of memory")                                 \
    X(FS_ERR_INTERNAL, 10, "internal error (a bug in fovsim)")            \
    X(FS_ERR_INCOMPLETE, 11, "a sweep has missing or failed tasks")         \
    X(FS_ERR_BUSY,       12, "another run is writing the output folder")    \
    X(FS_REGRESSION,     1, "fovsim check: results outside the baseline's tolerances") \
    X(FS_ERR_INTERRUPTED, 130, "interrupted")

typedef enum fs_status {
#define FS_STATUS_ENUM(name, code, text) name,
    FS_STATUS_TABLE(FS_STATUS_ENUM)
#undef FS_STATUS_ENUM
    FS_STATUS_COUNT
} fs_status;

/* Exit status of the process for a result code. */
int fs_status_exit_code(fs_status s);
/* Short English description, never NULL. */
const char *fs_status_text(fs_status s);

#ifdef __cplusplus
}
#endif

#endif
