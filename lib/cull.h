/* cull.h - SPH sampling kept near the surface: blocks proven outside skipped, nodes proven inside by partial sums not sampled. */
#ifndef JETMESH_CULL_H
#define JETMESH_CULL_H
#include "field.h"

/* 1 when every lattice node of the box [lo, hi] (the block's first and last
 * node coordinates) provably samples at or below the threshold under the
 * isotropic SPH field (splat.c), so the block holds no inside node and no
 * crossing; 0 when that cannot be proven. *inner gets the number of
 * particles (not isolated) within the box. The proof is at the top of
 * cull.c. */
int jm_sph_block_outside(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float lo[3],
                         const float hi[3], size_t *inner);

/* Bytes of the span array jm_sph_spans fills for n nodes a side. */
#define JM_CULL_SPAN_BYTES(n) (2 * (size_t)(n) * (size_t)(n))

/* From the partial sums part of the n^3 nodes (rows of JM_PAD(n), see
 * jm_sph_partial), span[2 r], span[2 r + 1] get [a, b), the nodes of node
 * row r = k n + j to sample (a == b: none): every node whose partial sum is
 * not above threshold and its 26 neighbours lie in the spans; every node
 * outside them is proven inside. Returns the number of nodes in the spans
 * (0: the whole block is inside). */
size_t jm_sph_spans(const float *part, int n, float threshold, uint8_t *span);
#endif
