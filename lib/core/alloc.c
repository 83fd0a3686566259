/* meristem — the allocator hook (meristem/alloc.h) and lib's calls through it. */
#include "config.h"

#include <meristem/alloc.h>

#include <assert.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include "core/alloc.h"

/* The one piece of process state the hook needs; set before use (alloc.h). */
static mer_malloc_fn use_malloc = malloc;
static mer_realloc_fn use_realloc = realloc;
static mer_free_fn use_free = free;

void mer_set_alloc_funcs(mer_malloc_fn malloc_fn, mer_realloc_fn realloc_fn,
                         mer_free_fn free_fn)
{
    if (malloc_fn == NULL && realloc_fn == NULL && free_fn == NULL) {
        use_malloc = malloc;
        use_realloc = realloc;
        use_free = free;
        return;
    }
    assert(malloc_fn != NULL && realloc_fn != NULL && free_fn != NULL);
    use_malloc = malloc_fn;
    use_realloc = realloc_fn;
    use_free = free_fn;
}

void mer_get_alloc_funcs(mer_malloc_fn *malloc_fn, mer_realloc_fn *realloc_fn,
                         mer_free_fn *free_fn)
{
    if (malloc_fn)
        *malloc_fn = use_malloc;
    if (realloc_fn)
        *realloc_fn = use_realloc;
    if (free_fn)
        *free_fn = use_free;
}

void *merp_malloc(size_t size)
{
    return use_malloc(size);
}

void *merp_calloc(size_t count, size_t size)
{
    if (size != 0 && count > SIZE_MAX / size)
        return NULL;
    /* The C library's calloc hands out fresh pages without writing them: a big
     * grid costs time and memory only where it is touched. */
    if (use_malloc == malloc)
        return calloc(count ? count : 1, size ? size : 1);
    void *p = use_malloc(count * size);
    if (p != NULL)
        memset(p, 0, count * size);
    return p;
}

void *merp_realloc(void *ptr, size_t size)
{
    return use_realloc(ptr, size);
}

void merp_free(void *ptr)
{
    use_free(ptr);
}

void merp_prefault(void *ptr, size_t from, size_t to)
{
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    /* Under a virtual machine a page fault costs several times the page: a
     * growing node array maps its pages in one call per pass. Only the C
     * library's blocks: every page the range touches then belongs to the block
     * or to the library's heap, both mapped and writable. */
    if (ptr == NULL || to <= from || use_malloc != malloc)
        return;
    size_t page = (size_t)sysconf(_SC_PAGESIZE);
    uintptr_t lo = (uintptr_t)ptr + from, hi = (uintptr_t)ptr + to;
    lo -= lo % page;
    hi += (page - hi % page) % page;
    (void)madvise((void *)lo, hi - lo, MADV_POPULATE_WRITE);
#else
    (void)ptr;
    (void)from;
    (void)to;
#endif
}
