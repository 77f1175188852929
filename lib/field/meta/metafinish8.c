/* metafinish8.c - the metasphere finish's per-triangle kernels, 8 triangles per pass of AVX2 (two a register), with the bits of metafinish.c's one-at-a-time ones. */
#include "field/meta/metafinish16.h"
#include "core/cpu.h"

/* As metafinish16.c on 256-bit registers, for the CPUs without AVX-512
 * (there the one-at-a-time code is a large part of the metasphere's
 * work): each 128-bit lane one triangle laid out as metafinish.c's
 * SSE2 code lays out one (x, y, z, +0), running that code's operations (its
 * shuffles stay within a lane). */
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

int jm_finish8_ok(void) { return jm_cpu_avx2(); }

#define AVX2 __attribute__((target("avx2")))

/* the point b + 3 v (x, y, z, +0), read as metafinish.c's ld3 reads it */
AVX2 static inline __m128 ld3(const float *b, uint32_t v)
{
    const float *p = b + 3 * (size_t)v;
    return _mm_movelh_ps(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)p)), _mm_load_ss(p + 2));
}
/* lane j: corner k of triangle v_j */
AVX2 static inline __m256 ld3x2(const float *b, const uint32_t *v0, const uint32_t *v1, int k)
{
    return _mm256_insertf128_ps(_mm256_castps128_ps256(ld3(b, v0[k])), ld3(b, v1[k]), 1);
}
/* lane j: x[v_j[k]] in its four floats */
AVX2 static inline __m256 splat2(const float *x, const uint32_t *v0, const uint32_t *v1, int k)
{
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_set1_ps(x[v0[k]])), _mm_set1_ps(x[v1[k]]), 1);
}
/* per lane u x w, as cross3 in metafinish.c */
AVX2 static inline __m256 cross2(__m256 u, __m256 w)
{
    const __m256 u1 = _mm256_shuffle_ps(u, u, _MM_SHUFFLE(3, 0, 2, 1)), w2 = _mm256_shuffle_ps(w, w, _MM_SHUFFLE(3, 1, 0, 2));
    const __m256 u2 = _mm256_shuffle_ps(u, u, _MM_SHUFFLE(3, 1, 0, 2)), w1 = _mm256_shuffle_ps(w, w, _MM_SHUFFLE(3, 0, 2, 1));
    return _mm256_sub_ps(_mm256_mul_ps(u1, w2), _mm256_mul_ps(u2, w1));
}
/* per lane, first float: s + m0 + m1 + m2, left to right (sum3) */
AVX2 static inline __m256 sum2(__m256 s, __m256 m)
{
    s = _mm256_add_ps(s, m);
    s = _mm256_add_ps(s, _mm256_shuffle_ps(m, m, 1));
    return _mm256_add_ps(s, _mm256_shuffle_ps(m, m, 2));
}
/* per lane, first float: a . b as dot3 */
AVX2 static inline __m256 dot2(__m256 a, __m256 b)
{
    const __m256 m = _mm256_mul_ps(a, b);
    return _mm256_add_ps(_mm256_add_ps(m, _mm256_shuffle_ps(m, m, 1)), _mm256_shuffle_ps(m, m, 2));
}
/* the first floats of the two lanes */
AVX2 static inline void firsts(__m256 x, float *out)
{
    out[0] = _mm_cvtss_f32(_mm256_castps256_ps128(x));
    out[1] = _mm_cvtss_f32(_mm256_extractf128_ps(x, 1));
}

AVX2 void jm_finish_sag8(const float *P, const float *N, const uint32_t *idx, size_t t0, float *as, float *area)
{
    for (int g = 0; g < 8; g += 2) {
        const uint32_t *v0 = idx + 3 * (t0 + g), *v1 = v0 + 3;
        const __m256 p0 = ld3x2(P, v0, v1, 0), p1 = ld3x2(P, v0, v1, 1), p2 = ld3x2(P, v0, v1, 2);
        const __m256 n0 = ld3x2(N, v0, v1, 0), n1 = ld3x2(N, v0, v1, 1), n2 = ld3x2(N, v0, v1, 2);
        const __m256 e1 = _mm256_sub_ps(p1, p0), e2 = _mm256_sub_ps(p2, p1), e3 = _mm256_sub_ps(p0, p2);
        const __m256 cr = cross2(e3, e1);
        const __m256 len = _mm256_sqrt_ps(dot2(cr, cr));
        const __m256 m1 = _mm256_mul_ps(_mm256_sub_ps(n1, n0), e1), m2 = _mm256_mul_ps(_mm256_sub_ps(n2, n1), e2),
                     m3 = _mm256_mul_ps(_mm256_sub_ps(n0, n2), e3);
        __m256 s = _mm256_add_ps(m1, _mm256_shuffle_ps(m1, m1, 1));
        s = _mm256_add_ps(s, _mm256_shuffle_ps(m1, m1, 2));
        s = sum2(sum2(s, m2), m3);
        const __m256 ar = _mm256_mul_ps(_mm256_set1_ps(0.5f), len);
        firsts(ar, area + g);
        firsts(_mm256_mul_ps(_mm256_mul_ps(ar, s), _mm256_set1_ps(1.0f / 24.0f)), as + g);
    }
}

AVX2 uint32_t jm_finish_fold8(const float *P, const float *N, const float *D, const uint32_t *idx, size_t t0,
                              int facing)
{
    uint32_t out = 0;
    for (int g = 0; g < 8; g += 2) {
        const uint32_t *v0 = idx + 3 * (t0 + g), *v1 = v0 + 3;
        __m256 p[3], q[3], n[3];
        for (int k = 0; k < 3; k++) {
            n[k] = ld3x2(N, v0, v1, k);
            p[k] = ld3x2(P, v0, v1, k);
            q[k] = _mm256_add_ps(p[k], _mm256_mul_ps(splat2(D, v0, v1, k), n[k]));
        }
        const __m256 c0 = cross2(_mm256_sub_ps(p[1], p[0]), _mm256_sub_ps(p[2], p[0]));
        const __m256 c1 = cross2(_mm256_sub_ps(q[1], q[0]), _mm256_sub_ps(q[2], q[0]));
        /* lane j's first float below zero: bit 4 j */
        const int f = _mm256_movemask_ps(_mm256_cmp_ps(dot2(c0, c1), _mm256_setzero_ps(), _CMP_LT_OQ));
        int away = 0;
        if (facing) {
            /* facing_away per lane: the corners' dots in its first three
             * floats */
            const __m256 cc = dot2(c1, c1);
            const __m256 lim2 = _mm256_mul_ps(_mm256_set1_ps(JM_FINISH_COS_MIN * JM_FINISH_COS_MIN),
                                              _mm256_shuffle_ps(cc, cc, 0));
            const __m256 ma = _mm256_mul_ps(n[0], c1), mb = _mm256_mul_ps(n[1], c1), mc = _mm256_mul_ps(n[2], c1);
            const __m256 lo = _mm256_unpacklo_ps(ma, mb), hi = _mm256_unpackhi_ps(ma, mb);
            const __m256 d = _mm256_add_ps(_mm256_add_ps(_mm256_shuffle_ps(lo, mc, _MM_SHUFFLE(3, 0, 1, 0)),
                                                         _mm256_shuffle_ps(lo, mc, _MM_SHUFFLE(3, 1, 3, 2))),
                                           _mm256_shuffle_ps(hi, mc, _MM_SHUFFLE(3, 2, 1, 0)));
            const __m256 ok = _mm256_and_ps(_mm256_cmp_ps(d, _mm256_setzero_ps(), _CMP_GT_OQ),
                                            _mm256_cmp_ps(_mm256_mul_ps(d, d), lim2, _CMP_GT_OQ));
            away = ~_mm256_movemask_ps(ok);
        }
        for (int j = 0; j < 2; j++) {
            out |= (uint32_t)(f >> (4 * j) & 1) << (g + j);
            out |= (uint32_t)((away >> (4 * j) & 7) != 0) << (16 + g + j);
        }
    }
    return out;
}
#else
int jm_finish8_ok(void) { return 0; }
void jm_finish_sag8(const float *P, const float *N, const uint32_t *idx, size_t t0, float *as, float *area)
{
    (void)P, (void)N, (void)idx, (void)t0, (void)as, (void)area;
}
uint32_t jm_finish_fold8(const float *P, const float *N, const float *D, const uint32_t *idx, size_t t0, int facing)
{
    (void)P, (void)N, (void)D, (void)idx, (void)t0, (void)facing;
    return 0;
}
#endif
