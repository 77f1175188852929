/* splat.h - SPH field sampling on a block: the kernel splatted row by row in SIMD chosen at run time. */
#ifndef JETMESH_SPLAT_H
#define JETMESH_SPLAT_H
#include "field.h"

/* Samples phi on the n^3 nodes x[i], y[j], z[k] into pad (n * n rows of
 * JM_PAD(n) floats: node (i, j, k) at (k n + j) JM_PAD(n) + i). The AVX2, SSE2 and plain C
 * variants perform the same IEEE operations in the same order (no FMA), so
 * every machine gives the same bits. */
void jm_sph_sample(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y,
                   const float *z, int n, float *pad);
#endif
