/* cull.h - SPH sampling kept near the surface: blocks proven outside skipped, nodes proven inside by partial sums not sampled. */
#ifndef JETMESH_CULL_H
#define JETMESH_CULL_H
#include "field.h"

/* The cubic spline's shape (1/4)(2-q)^3 - (1-q)^3 (each cube where its
 * base is positive) in double, for the bounds of the culling proofs
 * (cull.c, aniso_cull.c): evaluated with margin, never for output. */
static inline double jm_cull_kernel(double q)
{
    double a = 2.0 - q, b = 1.0 - q;
    a = a > 0.0 ? a : 0.0;
    b = b > 0.0 ? b : 0.0;
    return 0.25 * a * a * a - b * b * b;
}

/* A block about full of particles at the rest spacing 2r (inner of them
 * within the box [lo, hi]: 0.85 of (box volume / (2r)^3) or more) is mostly
 * inside the fluid: block.c proves its nodes inside with partial sums, and
 * jm_sph_block_outside does not try its proof there. Speed only. */
static inline int jm_sph_block_full(const jm_config *c, size_t inner, const float lo[3], const float hi[3])
{
    const double fill = (double)inner * 8.0 * c->r * c->r * c->r;
    const double vol = (double)(hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    return fill >= 0.85 * vol;
}

/* 1 when every lattice node of the box [lo, hi] (the block's first and last
 * node coordinates) provably samples at or below the threshold under the
 * isotropic SPH field (splat.c), so the block holds no inside node and no
 * crossing; 0 when that cannot be proven. *inner gets the number of
 * particles (not isolated) within the box; a full block
 * (jm_sph_block_full) returns 0 at once. The proof is at the top of
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
/* The box of a block's spans: the slabs [k0, k1) holding one, in slab k the
 * rows [j0[k], j1[k]) (j0 >= j1: none), the nodes [i0, i1) covering every
 * span. A kernel reaching no row and node of it adds to no span: the span
 * samplers (splat.c, aniso_splat.c) skip it and the rows outside the box,
 * whose spans are empty, so every span node keeps its terms and their
 * order. Speed only. */
typedef struct {
    int k0, k1, i0, i1;
    int j0[JM_PAD_MAX], j1[JM_PAD_MAX];
} jm_span_box;
void jm_span_box_of(const uint8_t *span, int n, jm_span_box *b);
#endif
