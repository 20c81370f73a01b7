/* stb_png.h: stb_image (PNG only) for tests that read the real textures of ../shared directly.
 * Static linkage: libtinygltf carries its own copy of stb_image. Its unused static declarations
 * are reported at the end of the including file, so that warning stays off there. */
#ifndef FOVSIM_STB_PNG_H
#define FOVSIM_STB_PNG_H

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#endif
