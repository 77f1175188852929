/* grow.c - arrays that grow across a frame: their own mappings (huge pages advised) grown by mremap on Linux (pages moved, not copied), realloc elsewhere. */
#if defined(__linux__)
#define _GNU_SOURCE
#include <sys/mman.h>
#endif
#include "core/grow.h"
#include <stdlib.h>
#include <string.h>

#if defined(__linux__) && defined(MREMAP_MAYMOVE)
static int mapped(size_t bytes) { return bytes >= JM_GROW_MAP; }
#else
static int mapped(size_t bytes) { (void)bytes; return 0; }
#endif

int jm_grow_moves(size_t bytes) { return mapped(bytes); }

#if defined(__linux__) && defined(MREMAP_MAYMOVE)
/* A mapping spans whole 2 MiB pages and is advised huge (jm_huge_advise):
 * the first touch of its pages faults once per 2 MiB instead of once per
 * 4 KiB, and growing moves whole huge pages. Only the bytes asked for are
 * counted. */
#define HUGE ((size_t)2 << 20)
static size_t span(size_t bytes) { return (bytes + HUGE - 1) & ~(HUGE - 1); }
#endif

void *jm_grow(jm_mem *m, void *p, size_t old_bytes, size_t new_bytes)
{
    if (new_bytes == 0) new_bytes = 1;
    if (!p) old_bytes = 0;
    if (!mapped(old_bytes) && !mapped(new_bytes)) return jm_realloc_lasting(m, p, old_bytes, new_bytes);
    size_t grow = new_bytes > old_bytes ? new_bytes - old_bytes : 0;
    if (m && grow && !jm_mem_take(m, grow)) return NULL;
    void *q = NULL;
#if defined(__linux__) && defined(MREMAP_MAYMOVE)
    if (mapped(old_bytes) && mapped(new_bytes)) {
        if (span(old_bytes) != span(new_bytes)) jm_heap_note();
        q = span(old_bytes) == span(new_bytes) ? p : mremap(p, span(old_bytes), span(new_bytes), MREMAP_MAYMOVE);
        if (q == MAP_FAILED) q = NULL; /* a moved mapping keeps its advice */
    } else if (mapped(new_bytes)) { /* from the heap into a mapping */
        jm_heap_note();
        q = mmap(NULL, span(new_bytes), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (q == MAP_FAILED) q = NULL;
        if (q) jm_huge_advise(q, span(new_bytes));
        if (q && p) {
            memcpy(q, p, old_bytes);
            jm_raw_free(m, p, old_bytes);
        }
    } else { /* from a mapping back to the heap */
        q = jm_raw_alloc(m, new_bytes);
        if (q) {
            memcpy(q, p, new_bytes);
            jm_heap_note();
            munmap(p, span(old_bytes));
        }
    }
#endif
    if (!q) {
        if (m && grow) jm_mem_sub(m, grow);
        return NULL;
    }
    if (m && new_bytes < old_bytes) jm_mem_sub(m, old_bytes - new_bytes);
    return q;
}

void jm_grow_free(jm_mem *m, void *p, size_t bytes)
{
    if (!p) return;
    if (bytes == 0) bytes = 1;
#if defined(__linux__) && defined(MREMAP_MAYMOVE)
    if (mapped(bytes)) {
        jm_heap_note();
        munmap(p, span(bytes));
        if (m) jm_mem_sub(m, bytes);
        return;
    }
#endif
    jm_free(m, p, bytes);
}
