/* plan.c: `fovsim plan`: what a scene and its options compile and run (src/passes/plan.c), printed
 * without drawing. */
#include "commands/commands.h"

#include <stdio.h>

#include "passes/plan.h"
#include "session/session.h"

fs_status cmd_plan(const run_desc *d)
{
    scene sc;
    fs_status st = session_load_scene(d, &sc);
    if (st != FS_OK)
        return st;
    plan pl;
    st = session_build_plan(d, &sc, &pl);
    if (st == FS_OK)
        plan_print(&pl, &sc, stdout);
    gaze_tracker_desc td = gaze_tracker_merge(&d->tracker, &sc.tracker);
    if (st == FS_OK && !gaze_tracker_is_ideal(&td)) { /* absent without one: plans print as before */
        char tr[160];
        gaze_tracker_format(&td, tr, sizeof tr);
        printf("tracker    %s: the rings follow the delivered gaze, metrics the true gaze\n", tr);
    }
    gaze_place_desc gp = gaze_place_merge(&d->place, &sc.gaze_place);
    if (st == FS_OK && (gp.map != GAZE_MAP_ANGLE || gp.screen.kind != GAZE_SCREEN_NONE)) { /* absent by default */
        char scr[64];
        gaze_screen_format(&gp.screen, scr, sizeof scr);
        printf("gaze map   %s%s%s\n", gaze_map_name(gp.map), scr[0] ? ", recording geometry " : "", scr);
    }
    scene_free(&sc);
    return st;
}
