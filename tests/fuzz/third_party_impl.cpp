// third_party_impl.cpp: fuzz build only (FOVSIM_FUZZ). tinygltf and stb_image compiled from their
// Debian headers with libFuzzer's coverage and the sanitizers, into fuzz_gltf and fuzz_scene_json.
// Debian's libtinygltf.so and libstb.so are not instrumented: inside them libFuzzer would see no
// branch and ASan no out-of-bounds access. These definitions, being in the executable, take
// precedence over the shared libraries' (same headers, same version, default options as Debian's
// build of tiny_gltf.cc: nlohmann-json, stb_image, stb_image_write).
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <tiny_gltf.h>
