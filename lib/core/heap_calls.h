/* heap_calls.h - the count of the library's calls to the system's allocator, which a frame after the first must not make. */
#ifndef JETMESH_HEAP_CALLS_H
#define JETMESH_HEAP_CALLS_H
#include <stddef.h>

/* Every call the library makes to malloc, calloc, realloc, posix_memalign,
 * free, mmap, mremap or munmap for its arrays: jm_heap_note() counts one,
 * jm_heap_calls() the count so far (tests: tests/test_realtime.c). */
void jm_heap_note(void);
size_t jm_heap_calls(void);
#endif
