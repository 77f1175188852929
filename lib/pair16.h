/* pair16.h - two independent 8-lane jobs in one AVX-512 register (lanes 0-7 the first, 8-15 the second): their broadcasts and shared loads. */
#ifndef JETMESH_PAIR16_H
#define JETMESH_PAIR16_H
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define JM_PAIR16 1

/* a in lanes 0-7, b in lanes 8-15 */
__attribute__((target("avx512f"))) static inline __m512 jm_pair16_set(float a, float b)
{
    return _mm512_mask_blend_ps(0xFF00, _mm512_set1_ps(a), _mm512_set1_ps(b));
}
/* the 8 floats at p in both halves: each job reads the same group */
__attribute__((target("avx512f"))) static inline __m512 jm_pair16_load8(const float *p)
{
    return _mm512_castpd_ps(_mm512_broadcast_f64x4(_mm256_castps_pd(_mm256_loadu_ps(p))));
}
#endif
#endif
