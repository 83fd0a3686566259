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

#ifdef __cplusplus
}
#endif

#endif
