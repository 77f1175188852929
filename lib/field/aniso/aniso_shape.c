/* aniso_shape.c - an anisotropic kernel's axes and how far its centre moves: the neighbourhood's shape, held back where it would open air pockets, thin a sheet, lose a droplet or reach past a rim. */
#include "field/aniso/aniso_shape.h"
#include <math.h>

/* Issue 31: with Yu & Turk's axes (proportional to the covariance's
 * eigenvalues, the smallest at least 1/k_r of the largest, here scaled to a
 * geometric mean of 1) a sheet's kernels flatten to 0.4 h = 0.8 r along its
 * normal, reaching 1.6 r: between layers 2 r apart the field fell to 0.3,
 * under the threshold (a closed inner shell, air inside the liquid), one
 * layer came out 26 % thinner than the isotropic surface (the same integral
 * in a narrower profile), and the particles just under any surface, whose
 * neighbourhoods the surface also cuts, flattened as well and opened holes
 * wherever the liquid is packed unevenly. Three bounds on the axes:
 * - JM_AN_NOISE: eigenvalue ratios up to 1.5 are left isotropic (only the
 *   part beyond shapes the axes): a full neighbourhood measures up to about
 *   that, and the particles a layer or two under a surface (ratios 1.3 to
 *   2.5) shape no surface, only holes.
 * - JM_AN_FLOOR: the shortest axis is at least 0.7 times the rest spacing
 *   2r (support 2.8 r): layers of the rest spacing, and the looser ones of
 *   real splashes and walls, overlap above the threshold (a stack of layers
 *   2r apart needs 0.55 in a model of infinite layers).
 * - JM_AN_SHEET: and at least 0.85 (2r)^2 / T, T = sqrt(12 s3 + (2r)^2) the
 *   thickness of the liquid along that axis (s3 the covariance's least
 *   eigenvalue: for L layers 2r apart, T = 2 r L): one layer keeps its
 *   thickness within 3 % of the isotropic surface's, two and more within 2 %
 *   in that model.
 * And a droplet near a sheet has the sheet's neighbourhood: its centre moved
 * several r into the sheet and its kernel took the sheet's shape. The near
 * count (jm_an_near: particles within the support, counted smoothly; one
 * layer has 8 to 10, a flat surface 15, bulk 23) holds both back: centres
 * move fully from 10 (jm_an_move_weight), kernels take their shape fully
 * from 5 (jm_an_shape_weight: single particles, pairs and threes keep the
 * sphere; sparse single layers, 4 to 9, need their flattening most). */
#define JM_AN_NOISE 1.5
#define JM_AN_FLOOR 0.7
#define JM_AN_SHEET 0.85
#define JM_AN_MOVE_LO 5.0
#define JM_AN_MOVE_HI 10.0
#define JM_AN_SHAPE_LO 2.0
#define JM_AN_SHAPE_HI 5.0
/* jm_an_rim: the mean's offset (in r) from which a kernel counts as a rim's,
 * fully from the second */
#define JM_AN_RIM_LO 0.5
#define JM_AN_RIM_HI 1.5

void jm_an_near_radius(const jm_config *c, float *S2, float *invB)
{
    const float S = c->support < c->an_radius ? c->support : c->an_radius;
    *S2 = S * S;
    *invB = 1.0f / (S * S * (1.0f - 0.5625f));
}

/* 0 up to lo, 1 from hi, smoothly (C1) between */
static double ramp(double x, double lo, double hi)
{
    double t = (x - lo) / (hi - lo);
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    return t * t * (3.0 - 2.0 * t);
}

double jm_an_move_weight(double near) { return ramp(near, JM_AN_MOVE_LO, JM_AN_MOVE_HI); }

double jm_an_shape_weight(double near) { return ramp(near, JM_AN_SHAPE_LO, JM_AN_SHAPE_HI); }

void jm_an_axes(const jm_config *c, const double val[3], double alpha, double s[3])
{
    /* ratios beyond the noise, at most k_r, to a geometric mean of 1 */
    double sv[3];
    for (int k = 0; k < 3; k++) {
        const double v = JM_AN_NOISE * val[k] / val[0];
        sv[k] = v < 1.0 ? v : 1.0;
        sv[k] = sv[k] > 1.0 / c->an_kr ? sv[k] : 1.0 / c->an_kr;
    }
    const double gm = cbrt(sv[0] * sv[1] * sv[2]);
    for (int k = 0; k < 3; k++) s[k] = sv[k] / gm;
    /* the floor f on the short axes (relative to h), the longer ones
     * shrunk alike so that the product stays 1 (s descending, f <= 1) */
    const double d = 2.0 * c->r, T = sqrt(12.0 * (val[2] > 0.0 ? val[2] : 0.0) + d * d);
    double f = d * fmax(JM_AN_FLOOR, JM_AN_SHEET * d / T) / c->sph_h;
    f = f < 1.0 ? f : 1.0;
    if (s[2] < f) {
        const double g = sqrt(s[2] / f);
        if (s[1] * g >= f) {
            s[0] *= g;
            s[1] *= g;
        } else {
            s[0] = 1.0 / (f * f);
            s[1] = f;
        }
        s[2] = f;
    }
    /* alpha blends toward the sphere, geometrically (the product stays) */
    for (int k = 0; k < 3; k++) s[k] = c->an_ks * (alpha < 1.0 ? pow(s[k], alpha) : s[k]);
}

/* (the sphere's reach / the kernel's reach)^2 along a direction with squared
 * cosines d2 to the axes s, the axes wider than the sphere (ks) shortened by
 * the fraction b: rises with b, and is at least 1 at b = 1 */
static double rim_f(const double s[3], const double d2[3], double ks, double b)
{
    double f = 0.0;
    for (int k = 0; k < 3; k++) {
        const double q = s[k] > ks ? ks + (s[k] - ks) * (1.0 - b) : s[k];
        f += d2[k] * (ks / q) * (ks / q);
    }
    return f;
}

/* Issue 31: a rim's kernels (a sheet's edge, a filament's end) widen along
 * the liquid, past the rim into the air, and joined to it the droplets that
 * the isotropic field keeps apart. Outward is away from the neighbourhood's
 * weighted mean; the axes wider than the sphere shrink alike by the least
 * fraction that brings the reach that way back to the sphere's, weighted by
 * the mean's offset (none under 0.5 r, where its direction is noise; all
 * from 1.5 r). The caller keeps the integral: no liquid is lost. */
void jm_an_rim(const jm_config *c, const double R[9], const double mean[3], double s[3])
{
    const double ml = sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]);
    const double w = ramp(ml / c->r, JM_AN_RIM_LO, JM_AN_RIM_HI), ks = c->an_ks;
    if (w <= 0.0) return;
    /* d2: the squared cosines of the outward direction with the axes */
    double d2[3];
    for (int k = 0; k < 3; k++) {
        const double d = (R[k] * mean[0] + R[3 + k] * mean[1] + R[6 + k] * mean[2]) / ml;
        d2[k] = d * d;
    }
    double lo = 0.0, hi = 1.0;
    if (rim_f(s, d2, ks, 0.0) >= 1.0) return;
    for (int it = 0; it < 30; it++) {
        const double mid = 0.5 * (lo + hi);
        if (rim_f(s, d2, ks, mid) < 1.0) lo = mid;
        else hi = mid;
    }
    for (int k = 0; k < 3; k++)
        if (s[k] > ks) s[k] = ks + (s[k] - ks) * (1.0 - w * hi);
}
