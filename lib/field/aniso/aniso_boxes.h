/* aniso_boxes.h - anisotropic SPH nodes proven inside a box of 3 x 3 x 3 nodes at a time: each kernel's tangent line in q^2 at the box's centre node. */
#ifndef JETMESH_ANISO_BOXES_H
#define JETMESH_ANISO_BOXES_H
#include "field/aniso/anisotropy.h"

/* The box pass runs on blocks JM_AN_BOX_FILL full of fluid or more (the
 * fill of jm_block_filled) when the lattice is fine against the kernel
 * (cube edge at most JM_BOX_MAX_H smoothing lengths, as the isotropic box
 * pass, inside_boxes.h); the partial sums (jm_aniso_partial) on the other
 * blocks JM_AN_FULL_FILL full. A kernel adds to the box centres within
 * JM_AN_BOX_REACH of its box's half sides. Speed only: every subset of
 * terms gives a lower bound (docs/culling.md). */
#define JM_AN_BOX_FILL 0.7
#define JM_AN_BOX_REACH 0.75f

/* 1 when the box pass applies to a block whose box [lo, hi] holds inner
 * particles (not isolated). */
int jm_aniso_boxes_apply(const jm_config *c, size_t inner, const float lo[3], const float hi[3]);

/* Lower bounds into out (laid out as jm_aniso_partial's: JM_PAD(n) floats
 * a row): the lattice's boxes of up to 3 x 3 x 3 nodes (along x from even
 * node index to even, overlapping; along y and z the nodes 3 i .. 3 i + 2,
 * tiling) each get one bound valid at all their nodes, and each node the
 * best of its boxes'. Returns the level above which a node's bound proves
 * its sample (jm_aniso_sample) above the threshold: the threshold raised by
 * the sample's rounding (+infinity: nothing proven). n <= 33; work holds
 * jm_aniso_box_work_bytes() bytes. The proof: docs/culling.md, part B. */
float jm_aniso_boxes(const jm_grid *g, const jm_config *c, const jm_an_cand *cand, const float *x, const float *y,
                     const float *z, int n, void *work, float *out);

/* Bytes of the work buffer jm_aniso_boxes takes. */
size_t jm_aniso_box_work_bytes(void);

/* The lines of the box pass, for tests: bin k < JM_AN_BOX_BINS - 1 holds
 * the tangent of W(sqrt s) at s = (k + 1/2) / JM_AN_BOX_BINS_PER_S, a[k]
 * rounded down and b[k] up; the last bin (s >= 3.875: W under 1e-5) the
 * zero line. */
#define JM_AN_BOX_BINS 32
#define JM_AN_BOX_BINS_PER_S 8.0
void jm_aniso_box_lines(float a[JM_AN_BOX_BINS], float b[JM_AN_BOX_BINS]);
#endif
