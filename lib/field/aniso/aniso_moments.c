/* aniso_moments.c - the weighted moments of a particle's neighbourhood for the anisotropic kernels, two particles at a time (AVX-512) or one (C). */
#include "field/aniso/aniso_moments.h"
#include "field/aniso/anisotropy.h"
#include "core/cpu.h"
#include "core/internal.h"
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <string.h>

/* The one-at-a-time loop is built for x86-64-v4 and AVX2 machines and for
 * any x86-64 (JM_KERNEL_V4, cpu.h): the same bits. */

JM_BODY void jm_an_moments_body(const float *xs, const float *ys, const float *zs, size_t groups, const float p[3],
                                const jm_an_radii *rad, double out[JM_AN_MOMENTS])
{
    const float R2 = rad->R2, invR = rad->invR, S2 = rad->S2, invB = rad->invB;
    float L[JM_AN_MOMENTS][8];
    memset(L, 0, sizeof L);
    const float px = p[0], py = p[1], pz = p[2];
    for (size_t b = 0; b < groups; b++)
        for (int l = 0; l < 8; l++) {
            const float ex = xs[8 * b + l] - px, ey = ys[8 * b + l] - py, ez = zs[8 * b + l] - pz;
            const float d2 = ex * ex + ey * ey + ez * ez;
            const float u = sqrtf(d2) * invR;
            const float w = d2 < R2 ? 1.0f - u * u * u : 0.0f;
            const float wx = w * ex, wy = w * ey, wz = w * ez;
            L[0][l] += w;
            L[1][l] += wx;
            L[2][l] += wy;
            L[3][l] += wz;
            L[4][l] += wx * ex;
            L[5][l] += wx * ey;
            L[6][l] += wx * ez;
            L[7][l] += wy * ey;
            L[8][l] += wy * ez;
            L[9][l] += wz * ez;
            L[10][l] += d2 < R2 && d2 > 0.0f ? 1.0f : 0.0f;
            L[11][l] += jm_an_near(d2, S2, invB);
        }
    for (int k = 0; k < JM_AN_MOMENTS; k++) {
        out[k] = 0.0;
        for (int l = 0; l < 8; l++) out[k] += L[k][l];
    }
}
JM_KERNEL_V4(, void, jm_an_moments, jm_an_moments_body, (const float *xs, const float *ys, const float *zs, size_t groups, const float p[3], const jm_an_radii *rad, double out[JM_AN_MOMENTS]), (xs, ys, zs, groups, p, rad, out))

#include "core/pair16.h"
#ifdef JM_PAIR16
/* Lanes 0-7 particle p, lanes 8-15 particle q, each group of 8 candidates
 * in both halves: every lane does what lane l of jm_an_moments does, the
 * same IEEE operations (no FMA) in the same order. */
__attribute__((target("avx512f"))) static void moments2_avx512(const float *xs, const float *ys, const float *zs,
                                                              size_t groups, const float p[3], const float q[3],
                                                              const jm_an_radii *rad, double out_p[JM_AN_MOMENTS],
                                                              double out_q[JM_AN_MOMENTS])
{
    const float R2 = rad->R2, invR = rad->invR;
    const __m512 px = jm_pair16_set(p[0], q[0]), py = jm_pair16_set(p[1], q[1]), pz = jm_pair16_set(p[2], q[2]);
    const __m512 vR2 = _mm512_set1_ps(R2), vinv = _mm512_set1_ps(invR), one = _mm512_set1_ps(1.0f);
    const __m512 zero = _mm512_setzero_ps();
    const __m512 vS2 = _mm512_set1_ps(rad->S2), vinvB = _mm512_set1_ps(rad->invB);
    __m512 L0 = zero, L1 = zero, L2 = zero, L3 = zero, L4 = zero, L5 = zero, L6 = zero, L7 = zero, L8 = zero;
    __m512 L9 = zero, L10 = zero, L11 = zero;
    for (size_t b = 0; b < groups; b++) {
        const __m512 ex = _mm512_sub_ps(jm_pair16_load8(xs + 8 * b), px);
        const __m512 ey = _mm512_sub_ps(jm_pair16_load8(ys + 8 * b), py);
        const __m512 ez = _mm512_sub_ps(jm_pair16_load8(zs + 8 * b), pz);
        const __m512 d2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(ex, ex), _mm512_mul_ps(ey, ey)), _mm512_mul_ps(ez, ez));
        const __m512 u = _mm512_mul_ps(_mm512_sqrt_ps(d2), vinv);
        const __mmask16 in = _mm512_cmp_ps_mask(d2, vR2, _CMP_LT_OQ);
        const __m512 w = _mm512_maskz_sub_ps(in, one, _mm512_mul_ps(_mm512_mul_ps(u, u), u));
        const __m512 wx = _mm512_mul_ps(w, ex), wy = _mm512_mul_ps(w, ey), wz = _mm512_mul_ps(w, ez);
        L0 = _mm512_add_ps(L0, w);
        L1 = _mm512_add_ps(L1, wx);
        L2 = _mm512_add_ps(L2, wy);
        L3 = _mm512_add_ps(L3, wz);
        L4 = _mm512_add_ps(L4, _mm512_mul_ps(wx, ex));
        L5 = _mm512_add_ps(L5, _mm512_mul_ps(wx, ey));
        L6 = _mm512_add_ps(L6, _mm512_mul_ps(wx, ez));
        L7 = _mm512_add_ps(L7, _mm512_mul_ps(wy, ey));
        L8 = _mm512_add_ps(L8, _mm512_mul_ps(wy, ez));
        L9 = _mm512_add_ps(L9, _mm512_mul_ps(wz, ez));
        const __mmask16 nb = _mm512_mask_cmp_ps_mask(in, d2, zero, _CMP_GT_OQ);
        L10 = _mm512_add_ps(L10, _mm512_maskz_mov_ps(nb, one));
        /* jm_an_near: min(max((S2 - d2) invB, 0), 1), the same operations */
        const __m512 t = _mm512_mul_ps(_mm512_sub_ps(vS2, d2), vinvB);
        L11 = _mm512_add_ps(L11, _mm512_min_ps(_mm512_max_ps(t, zero), one));
    }
    float s[JM_AN_MOMENTS][16];
    _mm512_storeu_ps(s[0], L0);
    _mm512_storeu_ps(s[1], L1);
    _mm512_storeu_ps(s[2], L2);
    _mm512_storeu_ps(s[3], L3);
    _mm512_storeu_ps(s[4], L4);
    _mm512_storeu_ps(s[5], L5);
    _mm512_storeu_ps(s[6], L6);
    _mm512_storeu_ps(s[7], L7);
    _mm512_storeu_ps(s[8], L8);
    _mm512_storeu_ps(s[9], L9);
    _mm512_storeu_ps(s[10], L10);
    _mm512_storeu_ps(s[11], L11);
    for (int k = 0; k < JM_AN_MOMENTS; k++) {
        out_p[k] = out_q[k] = 0.0;
        for (int l = 0; l < 8; l++) {
            out_p[k] += s[k][l];
            out_q[k] += s[k][8 + l];
        }
    }
}
#endif

void jm_an_moments2(const float *xs, const float *ys, const float *zs, size_t groups, const float p[3],
                    const float q[3], const jm_an_radii *rad, double out_p[JM_AN_MOMENTS],
                    double out_q[JM_AN_MOMENTS])
{
#ifdef JM_PAIR16
    if (jm_cpu_avx512()) {
        moments2_avx512(xs, ys, zs, groups, p, q, rad, out_p, out_q);
        return;
    }
#endif
    jm_an_moments(xs, ys, zs, groups, p, rad, out_p);
    jm_an_moments(xs, ys, zs, groups, q, rad, out_q);
}

/* a candidate's squared distance to [lo, hi] under lim (plain C) */
static inline int in_reach(float x, float y, float z, const float lo[3], const float hi[3], float lim)
{
    float dx = lo[0] - x > x - hi[0] ? lo[0] - x : x - hi[0];
    float dy = lo[1] - y > y - hi[1] ? lo[1] - y : y - hi[1];
    float dz = lo[2] - z > z - hi[2] ? lo[2] - z : z - hi[2];
    dx = dx > 0.0f ? dx : 0.0f;
    dy = dy > 0.0f ? dy : 0.0f;
    dz = dz > 0.0f ? dz : 0.0f;
    return dx * dx + dy * dy + dz * dz < lim;
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
/* 8 candidates at a time: the same comparisons in lanes, the kept ones
 * moved to the front of the step by a permutation from the mask's table */
static uint32_t perm[256][8]; /* per mask: the kept lanes' indices first */
static pthread_once_t perm_once = PTHREAD_ONCE_INIT;
static void perm_init(void)
{
    for (int k = 0; k < 256; k++) {
        int n = 0;
        for (int l = 0; l < 8; l++)
            if (k >> l & 1) perm[k][n++] = (uint32_t)l;
        while (n < 8) perm[k][n++] = 0;
    }
}

__attribute__((target("avx2"))) static size_t keep_avx2(float *xs, float *ys, float *zs, size_t m, const float lo[3],
                                                       const float hi[3], float lim, size_t *done)
{
    pthread_once(&perm_once, perm_init);
    const __m256 l0 = _mm256_set1_ps(lo[0]), l1 = _mm256_set1_ps(lo[1]), l2 = _mm256_set1_ps(lo[2]);
    const __m256 h0 = _mm256_set1_ps(hi[0]), h1 = _mm256_set1_ps(hi[1]), h2 = _mm256_set1_ps(hi[2]);
    const __m256 zero = _mm256_setzero_ps(), vlim = _mm256_set1_ps(lim);
    size_t k = 0, t = 0;
    for (; t + 8 <= m; t += 8) {
        const __m256 x = _mm256_loadu_ps(xs + t), y = _mm256_loadu_ps(ys + t), z = _mm256_loadu_ps(zs + t);
        /* max(a, b) as (a > b ? a : b): _mm256_max_ps(b, a) */
        const __m256 dx = _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(x, h0), _mm256_sub_ps(l0, x)), zero);
        const __m256 dy = _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(y, h1), _mm256_sub_ps(l1, y)), zero);
        const __m256 dz = _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(z, h2), _mm256_sub_ps(l2, z)), zero);
        const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
        const int mask = _mm256_movemask_ps(_mm256_cmp_ps(d2, vlim, _CMP_LT_OQ));
        const __m256i p = _mm256_loadu_si256((const __m256i *)perm[mask]);
        /* k <= t: the stores never pass the loads still to come */
        _mm256_storeu_ps(xs + k, _mm256_permutevar8x32_ps(x, p));
        _mm256_storeu_ps(ys + k, _mm256_permutevar8x32_ps(y, p));
        _mm256_storeu_ps(zs + k, _mm256_permutevar8x32_ps(z, p));
        k += (size_t)__builtin_popcount((unsigned)mask);
    }
    *done = t;
    return k;
}
#define JM_KEEP_AVX2 1
#endif

size_t jm_an_keep_in_reach(float *xs, float *ys, float *zs, size_t m, const float lo[3], const float hi[3], float R2)
{
    const float lim = R2 * 1.0001f;
    size_t k = 0, t = 0;
#ifdef JM_KEEP_AVX2
    if (jm_cpu_avx2()) k = keep_avx2(xs, ys, zs, m, lo, hi, lim, &t);
#endif
    for (; t < m; t++) {
        const float x = xs[t], y = ys[t], z = zs[t];
        /* written always, kept by advancing k (k <= t) */
        xs[k] = x;
        ys[k] = y;
        zs[k] = z;
        k += (size_t)in_reach(x, y, z, lo, hi, lim);
    }
    return k;
}
