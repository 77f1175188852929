/* aniso_shape.h - an anisotropic kernel's axes and how far its centre moves: the neighbourhood's shape, held back where it would open air pockets, thin a sheet, lose a droplet or reach past a rim. */
#ifndef JETMESH_ANISO_SHAPE_H
#define JETMESH_ANISO_SHAPE_H
#include "core/internal.h"

/* A neighbour at squared distance d2 in the near count: 1 within 3/4 of
 * the near radius S (S2 = S^2), falling linearly in d2 to 0 at S (invB =
 * 1 / (S2 - (3S/4)^2)): how many particles lie about a particle, changing
 * continuously as they move. Float, the same operations on every path
 * (aniso_moments.c, jm_an_add). */
static inline float jm_an_near(float d2, float S2, float invB)
{
    float t = (S2 - d2) * invB;
    t = t > 0.0f ? t : 0.0f;
    return t < 1.0f ? t : 1.0f;
}

/* S2 and invB of the near count: S the SPH support 2h (at most r_n). */
void jm_an_near_radius(const jm_config *c, float *S2, float *invB);

/* How far a particle's centre moves toward its smoothed place, 0 to 1,
 * from its near count (itself not counted): 0 for droplets and small
 * clusters (up to 5 others within the support), 1 from 10 (one layer of
 * particles has 8 to 10, a flat surface about 15, bulk 23), smoothly. */
double jm_an_move_weight(double near);

/* How much a kernel takes its neighbourhood's shape, 0 (a sphere) to 1,
 * from its near count: 0 up to 2 others within the support, 1 from 5. */
double jm_an_shape_weight(double near);

/* The axes s[0] >= s[1] >= s[2] relative to h (their product k_s^3) of a
 * kernel along the eigenvectors of its neighbourhood's covariance, from its
 * eigenvalues val (descending) and the shape weight alpha. */
void jm_an_axes(const jm_config *c, const double val[3], double alpha, double s[3]);

/* Shortens the axes s (from jm_an_axes) of a kernel at the rim of its
 * neighbourhood so that it reaches no further out, away from the
 * neighbourhood's weighted mean (mean, relative to the particle), than the
 * sphere: R the axes' unit vectors as columns (R[3 a + k]: component a of
 * axis k). The caller keeps the kernel's integral. */
void jm_an_rim(const jm_config *c, const double R[9], const double mean[3], double s[3]);
#endif
