/* asset.c: helpers shared by every asset source (glTF shim, generators). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"

bool material_is_alpha_mapped(const material *m)
{
    return m->alpha_kind == ALPHA_KIND_MASK || m->alpha_kind == ALPHA_KIND_BLEND;
}

void asset_free(asset *a)
{
    if (!a)
        return;
    for (int i = 0; i < a->prim_count; i++) {
        prim *p = &a->prims[i];
        free(p->positions);
        free(p->normals);
        free(p->uvs);
        free(p->colors);
        free(p->indices);
    }
    free(a->prims);
    for (int i = 0; i < a->image_count; i++)
        free(a->images[i].rgba);
    free(a->images);
    free(a->materials);
    memset(a, 0, sizeof *a);
}

void asset_compute_bounds(asset *a)
{
    vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (int i = 0; i < a->prim_count; i++) {
        const prim *p = &a->prims[i];
        for (uint32_t v = 0; v < p->vertex_count; v++) {
            vec3 q = v3(p->positions[3 * v], p->positions[3 * v + 1], p->positions[3 * v + 2]);
            lo = v3_min(lo, q);
            hi = v3_max(hi, q);
        }
    }
    if (lo.x > hi.x) /* no vertices */
        lo = hi = v3(0, 0, 0);
    a->bounds_min = lo;
    a->bounds_max = hi;
}

void prim_compute_normals(prim *p)
{
    memset(p->normals, 0, sizeof(float) * 3 * p->vertex_count);
    for (uint32_t t = 0; t + 2 < p->index_count; t += 3) {
        uint32_t i0 = p->indices[t], i1 = p->indices[t + 1], i2 = p->indices[t + 2];
        if (i0 >= p->vertex_count || i1 >= p->vertex_count || i2 >= p->vertex_count)
            continue; /* scene_validate reports it */
        const float *a = &p->positions[3 * i0], *b = &p->positions[3 * i1], *c = &p->positions[3 * i2];
        vec3 n = v3_cross(v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]), v3(c[0] - a[0], c[1] - a[1], c[2] - a[2]));
        for (int k = 0; k < 3; k++) {
            uint32_t idx = p->indices[t + k];
            p->normals[3 * idx] += n.x;
            p->normals[3 * idx + 1] += n.y;
            p->normals[3 * idx + 2] += n.z;
        }
    }
    for (uint32_t v = 0; v < p->vertex_count; v++) {
        vec3 n = v3_norm_or(v3(p->normals[3 * v], p->normals[3 * v + 1], p->normals[3 * v + 2]), v3(0, 1, 0));
        p->normals[3 * v] = n.x;
        p->normals[3 * v + 1] = n.y;
        p->normals[3 * v + 2] = n.z;
    }
}
