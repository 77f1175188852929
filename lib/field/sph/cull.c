/* cull.c - SPH sampling kept near the surface: blocks proven outside skipped, nodes proven inside by partial sums not sampled.
 *
 * Why no crossing is ever skipped and every sampled node keeps its bits.
 *
 * 1. What a node holds. splat.c gives node x the float sum, in the hood's
 *    particle order, of the terms t_p = fl(wgt_p * w_p), w_p the float cubic
 *    0.25 A^3 - B^3 (A = 2 - q, B = 1 - q, clamped at 0) at
 *    q_p = fl(fl(sqrt(dx^2 + dy^2 + dz^2)) * fl(1 / sph_h)), over particles
 *    that are not isolated, each lane of a row computed alone. Every term is
 *    >= 0: wgt_p = 1 / (a sum >= 1) > 0, and A >= 2 B makes 0.25 A^3 >= 2 B^3
 *    (a few ulps of rounding cannot undo a factor 2).
 *
 * 2. Blocks proven outside (jm_sph_block_outside). The block's nodes are the
 *    floats x[0..B], y[0..B], z[0..B], increasing: all lie in the box
 *    [lo, hi] of its first and last ones. Let dmin_p be the distance from
 *    particle p to that box (in double from the float coordinates); every
 *    node x has |x - q_p| >= dmin_p. The real kernel W(q) = 0.25 (2-q)+^3 -
 *    (1-q)+^3 is non-increasing and 1-Lipschitz. With u = 2^-24, the float
 *    q_p is at least (1 - 8u) times the real |x - q_p| / sph_h (at most 8
 *    relative roundings), and the float kernel is within 10u of W at the
 *    float q (terms <= 2, three roundings each). So w_p <= W(dmin_p / sph_h)
 *    + 26u and t_p <= wgt_p (W(dmin_p / sph_h) + 26u)(1 + u). A particle
 *    with dmin_p >= R (1 + 1e-5), R = 2 sph_h, has a float q > 2 at every
 *    node: w_p = 0 exactly, and adding +0 changes no sum. Over the m other
 *    ("near") particles, a float sum of non-negative terms is at most their
 *    exact sum times (1 + u)^(m-1) <= 1 + 1.01 m u (m u < 0.01). Hence every
 *    node holds
 *        v <= (U + 26u S)(1 + u)(1 + 1.01 m u)
 *          <= (U + 4e-6 S)(1 + 1.2e-7 (m + 8)),
 *    U = sum over the near p of wgt_p W(dmin_p / sph_h), S = the sum of
 *    their wgt_p (26u < 1.6e-6 and u + 1.02 m u < 1.2e-7 (m + 1); the double
 *    arithmetic computing dmin and U errs by ~1e-16 relative, far inside
 *    that slack). When the right side is below the threshold no node is
 *    inside (v > threshold). block.c, finding no inside node in a block,
 *    returns before looking at any cube; a proven block returns at that same
 *    point with the same empty result. (m >= 1e5: never skipped.)
 *
 * 3. Nodes proven inside (jm_sph_partial, jm_sph_partial_threshold,
 *    jm_sph_spans). Lower bound of a node's sample: each term is
 *    t_p = fl(wgt_p w_p) >= (1 - u) wgt_p (W_p - 26u), W_p the real kernel
 *    at the real q_p (the float q and kernel errs as in 2), and a float sum
 *    of m terms >= 0 is at least their exact sum times (1 - u)^(m-1), so
 *        v >= (1 - m u) sum_p wgt_p W_p - 26u S,
 *    m and S the count and the weights' sum of the hood's particles that are
 *    not isolated (every term's particle is one; the others add +0 or
 *    nothing). Upper bound of the partial sum L: its terms are
 *    max(0, l1, l2), l_i = fl(fl(wgt a_i) - fl(fl(fl(wgt b_i) i2) s))
 *    (or one fused rounding), i2 = fl(inv^2), inv = fl(1 / sph_h),
 *    s = fl(fl(dx^2) + fl(fl(dy^2) + fl(dz^2))) from rounded differences:
 *    s and b_i's product are within 5.1u and 5.1u of the real q_p^2 sph_h^2
 *    and wgt b_i / sph_h^2, so a positive l_i is at most
 *    wgt (a_i - b_i q_p^2) + 14 a_i u wgt <= wgt lambda_i(q_p) + 12u wgt
 *    (a_i <= 0.81), with lambda_i(q) = a_i - b_i q^2 <= W(q) for every q
 *    (cull.h: convexity). Hence every term is <= wgt_p W_p + 12u wgt_p over
 *    a subset of the pairs, and L <= (1 + 1.01 m u)(sum_p wgt_p W_p + 12u S)
 *    (its float sum, in any order, of at most m terms >= 0, +0 added
 *    elsewhere). Together, with m u <= 0.01:
 *        v >= L (1 - m u) / (1 + 1.01 m u) - 38u S
 *          >= L (1 - 2.02 m u) - 38u S,
 *    so L > T = (thr + 64u S)(1 + 2.5 (m + 1) u) proves v > thr (T taken in
 *    double and rounded up to a float; thr > 0, m < 1e5). The terms are
 *    lower bounds whatever their particles and nodes: the rows and window
 *    a particle's terms cover are speed only.
 * 3b. Nodes proven inside by boxes (inside_boxes.c, jm_sph_box_threshold),
 *    in blocks JM_BOX_FILL full on a fine lattice, instead of 3. A box is
 *    the nodes x = c + d (up to 3 x 3 x 3) around a centre node c: of odd
 *    index along x (boxes overlap on their end nodes), of index 3 i + 1
 *    (at most the last node) along y and z (boxes tile), |d_a| <= e_a (e_a
 *    the largest such offset of the block's float nodes along the axis, in
 *    double, raised), |d|^2 <= E2 (a float >= e0^2 + e1^2 + e2^2).
 *    Particle p (v = c - q_p, weight w) is at real squared distance s(x) =
 *    |v|^2 + 2 v.d + |d|^2 from node x. Its terms use the line a - b s (b >=
 *    0) of the bin picked from the float s at c (any pick will do): below
 *    W(sqrt(s) / sph_h) at every s, a tangent of that convex function
 *    lowered by 1e-4, which covers a and b being floats, or the zero line
 *    (test_cull.c checks the lines as floats). So its real term at x is at
 *    least w (a - b (|v|^2 + E2)) - 2 w b v.d, and over the box's particles
 *        sum_p wgt_p W_p(x) >= L - sum_a 2 e_a |G_a|,
 *    L = sum_p w (a - b (|v|^2 + E2)) and G_a = sum_p w b v_a in real
 *    arithmetic. Rounding: a term on a line of bin k has s below the bin's
 *    end, so |a - b (s + E2)| <= M and |b v_a| <= Gt (the largest over the
 *    bins, with 1e-6 to spare); each float term errs by at most 8u M w (4u
 *    Gt w) from its real value, and a float sum of mb terms, in any order,
 *    with or without fused multiply-adds, by at most 1.01 mb u times the
 *    sum of their magnitudes. So the float bound V = L - sum_a te_a |G_a|
 *    (te_a = 2 e_a rounded up) is within
 *        err = 1.02 u W ((mb + 16) M + (te_0 + te_1 + te_2)(mb + 8) Gt)
 *    of the real one, mb and W the count and weight sum of the particles
 *    the box's row of centres took (zero lines add exact zeros), and the
 *    last subtractions err by less than 4u |V|. Each node gets, from the
 *    best of its boxes, V - (err + 4u |V|) <= sum_p wgt_p W_p; with 3's
 *    v >= (1 - m u) sum_p wgt_p W_p - 26u S, a node whose bound is above
 *    T = (thr + 26u S) / (1 - m u) (in double, rounded up to a float; thr >
 *    0, m < 1e5) samples above thr. Boxes, reach and bins are speed only.
 * 4. No crossing skipped. A cube holds a crossing only if its corners
 *    differ. A cube whose 8 corners are all proven inside holds none. Any
 *    other cube has a corner u not proven, and each of its corners lies
 *    within one node of u on every axis; jm_sph_spans gives each row the
 *    hull of the unproven nodes of it and its 8 neighbour rows, widened by
 *    one node each way, so every corner of every such cube is in a span and
 *    sampled, and every node outside the spans is proven inside. The inside
 *    flags of all nodes and the values at every corner of every cube that
 *    holds a crossing are those of the full sampling. With no span at all
 *    every node is inside, and block.c returns with nothing meshed, as it
 *    does when the full sampling finds every node inside.
 *
 * 5. The same bits. With spans, splat.c runs the same particle loop in the
 *    same order with the same filters and runs; it computes only a part
 *    [s, t) of each run [a, e) covering the run's nodes inside the row's
 *    span, with s = a (mod 8) and t <= e. Each lane depends on its own node
 *    alone, so each node of a span gets the same terms in the same order as
 *    without culling: the same bits, on every SIMD path and for any thread
 *    count (each block decides alone). The span samplers skip the particles
 *    and rows outside the spans' box (jm_span_box_of): their runs meet no
 *    span, so no span node loses a term.
 *
 * Speed only (never the result): the partial pass runs on blocks a third
 * full of particles or more (jm_sph_block_full), the box pass instead on
 * those JM_BOX_FILL full when the lattice is fine (jm_sph_boxes_apply), and
 * the outside proof is not tried there (a proof not tried skips nothing). Measured and left
 * out: upper bounds over sub-boxes of 4, 8 and 12 cubes for the outside
 * (the nodes they skip are the ones few particles reach: kernel lanes -3 %,
 * instructions +3 to +17 %); lower bounds from each kernel at its farthest
 * point cannot prove the inside (at threshold 0.6 that bound is about 0.55
 * over a single cube of the r/2 lattice where the field is about 1.0).
 */
#include "field/sph/cull.h"
#include <math.h>
#include <string.h>

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])

float jm_sph_partial_threshold(const jm_config *c, const jm_hood *h)
{
    const double u = 0x1p-24, m = (double)h->live;
    if (!(c->threshold > 0.0f) || m >= 1e5) return INFINITY;
    return jm_float_up(((double)c->threshold + 64.0 * u * h->wsum) * (1.0 + 2.5 * (m + 1.0) * u));
}

int jm_sph_block_outside(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float lo[3],
                         const float hi[3], size_t *inner)
{
    const double thr = c->threshold, sph_h = c->sph_h, Rn = (double)c->support * (1.0 + 1e-5), Rn2 = Rn * Rn;
    int open = thr > 0.0; /* a proof is possible (every node is >= 0) */
    const double blo[3] = {lo[0], lo[1], lo[2]}, bhi[3] = {hi[0], hi[1], hi[2]};
    /* a first cut: splat.c's own filter (the particles it skips add nothing) */
    const float R = c->support;
    const float bx0 = lo[0] - R, bx1 = hi[0] + R, by0 = lo[1] - R, by1 = hi[1] + R, bz0 = lo[2] - R, bz1 = hi[2] + R;
    const size_t cells = (size_t)hood->n[0] * hood->n[1] * hood->n[2];
    double U = 0.0, S = 0.0;
    size_t m = 0, in = 0;
    /* first the particles within the box (a full block tries no proof),
     * from the hood cells that meet it */
    int b0[3], b1[3];
    for (int a = 0; a < 3; a++) jm_hood_cell_span(g, hood, a, lo[a], hi[a], 0.0f, &b0[a], &b1[a]);
    for (int cz = b0[2]; cz <= b1[2]; cz++)
        for (int cy = b0[1]; cy <= b1[1]; cy++)
            for (int cx = b0[0]; cx <= b1[0]; cx++) {
                const size_t k = ((size_t)cz * hood->n[1] + (size_t)cy) * hood->n[0] + (size_t)cx;
                for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {
                    const float *q = GP(g, p);
                    in += !g->isolated[p] && q[0] >= lo[0] && q[0] <= hi[0] && q[1] >= lo[1] && q[1] <= hi[1] &&
                          q[2] >= lo[2] && q[2] <= hi[2];
                }
            }
    *inner = in;
    if (!open || jm_sph_block_full(c, in, lo, hi)) return 0;
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
            U += wgt * jm_cull_kernel(sqrt(d2) / sph_h);
            S += wgt;
            m++;
            if (U >= thr || m >= 100000) return 0; /* no proof possible */
        }
    return open && (U + 4e-6 * S) * (1.0 + 1.2e-7 * ((double)m + 8.0)) < thr;
}

size_t jm_sph_spans(const float *part, int n, float threshold, uint8_t *span)
{
    const size_t ns = JM_PAD(n), rows = (size_t)n * n;
    uint8_t lo[JM_PAD_MAX * JM_PAD_MAX], hi[JM_PAD_MAX * JM_PAD_MAX]; /* per row: the nodes not proven, [lo, hi) */
    size_t open = 0; /* rows with a node not proven */
    for (size_t r = 0; r < rows; r++) {
        const float *p = part + r * ns;
        int proven = 0; /* counted first: a loop the compiler vectorises */
        for (int i = 0; i < n; i++) proven += p[i] > threshold;
        int a = 0, b = n;
        if (proven == n) a = b = n;
        else {
            while (a < n && p[a] > threshold) a++;
            while (b > a && p[b - 1] > threshold) b--;
            open++;
        }
        lo[r] = (uint8_t)a;
        hi[r] = (uint8_t)b;
    }
    if (!open) { /* every node proven: no spans */
        memset(span, 0, 2 * rows);
        return 0;
    }
    size_t nodes = 0;
    for (int k = 0; k < n; k++)
        for (int j = 0; j < n; j++) {
            int a = n, b = 0;
            for (int dk = -1; dk <= 1; dk++)
                for (int dj = -1; dj <= 1; dj++) {
                    int kk = k + dk, jj = j + dj;
                    if (kk < 0 || kk >= n || jj < 0 || jj >= n) continue;
                    size_t r = (size_t)kk * n + jj;
                    if (lo[r] >= hi[r]) continue;
                    if (lo[r] - 1 < a) a = lo[r] - 1;
                    if (hi[r] + 1 > b) b = hi[r] + 1;
                }
            if (a < 0) a = 0;
            if (b > n) b = n;
            if (a >= b) a = b = 0;
            uint8_t *sp = span + 2 * ((size_t)k * n + j);
            sp[0] = (uint8_t)a;
            sp[1] = (uint8_t)b;
            nodes += (size_t)(b - a);
        }
    return nodes;
}

void jm_span_box_of(const uint8_t *span, int n, jm_span_box *b)
{
    b->k0 = n;
    b->k1 = 0;
    b->i0 = n;
    b->i1 = 0;
    for (int k = 0; k < n; k++) {
        int j0 = n, j1 = 0;
        for (int j = 0; j < n; j++) {
            const uint8_t *sp = span + 2 * ((size_t)k * n + j);
            if (sp[0] >= sp[1]) continue;
            if (j0 == n) j0 = j;
            j1 = j + 1;
            b->i0 = sp[0] < b->i0 ? sp[0] : b->i0;
            b->i1 = sp[1] > b->i1 ? sp[1] : b->i1;
        }
        b->j0[k] = j0;
        b->j1[k] = j1;
        if (j0 < j1) {
            b->k0 = k < b->k0 ? k : b->k0;
            b->k1 = k + 1;
        }
    }
}
