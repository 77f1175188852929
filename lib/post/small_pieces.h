/* small_pieces.h - removes a mesh's outward pieces enclosing less than a volume, with the cavities inside them. */
#ifndef JETMESH_SMALL_PIECES_H
#define JETMESH_SMALL_PIECES_H
#include "core/internal.h"

/* Removes every connected piece whose signed volume is from 0 to below
 * min_volume (an outward shell: a stray blob), and every piece of negative
 * volume (a cavity) lying inside one of those (its winding number about
 * it), compacting the arrays in place in order (nrm, uv may be NULL).
 * *out_removed gets the outward pieces removed. The same result for any
 * pool. 0 if out of memory (the mesh then unchanged). */
int jm_drop_small_pieces(jm_mem *mem, jm_pool *pool, float *pos, float *nrm, float *uv, uint32_t *idx, size_t *nv,
                         size_t *ni, double min_volume, size_t *out_removed);
#endif
