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

/* floor and ceil without libm calls (x within int range) */
static inline int ifloor(float x)
{
    int t = (int)x;
    return t - (x < (float)t);
}
static inline int iceil(float x)
{
    int t = (int)x;
    return t + (x > (float)t);
}

/* index range [*a, *b) of the n nodes t[i] = t[0] + i h (as rounded) within
 * [lo, hi]; the estimate from the spacing is corrected against t[] itself */
static void node_span(const float *t, int n, float inv_h, float lo, float hi, int *a, int *b)
{
    float flo = (lo - t[0]) * inv_h, fhi = (hi - t[0]) * inv_h;
    if (flo > (float)n) flo = (float)n;
    if (fhi < -1.0f) fhi = -1.0f;
    int i = iceil(flo < 0.0f ? 0.0f : flo);
    int j = ifloor(fhi > (float)n ? (float)n : fhi) + 1;
    if (i > n) i = n;
    if (j > n) j = n;
    while (i < n && t[i] < lo) i++;
    while (i > 0 && t[i - 1] >= lo) i--;
    while (j > 0 && t[j - 1] > hi) j--;
    while (j < n && t[j] <= hi) j++;
    *a = i;
    *b = j > i ? j : i;
}

/* The splatting loops are built twice, for AVX2 machines and for any x86-64,
 * chosen at load time. No FMA contraction (-std=c11 implies
 * -ffp-contract=off), so both give the same bits. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(JM_NO_CLONES)
#define JM_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define JM_CLONES
#endif

JM_CLONES static void sample_sph(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x,
                       const float *y, const float *z, int n, float *f)
{
    const float R = c->support, R2 = R * R, inv = 1.0f / c->sph_h, inv_h = c->inv_h;
    size_t cells = (size_t)hood->n[0] * hood->n[1] * hood->n[2];
    memset(f, 0, (size_t)n * n * n * sizeof *f);
    for (size_t k = 0; k < cells; k++) {
        for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {
            if (g->isolated[p]) continue;
            const float *q = GP(g, p);
            const float wgt = g->weight[p];
            int i0, i1, j0, j1, k0, k1;
            node_span(x, n, inv_h, q[0] - R, q[0] + R, &i0, &i1);
            if (i0 >= i1) continue;
            node_span(y, n, inv_h, q[1] - R, q[1] + R, &j0, &j1);
            if (j0 >= j1) continue;
            node_span(z, n, inv_h, q[2] - R, q[2] + R, &k0, &k1);
            for (int kk = k0; kk < k1; kk++) {
                float dz = z[kk] - q[2], dz2 = dz * dz;
                for (int jj = j0; jj < j1; jj++) {
                    float dy = y[jj] - q[1], dyz2 = dy * dy + dz2;
                    if (dyz2 >= R2) continue;
                    /* only the chord of the support ball along this row */
                    float half = sqrtf(R2 - dyz2);
                    int a = iceil((q[0] - half - x[0]) * inv_h), b = ifloor((q[0] + half - x[0]) * inv_h) + 1;
                    a = a > i0 ? a : i0;
                    b = b < i1 ? b : i1;
                    float *restrict row = f + ((size_t)kk * n + jj) * n;
                    const float *restrict xr = x;
                    const float qx = q[0];
                    for (int ii = a; ii < b; ii++) {
                        float dx = xr[ii] - qx;
                        float qq = sqrtf(dx * dx + dyz2) * inv;
                        row[ii] += wgt * jm_cubic_w(qq); /* 0 beyond the support */
                    }
                }
            }
        }
    }
}

JM_CLONES static void sample_meta(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x,
                        const float *y, const float *z, int n, float *f, uint32_t *win)
{
    const uint32_t np = (uint32_t)g->n;
    const float r = c->r, inv_r = 1.0f / r, reach = r + c->margin, reach2 = reach * reach, inv_h = c->inv_h;
    const float floor_v = -c->margin * inv_r;
    size_t nn = (size_t)n * n * n;
    for (size_t i = 0; i < nn; i++) {
        f[i] = floor_v;
        win[i] = UINT32_MAX;
    }
    size_t cells = (size_t)hood->n[0] * hood->n[1] * hood->n[2];
    for (size_t k = 0; k < cells; k++) {
        for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {
            if (g->isolated[p]) continue;
            const float *q = GP(g, p);
            int i0, i1, j0, j1, k0, k1;
            /* the ball */
            node_span(x, n, inv_h, q[0] - reach, q[0] + reach, &i0, &i1);
            node_span(y, n, inv_h, q[1] - reach, q[1] + reach, &j0, &j1);
            node_span(z, n, inv_h, q[2] - reach, q[2] + reach, &k0, &k1);
            for (int kk = k0; kk < k1; kk++) {
                float dz = z[kk] - q[2], dz2 = dz * dz;
                for (int jj = j0; jj < j1; jj++) {
                    float dy = y[jj] - q[1], dyz2 = dy * dy + dz2;
                    if (dyz2 >= reach2) continue;
                    float *row = f + ((size_t)kk * n + jj) * n;
                    uint32_t *wrow = win + ((size_t)kk * n + jj) * n;
                    for (int ii = i0; ii < i1; ii++) {
                        float dx = x[ii] - q[0];
                        float v = 1.0f - sqrtf(dx * dx + dyz2) * inv_r;
                        if (v > row[ii]) {
                            row[ii] = v;
                            wrow[ii] = p;
                        }
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
                node_span(x, n, inv_h, lo[0], hi[0], &i0, &i1);
                node_span(y, n, inv_h, lo[1], hi[1], &j0, &j1);
                node_span(z, n, inv_h, lo[2], hi[2], &k0, &k1);
                for (int kk = k0; kk < k1; kk++) {
                    float wz = z[kk] - q[2];
                    for (int jj = j0; jj < j1; jj++) {
                        float wy = y[jj] - q[1];
                        float *row = f + ((size_t)kk * n + jj) * n;
                        uint32_t *wrow = win + ((size_t)kk * n + jj) * n;
                        float syz = wy * u[1] + wz * u[2], wyz2 = wy * wy + wz * wz;
                        for (int ii = i0; ii < i1; ii++) {
                            float wx = x[ii] - q[0];
                            float s = wx * u[0] + syz;
                            if (s < 0.0f || s > half) continue;
                            float q2 = wx * wx + wyz2 - s * s;
                            float v = jm_cos_quarter(s * inv_r) - sqrtf(q2 > 0.0f ? q2 : 0.0f) * inv_r;
                            if (v > row[ii]) {
                                row[ii] = v;
                                wrow[ii] = np + e;
                            }
                        }
                    }
                }
            }
        }
    }
}

void jm_field_sample(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x,
                     const float *y, const float *z, int n, float *f, uint32_t *win)
{
    if (c->field == JM_FIELD_SPH) sample_sph(g, c, hood, x, y, z, n, f);
    else sample_meta(g, c, hood, x, y, z, n, f, win);
}

float jm_prim_eval(const jm_grid *g, const jm_config *c, uint32_t id, const float p[3], float out[3])
{
    const float inv_r = 1.0f / c->r;
    if (id < g->n) {
        const float *q = GP(g, id);
        float w[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
        float d = sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        if (out && d > 0.0f)
            for (int a = 0; a < 3; a++) out[a] = w[a] / d;
        return 1.0f - d * inv_r;
    }
    uint32_t e = id - (uint32_t)g->n;
    const float *q = GP(g, g->nb_owner[e]), *o = GP(g, g->nb[e]);
    float u[3] = {o[0] - q[0], o[1] - q[1], o[2] - q[2]};
    float D = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int a = 0; a < 3; a++) u[a] /= D;
    float w[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    float s = w[0] * u[0] + w[1] * u[1] + w[2] * u[2];
    /* beyond its half the neck continues as the same formula; callers only
     * use primitives that won at a node next to p */
    if (s < 0.0f) s = 0.0f;
    if (s > 0.5f * D) s = 0.5f * D;
    float rad[3] = {w[0] - s * u[0], w[1] - s * u[1], w[2] - s * u[2]};
    float qq = sqrtf(rad[0] * rad[0] + rad[1] * rad[1] + rad[2] * rad[2]);
    if (out && qq > 0.0f) {
        float sn = sinf(s * inv_r), len = 0.0f;
        for (int a = 0; a < 3; a++) { out[a] = sn * u[a] + rad[a] / qq; len += out[a] * out[a]; }
        len = 1.0f / sqrtf(len);
        for (int a = 0; a < 3; a++) out[a] *= len;
    }
    return jm_cos_quarter(s * inv_r) - qq * inv_r;
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
    {
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
    }
    float len = sqrtf(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]);
    if (!(len > 0.0f) || !isfinite(len)) return 0;
    nrm[0] = out[0] / len;
    nrm[1] = out[1] / len;
    nrm[2] = out[2] / len;
    return 1;
}

