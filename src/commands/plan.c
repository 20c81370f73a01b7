/* plan.c: `fovsim plan`: what a scene and its options compile and run (src/passes/plan.c), printed
 * without drawing. */
#include "commands/commands.h"

#include <stdio.h>
#include <stdlib.h>

#include "fov/vrs_map.h"

#include "passes/plan.h"
#include "session/session.h"

/* VRS foveation (vrs_map.h): the rate map for the gaze at the display centre, its share of pixels
 * per rate and ideal saving, beside the rings' (plan_print printed them above). */
static void print_vrs(const run_desc *d, const scene *sc, const plan *pl)
{
    display_desc dd = plan_display(pl);
    vrs_spec spec;
    int tile, nx, ny;
    session_vrs(d, sc, &spec, &tile);
    vrs_tile_grid(&dd, tile, &nx, &ny);
    vrs_rate *rates = malloc((size_t)nx * (size_t)ny);
    if (!rates)
        return;
    vrs_map_fill(&dd, &spec, tile, 0.5f * (float)dd.width, 0.5f * (float)dd.height, rates);
    vrs_stats st = vrs_map_stats(&dd, tile, rates);
    free(rates);
    char text[256];
    vrs_spec_format(&spec, text, sizeof text);
    printf("foveation  vrs: one pass at full resolution, one shading rate per %d x %d tile (%d x %d tiles); coarse "
           "shading emulated in the forward passes (VRS)\n", tile, tile, nx, ny);
    printf("vrs        %s%s, gaze at the centre:\n", text,
           spec.is_auto ? " (acuity model per tile: docs/foveation.md \"Variable-rate shading\")" : "");
    for (int i = 0; i < VRS_RATE_COUNT; i++)
        if (st.pixels[i] > 0)
            printf("  %-4s     %5.1f %% of display pixels\n", vrs_rate_name(k_vrs_rates[i]), 100.0 * st.share[i]);
    double px = (double)dd.width * (double)dd.height;
    printf("  total      %.1f %% of display pixels shaded: ideal shading saving %.1f %% (ideal speedup %.2fx)\n",
           100.0 * st.shaded / px, 100.0 * st.saving, px / st.shaded);
    const fov_layout *rings = pl->vrs ? &pl->vrs_rings : &pl->layout;
    if (rings->count > 1 || rings->rings[0].scale_log2 > 0) {
        long long rp = fov_shaded_pixels(&dd, rings, 0.5f * (float)dd.width, 0.5f * (float)dd.height,
                                         FOV_MARGIN_BLOCKS, NULL);
        printf("  the rings would shade %.1f %%: saving %.1f %%\n", 100.0 * (double)rp / px, 100.0 * (1.0 - (double)rp / px));
    }
}

static double deg(float rad)
{
    return (double)rad * 180.0 / FS_PI;
}

/* An hmd display (docs/hmd.md): per eye its field of view, panel, principal point and pixels per
 * degree there, and its place in the head. The passes above stay the planar display's until two
 * eyes are drawn. */
static void print_hmd(const hmd_desc *h)
{
    char text[512];
    hmd_format(h, text, sizeof text);
    printf("hmd        %s: %.9g Hz, IPD %.9g mm; render and compare draw each eye as a run of its own, the passes "
           "above are the left eye's (docs/hmd.md \"Two eyes\")\n", text, (double)h->refresh_hz, (double)h->ipd_mm);
    for (int e = 0; e < 2; e++) {
        const hmd_eye *y = &h->eye[e];
        hmd_pinhole p = hmd_eye_pinhole(y);
        float px, py;
        hmd_ppd(y, &px, &py);
        printf("  %-5s eye  fov left %+.2f right %+.2f up %+.2f down %+.2f deg (%.2f x %.2f), panel %d x %d, "
               "principal point (%.1f, %.1f) px, %.2f x %.2f px/deg there, at x %+.1f mm\n",
               e == HMD_LEFT ? "left" : "right", deg(y->fov.left), deg(y->fov.right), deg(y->fov.up),
               deg(y->fov.down), deg(y->fov.right - y->fov.left), deg(y->fov.up - y->fov.down), y->width,
               y->height, (double)p.cx, (double)p.cy, (double)px, (double)py, 1000.0 * (double)y->position.x);
    }
}

fs_status cmd_plan(const run_desc *d_in)
{
    bool hmd_display = false;
    fs_status st = session_display_is_hmd(d_in, &hmd_display);
    if (st != FS_OK)
        return st;
    run_desc dk = *d_in; /* an hmd display: the left eye's plan */
    dk.eye_run = hmd_display ? 1 : 0;
    const run_desc *d = &dk;
    scene sc;
    st = session_load_scene(d, &sc);
    if (st != FS_OK)
        return st;
    plan pl;
    st = session_build_plan(d, &sc, &pl);
    if (st == FS_OK)
        plan_print(&pl, &sc, stdout);
    if (st == FS_OK && session_foveation(d, &sc) == FOVEATION_VRS)
        print_vrs(d, &sc, &pl);
    const hmd_desc *hmd = session_hmd(d, &sc);
    if (st == FS_OK && hmd) /* absent for a planar display: plans print as before */
        print_hmd(hmd);
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
