/* anisotropy.h - Yu-Turk anisotropic SPH kernels: per-particle smoothed centres and kernel matrices, and the kernels each block looks at. */
#ifndef JETMESH_ANISOTROPY_H
#define JETMESH_ANISOTROPY_H
#include "field/aniso/aniso_shape.h"
#include "field/field.h"

/* Per sorted particle, JM_AN_STRIDE floats in g->an:
 *   [0..2]   the smoothed centre cbar
 *   [3..8]   M = G^T G (m00, m01, m02, m11, m12, m22), world^-2: the kernel
 *            argument is q = sqrt(d^T M d), d = x - cbar, support q < 2
 *   [9]      amp = V_j h^3 det(G): the particle's weight on the cubic w(q)
 *   [10..12] half-sides of the box around cbar holding the ellipsoid q < 2
 *   [13]     gmin: at most the float q the splat computes at any point x,
 *            divided by |x - cbar| (its smallest axis scale, less the float
 *            slack of docs/culling.md, A.2) */
#define JM_AN_STRIDE 14

/* Accumulates one particle's neighbourhood (itself included) for the
 * weighted mean and covariance, in double, relative to the particle (the
 * brute-force path of jm_field_eval; the grid sums float lanes). */
typedef struct jm_an_acc {
    double w, s[3], ss[6];
    int count;   /* neighbours within the radius, itself not counted */
    double near; /* the near count, itself included (jm_an_near) */
} jm_an_acc;

static inline void jm_an_add(jm_an_acc *a, const float xi[3], const float xj[3], float radius, float S2, float invB)
{
    double d[3] = {(double)xj[0] - xi[0], (double)xj[1] - xi[1], (double)xj[2] - xi[2]};
    double l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], R = radius;
    const float f[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
    a->near += jm_an_near(f[0] * f[0] + f[1] * f[1] + f[2] * f[2], S2, invB);
    if (!(l2 < R * R)) return;
    double l = sqrt(l2) / R, w = 1.0 - l * l * l;
    a->w += w;
    for (int k = 0; k < 3; k++) a->s[k] += w * d[k];
    a->ss[0] += w * d[0] * d[0];
    a->ss[1] += w * d[0] * d[1];
    a->ss[2] += w * d[0] * d[2];
    a->ss[3] += w * d[1] * d[1];
    a->ss[4] += w * d[1] * d[2];
    a->ss[5] += w * d[2] * d[2];
    a->count += l2 > 0.0;
}

/* The particle's JM_AN_STRIDE floats from its accumulated neighbourhood and
 * its volume weight V (g->weight: 1 / sum of w(q) over its neighbours). */
void jm_an_finish(const jm_config *c, const float xi[3], const jm_an_acc *a, float V, float out[JM_AN_STRIDE]);

/* Fills g->an (counted in mem) and g->an_reach for every particle of g. */
jm_status jm_aniso_build(jm_grid *g, jm_mem *mem, jm_pool *pool, const jm_config *c);
void jm_aniso_free(jm_grid *g, jm_mem *mem);

/* The kernels (not isolated) whose box reaches a block's box [lo, hi]
 * widened by margin, as sorted particle indices in the hood's order: what
 * the block's sampling, culling and normals look at (each with its own
 * test on top, so the same kernels in the same order as over the hood). */
typedef struct jm_an_cand {
    uint32_t *idx;
    size_t n, cap; /* kernels, capacity */
    jm_mem *mem;   /* counts idx (NULL: uncounted) */
} jm_an_cand;
/* 0 if out of memory */
int jm_aniso_candidates(const jm_grid *g, const jm_hood *hood, const float lo[3], const float hi[3], float margin,
                        jm_an_cand *out);

/* The kernels reaching the box [lo, hi], for normals: groups of 8, each
 * JM_AN_GROUP floats (centre x8, y8, z8, m00 x8 ... m22 x8, amp x8). */
#define JM_AN_GROUP 80
typedef struct jm_an_list {
    float *buf;
    size_t n, cap; /* kernels (n = SIZE_MAX: out of memory), capacity */
    jm_mem *mem;   /* counts buf (NULL: uncounted) */
} jm_an_list;
/* From the candidates of a block whose widened box holds [lo, hi]. */
void jm_aniso_gather(const jm_grid *g, const jm_an_cand *cand, const float lo[3], const float hi[3], jm_an_list *out);
#endif
