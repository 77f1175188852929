/* aniso_cull.h - anisotropic SPH blocks proven outside by an upper bound of every kernel over the block. */
#ifndef JETMESH_ANISO_CULL_H
#define JETMESH_ANISO_CULL_H
#include "field/aniso/anisotropy.h"

/* 1 when every lattice node of the box [lo, hi] (the block's first and last
 * node coordinates) provably samples at or below the threshold under the
 * anisotropic SPH field (aniso_splat.c), so the block holds no inside node
 * and no crossing; 0 when that cannot be proven. cand: the block's
 * candidates (anisotropy.h). *inner gets the number of
 * particles (not isolated) within the box. The proof, and that of the
 * partial sums (jm_aniso_partial) proving nodes inside: docs/culling.md,
 * part A. */
int jm_aniso_block_outside(const jm_grid *g, const jm_config *c, const jm_an_cand *cand, const float lo[3],
                           const float hi[3], size_t *inner);
#endif
