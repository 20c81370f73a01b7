/* scene.h: everything fovsim draws, as plain C data (no GL, no C++).
 *
 * A scene is a list of assets (each one glTF file or one procedural generator), instances of those
 * assets with transforms, a camera path, a display and a light. An asset owns its primitives,
 * materials and images. Node hierarchies are flattened at load: every primitive's vertices are in
 * the asset's own space, which is also the "object space" hashed alpha anchors to (one tree = one
 * object, seed 000 §5).
 *
 * What it does NOT do: GPU upload (src/gl, src/passes), rendering decisions (plan.h), gaze.
 *
 * Usage:
 *   scene sc;
 *   fs_status s = scene_load_file("scenes/forest.json", &sc);   // or scene_load_builtin / glTF path
 *   if (s == FS_OK) s = scene_validate(&sc);
 *   ...
 *   scene_free(&sc);
 */
#ifndef FOVSIM_SCENE_H
#define FOVSIM_SCENE_H

#include <stdbool.h>
#include <stdint.h>

#include "core/config.h"
#include "core/display.h"
#include "core/fmath.h"
#include "core/status.h"
#include "fov/fov_ring.h"
#include "fov/vrs_map.h"
#include "gaze/gaze.h"
#include "gaze/gaze_tracker.h"
#include "hmd/hmd.h"
#include "common/shared_defs.h" /* FS_ALPHA_MODES, the table of alpha modes */

#ifdef __cplusplus
extern "C" {
#endif

/* >>materials */

/* How a material's alpha is meant to be used (glTF alphaMode). */
typedef enum alpha_kind {
    ALPHA_KIND_OPAQUE = 0,
    ALPHA_KIND_MASK,
    ALPHA_KIND_BLEND,
} alpha_kind;

/* Alpha-test strategy for MASK materials (docs/design.md "Alpha-test strategies",
 * docs/alpha-modes.md): one per row of FS_ALPHA_MODES (common/shared_defs.h),
 * ALPHA_MODE_TRADITIONAL = 1 and so on in the table's order. */
#define FS_ALPHA_MODE_ENUM(NAME, name, colour, traits) ALPHA_MODE_##NAME,
typedef enum alpha_mode {
    ALPHA_MODE_DEFAULT = 0, /* "not set": inherit the scene's or CLI's mode */
    FS_ALPHA_MODES(FS_ALPHA_MODE_ENUM)
    ALPHA_MODE_COUNT
} alpha_mode;
#undef FS_ALPHA_MODE_ENUM
/* Room for the modes in structs whose size is checked (run_desc): a new row of the table does not
 * change their layout. */
#define ALPHA_MODE_MAX 16
#ifndef __cplusplus
_Static_assert(ALPHA_MODE_COUNT <= ALPHA_MODE_MAX, "more alpha modes than ALPHA_MODE_MAX");
#endif

/* "traditional" etc. (the table's `name`), "default" for DEFAULT; NULL for an out-of-range value. */
const char *alpha_mode_name(alpha_mode m);
/* Parses a mode name; returns ALPHA_MODE_DEFAULT for an unknown name. */
alpha_mode alpha_mode_parse(const char *name);
/* Comma-separated list of every mode name, for error messages and --help. */
const char *alpha_mode_list(void);
/* The mode's ALPHA_TRAIT_* (common/shared_defs.h) or'ed; 0 for DEFAULT and out-of-range values. */
unsigned alpha_mode_traits(alpha_mode m);
/* Whether the mode has every trait in `traits`. */
bool alpha_mode_has(alpha_mode m, unsigned traits);
/* The mode's colour in plots as "#rrggbb" into buf (8 bytes); black for DEFAULT. Returns buf. */
const char *alpha_mode_colour(alpha_mode m, char buf[8]);

typedef enum tex_wrap { TEX_WRAP_REPEAT = 0, TEX_WRAP_CLAMP, TEX_WRAP_MIRROR } tex_wrap;
typedef enum tex_filter { TEX_FILTER_LINEAR = 0, TEX_FILTER_NEAREST } tex_filter;

/* An RGBA8 image, rows top to bottom, colour sRGB-encoded, alpha linear and straight (not
 * premultiplied), exactly as stored in PNG/JPEG. An image without an alpha channel has a = 255. */
typedef struct image_rgba8 {
    int width, height; /* texels, >= 1 */
    uint8_t *rgba;     /* width * height * 4 bytes, owned */
    char name[64];     /* for messages, may be empty */
} image_rgba8;

typedef struct material {
    char name[64];
    float base_color[4];     /* linear RGBA factor, default (1,1,1,1) */
    int base_color_image;    /* index into asset.images, -1 = none */
    tex_wrap wrap_s, wrap_t; /* default REPEAT (glTF sampler default) */
    tex_filter mag_filter;   /* default LINEAR; minification is always trilinear */
    alpha_kind alpha_kind;   /* glTF alphaMode, default OPAQUE */
    float alpha_cutoff;      /* glTF alphaCutoff, default 0.5 */
    bool double_sided;       /* glTF doubleSided, default false */
    alpha_mode alpha_mode;   /* per-material override from the scene file, DEFAULT = none */
    bool has_alpha_lod_max;  /* scene file "alpha_lod_max" given (docs/scene-format.md) */
    float alpha_lod_max;     /* with has_alpha_lod_max: the alpha test reads alpha at most at this
                              * mip level, in [0, ALPHA_LOD_MAX_LIMIT] (docs/hashed-alpha.md) */
} material;

/* >>geometry */

/* One drawable primitive: triangles, one material. Vertices are in asset space (node transforms
 * already applied). Every attribute array is always present: loaders fill missing normals with
 * computed ones, missing UVs with 0, missing colours with 1. */
typedef struct prim {
    uint32_t vertex_count;
    uint32_t index_count; /* multiple of 3 */
    float *positions;     /* 3 per vertex */
    float *normals;       /* 3 per vertex, unit length */
    float *uvs;           /* 2 per vertex, glTF convention: (0,0) = top-left of the image */
    float *colors;        /* 4 per vertex, linear (COLOR_0, default 1) */
    uint32_t *indices;    /* index_count */
    int material;         /* index into asset.materials */
} prim;

/* A camera found in an asset (glTF perspective camera), in asset space. */
typedef struct asset_camera {
    bool present;
    vec3 position, target;
    float hfov_deg;
} asset_camera;

typedef enum asset_source { ASSET_SOURCE_GLTF = 0, ASSET_SOURCE_GENERATOR } asset_source;

typedef struct asset {
    char name[128]; /* file name or generator name, for messages */
    asset_source source;
    prim *prims;
    int prim_count;
    material *materials;
    int material_count;
    image_rgba8 *images;
    int image_count;
    vec3 bounds_min, bounds_max; /* asset-space AABB of all prims */
    asset_camera camera;
} asset;

/* Frees everything an asset owns and zeroes it. No-op on a zeroed asset. */
void asset_free(asset *a);
/* Recomputes bounds_min/bounds_max from the prims. */
void asset_compute_bounds(asset *a);
/* Fills normals (area-weighted face normals) for a prim whose normals are all zero. */
void prim_compute_normals(prim *p);
/* True if the material's alpha matters: MASK or BLEND. */
bool material_is_alpha_mapped(const material *m);

/* >>scene */

/* Wind sway of one instance (src/scene/sway.h has the motion; docs/scene-format.md "sway").
 * Zeroed = still. */
typedef struct instance_sway {
    vec3 offset;     /* world displacement of the top at the wave's peak: amplitude * direction */
    float height;    /* asset-space height where the displacement reaches offset (> 0) */
    float frequency; /* Hz */
    float phase;     /* cycles, [0, 1) */
} instance_sway;

typedef struct instance {
    int asset;          /* index into scene.assets */
    mat4 transform;     /* asset space -> world space */
    instance_sway sway; /* zeroed: the instance stands still */
} instance;

/* A camera keyframe. The path between keys is a Catmull-Rom spline through positions and
 * targets, linear in fov (camera_path_eval). */
typedef struct camera_key {
    float time;     /* seconds, strictly increasing along the path */
    vec3 position;  /* world units */
    vec3 target;    /* world point looked at */
    float hfov_deg; /* horizontal field of view, 0 = the display's */
    bool cut;       /* a camera cut starts at this key (no interpolation from the previous one) */
} camera_key;

typedef struct camera_path {
    camera_key keys[MAX_CAMERA_KEYS];
    int count; /* >= 1 after load */
} camera_path;

/* Evaluated camera at one time. */
typedef struct camera_state {
    vec3 position, target;
    float hfov_deg;
} camera_state;

typedef struct light_desc {
    vec3 direction;   /* world direction the light travels (towards the ground), normalised */
    vec3 color;       /* linear radiance scale, default (1, 0.97, 0.9) */
    vec3 ambient;     /* linear ambient, default (0.25, 0.28, 0.32) */
    vec3 sky;         /* background colour, linear, default (0.45, 0.6, 0.8) */
} light_desc;

/* TAA settings from a scene file ("taa" object); zero fields = the defaults (see plan.h's
 * taa_controls). The CLI's --taa, --taa-blend, --taa-gamma, --taa-sparse and --jitter-length win. */
typedef struct scene_taa {
    bool given;         /* the scene file has a "taa" object */
    bool off;           /* "enabled": false */
    float blend, gamma; /* 0 = default */
    float sparse;       /* "sparse": 0 = default, negative = off (the file's 0 or false) */
    int jitter_length;  /* 0 = default */
} scene_taa;

typedef struct scene {
    char path[512];   /* the scene file, or "builtin:<name>" */
    asset *assets;
    int asset_count;
    instance *instances; /* grown by scene_add_instance only (its capacity is derived from the count) */
    int instance_count;
    camera_path camera;
    display_desc display;
    display_kind display_kind; /* "display": {"kind": ...}: planar (display above) or hmd (docs/hmd.md) */
    hmd_desc hmd;              /* the hmd, valid when display_kind is DISPLAY_HMD */
    light_desc light;
    alpha_mode alpha_mode; /* the scene's default mode, DEFAULT = traditional unless the CLI says */
    scene_taa taa;         /* TAA settings from the scene file */
    char rings[256];       /* foveation ring layout from the scene file ("auto", "off", "10:1:0,..."),
                              empty = not given (the CLI's --rings, else auto); the run record hashes it */
    fov_layout rings_layout; /* the same, parsed once when the file is read (valid when rings[0]);
                                FOV_LAYOUT_AUTO is resolved against the run's display later */
    foveation_kind foveation; /* "foveation": rings, vrs or off; UNSET = not given (the CLI's
                                 --foveation, else rings) */
    char vrs[128];         /* the VRS rate map from the scene file ("auto" or "10:1x1,*:4x4"), empty =
                              not given (the CLI's --vrs, else auto) */
    vrs_spec vrs_spec;     /* the same, parsed once when the file is read (valid when vrs[0]) */
    int vrs_tile;          /* "vrs_tile": 8, 16 or 32; 0 = not given (the CLI's --vrs-tile, else 16) */
    char ring_lod[128];    /* ring LOD from the scene file ("off", "simplify", "simplify:1,1,1/4"),
                              empty = not given (the CLI's --ring-lod, else off) */
    gaze_tracker_opts tracker; /* the eye tracker from the scene file's "gaze" object (latency, rate,
                                  noise, seed, loss); the CLI's --gaze-* win option by option */
    gaze_place_opts gaze_place; /* "gaze": "map" and "screen" (--gaze-map, --gaze-screen win) */
    float duration;        /* seconds: the last camera key's time (0 for a still camera) */
} scene;

/* Fills display, light, camera and mode defaults. Leaves assets and instances empty. */
void scene_init_defaults(scene *sc);
/* Loads a scene from a JSON scene file or, for a .gltf/.glb path, an asset-as-scene. */
fs_status scene_load_file(const char *path, scene *out);
/* Builds a built-in scene by name ("forest", "fence", "grass", "tree"). */
fs_status scene_load_builtin(const char *name, scene *out);
/* Space-separated names of the built-in scenes. */
const char *scene_builtin_list(void);
/* True for the name of a built-in scene ("fence"), which the command line takes for the built-in
 * even when a file or folder of that name is in the current folder. */
bool scene_is_builtin(const char *name);
/* Bounds-checks everything (indices < vertex_count, material and image indices, finite
 * positions and transforms); prints the first problem with its location. */
fs_status scene_validate(const scene *sc);
/* Frees everything the scene owns. No-op on a zeroed scene. */
void scene_free(scene *sc);
/* Adds an asset (moved in: the scene owns it afterwards and *a is zeroed); returns its index, or
 * -1 when out of memory, in which case the caller still owns *a. */
int scene_add_asset(scene *sc, asset *a);
/* Adds an instance of asset `asset_index`; returns false when out of memory. */
bool scene_add_instance(scene *sc, int asset_index, mat4 transform);
/* True when the instance sways (a nonzero offset). */
bool instance_sways(const instance *in);
/* Number of swaying instances: 0 = a static scene (the plan compiles no sway). */
int scene_sway_count(const scene *sc);
/* World-space AABB over all instances. */
void scene_bounds(const scene *sc, vec3 *min, vec3 *max);
/* A camera path that frames the whole scene from the front (used for glTF-as-scene). */
void scene_fit_camera(scene *sc);
/* A 64-bit key of everything that decides what the scene looks like from a given camera:
 * geometry, materials (not their alpha-mode overrides), images, instances, light and the
 * display's field of view. Not the camera path, the display size or the path it was loaded from:
 * those are keyed by whoever needs them (the reference cache keys each frame's camera). */
uint64_t scene_content_hash(const scene *sc);

/* Camera at time t (seconds; clamped to the path). A cut key starts a new spline: times before it
 * never interpolate towards it. */
camera_state camera_path_eval(const camera_path *path, float t);
/* True when a cut key's time lies in (t0, t1]: the frame at t1 must not reuse history from t0. */
bool camera_path_cut_between(const camera_path *path, float t0, float t1);

#ifdef __cplusplus
}
#endif

#endif
