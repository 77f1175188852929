/* alloc.c - counted heap allocation: every byte a context holds is tracked for peak and limits. */
#include "core/internal.h"
#include "core/keep.h"
#include <stdlib.h>
#include <stdatomic.h>
#include <stdint.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

/* Arrays this large are often given back to the system between frames
 * (malloc maps large blocks afresh and unmaps them on free, and trims its
 * heap's top), so a frame touches their pages anew. In 4 KiB pages each
 * first touch is a fault (tens of thousands on an 8M-particle frame);
 * advised huge, the kernel maps 2 MiB at a fault, far less work per byte. */
#define HUGE_MIN ((size_t)4 << 20)
#define HUGE_PAGE ((uintptr_t)2 << 20)

void jm_huge_advise(void *p, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (!p) return;
    /* the whole 2 MiB pages inside [p, p + bytes) */
    uintptr_t a = ((uintptr_t)p + HUGE_PAGE - 1) & ~(HUGE_PAGE - 1), e = ((uintptr_t)p + bytes) & ~(HUGE_PAGE - 1);
    if (e > a) madvise((void *)a, e - a, MADV_HUGEPAGE); /* advice only: a refusal changes nothing */
#else
    (void)p;
    (void)bytes;
#endif
}

static void *huge(void *p, size_t bytes)
{
    if (bytes >= HUGE_MIN) jm_huge_advise(p, bytes);
    return p;
}

/* The counters are updated from worker threads, hence atomics. */
static void count_add(jm_mem *a, size_t bytes)
{
    size_t now = atomic_fetch_add(&a->current, bytes) + bytes;
    size_t peak = atomic_load(&a->peak);
    while (now > peak && !atomic_compare_exchange_weak(&a->peak, &peak, now)) {
    }
}

static void count_sub(jm_mem *a, size_t bytes)
{
    atomic_fetch_sub(&a->current, bytes);
}

/* Counts bytes unless that takes the total past the limit (checked where
 * memory is taken, so the limit holds whatever the estimates said): then
 * counts nothing, records the refusal and returns 0. */
static int count_take(jm_mem *a, size_t bytes)
{
    if (!a->limit) {
        count_add(a, bytes);
        return 1;
    }
    size_t now = atomic_fetch_add(&a->current, bytes) + bytes;
    if (now > a->limit || now < bytes) {
        atomic_fetch_sub(&a->current, bytes);
        atomic_store(&a->over, 1);
        size_t r = atomic_load(&a->refused);
        while (now > r && !atomic_compare_exchange_weak(&a->refused, &r, now)) {
        }
        return 0;
    }
    size_t peak = atomic_load(&a->peak);
    while (now > peak && !atomic_compare_exchange_weak(&a->peak, &peak, now)) {
    }
    return 1;
}

void jm_mem_add(jm_mem *m, size_t bytes) { count_add(m, bytes); }
void jm_mem_sub(jm_mem *m, size_t bytes) { count_sub(m, bytes); }
int jm_mem_take(jm_mem *m, size_t bytes) { return count_take(m, bytes); }

int jm_mul_size(size_t a, size_t b, size_t *out)
{
    if (a != 0 && b > SIZE_MAX / a) return 0;
    *out = a * b;
    return 1;
}

/* A context's blocks of at most JM_KEEP_MAX bytes come from its kept
 * blocks and go back to them (keep.h); everything else from malloc. */
static int kept(const jm_mem *m, size_t bytes) { return m && m->keep && bytes <= JM_KEEP_MAX; }

void *jm_raw_alloc(jm_mem *m, size_t bytes)
{
    if (bytes == 0) bytes = 1;
    jm_heap_note();
    return malloc(kept(m, bytes) ? jm_keep_class_bytes(bytes) : bytes);
}

void jm_raw_free(jm_mem *m, void *p, size_t bytes)
{
    if (!p) return;
    if (bytes == 0) bytes = 1;
    if (kept(m, bytes)) jm_keep_give(m->keep, p, bytes);
    else {
        jm_heap_note();
        free(p);
    }
}

void *jm_alloc(jm_mem *m, size_t bytes)
{
    if (bytes == 0) bytes = 1;
    if (m && !count_take(m, bytes)) return NULL;
    if (!kept(m, bytes)) jm_heap_note();
    void *p = kept(m, bytes) ? jm_keep_take(m->keep, bytes) : malloc(bytes);
    if (!p && m) count_sub(m, bytes);
    return huge(p, bytes);
}

void *jm_alloc_lasting(jm_mem *m, size_t bytes)
{
    if (bytes == 0) bytes = 1;
    if (m && !count_take(m, bytes)) return NULL;
    void *p = jm_raw_alloc(m, bytes);
    if (!p && m) count_sub(m, bytes);
    return huge(p, bytes);
}

void *jm_realloc_lasting(jm_mem *m, void *p, size_t old_bytes, size_t new_bytes)
{
    if (new_bytes == 0) new_bytes = 1;
    if (!p) old_bytes = 0;
    const size_t ob = old_bytes ? old_bytes : 1;
    if (!kept(m, new_bytes) && !(p && kept(m, ob))) return jm_realloc(m, p, old_bytes, new_bytes);
    if (p && kept(m, ob) && kept(m, new_bytes) && jm_keep_class_bytes(ob) == jm_keep_class_bytes(new_bytes))
        return jm_realloc(m, p, old_bytes, new_bytes); /* the same block */
    void *q = jm_alloc_lasting(m, new_bytes);
    if (!q) return NULL;
    if (p) memcpy(q, p, old_bytes < new_bytes ? old_bytes : new_bytes);
    jm_free(m, p, old_bytes);
    return q;
}

void *jm_alloc_aligned(jm_mem *m, size_t bytes, size_t align)
{
    if (bytes == 0) bytes = 1;
    if (m && !count_take(m, bytes)) return NULL;
    void *p = NULL;
    jm_heap_note();
    if (posix_memalign(&p, align, bytes) != 0) p = NULL;
    if (!p && m) count_sub(m, bytes);
    return huge(p, bytes);
}

void *jm_calloc(jm_mem *m, size_t n, size_t size)
{
    size_t bytes;
    if (!jm_mul_size(n, size, &bytes)) return NULL;
    if (bytes == 0) bytes = 1;
    if (kept(m, bytes)) {
        void *p = jm_alloc(m, bytes);
        if (p) memset(p, 0, bytes);
        return p;
    }
    if (m && !count_take(m, bytes)) return NULL;
    jm_heap_note();
    void *p = calloc(1, bytes);
    if (!p && m) count_sub(m, bytes);
    return huge(p, bytes);
}

void *jm_realloc(jm_mem *m, void *p, size_t old_bytes, size_t new_bytes)
{
    if (new_bytes == 0) new_bytes = 1;
    if (!p) old_bytes = 0;
    if (kept(m, new_bytes) || (p && kept(m, old_bytes ? old_bytes : 1))) {
        const size_t ob = old_bytes ? old_bytes : 1;
        if (p && kept(m, ob) && kept(m, new_bytes) && jm_keep_class_bytes(ob) == jm_keep_class_bytes(new_bytes)) {
            /* the block holds both sizes: only the count changes */
            if (new_bytes > ob && !count_take(m, new_bytes - ob)) return NULL;
            if (new_bytes < ob) count_sub(m, ob - new_bytes);
            return p;
        }
        void *q = jm_alloc(m, new_bytes);
        if (!q) return NULL;
        if (p) memcpy(q, p, old_bytes < new_bytes ? old_bytes : new_bytes);
        jm_free(m, p, old_bytes);
        return q;
    }
    size_t grow = new_bytes > old_bytes ? new_bytes - old_bytes : 0;
    if (m && grow && !count_take(m, grow)) return NULL;
    jm_heap_note();
    void *q = huge(realloc(p, new_bytes), new_bytes);
    if (!q) {
        if (m && grow) count_sub(m, grow);
        return NULL;
    }
    if (m && new_bytes < old_bytes) count_sub(m, old_bytes - new_bytes);
    return q;
}

void jm_free(jm_mem *m, void *p, size_t bytes)
{
    if (!p) return;
    jm_raw_free(m, p, bytes);
    if (m) count_sub(m, bytes == 0 ? 1 : bytes);
}
