/* cavities.h - removes closed inward-facing shells smaller than a particle (sub-particle bubbles inside bulk fluid). */
#ifndef JETMESH_CAVITIES_H
#define JETMESH_CAVITIES_H

#include "core/internal.h"

/* Finds the connected components of the mesh (triangles sharing vertices)
 * and removes each one whose signed volume is negative (a closed shell
 * facing inward: a cavity inside the solid) and smaller in magnitude than
 * max_volume, compacting the arrays in place (order kept, so the result is
 * deterministic). nrm and uv may be NULL. *out_removed gets the number of
 * cavities removed. roots (NULL: none) is an array of *nv entries the pass
 * works in; when nothing was removed it holds each vertex's piece as
 * jm_mesh_pieces gives it (pieces.h), for smoothing to use again. pool
 * (NULL: this thread) finds the pieces. 0 if out of memory (the mesh is
 * then unchanged). */
/* vol[root] (vol zeroed, one entry per vertex) gets the signed volume of
 * each piece of the nt triangles idx, parent[v] being v's root as
 * jm_mesh_pieces gives it; summed in a fixed order whatever the pool's
 * threads. 0 if out of memory. */
int jm_piece_volumes(jm_mem *mem, jm_pool *pool, const float *pos, const uint32_t *idx, size_t nt,
                     const uint32_t *parent, double *vol);

int jm_drop_small_cavities(jm_mem *mem, jm_pool *pool, float *pos, float *nrm, float *uv, uint32_t *idx, size_t *nv,
                           size_t *ni, double max_volume, uint32_t *roots, size_t *out_removed);

#endif
