#include "scene/frame.h"

#include <math.h>

frame_record frame_record_make(const scene *sc, int index, float fps, int width, int height)
{
    float t = fps > 0.0f ? (float)index / fps : 0.0f;
    float prev = index > 0 && fps > 0.0f ? (float)(index - 1) / fps : -1.0f;
    return frame_record_at(sc, index, t, prev, width, height);
}

frame_record frame_record_at(const scene *sc, int index, float time, float prev_time, int width, int height)
{
    frame_record fr = {0};
    fr.index = index;
    fr.time = time;
    fr.camera = camera_path_eval(&sc->camera, fr.time);
    fr.cut = prev_time >= 0.0f && camera_path_cut_between(&sc->camera, prev_time, fr.time);
    fr.hfov_deg = fr.camera.hfov_deg > 0.0f ? fr.camera.hfov_deg : sc->display.hfov_deg;

    /* Clip planes: far just beyond the farthest scene corner, near as large as 24-bit depth
     * precision wants without clipping foliage right in front of the camera. */
    vec3 lo, hi;
    scene_bounds(sc, &lo, &hi);
    float far2 = 0.0f;
    for (int c = 0; c < 8; c++) {
        vec3 q = v3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
        vec3 d = v3_sub(q, fr.camera.position);
        far2 = fmaxf(far2, v3_dot(d, d));
    }
    fr.zfar = sqrtf(far2) * 1.05f + 1.0f;
    fr.znear = fmaxf(0.02f, fminf(0.1f, fr.zfar * 1e-4f));

    fr.view = m4_look_at(fr.camera.position, fr.camera.target, v3(0, 1, 0));
    fr.proj = m4_perspective_hfov(fr.hfov_deg * (float)FS_PI / 180.0f, (float)width / (float)height, fr.znear, fr.zfar);
    fr.view_proj = m4_mul(fr.proj, fr.view);
    fr.gaze[0] = 0.5f;
    fr.gaze[1] = 0.5f;
    return fr;
}
