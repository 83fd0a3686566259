// meristem — tinygltf's implementation, compiled once, with image loading and
// file-system access compiled out (gltf/tinygltf_private.h): meristem writes
// geometry, never textures, and lib does no I/O.
#include "config.h"

#define TINYGLTF_IMPLEMENTATION
#include "gltf/tinygltf_private.h"
