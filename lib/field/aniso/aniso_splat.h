/* aniso_splat.h - the anisotropic SPH field on a block: kernels splatted row by row (AVX-512/AVX2/SSE2/C), every node, spans or partial sums. */
#ifndef JETMESH_ANISO_SPLAT_H
#define JETMESH_ANISO_SPLAT_H
#include "field/aniso/anisotropy.h"

/* Samples the anisotropic field on the n^3 nodes into pad (n * n rows of
 * JM_PAD(n) floats, as jm_sph_sample), from the block's candidates
 * (anisotropy.h). Each node sums its particles in the global order of the
 * grid's cells (nodes outside a kernel add exact zeros),
 * so a node shared by two blocks gets the same bits. span (NULL: every node)
 * limits the samples to the nodes [span[2 r], span[2 r + 1]) of each row
 * r = k n + j (cull.h's jm_sph_spans): those get the same bits as without
 * it, the other nodes undefined values. The AVX-512, AVX2, SSE2 and plain C
 * variants perform the same IEEE operations in the same order (no FMA). */
void jm_aniso_sample(const jm_grid *g, const jm_config *c, const jm_an_cand *cand, const float *x, const float *y,
                     const float *z, int n, const uint8_t *span, float *pad);

/* The partial sums count a kernel's terms only where its argument q is
 * under JM_AN_PART_REACH of its support 2. Speed only. */
#define JM_AN_PART_REACH 0.6f
/* Partial sums into out (laid out as pad): each node gets, in the same order
 * and with the same bits, a subset of the terms jm_aniso_sample adds there,
 * so, every term being >= 0 and float addition monotone, out <= the node's
 * sample (the proof: docs/culling.md, A.3). */
void jm_aniso_partial(const jm_grid *g, const jm_config *c, const jm_an_cand *cand, const float *x, const float *y,
                      const float *z, int n, float *out);
#endif
