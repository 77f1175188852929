/* metasplat_rows.h - the metasphere splat over a block's pieces in runs of MS_W nodes, included once per width by metasplat.c. */
/* metasplat.c defines MS_W (the run), MS_NAME, MS_ATTR (the target) and
 * the runs MS_BALL and MS_NECK; a row is set to the floor the first time a
 * piece reaches it (rows: JM_ROW_SPLAT). */
MS_ATTR static void MS_NAME(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y,
                            const float *z, int n, float *f, uint32_t *win, uint8_t *rows)
{
    const uint32_t np = (uint32_t)g->n;
    const float r = c->r, inv_r = 1.0f / r, reach = r + c->margin, reach2 = reach * reach, inv_h = c->inv_h;
    const float floor_v = -c->margin * inv_r;
    /* 1.02: float slack on the bound below */
    const float neck_reach = fminf(reach, 1.02f * r);
    size_t cells = (size_t)hood->n[0] * hood->n[1] * hood->n[2];
    const float inf = c->influence, bx0 = x[0] - inf, bx1 = x[n - 1] + inf, by0 = y[0] - inf, by1 = y[n - 1] + inf;
    const float bz0 = z[0] - inf, bz1 = z[n - 1] + inf;
#define MS_ROW(kk, jj, row, wrow)                                        \
    const size_t rr_ = (size_t)(kk) * n + (jj);                          \
    float *row = f + rr_ * n;                                            \
    uint32_t *wrow = win + rr_ * n;                                      \
    if (rows[rr_] != JM_ROW_SPLAT) first_touch(f, win, rows, n, kk, jj, floor_v);
    for (size_t k = 0; k < cells; k++) {
        for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {
            const float *q = GP(g, p), qx = q[0];
            /* the hood's cells reach past the influence radius: skip what
             * cannot touch the block (nothing of a particle reaches further) */
            if (qx < bx0 || qx > bx1 || q[1] < by0 || q[1] > by1 || q[2] < bz0 || q[2] > bz1) continue;
            if (g->isolated[p]) continue;
            int i0, i1, j0, j1, k0, k1;
            /* the ball */
            node_span(x, n, inv_h, q[0] - reach, q[0] + reach, &i0, &i1);
            node_span(y, n, inv_h, q[1] - reach, q[1] + reach, &j0, &j1);
            node_span(z, n, inv_h, q[2] - reach, q[2] + reach, &k0, &k1);
            for (int kk = k0; kk < k1; kk++) {
                float dz = z[kk] - q[2], dz2 = dz * dz;
                for (int jj = j0; jj < j1; jj++) {
                    float dy = y[jj] - q[1], dyz2 = dy * dy + dz2;
                    if (dyz2 >= reach2 || i0 >= i1) continue;
                    MS_ROW(kk, jj, row, wrow)
                    for (int s0 = i0; s0 < i1; s0 += MS_W) {
                        const int a = s0 < n - MS_W ? s0 : n - MS_W;
                        MS_BALL(row + a, wrow + a, x + a, qx, dyz2, inv_r, p, a, i0, i1);
                    }
                }
            }
            /* half-necks toward each linked neighbour. Up to pi/2 r along
             * its axis a half-neck beats its own particle's ball only closer
             * than r to the axis (cos(s) - q > 1 - sqrt(s^2 + q^2), lengths
             * in units of r, needs q + sqrt(s^2 + q^2) < s^2 / (1 - cos s),
             * never met for q >= 1): farther out that ball, splatted above,
             * already holds the maximum, so the box hugs the axis closer. */
            for (uint32_t e = g->nb_start[p]; e < g->nb_start[p + 1]; e++) {
                const float *u = &g->nb_dir[4 * (size_t)e];
                const float half = 0.5f * u[3];
                const float nr = jm_neck_reach(r, u[3], neck_reach, reach);
                float lo[3], hi[3];
                for (int a = 0; a < 3; a++) {
                    float m = q[a] + u[a] * half;
                    lo[a] = fminf(q[a], m) - nr;
                    hi[a] = fmaxf(q[a], m) + nr;
                }
                node_span(x, n, inv_h, lo[0], hi[0], &i0, &i1);
                node_span(y, n, inv_h, lo[1], hi[1], &j0, &j1);
                node_span(z, n, inv_h, lo[2], hi[2], &k0, &k1);
                if (i0 >= i1) continue;
                for (int kk = k0; kk < k1; kk++) {
                    float wz = z[kk] - q[2];
                    for (int jj = j0; jj < j1; jj++) {
                        float wy = y[jj] - q[1];
                        MS_ROW(kk, jj, row, wrow)
                        float syz = wy * u[1] + wz * u[2], wyz2 = wy * wy + wz * wz;
                        for (int s0 = i0; s0 < i1; s0 += MS_W) {
                            const int a = s0 < n - MS_W ? s0 : n - MS_W;
                            MS_NECK(row + a, wrow + a, x + a, qx, u[0], syz, wyz2, half, inv_r, floor_v, np + e, a, i0, i1);
                        }
                    }
                }
            }
        }
    }
#undef MS_ROW
}
#undef MS_W
#undef MS_NAME
#undef MS_ATTR
#undef MS_BALL
#undef MS_NECK
