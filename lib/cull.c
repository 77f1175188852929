/* cull.c - SPH blocks proven to lie outside the surface, skipped unsampled: an upper bound of the field over the block.
 *
 * Why a skipped block never holds a crossing, so the mesh keeps its bytes.
 *
 * 1. What a node holds. splat.c gives node x the float sum, in the hood's
 *    particle order, of the terms t_p = fl(wgt_p * w_p), w_p the float cubic
 *    0.25 A^3 - B^3 (A = 2 - q, B = 1 - q, clamped at 0) at
 *    q_p = fl(fl(sqrt(dx^2 + dy^2 + dz^2)) * fl(1 / sph_h)), over particles
 *    that are not isolated. Every term is >= 0: wgt_p = 1 / (a sum >= 1) > 0,
 *    and A >= 2 B makes 0.25 A^3 >= 2 B^3 (a few ulps of rounding cannot undo
 *    a factor 2).
 *
 * 2. An upper bound. The block's nodes are the floats x[0..B], y[0..B],
 *    z[0..B], increasing: all lie in the box [lo, hi] of its first and last
 *    ones. Let dmin_p be the distance from particle p to that box (computed
 *    in double from the float coordinates); every node x has
 *    |x - q_p| >= dmin_p. The real kernel W(q) = 0.25 (2-q)+^3 - (1-q)+^3 is
 *    non-increasing and 1-Lipschitz. With u = 2^-24, the float q_p is at
 *    least (1 - 8u) times the real |x - q_p| / sph_h (three subtractions,
 *    three products, two sums, the square root, fl(1 / sph_h) and the last
 *    product: at most 8 relative roundings), and the float kernel is within
 *    10u of W at the float q (terms <= 2, three roundings each). So
 *    w_p <= W(dmin_p / sph_h) + 26u and t_p <= wgt_p (W(dmin_p / sph_h) +
 *    26u)(1 + u). A particle with dmin_p >= R (1 + 1e-5), R = 2 sph_h, has a
 *    float q > 2 at every node: w_p = 0 exactly, and adding +0 changes no
 *    sum. Over the m other ("near") particles, a float sum of non-negative
 *    terms is at most their exact sum times (1 + u)^(m-1) <= 1 + 1.01 m u
 *    (m u < 0.01). Hence every node holds
 *        v <= (U + 26u S)(1 + u)(1 + 1.01 m u)
 *          <= (U + 4e-6 S)(1 + 1.2e-7 (m + 8)),
 *    U = sum over the near p of wgt_p W(dmin_p / sph_h), S = the sum of
 *    their wgt_p (26u < 1.6e-6 and u + 1.02 m u < 1.2e-7 (m + 1); the double
 *    arithmetic computing dmin and U errs by ~1e-16 relative, far inside
 *    that slack). When the right side is below the threshold, every node has
 *    v < threshold: no node is inside (v > threshold). Blocks with m >= 1e5
 *    near particles are never skipped.
 *
 * 3. The same mesh. block.c marks the nodes inside (v > threshold) and, when
 *    no node of a block is inside, returns with nothing meshed before any
 *    cube is looked at. A block proven here returns at the same point, with
 *    the same (empty) result; the other blocks are sampled exactly as
 *    before. So the mesh has the same bytes for any thread count.
 *
 * Only whole blocks are skipped. Sub-boxes (4, 8 and 12 cubes a side, a row
 * span each, the spans' runs kept in step with the full ones for the same
 * bits) were measured on the 100k block and the dam break and bunny frames:
 * the nodes they skip are the ones few particles reach, so the kernel lanes
 * fell by 3 % (dam break, 4 cubes) while the bounds and spans cost more
 * (callgrind instructions +3 to +17 % against no culling). Inside the fluid no box can be proven: at threshold 0.6 the bound
 * sum of W at the farthest point is about 0.55 over a single cube of the
 * r/2 lattice where the field is about 1.0.
 */
#include "cull.h"
#include <math.h>

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])

static double kernel(double q)
{
    double a = 2.0 - q, b = 1.0 - q;
    a = a > 0.0 ? a : 0.0;
    b = b > 0.0 ? b : 0.0;
    return 0.25 * a * a * a - b * b * b;
}

int jm_sph_block_outside(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float lo[3],
                         const float hi[3])
{
    const double thr = c->threshold, sph_h = c->sph_h, Rn = (double)c->support * (1.0 + 1e-5), Rn2 = Rn * Rn;
    if (!(thr > 0.0)) return 0; /* every node is >= 0 */
    const double blo[3] = {lo[0], lo[1], lo[2]}, bhi[3] = {hi[0], hi[1], hi[2]};
    /* a first cut: splat.c's own filter (the particles it skips add nothing) */
    const float R = c->support;
    const float bx0 = lo[0] - R, bx1 = hi[0] + R, by0 = lo[1] - R, by1 = hi[1] + R, bz0 = lo[2] - R, bz1 = hi[2] + R;
    const size_t cells = (size_t)hood->n[0] * hood->n[1] * hood->n[2];
    double U = 0.0, S = 0.0;
    size_t m = 0;
    for (size_t k = 0; k < cells; k++)
        for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {
            const float *q = GP(g, p);
            if (q[0] < bx0 || q[0] > bx1 || q[1] < by0 || q[1] > by1 || q[2] < bz0 || q[2] > bz1) continue;
            if (g->isolated[p]) continue;
            double d2 = 0.0;
            for (int a = 0; a < 3; a++) {
                double qa = q[a], d = qa < blo[a] ? blo[a] - qa : (qa > bhi[a] ? qa - bhi[a] : 0.0);
                d2 += d * d;
            }
            if (d2 >= Rn2) continue;
            const double wgt = g->weight[p];
            U += wgt * kernel(sqrt(d2) / sph_h);
            S += wgt;
            m++;
            if (U >= thr || m >= 100000) return 0; /* no proof possible */
        }
    return (U + 4e-6 * S) * (1.0 + 1.2e-7 * ((double)m + 8.0)) < thr;
}
