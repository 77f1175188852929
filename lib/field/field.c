/* field.c - the cells of the grid around a block (its hood), and one metasphere piece evaluated at a point. */
#include "field/field.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])

int jm_hood_size(jm_hood *hood, const jm_grid *g, const jm_config *c, const float lo[3], const float hi[3])
{
    size_t total = 1;
    for (int a = 0; a < 3; a++) {
        hood->c0[a] = jm_hood_cell_lo(g, c, lo[a]);
        int64_t c1 = (int64_t)floorf((hi[a] + c->influence) * g->inv_cell) + 1;
        hood->n[a] = (int)(c1 - hood->c0[a] + 1);
        total *= (size_t)hood->n[a];
    }
    if (total > hood->cap) {
        uint32_t *r = jm_realloc_lasting(hood->mem, hood->range, 2 * hood->cap * sizeof *r, 2 * total * sizeof *r);
        if (!r) return 0;
        hood->range = r;
        hood->cap = total;
    }
    return 1;
}

int jm_hood_build(jm_hood *hood, const jm_grid *g, const jm_config *c, const float lo[3], const float hi[3])
{
    if (!jm_hood_size(hood, g, c, lo, hi)) return 0;
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

/* out[a] = x_a / d for a < 3, as three divisions would give them: one
 * vector division where SSE2 is (the divider is the pieces' bottleneck) */
#ifdef __SSE2__
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

