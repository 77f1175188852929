/* field.c - the metasphere and SPH fields: splatting onto block nodes, gradients at points. */
#include "field.h"
#include "splat.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])

int jm_hood_build(jm_hood *hood, const jm_grid *g, const jm_config *c, const float lo[3], const float hi[3])
{
    size_t total = 1;
    for (int a = 0; a < 3; a++) {
        hood->c0[a] = jm_hood_cell_lo(g, c, lo[a]);
        int64_t c1 = (int64_t)floorf((hi[a] + c->influence) * g->inv_cell) + 1;
        hood->n[a] = (int)(c1 - hood->c0[a] + 1);
        total *= (size_t)hood->n[a];
    }
    if (total > hood->cap) {
        uint32_t *r = jm_realloc(hood->mem, hood->range, 2 * hood->cap * sizeof *r, 2 * total * sizeof *r);
        if (!r) return 0;
        hood->range = r;
        hood->cap = total;
    }
    size_t k = 0;
    hood->particles = 0;
    hood->live = 0;
    hood->wsum = 0.0;
    /* the cells holding particles lie within those of the particles'
     * bounds: no lookup outside them (most of a thin jet's hoods) */
    int64_t in_lo[3], in_hi[3];
    for (int a = 0; a < 3; a++) {
        in_lo[a] = (int64_t)floorf(g->lo[a] * g->inv_cell) - hood->c0[a];
        in_hi[a] = (int64_t)floorf(g->hi[a] * g->inv_cell) - hood->c0[a];
    }
    for (int z = 0; z < hood->n[2]; z++)
        for (int y = 0; y < hood->n[1]; y++)
            for (int x = 0; x < hood->n[0]; x++, k++) {
                const int outside = x < in_lo[0] || x > in_hi[0] || y < in_lo[1] || y > in_hi[1] || z < in_lo[2] ||
                                    z > in_hi[2];
                uint32_t ci = outside ? UINT32_MAX : jm_grid_cell(g, hood->c0[0] + x, hood->c0[1] + y, hood->c0[2] + z);
                if (ci == UINT32_MAX) {
                    hood->range[2 * k] = hood->range[2 * k + 1] = 0;
                } else {
                    hood->range[2 * k] = g->cell_start[ci];
                    hood->range[2 * k + 1] = g->cell_start[ci + 1];
                    hood->particles += g->cell_start[ci + 1] - g->cell_start[ci];
                    if (g->cell_live) {
                        hood->live += g->cell_live[ci];
                        hood->wsum += g->cell_wsum[ci];
                    }
                }
            }
    return 1;
}

/* The splatting loops are built twice, for AVX2 machines and for any x86-64
 * (JM_CLONES_AVX2, internal.h): the same bits. */

/* Both pieces are splatted in runs of 4 nodes from the start of their span
 * (the last run shifted back to end at the row's end; n >= 9): a node past
 * the span but in the run gets a value no greater than what it holds
 * (beyond a ball's reach the ball is under the floor; beyond a half-neck's
 * box the neck is under its own ball, and off its axis span it is masked),
 * so the runs change nothing but speed. The SSE2 runs and the plain C ones
 * do the same float operations in the same order: the same bits. */
#define RUN 4
#ifndef JM_SPLAT_VARIANT
#define JM_SPLAT_VARIANT 0
#endif
#if defined(__SSE2__) && JM_SPLAT_VARIANT != 1 /* 1: plain C, for the tests */
#include <emmintrin.h>
typedef __m128 vf;
#define V1(x) _mm_set1_ps(x)
#define VLD(p) _mm_loadu_ps(p)
#define VADD _mm_add_ps
#define VSUB _mm_sub_ps
#define VMUL _mm_mul_ps
#define VSQRT _mm_sqrt_ps
#define VMAX0(x) _mm_max_ps(x, _mm_setzero_ps()) /* x > 0 ? x : 0 (NaN-free here) */
/* row, wrow = v, id where v > row */
static inline __attribute__((always_inline)) void keep_max(float *row, uint32_t *wrow, vf v, uint32_t id)
{
    vf old = _mm_loadu_ps(row), m = _mm_cmpgt_ps(v, old);
    _mm_storeu_ps(row, _mm_or_ps(_mm_and_ps(m, v), _mm_andnot_ps(m, old)));
    __m128i w = _mm_loadu_si128((const __m128i *)wrow), mi = _mm_castps_si128(m);
    __m128i idv = _mm_set1_epi32((int)id);
    _mm_storeu_si128((__m128i *)wrow, _mm_or_si128(_mm_and_si128(mi, idv), _mm_andnot_si128(mi, w)));
}
static inline __attribute__((always_inline)) void ball_run(float *row, uint32_t *wrow, const float *x, float qx,
                                                           float dyz2, float inv_r, uint32_t id)
{
    vf dx = VSUB(VLD(x), V1(qx));
    vf v = VSUB(V1(1.0f), VMUL(VSQRT(VADD(VMUL(dx, dx), V1(dyz2))), V1(inv_r)));
    keep_max(row, wrow, v, id);
}
static inline __attribute__((always_inline)) void neck_run(float *row, uint32_t *wrow, const float *x, float qx,
                                                           float u0, float syz, float wyz2, float half, float inv_r,
                                                           float floor_v, uint32_t id)
{
    vf wx = VSUB(VLD(x), V1(qx));
    vf s = VADD(VMUL(wx, V1(u0)), V1(syz));
    vf q2 = VSUB(VADD(VMUL(wx, wx), V1(wyz2)), VMUL(s, s));
    vf t = VMUL(s, V1(inv_r)), t2 = VMUL(t, t);
    /* jm_cos_quarter, term by term */
    vf cs = VSUB(V1(1.0f / 40320), VMUL(t2, V1(1.0f / 3628800)));
    cs = VADD(V1(-1.0f / 720), VMUL(t2, cs));
    cs = VADD(V1(1.0f / 24), VMUL(t2, cs));
    cs = VADD(V1(-0.5f), VMUL(t2, cs));
    cs = VADD(V1(1.0f), VMUL(t2, cs));
    vf v = VSUB(cs, VMUL(VSQRT(VMAX0(q2)), V1(inv_r)));
    vf ok = _mm_and_ps(_mm_cmpge_ps(s, _mm_setzero_ps()), _mm_cmple_ps(s, V1(half)));
    v = _mm_or_ps(_mm_and_ps(ok, v), _mm_andnot_ps(ok, V1(floor_v)));
    keep_max(row, wrow, v, id);
}
#else
static inline void keep_max(float *row, uint32_t *wrow, const float *v, uint32_t id)
{
    for (int l = 0; l < RUN; l++) {
        int m = v[l] > row[l];
        row[l] = m ? v[l] : row[l];
        wrow[l] = m ? id : wrow[l];
    }
}
static inline void ball_run(float *row, uint32_t *wrow, const float *x, float qx, float dyz2, float inv_r, uint32_t id)
{
    float v[RUN];
    for (int l = 0; l < RUN; l++) {
        float dx = x[l] - qx;
        v[l] = 1.0f - sqrtf(dx * dx + dyz2) * inv_r;
    }
    keep_max(row, wrow, v, id);
}
static inline void neck_run(float *row, uint32_t *wrow, const float *x, float qx, float u0, float syz, float wyz2,
                            float half, float inv_r, float floor_v, uint32_t id)
{
    float v[RUN];
    for (int l = 0; l < RUN; l++) {
        float wx = x[l] - qx;
        float s = wx * u0 + syz;
        float q2 = wx * wx + wyz2 - s * s;
        float t = jm_cos_quarter(s * inv_r) - sqrtf(q2 > 0.0f ? q2 : 0.0f) * inv_r;
        v[l] = s >= 0.0f && s <= half ? t : floor_v;
    }
    keep_max(row, wrow, v, id);
}
#endif

JM_CLONES_AVX2 static void sample_meta(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x,
                        const float *y, const float *z, int n, float *f, uint32_t *win)
{
    const uint32_t np = (uint32_t)g->n;
    const float r = c->r, inv_r = 1.0f / r, reach = r + c->margin, reach2 = reach * reach, inv_h = c->inv_h;
    const float floor_v = -c->margin * inv_r;
    /* 1.02: float slack on the bound below */
    const float neck_reach = fminf(reach, 1.02f * r);
    size_t nn = (size_t)n * n * n;
    for (size_t i = 0; i < nn; i++) {
        f[i] = floor_v;
        win[i] = UINT32_MAX;
    }
    size_t cells = (size_t)hood->n[0] * hood->n[1] * hood->n[2];
    const float inf = c->influence, bx0 = x[0] - inf, bx1 = x[n - 1] + inf, by0 = y[0] - inf, by1 = y[n - 1] + inf;
    const float bz0 = z[0] - inf, bz1 = z[n - 1] + inf;
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
                    if (dyz2 >= reach2) continue;
                    float *row = f + ((size_t)kk * n + jj) * n;
                    uint32_t *wrow = win + ((size_t)kk * n + jj) * n;
                    for (int s0 = i0; s0 < i1; s0 += RUN) {
                        const int a = s0 < n - RUN ? s0 : n - RUN;
                        ball_run(row + a, wrow + a, x + a, qx, dyz2, inv_r, p);
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
                for (int kk = k0; kk < k1; kk++) {
                    float wz = z[kk] - q[2];
                    for (int jj = j0; jj < j1; jj++) {
                        float wy = y[jj] - q[1];
                        float *row = f + ((size_t)kk * n + jj) * n;
                        uint32_t *wrow = win + ((size_t)kk * n + jj) * n;
                        float syz = wy * u[1] + wz * u[2], wyz2 = wy * wy + wz * wz;
                        for (int s0 = i0; s0 < i1; s0 += RUN) {
                            const int a = s0 < n - RUN ? s0 : n - RUN;
                            neck_run(row + a, wrow + a, x + a, qx, u[0], syz, wyz2, half, inv_r, floor_v, np + e);
                        }
                    }
                }
            }
        }
    }
}

const float *jm_field_sample(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x,
                             const float *y, const float *z, int n, float *f, uint32_t *win, float *pad,
                             size_t *out_stride)
{
    if (c->field == JM_FIELD_SPH) {
        jm_sph_sample(g, c, hood, x, y, z, n, NULL, pad);
        *out_stride = JM_PAD(n);
        return pad;
    }
    sample_meta(g, c, hood, x, y, z, n, f, win);
    *out_stride = (size_t)n;
    return f;
}

/* out[a] = x_a / d for a < 3, as three divisions would give them: one
 * vector division where SSE2 is (the divider is the pieces' bottleneck) */
#if defined(__SSE2__) && JM_SPLAT_VARIANT != 1
#include <emmintrin.h>
static inline void div3(float x0, float x1, float x2, float d, float out[3])
{
    const __m128 q = _mm_div_ps(_mm_setr_ps(x0, x1, x2, 1.0f), _mm_set1_ps(d));
    _mm_storel_pi((__m64 *)out, q);
    _mm_store_ss(out + 2, _mm_movehl_ps(q, q));
}
#else
static inline void div3(float x0, float x1, float x2, float d, float out[3])
{
    out[0] = x0 / d;
    out[1] = x1 / d;
    out[2] = x2 / d;
}
#endif

float jm_prim_eval(const jm_grid *g, const jm_config *c, uint32_t id, const float p[3], float out[3], float *out_glen)
{
    const float inv_r = c->mv_inv_r;
    if (out_glen) *out_glen = inv_r;
    if (id < g->n) {
        const float *q = GP(g, id);
        float w[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
        float d = sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        if (out && d > 0.0f) div3(w[0], w[1], w[2], d, out);
        return 1.0f - d * inv_r;
    }
    uint32_t e = id - (uint32_t)g->n;
    const float *q = GP(g, g->nb_owner[e]), *u = &g->nb_dir[4 * (size_t)e];
    const float D = u[3];
    float w[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    float s = w[0] * u[0] + w[1] * u[1] + w[2] * u[2];
    /* beyond its half the neck continues as the same formula; callers only
     * use primitives that won at a node next to p */
    int clamped = s < 0.0f || s > 0.5f * D;
    if (s < 0.0f) s = 0.0f;
    if (s > 0.5f * D) s = 0.5f * D;
    float rad[3] = {w[0] - s * u[0], w[1] - s * u[1], w[2] - s * u[2]};
    float qq = sqrtf(rad[0] * rad[0] + rad[1] * rad[1] + rad[2] * rad[2]);
    if ((out || out_glen) && qq > 0.0f) {
        float sn = clamped ? 0.0f : jm_sin_quarter(s * inv_r), len = 0.0f, o[3], rq[3];
        div3(rad[0], rad[1], rad[2], qq, rq);
        for (int a = 0; a < 3; a++) { o[a] = sn * u[a] + rq[a]; len += o[a] * o[a]; }
        len = sqrtf(len);
        if (out_glen) *out_glen = len * inv_r;
        if (out) div3(o[0], o[1], o[2], len, out);
    }
    return jm_cos_quarter(s * inv_r) - qq * inv_r;
}

