/* vrs_shade.c: C twin of VRS foveation's coarse-shading math (vrs_shade.h; GLSL:
 * shaders/common/vrs_shade.glsl, shaders/forward_vrs.geom). Same operations in the same order. */
#include "passes/vrs_shade.h"

#include "passes/alpha_hash.h"

void vrs_coarse_pixel(int px, int py, vrs_rate r, int height, int origin[2], float centre[2])
{
    int w = vrs_rate_width(r), h = vrs_rate_height(r);
    int top = height - 1 - py;
    origin[0] = px & ~(w - 1);
    origin[1] = top & ~(h - 1);
    centre[0] = (float)origin[0] + 0.5f * (float)w;
    centre[1] = (float)(height - origin[1]) - 0.5f * (float)h;
}

static void cross3(const float a[3], const float b[3], float out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

void vrs_triangle_edges(const float clip[3][4], float edge[3][3])
{
    float c[3][3];
    for (int i = 0; i < 3; i++) {
        c[i][0] = clip[i][0];
        c[i][1] = clip[i][1];
        c[i][2] = clip[i][3];
    }
    for (int i = 0; i < 3; i++)
        cross3(c[(i + 1) % 3], c[(i + 2) % 3], edge[i]);
}

void vrs_bary(const float edge[3][3], float cx, float cy, float step_x, float step_y, float vw, float vh, float b[3],
              float bx[3], float by[3])
{
    float nx = cx * (2.0f / vw) - 1.0f, ny = cy * (2.0f / vh) - 1.0f;
    float e[3];
    for (int i = 0; i < 3; i++)
        e[i] = nx * edge[i][0] + ny * edge[i][1] + edge[i][2];
    float sum = e[0] + e[1] + e[2];
    for (int i = 0; i < 3; i++)
        b[i] = e[i] / sum;
    float sx = edge[0][0] + edge[1][0] + edge[2][0], sy = edge[0][1] + edge[1][1] + edge[2][1];
    float kx = step_x * (2.0f / vw), ky = step_y * (2.0f / vh);
    for (int i = 0; i < 3; i++) {
        bx[i] = (edge[i][0] - b[i] * sx) / sum * kx;
        by[i] = (edge[i][1] - b[i] * sy) / sum * ky;
    }
}

float vrs_coarse_lod(const float duv_dx[2], const float duv_dy[2], vrs_rate r, const float tex_size[2],
                     float mip_scale)
{
    float w = (float)vrs_rate_width(r), h = (float)vrs_rate_height(r);
    float gx[2] = {duv_dx[0] * w, duv_dx[1] * w}, gy[2] = {duv_dy[0] * h, duv_dy[1] * h};
    return alpha_texture_fade_level(gx, gy, tex_size, mip_scale);
}
