/* round8.h - iceil and ifloor (field.h) on 8 AVX2 lanes: truncation stepped by a compare, the same integers lane by lane. */
#ifndef JETMESH_ROUND8_H
#define JETMESH_ROUND8_H
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

/* iceil on every lane: t = (int)x, plus 1 where x > t (the compare's mask
 * is -1); for x within +-2^31 */
__attribute__((target("avx2"), always_inline)) static inline __m256i jm_iceil8(__m256 x)
{
    const __m256i t = _mm256_cvttps_epi32(x);
    return _mm256_sub_epi32(t, _mm256_castps_si256(_mm256_cmp_ps(x, _mm256_cvtepi32_ps(t), _CMP_GT_OQ)));
}
/* ifloor on every lane: t = (int)x, less 1 where x < t */
__attribute__((target("avx2"), always_inline)) static inline __m256i jm_ifloor8(__m256 x)
{
    const __m256i t = _mm256_cvttps_epi32(x);
    return _mm256_add_epi32(t, _mm256_castps_si256(_mm256_cmp_ps(x, _mm256_cvtepi32_ps(t), _CMP_LT_OQ)));
}
#endif
#endif
