/* meristem — tinygltf as libmeristem builds it: image loading compiled out
 * (meristem writes geometry, never textures) and its warnings silenced (it is
 * not our code). lib/gltf/tinygltf.cc defines TINYGLTF_IMPLEMENTATION before
 * including this; the C++ unit tests include it to read our output back. Not
 * installed. */
#ifndef MERISTEM_TINYGLTF_PRIVATE_H
#define MERISTEM_TINYGLTF_PRIVATE_H

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wnull-dereference"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wcast-align"
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
#pragma GCC diagnostic ignored "-Wpedantic"
#endif
#include <tiny_gltf.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#endif
