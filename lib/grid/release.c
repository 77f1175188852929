/* release.c - the SPH grid's arrays on whole pages, given back behind the block sweep, and freed as counted. */
#include "grid/release.h"
#include <stdatomic.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

static atomic_int mode_key = 1, mode_release = 1;
static _Atomic size_t mode_page; /* 0: REL_PAGE */
void jm_testing_grid_mode(int key_order, int release, size_t page)
{
    atomic_store(&mode_key, key_order != 0);
    atomic_store(&mode_release, release);
    atomic_store(&mode_page, page);
}

/* Released in whole 2 MiB pages: the arrays of a grid that may be released
 * start on such a page (so that what is released, and counted, is the same
 * on every run) and are advised huge, so that the next frame, which takes
 * the same memory again, faults it back once per 2 MiB, not per 4 KiB */
#define REL_PAGE ((size_t)2 << 20)
static size_t rel_page(void) { return atomic_load(&mode_page) ? atomic_load(&mode_page) : REL_PAGE; }

/* SPH grids are numbered in key order, and can be released */
int jm_grid_keyed(const jm_config *c) { return c->field == JM_FIELD_SPH && atomic_load(&mode_key); }

/* An array of a grid: where it can be released and spans a page at least,
 * aligned to the page and advised huge */
void *jm_grid_alloc(const jm_config *c, jm_grid *g, jm_mem *mem, size_t bytes)
{
    const size_t ps = rel_page();
    if (!jm_grid_keyed(c) || bytes < ps) return jm_alloc(mem, bytes);
    g->aligned_min = ps;
    void *p = jm_alloc_aligned(mem, bytes, ps);
    jm_huge_advise(p, bytes);
    return p;
}

/* The whole pages of [base, base + prefix) from the first not yet released
 * (*rel bytes from the first whole page) on: returned to the system and no
 * longer counted. */
static void release_prefix(jm_mem *mem, void *base, size_t prefix, size_t *rel)
{
    const uintptr_t ps = rel_page(), a = (uintptr_t)base, e = a + (prefix & ~(ps - 1));
    if (!base || (a & (ps - 1))) return; /* smaller than a page: not aligned */
    if (e <= a + *rel) return;
#if defined(__linux__) && defined(MADV_DONTNEED)
    void *from = (void *)(a + *rel);
    const size_t len = e - a - *rel;
    if (madvise(from, len, MADV_DONTNEED) != 0) return; /* still held: still counted */
    if (atomic_load(&mode_release) == 2) mprotect(from, len, PROT_NONE);
    jm_mem_sub(mem, len);
    *rel = e - a;
#else
    (void)mem; /* elsewhere the pages are not given back: nothing changes */
#endif
}

/* Frees an array of `bytes` (as counted when taken) of which rel were
 * released; aligned_min: as in jm_grid (an array from jm_alloc goes back
 * through jm_free, to the context's kept blocks). */
void jm_grid_free_released(jm_mem *mem, void *p, size_t bytes, size_t rel, size_t aligned_min)
{
    if (!p) return;
    if (!rel && (!aligned_min || (bytes ? bytes : 1) < aligned_min)) {
        jm_free(mem, p, bytes);
        return;
    }
#if defined(__linux__)
    if (rel && atomic_load(&mode_release) == 2) {
        mprotect(p, rel, PROT_READ | PROT_WRITE);
    }
#endif
    jm_free(NULL, p, bytes);
    jm_mem_sub(mem, (bytes ? bytes : 1) - rel);
}

void jm_grid_release_below(jm_grid *g, jm_mem *mem, int64_t cz)
{
    if (!g->slab_first || !g->cell_start || atomic_load(&mode_release) == 0 || cz <= g->slab_z0) return;
    const size_t j = (uint64_t)(cz - g->slab_z0) > g->slab_n ? g->slab_n : (size_t)(cz - g->slab_z0);
    const uint32_t cells = g->slab_first[j];
    if (cells <= g->rel_cells) return;
    g->rel_cells = cells;
    const size_t parts = g->cell_start[cells];
    release_prefix(mem, g->pos, 3 * parts * sizeof(float), &g->rel[0]);
    release_prefix(mem, g->weight, parts * sizeof(float), &g->rel[1]);
    release_prefix(mem, g->isolated, parts, &g->rel[2]);
    release_prefix(mem, g->cell_start, cells * sizeof(uint32_t), &g->rel[3]);
    if (g->dense && cz > g->dense_lo[2]) {
        int64_t dz = cz - g->dense_lo[2];
        if (dz > g->dense_n[2]) dz = g->dense_n[2];
        release_prefix(mem, g->dense, (size_t)(dz * g->dense_n[0] * g->dense_n[1]) * sizeof *g->dense, &g->rel[4]);
    }
}
