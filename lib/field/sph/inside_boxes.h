/* inside_boxes.h - SPH nodes proven inside a box of 3 x 3 x 3 nodes at a time: each particle's tangent line at the box's centre node. */
#ifndef JETMESH_INSIDE_BOXES_H
#define JETMESH_INSIDE_BOXES_H
#include "field/sph/cull.h"
#include <math.h>

/* The box pass (jm_sph_boxes) runs, instead of the partial sums
 * (jm_sph_partial), on blocks JM_BOX_FILL full of fluid or more (the fill of
 * jm_sph_block_full) when the lattice is fine against the kernel: cube
 * edge h at most JM_BOX_MAX_H smoothing lengths (the box bound loses about
 * 4.5 (h / sph_h)^2 of the field at its corners: at h = sph_h / 4 it proves
 * a uniform interior's nodes by a margin of 0.05 at threshold 0.6, and at
 * 0.375 sph_h none). Next to the surface, where a box's corners lose more,
 * the partial sums prove more nodes. Speed only: both passes give lower
 * bounds (docs/culling.md). */
#define JM_BOX_FILL 0.8
#define JM_BOX_MAX_H 0.26
/* Rows of boxes within JM_BOX_REACH of the support radius of a particle
 * get its terms (0.65 proves no node of a uniform interior, 0.7 all; 0.75
 * keeps a margin). Speed only: any subset of terms is a bound. */
#define JM_BOX_REACH 0.75f

/* 1 when the box pass applies to a block whose box [lo, hi] holds inner
 * particles (not isolated). */
int jm_sph_boxes_apply(const jm_config *c, size_t inner, const float lo[3], const float hi[3]);

/* The level above which a node's bound from jm_sph_boxes proves its sample
 * above the threshold, for the block of the hood h: the threshold raised
 * by the sample's rounding (the bounds come with their own rounding taken
 * off, docs/culling.md, 3b), from h->live and h->wsum; +infinity (nothing proven)
 * when the threshold is not above 0 or the hood holds 1e5 particles not
 * isolated or more. */
float jm_sph_box_threshold(const jm_config *c, const jm_hood *h);

/* Lower bounds into out (laid out as jm_sph_partial's): the lattice's
 * boxes of up to 3 x 3 x 3 nodes (along x from even node index to even,
 * overlapping; along y and z the nodes 3 i .. 3 i + 2, tiling) each get one
 * bound valid at all their nodes, and each node the best of its boxes' (a
 * node whose value is above jm_sph_box_threshold samples above the
 * threshold). n <= 33 (blocks of at most 32 cubes). AVX-512 where the CPU
 * has it, else AVX2 with FMA, else plain C (cpu.h's level): the bound
 * holds for either rounding, so the paths may prove different nodes but the
 * samples, and meshes, are the same. */
void jm_sph_boxes(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y,
                  const float *z, int n, void *work, float *out);
/* The path jm_sph_boxes runs, from cpu.h's level (jm_testing_force_cpu). */
enum { JM_BOX_C = 0, JM_BOX_AVX2 = 1, JM_BOX_AVX512 = 2 };
int jm_box_path(void);
/* Bytes of the work buffer jm_sph_boxes takes (a block scratch's, block.c;
 * suitably aligned for floats). */
size_t jm_box_work_bytes(void);

/* The lines of the box pass, for tests: bin k < JM_BOX_BINS - 1 holds the
 * tangent of W(sqrt s) at s = (k + 1/2) / JM_BOX_BINS_PER_S lowered by
 * JM_BOX_LOWER, the last bin the zero line; a[k] - b[k] s with s in units of
 * sph_h^2 (jm_config's box_a, box_b hold b over sph_h^2, for s in world
 * units). */
#define JM_BOX_BINS_PER_S 8.0
#define JM_BOX_LOWER 1e-4
void jm_box_lines(float a[JM_BOX_BINS], float b[JM_BOX_BINS], double inv_sph_h2);
/* The largest distance along one axis from a box's centre node to its
 * nodes (box i: centre min(S i + 1, n - 1), nodes S i .. S i + 2 below
 * n; along x S = 2, overlapping, along y and z S = 3, tiling), in double
 * from the float nodes (not exactly evenly spaced), raised a little: the
 * sph and the anisotropic box passes' reach (docs/culling.md). */
static inline double jm_box_extent(const float *t, int n, int S, int nb)
{
    double m = 0.0;
    for (int i = 0; i < nb; i++) {
        const int cc = S * i + 1 < n ? S * i + 1 : n - 1;
        for (int k = S * i; k <= S * i + 2 && k < n; k++) m = fmax(m, fabs((double)t[k] - (double)t[cc]));
    }
    return m * (1.0 + 1e-9);
}
/* The AVX2 box rows' windows of 8 boxes (of a row's 16) that the boxes
 * marked in live (bit k: box k in a particle's reach; live != 0) need: one
 * window at woff[0] when they span fewer than 8, else both halves. Returns
 * the number of windows. */
static inline int jm_box_windows(unsigned live, int woff[2])
{
    const int first = __builtin_ctz(live), last = 31 - __builtin_clz(live);
    if (last - first < 8) {
        woff[0] = first < 8 ? first : 8;
        return 1;
    }
    woff[0] = 0;
    woff[1] = 8;
    return 2;
}
#endif
