/* pose_scene.c: EyeNavGS's scene_setting.csv, the tilt, scale and initial position of the scene a
 * recording was made in (pose_trace.h, pose_scene). One row per scene:
 *   Scene_Name,Quaternion,Scale,Initial_Position
 *   bicycle,"-0.1142, 0.0000, 0.0000, 0.9935",1.25,"1.5,1.1,0"
 * The file starts with a UTF-8 BOM. How the reader finds it: docs/gaze-formats.md ("EyeNavGS").
 */
#include "gaze/gaze_read.h"
#include "gaze/pose_trace.h"

#include <math.h>
#include <stdio.h>

enum { SCENE_NUMS = 8 }; /* quaternion x, y, z, w, scale, initial x, y, z */

/* The numbers of one field, itself comma-separated when it was quoted; false (err set) on a bad one. */
static bool field_numbers(span f, double *v, int *n, char *err, size_t cap)
{
    const char *p = f.p, *end = f.p + f.n;
    for (;;) {
        const char *b = p;
        while (p < end && *p != ',')
            p++;
        span num = {b, (size_t)(p - b)};
        char g[64];
        if (*n == SCENE_NUMS || gaze_parse_num(num, &v[*n]) != NUM_OK) {
            snprintf(err, cap, "expected %s, got %s", *n == SCENE_NUMS ? "8 numbers after the name" : "a number",
                     gaze_snip(g, sizeof g, num.p, num.n));
            return false;
        }
        ++*n;
        if (p >= end)
            return true;
        p++;
    }
}

bool pose_scene_parse_row(const char *row, size_t len, pose_scene *out, char *err, size_t cap)
{
    double v[SCENE_NUMS];
    int n = 0, k = 0;
    span name = {0};
    for (const char *p = row, *end = row + len;; p++, k++) {
        span f;
        if (!gaze_csv_field(&p, end, &f)) {
            snprintf(err, cap, "expected a closing '\"', got the end of the line");
            return false;
        }
        if (k == 0)
            name = f;
        else if (!field_numbers(f, v, &n, err, cap))
            return false;
        if (p >= end)
            break;
    }
    if (name.n == 0 || name.n >= sizeof out->name || n != SCENE_NUMS) {
        snprintf(err, cap, "expected Name,\"qx, qy, qz, qw\",scale,\"x,y,z\" (a name of 1..%zu bytes, 8 numbers), got "
                 "%d numbers", sizeof out->name - 1, n);
        return false;
    }
    double qn = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
    if (!(fabs(qn - 1) <= 0.05) || !(v[4] > 0)) {
        snprintf(err, cap, "expected a unit quaternion (norm 1 +- 0.05) and a scale > 0, got norm %.6g, scale %.6g",
                 qn, v[4]);
        return false;
    }
    *out = (pose_scene){.scale = v[4], .initial = {v[5], v[6], v[7]}};
    out->tilt = pose_qnorm((pose_quat){v[0], v[1], v[2], v[3]});
    memcpy(out->name, name.p, name.n);
    out->name[name.n] = '\0';
    return true;
}

fs_status pose_scene_find(const char *text, size_t size, const char *file, const char *scene, pose_scene *out)
{
    pctx c = {.name = file, .text = text, .size = size};
    if (c.size >= 3 && memcmp(c.text, "\xEF\xBB\xBF", 3) == 0)
        c.text += 3, c.size -= 3;
    line_it it = {c.text, c.text + c.size, 0};
    span header = {0}, line;
    int second;
    if (!gaze_csv_header(&it, &header) || gaze_csv_header_col(header, "Scene_Name", &second) != 0)
        return gaze_fail(&c, it.no ? it.no : 1, 1, "expected the header Scene_Name,Quaternion,Scale,Initial_Position, "
                         "got %s", header.n ? "another line" : "none");
    while (gaze_next_line(&it, &line)) {
        const char *p = line.p;
        span name;
        if (gaze_is_blank(line) || !gaze_csv_field(&p, line.p + line.n, &name) || !gaze_ieq(name.p, name.n, scene))
            continue;
        char err[256];
        if (!pose_scene_parse_row(line.p, line.n, out, err, sizeof err))
            return gaze_fail(&c, it.no, 1, "%s", err);
        return FS_OK;
    }
    char g[80];
    return gaze_fail(&c, it.no, 1, "expected a row for the scene %s, got none",
                     gaze_snip(g, sizeof g, scene, strlen(scene)));
}
