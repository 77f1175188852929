/* aniso_cull.c - anisotropic SPH blocks proven outside by an upper bound of every kernel over the block.
 *
 * Why no crossing is ever skipped and every sampled node keeps its bits
 * (the anisotropic twin of cull.c; u = 2^-24, gamma_k = k u / (1 - k u)).
 *
 * 1. What a node holds. aniso_splat.c gives node x the float sum, in the
 *    hood's particle order, of the terms t_p = fl(amp_p * w_p) of the
 *    kernels (not isolated, their box reaching the block) whose row run
 *    covers x, w_p the float cubic 0.25 A^3 - B^3 (A = 2 - q, B = 1 - q,
 *    clamped at 0) at q = fl(sqrt(max(q2, 0))), q2 the float
 *    ((m00 dx + 2 B) dx + C), B = m01 dy + m02 dz, C = (m11 dy + 2 m12 dz)
 *    dy + m22 dz dz, (dx, dy, dz) = fl(x - cbar_p) per axis; each lane of a
 *    row computed alone. Every term is >= 0: amp_p = V / (s0 s1 s2) > 0, and
 *    A >= 2 B makes 0.25 A^3 >= 2 B^3 (a few ulps cannot undo a factor 2).
 *
 * 2. Blocks proven outside (jm_aniso_block_outside). The block's nodes are
 *    the floats x[0..B], y[0..B], z[0..B]: all lie in the box [lo, hi] of
 *    its first and last ones. Let dmin_p be the distance from the centre
 *    cbar_p to that box (in double from the floats); every node x has
 *    |x - cbar_p| >= dmin_p.
 *    a. A lower bound of q. jm_an_finish builds M = R diag(lambda_k) R^T in
 *       double, lambda_k = 1 / (h s_k)^2, R a rotation (Jacobi, orthogonal
 *       to ~1e-15), and stores M_f = fl(M) and gmin = fl(g (1 - 16 kappa u)),
 *       g = 1 / (h s_max) = sqrt(lambda_min), kappa = lambda_max /
 *       lambda_min = (s_max / s_min)^2. Then ||M_f - M||_2 <= ||M_f - M||_F
 *       <= u ||M||_F (1 + 1e-12) <= sqrt(3) u lambda_max (1 + 1e-12), and the
 *       double rounding of M and R's departure from a rotation move
 *       lambda_min by under 1e-13 lambda_max: lambda_min(M_f) >= g^2 (1 -
 *       1.8 kappa u). Expanding q2, each of its six products (m00 dx^2,
 *       2 m01 dx dy, ..., m22 dz^2; the factors 2 are exact) carries at most
 *       5 roundings, so |q2 - d_f^T M_f d_f| <= gamma_5 |d_f|^T |M_f| |d_f|
 *       <= gamma_5 ||M_f||_F |d_f|^2 <= 8.7 kappa u g^2 |d_f|^2, d_f the
 *       float differences; |d_f| >= (1 - u) |x - cbar|. Hence q2 >= g^2
 *       |x - cbar|^2 (1 - 12.6 kappa u) > 0 and, the square root rounding
 *       once, q >= g |x - cbar| (1 - 7.4 kappa u) >= gmin |x - cbar| (the
 *       conversion of gmin to float rounds up by at most u <= kappa u).
 *       Along an axis a: every node has |x_a - cbar_a| >= delta_a, the
 *       distance from cbar_a to [lo_a, hi_a], and over the d with d_a = t
 *       the least d^T M d is t^2 / (M^-1)_aa, (M^-1)_aa = h^2 sum_k s_k^2
 *       R_ak^2, whose root the stored half-side a[10 + a] exceeds by the
 *       factor 2 (1 + 1e-5) (1 - u) (its float rounding). From the bounds
 *       above, M_f >= M (1 - 1.8 kappa u) (Loewner order), the float
 *       differences move d^T M d by at most 2.1 kappa u relatively (||D M D -
 *       M|| <= 2.1 u lambda_max, D = diag(1 + e_a), |e_a| <= u), and q2 is
 *       within 8.8 kappa u of d_f^T M_f d_f relatively: q2 >= d^T M d (1 -
 *       12.7 kappa u), and q >= (2 delta_a / a[10 + a]) (1 - 7.4 kappa u)
 *       >= (2 delta_a / a[10 + a]) (1 - 20 k_r^2 u), since s_max / s_min <=
 *       k_r makes kappa <= k_r^2 (jm_an_axes clamps the ratios of the
 *       eigenvalues it keeps at k_r; its floor on the short axes and its
 *       blend toward the sphere, powers alpha <= 1 of the axes, only lower
 *       the ratio; few neighbours: a sphere). So q >= ql
 *       = the larger of gmin dmin and the largest of these axis bounds.
 *    b. An upper bound of each term. With A = fl(2 - q) = (2 - q)(1 + d0)
 *       and two roundings per cube, 0.25 A^3 is within gamma_5 of 0.25
 *       (2 - q)^3 relatively, B^3 likewise, and the difference rounds once:
 *       w_p <= (W(q) + 3 gamma_5)(1 + u) <= W(q) + 17 u, W(q) = 0.25
 *       (2 - q)+^3 - (1 - q)+^3 the real kernel, non-increasing. So t_p <=
 *       amp_p (W(ql_p) + 17 u)(1 + u) at every node. A kernel with ql_p >=
 *       2 (1 + 1e-5) has q > 2 at every node: A = B = 0, w_p = 0 exactly,
 *       and adding +0 changes no sum.
 *    c. The sum. Over the m other ("near") kernels, a float sum of
 *       non-negative terms is at most their exact sum times (1 + u)^(m-1) <=
 *       1 + 1.01 m u (m u < 0.01). Hence every node holds
 *           v <= (U + 17u S)(1 + u)(1 + 1.01 m u)
 *             <= (U + 4e-6 S)(1 + 1.2e-7 (m + 8)),
 *       U = sum over the near p of amp_p W(ql_p), S = the sum of
 *       their amp_p (the double arithmetic computing dmin and U errs by
 *       ~1e-16 relative, far inside that slack). When the right side is
 *       below the threshold no node is inside (v > threshold). block.c,
 *       finding no inside node in a block, returns before looking at any
 *       cube; a proven block returns at that same point with the same empty
 *       result. (m >= 1e5: never skipped.)
 *
 * 3. Nodes proven inside (jm_aniso_partial, then cull.c's jm_sph_spans). The
 *    partial sum of a node adds, in the same order, the same terms (bit for
 *    bit: the same operations on the same operands, the row's B, C and amp
 *    formed alike) for a subset of the (kernel, node) pairs the full sum
 *    has: the same kernels, a subset of the same slabs and rows (those also
 *    cutting the inner ellipsoid), and on each row the inner chord, inside
 *    the row's chord [i0, i1) and so inside the run [i0, e) that the full
 *    sum covers (the other lanes of a vector step add +0). The inner chord
 *    comes from the same B, C and m00 C, with fl(4 m00 rho^2) <= 4 m00 for
 *    4 m00 and no 0.01 slack: float rounding is monotone, so its
 *    discriminant is at most the full one (positive when it is), its root
 *    at most the full root, and each end, scaled by sc > 0 (m00 > 0, a
 *    diagonal entry of a positive definite M), lies within the full chord's
 *    ends; iceil, ifloor and the clips to [0, n) keep that order. By
 *    induction over the full
 *    order the partial sum never exceeds the full one: a shared term goes to
 *    fl(p + t) <= fl(f + t) (rounding is monotone), a skipped term leaves
 *    p <= f <= fl(f + t) (t >= 0). So a partial sum above the threshold
 *    proves the node inside. Part 4 of cull.c then holds word for word: no
 *    cube with a crossing loses a corner, and every node off the spans is
 *    inside.
 *
 * 4. The same bits. With spans, aniso_splat.c runs the same kernel loop in
 *    the same order with the same filters, slabs, rows and chords; of each
 *    run [i0, e) it computes [s, t) covering the run's nodes in the row's
 *    span, with s = i0 (mod 8) and t <= e. Each lane depends on its own node
 *    alone, so each node of a span gets the same terms in the same order as
 *    without culling: the same bits, on every SIMD path and for any thread
 *    count (each block decides alone). All passes take the kernels from the
 *    block's candidates (jm_aniso_candidates: the hood's kernels whose box
 *    reaches the block's box widened, in the hood's order) and test each
 *    again as they did over the hood: the same kernels in the same order.
 */
#include "field/aniso/aniso_cull.h"
#include "field/sph/cull.h"
#include <math.h>

#ifndef JM_AN_CULL_BREAK
#define JM_AN_CULL_BREAK 0
#endif
#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])
#define AN(g, i) (&(g)->an[JM_AN_STRIDE * (size_t)(i)])

int jm_aniso_block_outside(const jm_grid *g, const jm_config *c, const jm_an_cand *cand, const float lo[3],
                           const float hi[3], size_t *inner)
{
    const double thr = c->threshold, qmax = 2.0 * (1.0 + 1e-5);
    const double axis_slack = 1.0 - 20.0 * (double)c->an_kr * c->an_kr * 0x1p-24;
    int open = thr > 0.0; /* a proof is possible (every node is >= 0) */
    const double blo[3] = {lo[0], lo[1], lo[2]}, bhi[3] = {hi[0], hi[1], hi[2]};
    double U = 0.0, S = 0.0;
    size_t m = 0, in = 0;
    for (size_t ci = 0; ci < cand->n; ci++) {
        const uint32_t p = cand->idx[ci];
        const float *a = AN(g, p);
        /* aniso_splat.c's own filter (the kernels it skips add nothing) */
        if (a[0] + a[10] < lo[0] || a[0] - a[10] > hi[0] || a[1] + a[11] < lo[1] || a[1] - a[11] > hi[1] ||
            a[2] + a[12] < lo[2] || a[2] - a[12] > hi[2])
            continue;
        const float *q = GP(g, p);
        in += q[0] >= lo[0] && q[0] <= hi[0] && q[1] >= lo[1] && q[1] <= hi[1] && q[2] >= lo[2] && q[2] <= hi[2];
        if (!open) continue;
        double d2 = 0.0, ax_q = 0.0;
        for (int ax = 0; ax < 3; ax++) {
            double ca = a[ax], d = ca < blo[ax] ? blo[ax] - ca : (ca > bhi[ax] ? ca - bhi[ax] : 0.0);
            d2 += d * d;
            const double t = d / a[10 + ax];
            ax_q = t > ax_q ? t : ax_q;
        }
        /* q at every node is at least both bounds (2a) */
        const double gm = a[13], qg = gm * sqrt(d2), qa = 2.0 * ax_q * axis_slack;
        /* tests/t_aniso_cull_broken.sh: kernels bounded as if 15 % farther
         * must fail test_aniso_cull */
        const double ql = (qg > qa ? qg : qa) * (JM_AN_CULL_BREAK == 1 ? 1.15 : 1.0);
        if (ql >= qmax) continue;
        const double amp = a[9];
        U += amp * jm_cull_kernel(ql);
        S += amp;
        m++;
        if (U >= thr || m >= 100000) open = 0; /* no proof possible */
    }
    *inner = in;
    return open && (U + 4e-6 * S) * (1.0 + 1.2e-7 * ((double)m + 8.0)) < thr;
}
