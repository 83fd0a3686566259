/* meristem — lib's allocation functions: every allocation goes through the hook
 * of meristem/alloc.h. Not installed. */
#ifndef MERISTEM_CORE_ALLOC_H
#define MERISTEM_CORE_ALLOC_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

void *merp_malloc(size_t size);
/* Zeroed; NULL when `count` * `size` overflows. */
void *merp_calloc(size_t count, size_t size);
void *merp_realloc(void *ptr, size_t size);
void merp_free(void *ptr);
/* Maps now the pages holding bytes [from, to) of the block `ptr` (from the
 * allocation functions above), which the caller is about to write: one call
 * instead of a page fault per page. Contents are unchanged; it does nothing where
 * the system cannot or a caller's allocator is in use. O(pages). */
void merp_prefault(void *ptr, size_t from, size_t to);

#ifdef __cplusplus
}
#endif

#endif
