/* cull.c - SPH sampling kept near the surface: blocks proven outside skipped, nodes proven inside by partial sums not sampled. */
/* The proof that no crossing is skipped and every sampled node keeps its
 * bits: docs/culling.md, part I (cited below by its parts, e.g. "3b"). */
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
