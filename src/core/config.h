/* config.h: compile-time limits of fovsim.
 *
 * Each limit is guarded with #ifndef so a build can override it with -D. Runtime choices do not
 * belong here; they go in the *_desc structs of the module that uses them.
 */
#ifndef FOVSIM_CONFIG_H
#define FOVSIM_CONFIG_H

#define FOVSIM_VERSION "0.1.0"

/* Most assets one scene may reference (glTF files or generators). */
#ifndef MAX_SCENE_ASSETS
#define MAX_SCENE_ASSETS 64
#endif

/* Most camera keyframes in a scene's camera path. */
#ifndef MAX_CAMERA_KEYS
#define MAX_CAMERA_KEYS 256
#endif

/* Largest texture edge accepted from an asset, in texels (GL 4.5 guarantees 16384). */
#ifndef MAX_TEXTURE_SIZE
#define MAX_TEXTURE_SIZE 16384
#endif

/* Largest display edge accepted, in pixels. */
/* glTF JSON: arrays and objects nested deeper than this are refused before tinygltf parses them
 * (its parser recurses; 20,000 levels overflowed the stack). Real assets nest about 8 deep. */
#ifndef MAX_GLTF_JSON_DEPTH
#define MAX_GLTF_JSON_DEPTH 64
#endif

/* Largest file a glTF asset may be or reference (its .gltf/.glb, .bin buffers, images), in bytes. */
#ifndef MAX_ASSET_FILE_BYTES
#define MAX_ASSET_FILE_BYTES (1u << 30)
#endif

/* glTF node hierarchy: the flattener recurses along it, so a deeper chain of children is refused. */
#ifndef MAX_GLTF_NODE_DEPTH
#define MAX_GLTF_NODE_DEPTH 1024
#endif

#ifndef MAX_DISPLAY_SIZE
#define MAX_DISPLAY_SIZE 8192
#endif

/* Most instances one scatter entry of a scene file may create (64 bytes of transform each). */
#ifndef MAX_SCATTER_COUNT
#define MAX_SCATTER_COUNT 100000
#endif

/* Most instances one scene may hold in all (64 MB of transforms). */
#ifndef MAX_SCENE_INSTANCES
#define MAX_SCENE_INSTANCES 1000000
#endif

/* Largest scene file read, in bytes (a scene file is a description, not data). */
#ifndef MAX_SCENE_FILE_BYTES
#define MAX_SCENE_FILE_BYTES (64u << 20)
#endif

/* Most foveation rings in one layout (innermost first; the last covers the display). */
#ifndef MAX_FOV_RINGS
#define MAX_FOV_RINGS 8
#endif

/* Coarsest ring resolution, as log2 of the downsampling factor (4 = 1/16). */
#ifndef MAX_FOV_SCALE_LOG2
#define MAX_FOV_SCALE_LOG2 4
#endif

/* Largest gaze trace file read, in bytes (a 2 kHz binocular EyeLink ASC hour is ~400 MB). */
#ifndef MAX_GAZE_FILE_BYTES
#define MAX_GAZE_FILE_BYTES (512u << 20)
#endif

/* Most frames one render may ask for (about 15 minutes at 120 fps). */
/* Longest line of a Tobii livedata.json (one JSON record), bytes: cJSON builds a tree of each line
 * at about 40 times its length (a 100 MB line took 4 GB). The recordings' lines are under 100. */
#ifndef MAX_TOBII_RECORD_BYTES
#define MAX_TOBII_RECORD_BYTES (64u << 10)
#endif

#ifndef MAX_FRAMES
#define MAX_FRAMES 100000
#endif
/* Latencies in one latency study (compare --gaze-latency MS,MS,...). */
#ifndef MAX_GAZE_LATENCIES
#define MAX_GAZE_LATENCIES 16
#endif

/* --fps range (README "Limits", numbers): one frame per 1000 s at the slowest, so that every frame's time
 * (MAX_FRAMES / FPS_MIN at most) is a finite 32-bit float with room to spare. */
#define FPS_MIN 0.001f
#define FPS_MAX 1000.0f

/* --wait-lock's longest wait, in seconds (a day): a run never waits without bound for another. */
#define WAIT_LOCK_MAX_S 86400

/* Frames the EXR writer may hold queued (besides one in flight per worker thread) before
 * rendering waits for it. */
#ifndef EXR_QUEUE_DEPTH
#define EXR_QUEUE_DEPTH 4
#endif

#endif
