/* pair16.h - two independent 8-lane jobs in one AVX-512 register (lanes 0-7 the first, 8-15 the second): their broadcasts and shared loads. */
#ifndef JETMESH_PAIR16_H
#define JETMESH_PAIR16_H
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#include "core/internal.h"
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
/* jm_cubic_dw (internal.h) on every lane, the same operations in the same
 * order: -0.75 a a + 3 b b, a = max(2 - q, 0), b = max(1 - q, 0) */
__attribute__((target("avx512f"))) static inline __m512 jm_pair16_cubic_dw(__m512 q)
{
    const __m512 zero = _mm512_setzero_ps();
    const __m512 A = _mm512_max_ps(_mm512_sub_ps(_mm512_set1_ps(2.0f), q), zero);
    const __m512 B = _mm512_max_ps(_mm512_sub_ps(_mm512_set1_ps(1.0f), q), zero);
    return _mm512_add_ps(_mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(-0.75f), A), A),
                         _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(3.0f), B), B));
}
/* jm_cubic_w (internal.h) on every lane, the same operations in the same
 * order: 0.25 a a a - b b b */
__attribute__((target("avx512f"))) static inline __m512 jm_pair16_cubic_w(__m512 q)
{
    const __m512 zero = _mm512_setzero_ps();
    const __m512 A = _mm512_max_ps(_mm512_sub_ps(_mm512_set1_ps(2.0f), q), zero);
    const __m512 B = _mm512_max_ps(_mm512_sub_ps(_mm512_set1_ps(1.0f), q), zero);
    return _mm512_sub_ps(_mm512_mul_ps(_mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(0.25f), A), A), A),
                         _mm512_mul_ps(_mm512_mul_ps(B, B), B));
}
/* gradient sums per lane as two normals: jm_normal_from_lanes8 on lanes
 * 0-7 into np and on lanes 8-15 into nq (each untouched where its sum
 * vanishes) */
__attribute__((target("avx512f"))) static inline void jm_pair16_normals(__m512 gx, __m512 gy, __m512 gz, float np[3],
                                                                       float nq[3])
{
    float sx[16], sy[16], sz[16];
    _mm512_storeu_ps(sx, gx);
    _mm512_storeu_ps(sy, gy);
    _mm512_storeu_ps(sz, gz);
    jm_normal_from_lanes8(sx, sy, sz, np);
    jm_normal_from_lanes8(sx + 8, sy + 8, sz + 8, nq);
}
#endif
#endif
