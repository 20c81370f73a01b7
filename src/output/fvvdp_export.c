/* fvvdp_export.c: see fvvdp_export.h. */
#include "output/fvvdp_export.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/file_read.h"
#include "core/log.h"
#include "core/spawn.h"
#include "output/png_write.h"

struct fvvdp_export {
    char dir[1100];
    const char *names[FVVDP_MAX_SEQUENCES];
    int count, width, height, frames;
    float hfov, fps;
    FILE *fix;
};

fvvdp_export *fvvdp_export_begin(const char *out_dir, const char *const names[], int count, int width, int height,
                                 float hfov_deg, float fps, fs_status *st)
{
    FS_ASSERT(count >= 2 && count <= FVVDP_MAX_SEQUENCES);
    fvvdp_export *e = calloc(1, sizeof *e);
    if (!e) {
        *st = FS_ERR_NOMEM;
        return NULL;
    }
    snprintf(e->dir, sizeof e->dir, "%s/fvvdp", out_dir);
    memcpy(e->names, names, sizeof(names[0]) * (size_t)count);
    e->count = count;
    e->width = width;
    e->height = height;
    e->hfov = hfov_deg;
    e->fps = fps;
    *st = FS_OK;
    for (int i = 0; i < count && *st == FS_OK; i++) {
        char d[1300];
        snprintf(d, sizeof d, "%s/%s", e->dir, names[i]);
        *st = file_make_dirs(d);
    }
    char path[1300];
    snprintf(path, sizeof path, "%s/fixation.csv", e->dir);
    if (*st == FS_OK && !(e->fix = fopen(path, "w"))) {
        log_error("%s: cannot create: %s", path, strerror(errno));
        *st = FS_ERR_IO;
    }
    if (*st != FS_OK) {
        free(e);
        return NULL;
    }
    fprintf(e->fix, "frame,gaze_x_norm,gaze_y_norm,fix_x_px,fix_y_px,gaze_x_deg,gaze_y_deg\n");
    return e;
}

fs_status fvvdp_export_frame(fvvdp_export *e, int index, const frame_record *fr, const exr_image *const images[])
{
    for (int i = 0; i < e->count; i++) {
        const exr_image *img = images[i];
        const float *rgb[3] = {exr_image_channel(img, "R"), exr_image_channel(img, "G"), exr_image_channel(img, "B")};
        FS_ASSERT(rgb[0] && rgb[1] && rgb[2] && img->width == e->width && img->height == e->height);
        char path[1400];
        snprintf(path, sizeof path, "%s/%s/%s.%04d.png", e->dir, e->names[i], e->names[i], index);
        fs_status st = png_write_srgb(path, img->width, img->height, rgb, 16);
        if (st != FS_OK)
            return st;
    }
    /* FovVideoVDP's pixel coordinates put pixel centres at integers: (0, 0) is the centre of the
     * top-left pixel. */
    /* where the viewer looks: the true gaze (frame.h), not the eye tracker's */
    fprintf(e->fix, "%d,%.9g,%.9g,%.9g,%.9g,%.6g,%.6g\n", index, (double)fr->true_gaze[0], (double)fr->true_gaze[1],
            (double)fr->true_gaze[0] * e->width - 0.5, (double)fr->true_gaze[1] * e->height - 0.5,
            (double)fr->true_gaze_deg[0], (double)fr->true_gaze_deg[1]);
    e->frames = index + 1 > e->frames ? index + 1 : e->frames;
    return ferror(e->fix) ? FS_ERR_IO : FS_OK;
}

/* The script is fovsim's own: it calls pyfvvdp's public Python API and reads the PNGs itself (they
 * are written one way: 16-bit RGB, filter 0), so it needs nothing beyond pyfvvdp and its numpy and
 * torch. */
static const char k_script[] =
    "#!/usr/bin/env python3\n"
    "# Written by fovsim (compare --export-fvvdp). Runs FovVideoVDP (pyfvvdp, installed by you; not part of\n"
    "# fovsim: CC BY-NC 4.0) on the sequences next to this file and writes results.json with each JOD.\n"
    "import json, os, struct, sys, zlib\n"
    "import numpy as np, torch, pyfvvdp\n"
    "from pyfvvdp.fvvdp_display_model import fvvdp_display_geometry\n"
    "D = os.path.dirname(os.path.abspath(__file__))\n"
    "cfg = json.load(open(os.path.join(D, 'display.json')))\n"
    "W, H, N = cfg['width'], cfg['height'], cfg['frames']\n"
    "def png16(path):\n"
    "    b = open(path, 'rb').read(); i = 8; idat = b''\n"
    "    while i < len(b):\n"
    "        n, t = struct.unpack('>I4s', b[i:i + 8]); idat += b[i + 8:i + 8 + n] if t == b'IDAT' else b''; i += 12 + n\n"
    "    a = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(H, 1 + W * 6)[:, 1:]\n"
    "    return a.reshape(H, W * 3, 2)[:, :, 0].astype(np.uint16) * 256 + a.reshape(H, W * 3, 2)[:, :, 1]\n"
    "def seq(name):\n"
    "    return np.stack([png16(os.path.join(D, name, '%s.%04d.png' % (name, f))).reshape(H, W, 3) for f in range(N)])\n"
    "fix = np.loadtxt(os.path.join(D, 'fixation.csv'), delimiter=',', skiprows=1, ndmin=2)[:, 3:5]\n"
    "m = pyfvvdp.fvvdp(display_name=cfg['display_name'], foveated=True, heatmap=None, quiet=True,\n"
    "                  display_geometry=fvvdp_display_geometry((W, H), fov_horizontal=cfg['hfov_deg']),\n"
    "                  device=torch.device('cpu'), temp_padding='replicate')\n"
    "ref = seq(cfg['reference'])\n"
    "out = {'jod': {}}\n"
    "for name in cfg['tests']:\n"
    "    with torch.no_grad():\n"
    "        q, _ = m.predict(seq(name), ref, dim_order='FHWC', frames_per_second=cfg['fps'],\n"
    "                         fixation_point=torch.tensor(fix, dtype=torch.float32))\n"
    "    out['jod'][name] = float(q)\n"
    "    print('%-12s JOD %.4f' % (name, float(q)), flush=True)\n"
    "json.dump(out, open(os.path.join(D, 'results.json'), 'w'), indent=1)\n";

static fs_status write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    bool ok = f && fputs(text, f) >= 0;
    if (f && fclose(f) != 0)
        ok = false;
    if (!ok) {
        log_error("%s: cannot write: %s", path, strerror(errno));
        return FS_ERR_IO;
    }
    return FS_OK;
}

fs_status fvvdp_export_end(fvvdp_export *e)
{
    fs_status st = FS_OK;
    if (fclose(e->fix) != 0) {
        log_error("%s/fixation.csv: cannot write: %s", e->dir, strerror(errno));
        st = FS_ERR_IO;
    }
    char json[4096], path[1300];
    int o = snprintf(json, sizeof json,
                     "{\n  \"width\": %d,\n  \"height\": %d,\n  \"frames\": %d,\n  \"fps\": %g,\n  \"hfov_deg\": %g,\n"
                     "  \"geometry\": \"planar (pinhole), fvvdp_display_geometry((width, height), fov_horizontal=hfov_deg)\",\n"
                     "  \"display_name\": \"standard_hmd\",\n  \"encoding\": \"sRGB OETF of linear display values, "
                     "1.0 = peak, 16 bit\",\n  \"reference\": \"%s\",\n  \"tests\": [",
                     e->width, e->height, e->frames, (double)e->fps, (double)e->hfov, e->names[e->count - 1]);
    for (int i = 0; i + 1 < e->count; i++)
        o += snprintf(json + o, sizeof json - (size_t)o, "%s\"%s\"", i ? ", " : "", e->names[i]);
    snprintf(json + o, sizeof json - (size_t)o, "]\n}\n");
    snprintf(path, sizeof path, "%s/display.json", e->dir);
    if (st == FS_OK)
        st = write_text(path, json);
    snprintf(path, sizeof path, "%s/run_fvvdp.py", e->dir);
    if (st == FS_OK)
        st = write_text(path, k_script);
    free(e);
    return st;
}

/* The interpreter both the check and the run use: python3 as found on PATH, once. */
static bool python(char *exe, size_t n)
{
    return spawn_find("python3", exe, n);
}

bool fvvdp_available(void)
{
    char exe[PATH_MAX];
    char *argv[] = {exe, "-c", "import pyfvvdp", NULL};
    return python(exe, sizeof exe) && spawn_run(argv, &(spawn_opts){.quiet = true}) == 0;
}

fs_status fvvdp_run(const char *out_dir, const char *const names[], int count, double jod[])
{
    for (int i = 0; i + 1 < count; i++)
        jod[i] = NAN;
    char exe[PATH_MAX], dir[PATH_MAX + 16], path[PATH_MAX + 64];
    snprintf(dir, sizeof dir, "%s/fvvdp", out_dir);
    /* Run in DIR/fvvdp (the script finds its inputs next to itself), its output in fvvdp.log. */
    char *argv[] = {exe, "./run_fvvdp.py", NULL};
    int rc = python(exe, sizeof exe) ? spawn_run(argv, &(spawn_opts){.dir = dir, .output = "fvvdp.log"})
                                     : SPAWN_NOT_FOUND;
    if (rc != 0) {
        if (rc == SPAWN_NOT_FOUND)
            log_error("FovVideoVDP: python3 is not on PATH; the inputs are in %s", dir);
        else if (rc == SPAWN_FAILED)
            log_error("FovVideoVDP: cannot run %s in %s: %s", exe, dir, strerror(errno));
        else
            log_error("FovVideoVDP: %s run_fvvdp.py failed with status %d (its output is in %s/fvvdp.log)", exe, rc,
                      dir);
        return FS_ERR_IO;
    }
    snprintf(path, sizeof path, "%s/fvvdp/results.json", out_dir);
    char *text = NULL;
    size_t n = 0;
    fs_status st = file_read_all(path, 1u << 20, "FovVideoVDP's results", FS_ERR_IO, &text, &n);
    if (st != FS_OK)
        return st;
    for (int i = 0; i + 1 < count; i++) {
        char key[80];
        snprintf(key, sizeof key, "\"%s\":", names[i]);
        const char *p = strstr(text, key);
        if (p)
            jod[i] = strtod(p + strlen(key), NULL);
    }
    free(text);
    return FS_OK;
}
