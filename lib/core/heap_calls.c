/* heap_calls.c - the count of the library's calls to the system's allocator, which a frame after the first must not make. */
#include "core/heap_calls.h"
#include <stdatomic.h>

static _Atomic size_t heap_calls;
void jm_heap_note(void) { atomic_fetch_add_explicit(&heap_calls, 1, memory_order_relaxed); }
size_t jm_heap_calls(void) { return atomic_load(&heap_calls); }
