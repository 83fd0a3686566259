/* meristem — the library's allocator hook, after jansson's json_set_alloc_funcs.
 *
 * Every buffer libmeristem allocates in its C parts (scenes, skeletons, markers,
 * shadow grids, meshes, the bytes mer_gltf_write_tree and mer_gltf_read_triangles
 * return) goes through the three functions set here. The glTF module's C++
 * internals (tinygltf's model, std::vector and std::string scratch space inside
 * one call) stay on the default C++ allocator: a failure there surfaces as
 * std::bad_alloc, which every entry point maps to MER_ERR_NOMEM.
 *
 * The hook exists so that a program can bound or account for the library's
 * memory, and so that tests can fail the N-th allocation and check the promise
 * of meristem/result.h: a call that returns MER_ERR_NOMEM changed nothing.
 */
#ifndef MERISTEM_ALLOC_H
#define MERISTEM_ALLOC_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Same contracts as the C library's malloc, realloc and free: a NULL return means
 * failure (and for realloc leaves the old block as it was); free takes NULL. */
typedef void *(*mer_malloc_fn)(size_t size);
typedef void *(*mer_realloc_fn)(void *ptr, size_t size);
typedef void (*mer_free_fn)(void *ptr);

/* Makes the library allocate with `malloc_fn`, `realloc_fn` and `free_fn`. Passing
 * NULL for all three restores the C library's functions; otherwise all three must
 * be non-NULL. Process-wide and not thread-safe: call it before any other
 * mer_ function, or while no other thread is in the library, and never while the
 * library still owns memory from the previous functions (scenes, meshes, bytes
 * not yet freed), which would be freed with the new `free_fn`. Cost O(1). */
void mer_set_alloc_funcs(mer_malloc_fn malloc_fn, mer_realloc_fn realloc_fn,
                         mer_free_fn free_fn);

/* The functions in use (never NULL). Any argument may be NULL. Cost O(1). */
void mer_get_alloc_funcs(mer_malloc_fn *malloc_fn, mer_realloc_fn *realloc_fn,
                         mer_free_fn *free_fn);

#ifdef __cplusplus
}
#endif

#endif
