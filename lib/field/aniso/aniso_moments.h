/* aniso_moments.h - the weighted moments of a particle's neighbourhood for the anisotropic kernels, two particles at a time (AVX-512) or one (C). */
#ifndef JETMESH_ANISO_MOMENTS_H
#define JETMESH_ANISO_MOMENTS_H
#include <stddef.h>

/* The radii of the sums: R2 = r_n^2 and invR = 1 / r_n for the moments,
 * S2 and invB for the near count (anisotropy.h, jm_an_near). */
typedef struct jm_an_radii {
    float R2, invR, S2, invB;
} jm_an_radii;

/* The moments of particle (px, py, pz) over the candidates xs[t], ys[t],
 * zs[t], t < 8 groups (padded with far points): with d = x_t - p,
 * d2 = |d|^2 and w = 1 - (sqrt(d2) invR)^3 where d2 < R2, else 0, the
 * sums of w, w d (3), w d d^T (6: xx, xy, xz, yy, yz, zz), of the
 * neighbours (0 < d2 < R2) and of jm_an_near(d2) (itself included), in
 * that order. Each is summed in 8 float lanes, lane l taking the candidates
 * t = l (mod 8) in order, then the lanes in double in order 0..7: the same
 * bits on every path. */
#define JM_AN_MOMENTS 12
void jm_an_moments(const float *xs, const float *ys, const float *zs, size_t groups, const float p[3],
                   const jm_an_radii *rad, double out[JM_AN_MOMENTS]);
/* The same for two particles p and q (AVX-512 runs both in one pass). */
void jm_an_moments2(const float *xs, const float *ys, const float *zs, size_t groups, const float p[3],
                    const float q[3], const jm_an_radii *rad, double out_p[JM_AN_MOMENTS],
                    double out_q[JM_AN_MOMENTS]);

/* Keeps, in order, the m candidates xs[t], ys[t], zs[t] within r_n (R2 =
 * r_n^2, with 1e-4 to spare for float distances) of the box [lo, hi]
 * holding a cell's particles: the others add exact zeros to every moment
 * of every particle there (a third of the cells around a cell lie out of
 * reach of all of it). Returns the count kept; the same on every path
 * (AVX-512, AVX2 or C: the same float comparisons). */
size_t jm_an_keep_in_reach(float *xs, float *ys, float *zs, size_t m, const float lo[3], const float hi[3], float R2);
#endif
