/* ref_interpolate.c - the brute-force reference of the interpolated attributes at one point: normalised cubic-spline weights in double, and the nearest particle. */
#include "ref_interpolate.h"
#include <math.h>

static double cubic(double q)
{
    double a = 2 - q > 0 ? 2 - q : 0, b = 1 - q > 0 ? 1 - q : 0;
    return 0.25 * a * a * a - b * b * b;
}

void ref_interpolate(const float *p, const float *xyz, const float *vel, const float *rho, size_t n, double h,
                     ref_interp *out)
{
    double bd = INFINITY;
    *out = (ref_interp){0};
    for (size_t j = 0; j < n; j++) {
        double d2 = 0;
        for (int k = 0; k < 3; k++) d2 += ((double)p[k] - xyz[3 * j + k]) * ((double)p[k] - xyz[3 * j + k]);
        if (d2 < bd) { bd = d2; out->nearest = j; }
        double q = sqrt(d2) / h;
        if (q >= 2) continue;
        double w = cubic(q);
        out->sw += w;
        for (int k = 0; k < 3; k++) out->a[k] += w * vel[3 * j + k];
        out->a[3] += w * rho[j];
    }
}
