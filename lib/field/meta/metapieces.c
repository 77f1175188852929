/* metapieces.c - every metasphere piece that can reach a block, handed to a visitor with the block's parts it reaches. */
#include "field/meta/metapieces.h"

void jm_probe_pieces(const jm_grid *g, const jm_config *c, const jm_hood *hood, int B, int pc, const float *x, const float *y,
                     const float *z, const jm_piece_visitor *v)
{
    const float x0[3] = {x[0], y[0], z[0]};
    const double inv_hd = 1.0 / (double)c->h;
    const float rb = v->rb;
    const float blo[3] = {x[0] - c->influence, y[0] - c->influence, z[0] - c->influence};
    const float bhi[3] = {x[B] + c->influence, y[B] + c->influence, z[B] + c->influence};
    const size_t cells = (size_t)hood->n[0] * hood->n[1] * hood->n[2];
    for (size_t cell = 0; cell < cells; cell++)
        for (uint32_t p = hood->range[2 * cell]; p < hood->range[2 * cell + 1]; p++) {
            const float *q = &g->pos[3 * (size_t)p];
            if (q[0] < blo[0] || q[0] > bhi[0] || q[1] < blo[1] || q[1] > bhi[1] || q[2] < blo[2] || q[2] > bhi[2])
                continue;
            if (g->isolated[p]) continue;
            int lo[3], hi[3];
            float l3[3] = {q[0] - rb, q[1] - rb, q[2] - rb}, h3[3] = {q[0] + rb, q[1] + rb, q[2] + rb};
            if (jm_probe_part_span(x0, B, pc, inv_hd, l3, h3, lo, hi)) v->ball(v->ctx, lo, hi, q);
            for (uint32_t e = g->nb_start[p]; e < g->nb_start[p + 1]; e++) {
                const uint32_t m = g->nb[e];
                const float *qm = &g->pos[3 * (size_t)m];
                if (m < p && !(qm[0] < blo[0] || qm[0] > bhi[0] || qm[1] < blo[1] || qm[1] > bhi[1] ||
                               qm[2] < blo[2] || qm[2] > bhi[2]))
                    continue;
                const float *u = &g->nb_dir[4 * (size_t)e];
                const float rr = jm_neck_reach(c->r, u[3], v->rn, rb);
                for (int a = 0; a < 3; a++) {
                    l3[a] = (qm[a] < q[a] ? qm[a] : q[a]) - rr;
                    h3[a] = (qm[a] > q[a] ? qm[a] : q[a]) + rr;
                }
                if (jm_probe_part_span(x0, B, pc, inv_hd, l3, h3, lo, hi)) v->link(v->ctx, lo, hi, q, u, u[3], rr * rr);
            }
        }
}
