/* metafinish16.c - the metasphere finish's per-triangle kernels, 16 triangles per AVX-512 pass, with the bits of metafinish.c's one-at-a-time ones. */
#include "field/meta/metafinish16.h"
#include "core/cpu.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

/* the 128-bit masked loads are AVX-512VL, part of cpu.h's AVX-512 level */
int jm_finish16_ok(void) { return jm_cpu_avx512(); }

/* Four triangles a register, one a 128-bit lane laid out as metafinish.c's
 * SSE2 code lays out one (x, y, z, +0), so that each lane runs that code's
 * operations: its shuffles stay within a lane. */
#define AVX512 __attribute__((target("avx512f,avx512vl")))

/* lane j: the point b + 3 v[j] (x, y, z, +0; masked loads read nothing
 * past it) */
AVX512 static inline __m512 ld3x4(const float *b, const uint32_t *v0, const uint32_t *v1, const uint32_t *v2,
                                  const uint32_t *v3, int k)
{
    __m512 r = _mm512_castps128_ps512(_mm_maskz_loadu_ps(7, b + 3 * (size_t)v0[k]));
    r = _mm512_insertf32x4(r, _mm_maskz_loadu_ps(7, b + 3 * (size_t)v1[k]), 1);
    r = _mm512_insertf32x4(r, _mm_maskz_loadu_ps(7, b + 3 * (size_t)v2[k]), 2);
    return _mm512_insertf32x4(r, _mm_maskz_loadu_ps(7, b + 3 * (size_t)v3[k]), 3);
}
/* lane j: x[v[j]] in its four floats */
AVX512 static inline __m512 splat4(const float *x, const uint32_t *v0, const uint32_t *v1, const uint32_t *v2,
                                   const uint32_t *v3, int k)
{
    const __m512 s = _mm512_castps128_ps512(_mm_setr_ps(x[v0[k]], x[v1[k]], x[v2[k]], x[v3[k]]));
    return _mm512_permutexvar_ps(_mm512_set_epi32(3, 3, 3, 3, 2, 2, 2, 2, 1, 1, 1, 1, 0, 0, 0, 0), s);
}
/* per lane u x w, as cross3 in metafinish.c */
AVX512 static inline __m512 cross4(__m512 u, __m512 w)
{
    const __m512 u1 = _mm512_shuffle_ps(u, u, _MM_SHUFFLE(3, 0, 2, 1)), w2 = _mm512_shuffle_ps(w, w, _MM_SHUFFLE(3, 1, 0, 2));
    const __m512 u2 = _mm512_shuffle_ps(u, u, _MM_SHUFFLE(3, 1, 0, 2)), w1 = _mm512_shuffle_ps(w, w, _MM_SHUFFLE(3, 0, 2, 1));
    return _mm512_sub_ps(_mm512_mul_ps(u1, w2), _mm512_mul_ps(u2, w1));
}
/* per lane, first float: s + m0 + m1 + m2, left to right (sum3) */
AVX512 static inline __m512 sum4(__m512 s, __m512 m)
{
    s = _mm512_add_ps(s, m);
    s = _mm512_add_ps(s, _mm512_shuffle_ps(m, m, 1));
    return _mm512_add_ps(s, _mm512_shuffle_ps(m, m, 2));
}
/* per lane, first float: a . b as dot3 */
AVX512 static inline __m512 dot4(__m512 a, __m512 b)
{
    const __m512 m = _mm512_mul_ps(a, b);
    return _mm512_add_ps(_mm512_add_ps(m, _mm512_shuffle_ps(m, m, 1)), _mm512_shuffle_ps(m, m, 2));
}
/* the first floats of the four lanes */
AVX512 static inline void firsts(__m512 x, float *out)
{
    _mm_storeu_ps(out, _mm512_castps512_ps128(_mm512_permutexvar_ps(_mm512_set_epi32(0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 12, 8, 4, 0), x)));
}

AVX512 void jm_finish_sag16(const float *P, const float *N, const uint32_t *idx, size_t t0, float *as, float *area)
{
    for (int g = 0; g < 16; g += 4) {
        const uint32_t *v0 = idx + 3 * (t0 + g), *v1 = v0 + 3, *v2 = v0 + 6, *v3 = v0 + 9;
        const __m512 p0 = ld3x4(P, v0, v1, v2, v3, 0), p1 = ld3x4(P, v0, v1, v2, v3, 1),
                     p2 = ld3x4(P, v0, v1, v2, v3, 2);
        const __m512 n0 = ld3x4(N, v0, v1, v2, v3, 0), n1 = ld3x4(N, v0, v1, v2, v3, 1),
                     n2 = ld3x4(N, v0, v1, v2, v3, 2);
        const __m512 e1 = _mm512_sub_ps(p1, p0), e2 = _mm512_sub_ps(p2, p1), e3 = _mm512_sub_ps(p0, p2);
        const __m512 cr = cross4(e3, e1);
        const __m512 len = _mm512_sqrt_ps(dot4(cr, cr));
        const __m512 m1 = _mm512_mul_ps(_mm512_sub_ps(n1, n0), e1), m2 = _mm512_mul_ps(_mm512_sub_ps(n2, n1), e2),
                     m3 = _mm512_mul_ps(_mm512_sub_ps(n0, n2), e3);
        __m512 s = _mm512_add_ps(m1, _mm512_shuffle_ps(m1, m1, 1));
        s = _mm512_add_ps(s, _mm512_shuffle_ps(m1, m1, 2));
        s = sum4(sum4(s, m2), m3);
        const __m512 ar = _mm512_mul_ps(_mm512_set1_ps(0.5f), len);
        firsts(ar, area + g);
        firsts(_mm512_mul_ps(_mm512_mul_ps(ar, s), _mm512_set1_ps(1.0f / 24.0f)), as + g);
    }
}

AVX512 uint32_t jm_finish_fold16(const float *P, const float *N, const float *D, const uint32_t *idx, size_t t0,
                                 int facing)
{
    uint32_t out = 0;
    for (int g = 0; g < 16; g += 4) {
        const uint32_t *v0 = idx + 3 * (t0 + g), *v1 = v0 + 3, *v2 = v0 + 6, *v3 = v0 + 9;
        __m512 p[3], q[3], n[3];
        for (int k = 0; k < 3; k++) {
            n[k] = ld3x4(N, v0, v1, v2, v3, k);
            p[k] = ld3x4(P, v0, v1, v2, v3, k);
            q[k] = _mm512_add_ps(p[k], _mm512_mul_ps(splat4(D, v0, v1, v2, v3, k), n[k]));
        }
        const __m512 c0 = cross4(_mm512_sub_ps(p[1], p[0]), _mm512_sub_ps(p[2], p[0]));
        const __m512 c1 = cross4(_mm512_sub_ps(q[1], q[0]), _mm512_sub_ps(q[2], q[0]));
        /* lane j's first float below zero: bit 4 j */
        const __mmask16 f = _mm512_cmp_ps_mask(dot4(c0, c1), _mm512_setzero_ps(), _CMP_LT_OQ);
        uint32_t away = 0;
        if (facing) {
            /* facing_away per lane: the corners' dots in its first three
             * floats */
            const __m512 cc = dot4(c1, c1);
            const __m512 lim2 = _mm512_mul_ps(_mm512_set1_ps(JM_FINISH_COS_MIN * JM_FINISH_COS_MIN),
                                              _mm512_shuffle_ps(cc, cc, 0));
            const __m512 ma = _mm512_mul_ps(n[0], c1), mb = _mm512_mul_ps(n[1], c1), mc = _mm512_mul_ps(n[2], c1);
            const __m512 lo = _mm512_unpacklo_ps(ma, mb), hi = _mm512_unpackhi_ps(ma, mb);
            const __m512 d = _mm512_add_ps(_mm512_add_ps(_mm512_shuffle_ps(lo, mc, _MM_SHUFFLE(3, 0, 1, 0)),
                                                         _mm512_shuffle_ps(lo, mc, _MM_SHUFFLE(3, 1, 3, 2))),
                                           _mm512_shuffle_ps(hi, mc, _MM_SHUFFLE(3, 2, 1, 0)));
            const __mmask16 ok = _mm512_cmp_ps_mask(d, _mm512_setzero_ps(), _CMP_GT_OQ) &
                                 _mm512_cmp_ps_mask(_mm512_mul_ps(d, d), lim2, _CMP_GT_OQ);
            away = ~(uint32_t)ok;
        }
        for (int j = 0; j < 4; j++) {
            out |= (uint32_t)(f >> (4 * j) & 1) << (g + j);
            out |= (uint32_t)((away >> (4 * j) & 7) != 0) << (16 + g + j);
        }
    }
    return out;
}
#else
int jm_finish16_ok(void) { return 0; }
void jm_finish_sag16(const float *P, const float *N, const uint32_t *idx, size_t t0, float *as, float *area)
{
    (void)P, (void)N, (void)idx, (void)t0, (void)as, (void)area;
}
uint32_t jm_finish_fold16(const float *P, const float *N, const float *D, const uint32_t *idx, size_t t0, int facing)
{
    (void)P, (void)N, (void)D, (void)idx, (void)t0, (void)facing;
    return 0;
}
#endif
