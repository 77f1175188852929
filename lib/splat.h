/* splat.h - SPH field sampling on a block: the kernel splatted row by row in SIMD chosen at run time. */
#ifndef JETMESH_SPLAT_H
#define JETMESH_SPLAT_H
#include "field.h"

/* Samples phi on the n^3 nodes x[i], y[j], z[k] into pad (n * n rows of
 * JM_PAD(n) floats: node (i, j, k) at (k n + j) JM_PAD(n) + i). span (NULL:
 * every node) limits the samples to the nodes [span[2 r], span[2 r + 1]) of
 * each row r = k n + j (see cull.h): those get the same bits as without it,
 * the other nodes undefined values. The AVX-512, AVX2, SSE2 and plain C
 * variants perform the same IEEE operations in the same order (no FMA), so
 * every machine gives the same bits. */
void jm_sph_sample(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y,
                   const float *z, int n, const uint8_t *span, float *pad);

/* The partial sums count a particle's terms on the rows within
 * JM_PART_REACH of its support radius, on a window of nodes about its own
 * (0.6: measured best with 0.55 and 0.7 on the 100k block and the dam break
 * and bunny frames; 0.5 proves too few nodes of the block inside). */
#define JM_PART_REACH 0.6f
/* Partial sums into out (laid out as pad): each node gets, in the same order
 * and with the same bits, a subset of the terms jm_sph_sample adds there, so,
 * every term being >= 0 and float addition monotone, out <= the node's
 * sample. */
void jm_sph_partial(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y,
                    const float *z, int n, float *out);
#endif
