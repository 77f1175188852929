/* scratch_even.c - the workers' growing scratch evened out after a frame's blocks, so that any worker can take any block of a frame as large without allocating. */
#include "extract/scratch_even.h"
#include <string.h>

/* *p, an array of cap elements of width bytes (contents not kept), grown
 * to hold want of them */
static int widen(jm_mem *mem, void **p, size_t *cap, size_t want, size_t width)
{
    if (want <= *cap) return 1;
    void *q = jm_realloc_lasting(mem, *p, *cap * width, want * width);
    if (!q) return 0;
    *p = q;
    *cap = want;
    return 1;
}

int jm_scratch_even(jm_scratch *s, int n)
{
    if (n < 2) return 1;
    /* the largest of every capacity */
    jm_scratch big;
    memset(&big, 0, sizeof big);
    for (int i = 0; i < n; i++) {
        const jm_scratch *w = &s[i];
        if (w->hood.cap > big.hood.cap) big.hood.cap = w->hood.cap;
        if (w->soa.cap > big.soa.cap) big.soa.cap = w->soa.cap;
        if (w->cap_order > big.cap_order) big.cap_order = w->cap_order;
        if (w->an_list.cap > big.an_list.cap) big.an_list.cap = w->an_list.cap;
        if (w->an_cand.cap > big.an_cand.cap) big.an_cand.cap = w->an_cand.cap;
    }
    /* and each worker's probe, normals and roots to every other's */
    int ok = 1;
    for (int i = 0; i < n && ok; i++) {
        jm_scratch *w = &s[i];
        ok = widen(w->hood.mem, (void **)&w->hood.range, &w->hood.cap, big.hood.cap, 2 * sizeof(uint32_t)) &&
             widen(w->soa.mem, (void **)&w->soa.buf, &w->soa.cap, big.soa.cap, 4 * sizeof(float)) &&
             widen(w->hood.mem, (void **)&w->order, &w->cap_order, big.cap_order, sizeof(uint32_t)) &&
             widen(w->an_list.mem, (void **)&w->an_list.buf, &w->an_list.cap, big.an_list.cap, 10 * sizeof(float)) &&
             widen(w->an_cand.mem, (void **)&w->an_cand.idx, &w->an_cand.cap, big.an_cand.cap, sizeof(uint32_t));
        for (int j = 0; j < n && ok; j++)
            if (j != i)
                ok = jm_probe_match(&w->probe, &s[j].probe) && jm_mnorm_match(&w->mnorm, &s[j].mnorm) &&
                     jm_roots_match(&w->roots, &s[j].roots);
    }
    return ok;
}
