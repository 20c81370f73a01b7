/* generators.h: procedural foliage assets, no files needed.
 *
 * Each generator fills an `asset` with geometry, materials and generated RGBA8 images. Leaf,
 * blade and wire textures are alpha-mapped like production foliage: most texels transparent
 * (50–75 % for leaves, blades and fronds; about 79 % for the default chain-link wire, which is
 * mostly holes), thin features 1–5 texels wide, optional transparent padding, so they are the cases
 * where coverage disappears under traditional alpha testing. Everything is deterministic in `seed`.
 *
 * What it does NOT do: placement of many instances (the scene does that), animation.
 * Zero in any desc field means "default" (gen_*_defaults documents each).
 */
#ifndef FOVSIM_GENERATORS_H
#define FOVSIM_GENERATORS_H

#include <stdint.h>

#include "core/status.h"
#include "scene/scene.h"

typedef struct gen_tree_desc {
    uint32_t seed;       /* default 1 */
    float height;        /* world units (metres), default 6 */
    float crown_radius;  /* default 2 */
    int card_count;      /* crossed leaf-card clusters in the crown, default 60 */
    float card_size;     /* edge of one leaf card, default 1.2 */
    int texture_size;    /* leaf texture edge in texels (power of two), default 256 */
    float alpha_cutoff;  /* MASK cutoff of the leaf material, default 0.5 */
} gen_tree_desc;

typedef struct gen_grass_desc {
    uint32_t seed;       /* default 1 */
    float extent;        /* side of the square field, default 10 */
    int card_count;      /* grass tuft cards, default 400 */
    float blade_height;  /* default 0.5 */
    int texture_size;    /* default 128 */
    float alpha_cutoff;  /* default 0.5 */
} gen_grass_desc;

typedef struct gen_fence_desc {
    uint32_t seed;       /* default 1 (unused by the wire pattern, kept for symmetry) */
    float length;        /* along +X, default 10 */
    float height;        /* default 2 */
    float cell_size;     /* world size of one diamond mesh cell, default 0.1 */
    int texture_size;    /* texels per cell-tile texture edge, default 64 */
    int wire_texels;     /* wire thickness in texels (1..5), default 3 */
    float alpha_cutoff;  /* default 0.5 */
} gen_fence_desc;

typedef struct gen_fern_desc {
    uint32_t seed;       /* default 1 */
    float size;          /* frond length, default 1 */
    int frond_count;     /* default 8 */
    int texture_size;    /* default 128 */
    float alpha_cutoff;  /* default 0.5 */
} gen_fern_desc;

gen_tree_desc gen_tree_defaults(const gen_tree_desc *d);
gen_grass_desc gen_grass_defaults(const gen_grass_desc *d);
gen_fence_desc gen_fence_defaults(const gen_fence_desc *d);
gen_fern_desc gen_fern_defaults(const gen_fern_desc *d);

/* Each fills *out (zeroed first); FS_ERR_NOMEM on allocation failure, FS_ERR_SCENE for a desc
 * value out of range (message names the field). */
fs_status gen_tree(const gen_tree_desc *d, asset *out);
fs_status gen_grass(const gen_grass_desc *d, asset *out);
fs_status gen_fence(const gen_fence_desc *d, asset *out);
fs_status gen_fern(const gen_fern_desc *d, asset *out);

#endif
