/* cubic8.h - the cubic spline kernel and its derivative on 8 lanes (AVX2): the same IEEE operations, in the same order, as jm_cubic_w and jm_cubic_dw. */
#ifndef JETMESH_CUBIC8_H
#define JETMESH_CUBIC8_H
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define JM_CUBIC8 1

/* jm_cubic_w (internal.h) on every lane: 0.25 a a a - b b b, a = max(2 - q,
 * 0), b = max(1 - q, 0) (max_ps gives +0 where the C's a > 0 ? a : 0 does) */
__attribute__((target("avx2"), always_inline)) static inline __m256 jm_cubic_w8(__m256 q)
{
    const __m256 zero = _mm256_setzero_ps();
    const __m256 A = _mm256_max_ps(_mm256_sub_ps(_mm256_set1_ps(2.0f), q), zero);
    const __m256 B = _mm256_max_ps(_mm256_sub_ps(_mm256_set1_ps(1.0f), q), zero);
    return _mm256_sub_ps(_mm256_mul_ps(_mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(0.25f), A), A), A),
                         _mm256_mul_ps(_mm256_mul_ps(B, B), B));
}
/* jm_cubic_dw (internal.h) on every lane: -0.75 a a + 3 b b */
__attribute__((target("avx2"), always_inline)) static inline __m256 jm_cubic_dw8(__m256 q)
{
    const __m256 zero = _mm256_setzero_ps();
    const __m256 A = _mm256_max_ps(_mm256_sub_ps(_mm256_set1_ps(2.0f), q), zero);
    const __m256 B = _mm256_max_ps(_mm256_sub_ps(_mm256_set1_ps(1.0f), q), zero);
    return _mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(-0.75f), A), A),
                         _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(3.0f), B), B));
}
#endif
#endif
