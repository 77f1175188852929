/* aniso_moments.c - the weighted moments of a particle's neighbourhood for the anisotropic kernels, two particles at a time (AVX-512) or one (C). */
#include "aniso_moments.h"
#include "anisotropy.h"
#include "cpu.h"
#include "internal.h"
#include <string.h>
#include <math.h>

/* The one-at-a-time loop is built for x86-64-v4 and AVX2 machines and for
 * any x86-64 (JM_CLONES_V4, internal.h): the same bits. */

JM_CLONES_V4 void jm_an_moments(const float *xs, const float *ys, const float *zs, size_t groups, const float p[3],
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

#include "pair16.h"
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
