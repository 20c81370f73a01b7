#include "status.h"

int fs_status_exit_code(fs_status s)
{
    static const int codes[] = {
#define FS_STATUS_CODE(name, code, text) code,
        FS_STATUS_TABLE(FS_STATUS_CODE)
#undef FS_STATUS_CODE
    };
    return (unsigned)s < FS_STATUS_COUNT ? codes[s] : 10;
}

const char *fs_status_text(fs_status s)
{
    static const char *texts[] = {
#define FS_STATUS_TEXT(name, code, text) text,
        FS_STATUS_TABLE(FS_STATUS_TEXT)
#undef FS_STATUS_TEXT
    };
    return (unsigned)s < FS_STATUS_COUNT ? texts[s] : "unknown status";
}
