/* cull.h - SPH blocks proven to lie outside the surface, skipped unsampled: an upper bound of the field over the block. */
#ifndef JETMESH_CULL_H
#define JETMESH_CULL_H
#include "field.h"

/* 1 when every lattice node of the box [lo, hi] (the block's first and last
 * node coordinates) provably samples at or below the threshold under the
 * isotropic SPH field (splat.c), so the block holds no inside node and no
 * crossing; 0 when that cannot be proven. The proof is at the top of
 * cull.c. */
int jm_sph_block_outside(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float lo[3],
                         const float hi[3]);
#endif
