/* skew.h - parallel arrays in one block, each shifted a few cache lines so that their k-th elements fall in different sets of the L1 cache. */
#ifndef JETMESH_SKEW_H
#define JETMESH_SKEW_H
#include <stddef.h>

/* Per-vertex arrays of a power-of-two capacity (a multiple of 4 KiB each)
 * would share their offset within every page: a vertex's stores to ten of
 * them would all land in one set of the 8-way L1 cache and evict each
 * other. Array i of a block starts JM_SKEW bytes past the end of array
 * i - 1's capacity: three cache lines, so up to 21 arrays of one element
 * size map their k-th elements to different sets. */
#define JM_SKEW ((size_t)192)

/* The bytes of a block of k arrays of n elements of esz[i] bytes. */
static inline size_t jm_skew_bytes(const size_t *esz, int k, size_t n)
{
    size_t b = 0;
    for (int i = 0; i < k; i++) b += n * esz[i] + JM_SKEW;
    return b;
}

/* Array i's start in block b (the arrays as jm_skew_bytes counts them). */
static inline void *jm_skew_at(void *b, const size_t *esz, int i, size_t n)
{
    char *p = (char *)b;
    for (int j = 0; j < i; j++) p += n * esz[j] + JM_SKEW;
    return p;
}
#endif
