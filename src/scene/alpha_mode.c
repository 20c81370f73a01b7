/* alpha_mode.c: names, traits and plot colours of the alpha modes, read from their one table,
 * FS_ALPHA_MODES in common/shared_defs.h (scene.h declares the functions). */
#include <stdio.h>
#include <string.h>

#include "scene/scene.h"

typedef struct mode_row {
    const char *name;
    unsigned colour; /* 0xRRGGBB */
    unsigned traits; /* ALPHA_TRAIT_* */
} mode_row;

#define FS_ALPHA_MODE_ROW(NAME, name, colour, traits) [ALPHA_MODE_##NAME] = {#name, colour, traits},
static const mode_row k_modes[ALPHA_MODE_COUNT] = {
    [ALPHA_MODE_DEFAULT] = {"default", 0x000000, 0},
    FS_ALPHA_MODES(FS_ALPHA_MODE_ROW)
};
#undef FS_ALPHA_MODE_ROW

/* ", traditional, stochastic, ...": alpha_mode_list skips the first separator. */
#define FS_ALPHA_MODE_LIST(NAME, name, colour, traits) ", " #name
static const char k_list[] = FS_ALPHA_MODES(FS_ALPHA_MODE_LIST);
#undef FS_ALPHA_MODE_LIST

const char *alpha_mode_name(alpha_mode m)
{
    return (unsigned)m < ALPHA_MODE_COUNT ? k_modes[m].name : NULL;
}

alpha_mode alpha_mode_parse(const char *name)
{
    if (!name)
        return ALPHA_MODE_DEFAULT;
    for (int m = ALPHA_MODE_TRADITIONAL; m < ALPHA_MODE_COUNT; m++)
        if (strcmp(name, k_modes[m].name) == 0)
            return (alpha_mode)m;
    return ALPHA_MODE_DEFAULT;
}

const char *alpha_mode_list(void)
{
    return k_list + 2;
}

unsigned alpha_mode_traits(alpha_mode m)
{
    return (unsigned)m < ALPHA_MODE_COUNT ? k_modes[m].traits : 0u;
}

bool alpha_mode_has(alpha_mode m, unsigned traits)
{
    return (alpha_mode_traits(m) & traits) == traits;
}

const char *alpha_mode_colour(alpha_mode m, char buf[8])
{
    snprintf(buf, 8, "#%06x", (unsigned)m < ALPHA_MODE_COUNT ? k_modes[m].colour & 0xffffffu : 0u);
    return buf;
}
