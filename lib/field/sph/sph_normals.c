/* sph_normals.c - SPH normals: the particles near a part of a block gathered in groups of 8 (only the hood's cells that can hold them visited) and the gradient summed over them. */
#include "field/sph/sph_normals.h"
#include "core/cpu.h"
#include "core/cubic8.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])

/* The normal loop is built twice, for AVX2 machines and for any x86-64
 * (JM_KERNEL_AVX2, cpu.h); where the CPU has AVX-512 two vertices
 * share one register, and where it has AVX2 alone a hand-written loop skips
 * the groups out of reach (jm_sph_normals): the same bits. */

/* Only the hood's cells that can hold a particle of the box are visited, in
 * the hood's order: the same particles in the same order as a visit of
 * every cell. */
void jm_sph_gather(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float lo[3], const float hi[3],
                   jm_soa *out)
{
    const float R = c->support;
    int x0, x1, y0, y1, z0, z1;
    jm_hood_cell_span(g, hood, 0, lo[0], hi[0], R, &x0, &x1);
    jm_hood_cell_span(g, hood, 1, lo[1], hi[1], R, &y0, &y1);
    jm_hood_cell_span(g, hood, 2, lo[2], hi[2], R, &z0, &z1);
    out->n = 0;
    for (int z = z0; z <= z1; z++)
        for (int y = y0; y <= y1; y++)
            for (int x = x0; x <= x1; x++) {
                const size_t k = ((size_t)z * hood->n[1] + (size_t)y) * hood->n[0] + (size_t)x;
                for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {
                    const float *q = GP(g, p);
                    if (q[0] < lo[0] - R || q[0] > hi[0] + R || q[1] < lo[1] - R || q[1] > hi[1] + R ||
                        q[2] < lo[2] - R || q[2] > hi[2] + R || g->isolated[p])
                        continue;
                    if (out->n + 8 > out->cap) {
                        size_t nc = out->cap ? out->cap * 2 : 1024;
                        float *b = jm_realloc_lasting(out->mem, out->buf, 4 * out->cap * sizeof *b, 4 * nc * sizeof *b);
                        if (!b) { out->n = SIZE_MAX; return; }
                        out->buf = b;
                        out->cap = nc;
                    }
                    float *b = out->buf + 4 * (out->n & ~(size_t)7) + (out->n & 7);
                    b[0] = q[0];
                    b[8] = q[1];
                    b[16] = q[2];
                    b[24] = g->weight[p];
                    out->n++;
                }
            }
    /* pad the last group of 8 with weightless particles far away */
    for (size_t m = out->n; m & 7; m++) {
        float *b = out->buf + 4 * (m & ~(size_t)7) + (m & 7);
        b[0] = b[8] = b[16] = 1e30f;
        b[24] = 0.0f;
    }
}

/* Outward normal from the gathered particles: groups of 8 (x8, y8, z8, w8),
 * eight lanes summed in a fixed order, so SSE and AVX builds agree. */
JM_BODY int jm_sph_normal_body(const jm_config *c, const jm_soa *s, const float p[3], float nrm[3])
{
    const float R2 = c->support * c->support, inv = 1.0f / c->sph_h;
    float gx[8] = {0}, gy[8] = {0}, gz[8] = {0};
    size_t groups = (s->n + 7) / 8;
    for (size_t gi = 0; gi < groups; gi++) {
        const float *b = s->buf + 32 * gi;
        for (int l = 0; l < 8; l++) {
            float dx = p[0] - b[l], dy = p[1] - b[8 + l], dz = p[2] - b[16 + l];
            float d2 = dx * dx + dy * dy + dz * dz;
            float d = sqrtf(d2);
            float k = d2 < R2 && d2 > 0.0f ? b[24 + l] * jm_cubic_dw(d * inv) / d : 0.0f;
            gx[l] += k * dx;
            gy[l] += k * dy;
            gz[l] += k * dz;
        }
    }
    return jm_normal_from_lanes8(gx, gy, gz, nrm);
}
JM_KERNEL_AVX2(, int, jm_sph_normal, jm_sph_normal_body, (const jm_config *c, const jm_soa *s, const float p[3], float nrm[3]), (c, s, p, nrm))

#include "core/pair16.h"
#ifdef JM_PAIR16
/* Lanes 0-7 vertex p, lanes 8-15 vertex q, each group of 8 particles in
 * both halves: every lane does what lane l of jm_sph_normal does, the same
 * IEEE operations (no FMA) in the same order; a lane out of the support
 * adds k = 0 times its offset, a zero, as there (sums are never -0). */
__attribute__((target("avx512f"))) static void normal2_avx512(const jm_config *c, const jm_soa *s, const float p[3],
                                                             const float q[3], float np[3], float nq[3])
{
    const __m512 px = jm_pair16_set(p[0], q[0]), py = jm_pair16_set(p[1], q[1]), pz = jm_pair16_set(p[2], q[2]);
    const __m512 zero = _mm512_setzero_ps();
    const __m512 R2 = _mm512_set1_ps(c->support * c->support), inv = _mm512_set1_ps(1.0f / c->sph_h);
    __m512 gx = zero, gy = zero, gz = zero;
    const size_t groups = (s->n + 7) / 8;
    for (size_t gi = 0; gi < groups; gi++) {
        const float *b = s->buf + 32 * gi;
        const __m512 dx = _mm512_sub_ps(px, jm_pair16_load8(b)), dy = _mm512_sub_ps(py, jm_pair16_load8(b + 8));
        const __m512 dz = _mm512_sub_ps(pz, jm_pair16_load8(b + 16));
        const __m512 d2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)), _mm512_mul_ps(dz, dz));
        const __mmask16 in = _mm512_cmp_ps_mask(d2, R2, _CMP_LT_OQ) & _mm512_cmp_ps_mask(d2, zero, _CMP_GT_OQ);
        if (!in) continue;
        const __m512 d = _mm512_sqrt_ps(d2), dw = jm_pair16_cubic_dw(_mm512_mul_ps(d, inv));
        const __m512 k = _mm512_maskz_div_ps(in, _mm512_mul_ps(jm_pair16_load8(b + 24), dw), d);
        gx = _mm512_add_ps(gx, _mm512_mul_ps(k, dx));
        gy = _mm512_add_ps(gy, _mm512_mul_ps(k, dy));
        gz = _mm512_add_ps(gz, _mm512_mul_ps(k, dz));
    }
    jm_pair16_normals(gx, gy, gz, np, nq);
}

/* jm_sph_normal written out in AVX2 (the clone above is the compiler's): a
 * group of 8 with no particle in the support, whose lanes would each add
 * k = 0 times their offset, zeros, is skipped. The same IEEE operations in
 * the same order per lane, no FMA: the same bits. */
__attribute__((target("avx2"))) static void normal_avx2(const jm_config *c, const jm_soa *s, const float p[3],
                                                       float nrm[3])
{
    const __m256 px = _mm256_set1_ps(p[0]), py = _mm256_set1_ps(p[1]), pz = _mm256_set1_ps(p[2]);
    const __m256 zero = _mm256_setzero_ps();
    const __m256 R2 = _mm256_set1_ps(c->support * c->support), inv = _mm256_set1_ps(1.0f / c->sph_h);
    __m256 gx = zero, gy = zero, gz = zero;
    const size_t groups = (s->n + 7) / 8;
    for (size_t gi = 0; gi < groups; gi++) {
        const float *b = s->buf + 32 * gi;
        const __m256 dx = _mm256_sub_ps(px, _mm256_loadu_ps(b)), dy = _mm256_sub_ps(py, _mm256_loadu_ps(b + 8));
        const __m256 dz = _mm256_sub_ps(pz, _mm256_loadu_ps(b + 16));
        const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
        const __m256 in = _mm256_and_ps(_mm256_cmp_ps(d2, R2, _CMP_LT_OQ), _mm256_cmp_ps(d2, zero, _CMP_GT_OQ));
        if (_mm256_testz_ps(in, in)) continue;
        const __m256 d = _mm256_sqrt_ps(d2), dw = jm_cubic_dw8(_mm256_mul_ps(d, inv));
        /* lanes out of the support: d may be 0 (0 / 0): masked to k = 0 after the division */
        const __m256 k = _mm256_and_ps(in, _mm256_div_ps(_mm256_mul_ps(_mm256_loadu_ps(b + 24), dw), d));
        gx = _mm256_add_ps(gx, _mm256_mul_ps(k, dx));
        gy = _mm256_add_ps(gy, _mm256_mul_ps(k, dy));
        gz = _mm256_add_ps(gz, _mm256_mul_ps(k, dz));
    }
    float sx[8], sy[8], sz[8];
    _mm256_storeu_ps(sx, gx);
    _mm256_storeu_ps(sy, gy);
    _mm256_storeu_ps(sz, gz);
    jm_normal_from_lanes8(sx, sy, sz, nrm);
}
#endif

void jm_sph_normals(const jm_config *c, const jm_soa *s, const uint32_t *idx, size_t count, const float *pos,
                    float *nrm)
{
    size_t k = 0;
#ifdef JM_PAIR16
    if (jm_cpu_avx512())
        for (; k + 1 < count; k += 2)
            normal2_avx512(c, s, &pos[3 * (size_t)idx[k]], &pos[3 * (size_t)idx[k + 1]], &nrm[3 * (size_t)idx[k]],
                           &nrm[3 * (size_t)idx[k + 1]]);
    if (jm_cpu_avx2()) {
        for (; k < count; k++) normal_avx2(c, s, &pos[3 * (size_t)idx[k]], &nrm[3 * (size_t)idx[k]]);
        return;
    }
#endif
    for (; k < count; k++) jm_sph_normal(c, s, &pos[3 * (size_t)idx[k]], &nrm[3 * (size_t)idx[k]]);
}
