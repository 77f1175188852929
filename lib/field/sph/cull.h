/* cull.h - SPH sampling kept near the surface: blocks proven outside skipped, nodes proven inside by partial sums not sampled. */
#ifndef JETMESH_CULL_H
#define JETMESH_CULL_H
#include "field/field.h"
#include <math.h>

/* The cubic spline's shape (1/4)(2-q)^3 - (1-q)^3 (each cube where its
 * base is positive) in double, for the bounds of the culling proofs
 * (docs/culling.md): evaluated with margin, never for output. */
static inline double jm_cull_kernel(double q)
{
    double a = 2.0 - q, b = 1.0 - q;
    a = a > 0.0 ? a : 0.0;
    b = b > 0.0 ? b : 0.0;
    return 0.25 * a * a * a - b * b * b;
}

/* A block a third or more full of particles at the rest spacing 2r (inner
 * of them within the box [lo, hi]: 0.3 of (box volume / (2r)^3) or more)
 * holds fluid enough that block.c proves its nodes inside with partial sums
 * and samples only the rest, and jm_sph_block_outside does not try its
 * proof there. Speed only (docs/culling.md). */
#define JM_FULL_FILL 0.3
/* The anisotropic kernels' exact partial sums (aniso_splat.c) pay only in
 * blocks nine tenths full. Speed only. */
#define JM_AN_FULL_FILL 0.9
/* 1 when inner particles at the rest spacing 2r fill the fraction frac of
 * the box [lo, hi] or more */
static inline int jm_block_filled(const jm_config *c, size_t inner, const float lo[3], const float hi[3], double frac)
{
    const double fill = (double)inner * 8.0 * c->r * c->r * c->r;
    const double vol = (double)(hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    return fill >= frac * vol;
}
static inline int jm_sph_block_full(const jm_config *c, size_t inner, const float lo[3], const float hi[3])
{
    return jm_block_filled(c, inner, lo, hi, c->aniso ? JM_AN_FULL_FILL : JM_FULL_FILL);
}

/* T as a float at least T (the proofs' levels, docs/culling.md) */
static inline float jm_float_up(double T)
{
    const float t = (float)T;
    return (double)t < T ? nextafterf(t, INFINITY) : t;
}

/* The partial sums' kernel (jm_sph_partial): two tangents of the cubic
 * spline's shape W as a function of s = q^2, at s = 0.64 and s = 1.74,
 * each lowered by 1e-3: W(sqrt s) is convex in s (docs/culling.md, the
 * lemma), so max(0, line 1, line 2) is a lower bound of the kernel with no
 * square root. Together they keep about 0.80 of a uniform interior's field
 * within JM_PART_REACH. test_cull.c checks the lines against W. */
#define JM_TAN_A1 0.807f
#define JM_TAN_B1 0.6f
#define JM_TAN_A2 0.3073f
#define JM_TAN_B2 0.1318f

/* The level above which a partial sum (jm_sph_partial) proves its node's
 * sample above the threshold, for the block of the hood h: the threshold
 * raised by the rounding of both sums (docs/culling.md, 3), from the count and
 * weight sum of the hood's particles that are not isolated (h->live,
 * h->wsum); +infinity (nothing proven) when the threshold is not above 0
 * or the hood holds 1e5 such particles or more. */
float jm_sph_partial_threshold(const jm_config *c, const jm_hood *h);

/* 1 when every lattice node of the box [lo, hi] (the block's first and last
 * node coordinates) provably samples at or below the threshold under the
 * isotropic SPH field (splat.c), so the block holds no inside node and no
 * crossing; 0 when that cannot be proven. *inner gets the number of
 * particles (not isolated) within the box; a full block
 * (jm_sph_block_full) returns 0 at once. The proof: docs/culling.md,
 * part I. */
int jm_sph_block_outside(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float lo[3],
                         const float hi[3], size_t *inner);

/* Bytes of the span array jm_sph_spans fills for n nodes a side. */
#define JM_CULL_SPAN_BYTES(n) (2 * (size_t)(n) * (size_t)(n) + 16) /* 16: splat.c's eight-row loads */

/* From the partial sums part of the n^3 nodes (rows of JM_PAD(n), see
 * jm_sph_partial), span[2 r], span[2 r + 1] get [a, b), the nodes of node
 * row r = k n + j to sample (a == b: none): every node whose partial sum is
 * not above threshold (jm_sph_partial_threshold for the isotropic field,
 * the threshold itself for the anisotropic one's exact partial sums) and
 * its 26 neighbours lie in the spans; every node outside them is proven
 * inside. Returns the number of nodes in the spans
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
