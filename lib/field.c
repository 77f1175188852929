/* field.c - the metasphere and SPH fields: splatting onto block nodes, gradients at points. */
#include "field.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])

int jm_hood_build(jm_hood *hood, const jm_grid *g, const jm_config *c, const float lo[3], const float hi[3])
{
    size_t total = 1;
    for (int a = 0; a < 3; a++) {
        hood->c0[a] = (int64_t)floorf((lo[a] - c->influence) * g->inv_cell) - 1;
        int64_t c1 = (int64_t)floorf((hi[a] + c->influence) * g->inv_cell) + 1;
        hood->n[a] = (int)(c1 - hood->c0[a] + 1);
        total *= (size_t)hood->n[a];
    }
    if (total > hood->cap) {
        uint32_t *r = realloc(hood->range, 2 * total * sizeof *r);
        if (!r) return 0;
        hood->range = r;
        hood->cap = total;
    }
    size_t k = 0;
    hood->particles = 0;
    for (int z = 0; z < hood->n[2]; z++)
        for (int y = 0; y < hood->n[1]; y++)
            for (int x = 0; x < hood->n[0]; x++, k++) {
                uint32_t ci = jm_grid_cell(g, hood->c0[0] + x, hood->c0[1] + y, hood->c0[2] + z);
                if (ci == UINT32_MAX) {
                    hood->range[2 * k] = hood->range[2 * k + 1] = 0;
                } else {
                    hood->range[2 * k] = g->cell_start[ci];
                    hood->range[2 * k + 1] = g->cell_start[ci + 1];
                    hood->particles += g->cell_start[ci + 1] - g->cell_start[ci];
                }
            }
    return 1;
}

/* index range [*a, *b) of nodes t[] (ascending) within [lo, hi] */
static void node_span(const float *t, int n, float lo, float hi, int *a, int *b)
{
    int i = 0;
    while (i < n && t[i] < lo) i++;
    int j = n;
    while (j > i && t[j - 1] > hi) j--;
    *a = i;
    *b = j;
}

static void sample_sph(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x,
                       const float *y, const float *z, int n, float *f)
{
    const float R = c->support, R2 = R * R, inv = 1.0f / c->sph_h;
    size_t cells = (size_t)hood->n[0] * hood->n[1] * hood->n[2];
    memset(f, 0, (size_t)n * n * n * sizeof *f);
    for (size_t k = 0; k < cells; k++) {
        for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {
            if (g->isolated[p]) continue;
            const float *q = GP(g, p);
            const float wgt = g->weight[p];
            int i0, i1, j0, j1, k0, k1;
            node_span(x, n, q[0] - R, q[0] + R, &i0, &i1);
            if (i0 >= i1) continue;
            node_span(y, n, q[1] - R, q[1] + R, &j0, &j1);
            if (j0 >= j1) continue;
            node_span(z, n, q[2] - R, q[2] + R, &k0, &k1);
            for (int kk = k0; kk < k1; kk++) {
                float dz = z[kk] - q[2], dz2 = dz * dz;
                for (int jj = j0; jj < j1; jj++) {
                    float dy = y[jj] - q[1], dyz2 = dy * dy + dz2;
                    if (dyz2 >= R2) continue;
                    float *row = f + ((size_t)kk * n + jj) * n;
                    for (int ii = i0; ii < i1; ii++) {
                        float dx = x[ii] - q[0];
                        float d2 = dx * dx + dyz2;
                        float w = jm_cubic_w(sqrtf(d2) * inv);
                        row[ii] += d2 < R2 ? wgt * w : 0.0f;
                    }
                }
            }
        }
    }
}

static void sample_meta(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x,
                        const float *y, const float *z, int n, float *f)
{
    const float r = c->r, inv_r = 1.0f / r, reach = r + c->margin, reach2 = reach * reach;
    const float floor_v = -c->margin * inv_r;
    size_t nn = (size_t)n * n * n;
    for (size_t i = 0; i < nn; i++) f[i] = floor_v;
    size_t cells = (size_t)hood->n[0] * hood->n[1] * hood->n[2];
    for (size_t k = 0; k < cells; k++) {
        for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {
            if (g->isolated[p]) continue;
            const float *q = GP(g, p);
            int i0, i1, j0, j1, k0, k1;
            /* the ball */
            node_span(x, n, q[0] - reach, q[0] + reach, &i0, &i1);
            node_span(y, n, q[1] - reach, q[1] + reach, &j0, &j1);
            node_span(z, n, q[2] - reach, q[2] + reach, &k0, &k1);
            for (int kk = k0; kk < k1; kk++) {
                float dz = z[kk] - q[2], dz2 = dz * dz;
                for (int jj = j0; jj < j1; jj++) {
                    float dy = y[jj] - q[1], dyz2 = dy * dy + dz2;
                    if (dyz2 >= reach2) continue;
                    float *row = f + ((size_t)kk * n + jj) * n;
                    for (int ii = i0; ii < i1; ii++) {
                        float dx = x[ii] - q[0];
                        float v = 1.0f - sqrtf(dx * dx + dyz2) * inv_r;
                        row[ii] = v > row[ii] ? v : row[ii];
                    }
                }
            }
            /* half-necks toward each linked neighbour */
            for (uint32_t e = g->nb_start[p]; e < g->nb_start[p + 1]; e++) {
                const float *o = GP(g, g->nb[e]);
                float u[3] = {o[0] - q[0], o[1] - q[1], o[2] - q[2]};
                float D = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
                float half = 0.5f * D;
                for (int a = 0; a < 3; a++) u[a] /= D;
                float lo[3], hi[3];
                for (int a = 0; a < 3; a++) {
                    float m = q[a] + u[a] * half;
                    lo[a] = fminf(q[a], m) - reach;
                    hi[a] = fmaxf(q[a], m) + reach;
                }
                node_span(x, n, lo[0], hi[0], &i0, &i1);
                node_span(y, n, lo[1], hi[1], &j0, &j1);
                node_span(z, n, lo[2], hi[2], &k0, &k1);
                for (int kk = k0; kk < k1; kk++) {
                    float wz = z[kk] - q[2];
                    for (int jj = j0; jj < j1; jj++) {
                        float wy = y[jj] - q[1];
                        float *row = f + ((size_t)kk * n + jj) * n;
                        float syz = wy * u[1] + wz * u[2], wyz2 = wy * wy + wz * wz;
                        for (int ii = i0; ii < i1; ii++) {
                            float wx = x[ii] - q[0];
                            float s = wx * u[0] + syz;
                            if (s < 0.0f || s > half) continue;
                            float q2 = wx * wx + wyz2 - s * s;
                            float v = cosf(s * inv_r) - sqrtf(q2 > 0.0f ? q2 : 0.0f) * inv_r;
                            row[ii] = v > row[ii] ? v : row[ii];
                        }
                    }
                }
            }
        }
    }
}

void jm_field_sample(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x,
                     const float *y, const float *z, int n, float *f)
{
    if (c->field == JM_FIELD_SPH) sample_sph(g, c, hood, x, y, z, n, f);
    else sample_meta(g, c, hood, x, y, z, n, f);
}

/* cells of the hood within one cell of p */
#define HOOD_NEAR(g, hood, p, ...)                                                          \
    do {                                                                                     \
        int64_t pc_[3];                                                                      \
        int lo_[3], hi_[3];                                                                  \
        for (int a_ = 0; a_ < 3; a_++) {                                                     \
            pc_[a_] = (int64_t)floorf((p)[a_] * (g)->inv_cell) - (hood)->c0[a_];             \
            lo_[a_] = pc_[a_] - 1 < 0 ? 0 : (int)(pc_[a_] - 1);                              \
            hi_[a_] = pc_[a_] + 1 >= (hood)->n[a_] ? (hood)->n[a_] - 1 : (int)(pc_[a_] + 1); \
        }                                                                                    \
        for (int z_ = lo_[2]; z_ <= hi_[2]; z_++)                                            \
            for (int y_ = lo_[1]; y_ <= hi_[1]; y_++)                                        \
                for (int x_ = lo_[0]; x_ <= hi_[0]; x_++) {                                  \
                    size_t k_ = ((size_t)z_ * (hood)->n[1] + y_) * (hood)->n[0] + x_;        \
                    for (uint32_t j = (hood)->range[2 * k_]; j < (hood)->range[2 * k_ + 1]; j++) { \
                        if ((g)->isolated[j]) continue;                                      \
                        __VA_ARGS__                                                                 \
                    }                                                                        \
                }                                                                            \
    } while (0)

int jm_field_normal(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float p[3], float nrm[3])
{
    float out[3] = {0, 0, 0};
    if (c->field == JM_FIELD_SPH) {
        const float R2 = c->support * c->support, inv = 1.0f / c->sph_h;
        float gr[3] = {0, 0, 0};
        HOOD_NEAR(g, hood, p, {
            const float *q = GP(g, j);
            float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
            float d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            if (d2 < R2 && d2 > 0.0f) {
                float dist = sqrtf(d2);
                float s = g->weight[j] * jm_cubic_dw(dist * inv) / dist;
                gr[0] += s * d[0];
                gr[1] += s * d[1];
                gr[2] += s * d[2];
            }
        });
        out[0] = -gr[0];
        out[1] = -gr[1];
        out[2] = -gr[2];
    } else {
        /* The metasphere is a union, so its gradient jumps where two pieces
         * meet. Pieces within tau of the maximum share the normal, weighted
         * linearly: the analytic gradient wherever one piece dominates, a
         * blend of the one-sided gradients along creases. */
        const float best = jm_field_value(g, c, hood, p);
        const float tau = 0.1f * c->h / c->r;
        const float r = c->r, inv_r = 1.0f / r;
        const float reach = 1.5708f * r + 1e-3f * r, reach2 = reach * reach;
        HOOD_NEAR(g, hood, p, {
            const float *q = GP(g, j);
            float w[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
            float d2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
            if (d2 < reach2) {
                float d = sqrtf(d2);
                float v = 1.0f - d * inv_r;
                float wt = 1.0f - (best - v) / tau;
                if (wt > 0.0f && d > 0.0f)
                    for (int a = 0; a < 3; a++) out[a] += wt * w[a] / d;
                for (uint32_t e = g->nb_start[j]; e < g->nb_start[j + 1]; e++) {
                    const float *o = GP(g, g->nb[e]);
                    float u[3] = {o[0] - q[0], o[1] - q[1], o[2] - q[2]};
                    float D = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
                    for (int a = 0; a < 3; a++) u[a] /= D;
                    float s = w[0] * u[0] + w[1] * u[1] + w[2] * u[2];
                    if (s < 0.0f || s > 0.5f * D) continue;
                    float rad[3] = {w[0] - s * u[0], w[1] - s * u[1], w[2] - s * u[2]};
                    float qq = sqrtf(rad[0] * rad[0] + rad[1] * rad[1] + rad[2] * rad[2]);
                    float nv = cosf(s * inv_r) - qq * inv_r;
                    float nw = 1.0f - (best - nv) / tau;
                    if (nw > 0.0f && qq > 0.0f) {
                        float sn = sinf(s * inv_r);
                        float g3[3], gl = 0.0f;
                        for (int a = 0; a < 3; a++) { g3[a] = sn * u[a] + rad[a] / qq; gl += g3[a] * g3[a]; }
                        gl = 1.0f / sqrtf(gl);
                        for (int a = 0; a < 3; a++) out[a] += nw * g3[a] * gl;
                    }
                }
            }
        });
    }
    float len = sqrtf(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]);
    if (!(len > 0.0f) || !isfinite(len)) return 0;
    nrm[0] = out[0] / len;
    nrm[1] = out[1] / len;
    nrm[2] = out[2] / len;
    return 1;
}

float jm_field_value(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float p[3])
{
    const float r = c->r, inv_r = 1.0f / r;
    const float reach = 1.5708f * r + 1e-3f * r, reach2 = reach * reach;
    float best = -c->margin * inv_r;
    HOOD_NEAR(g, hood, p, {
        const float *q = GP(g, j);
        float w[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
        float d2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        if (d2 < reach2) {
            float v = 1.0f - sqrtf(d2) * inv_r;
            best = v > best ? v : best;
            for (uint32_t e = g->nb_start[j]; e < g->nb_start[j + 1]; e++) {
                const float *o = GP(g, g->nb[e]);
                float u[3] = {o[0] - q[0], o[1] - q[1], o[2] - q[2]};
                float D = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
                float s = (w[0] * u[0] + w[1] * u[1] + w[2] * u[2]) / D;
                if (s < 0.0f || s > 0.5f * D) continue;
                float q2 = d2 - s * s;
                float nv = cosf(s * inv_r) - sqrtf(q2 > 0.0f ? q2 : 0.0f) * inv_r;
                best = nv > best ? nv : best;
            }
        }
    });
    return best;
}
