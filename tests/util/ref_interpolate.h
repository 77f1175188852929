/* ref_interpolate.h - the brute-force reference of the interpolated attributes at one point: normalised cubic-spline weights in double, and the nearest particle. */
#ifndef JETMESH_TEST_REF_INTERPOLATE_H
#define JETMESH_TEST_REF_INTERPOLATE_H
#include <stddef.h>

typedef struct ref_interp {
    double sw;      /* the weights' sum (0: no particle within 2h) */
    double a[4];    /* the weighted sums of vel (3) and rho (1), not yet divided by sw */
    size_t nearest; /* the nearest particle (the fallback where sw is 0) */
} ref_interp;

/* Every one of the n particles xyz (with vel, rho) against the point p, the
 * kernel's support 2h. */
void ref_interpolate(const float *p, const float *xyz, const float *vel, const float *rho, size_t n, double h,
                     ref_interp *out);
#endif
