/* aniso_normals.c - unit normals of the anisotropic SPH field at mesh vertices, two at a time (AVX-512) or one (C). */
#include "field/aniso/aniso_normals.h"
#include "core/cpu.h"
#include <math.h>

/* The one-at-a-time loop is built for x86-64-v4 and AVX2 machines and for
 * any x86-64 (JM_KERNEL_V4, cpu.h): the same bits. */

JM_BODY int jm_aniso_normal_body(const jm_an_list *l, const float p[3], float nrm[3])
{
    /* grad phi = sum amp w'(q) / q M d, with q = sqrt(d^T M d); 8 lanes
     * summed in a fixed order */
    float gx[8] = {0}, gy[8] = {0}, gz[8] = {0};
    size_t groups = (l->n + 7) / 8;
    for (size_t gi = 0; gi < groups; gi++) {
        const float *b = l->buf + JM_AN_GROUP * gi;
        for (int t = 0; t < 8; t++) {
            const float d0 = p[0] - b[t], d1 = p[1] - b[8 + t], d2 = p[2] - b[16 + t];
            const float m00 = b[24 + t], m01 = b[32 + t], m02 = b[40 + t], m11 = b[48 + t], m12 = b[56 + t];
            const float m22 = b[64 + t], amp = b[72 + t];
            const float md0 = m00 * d0 + m01 * d1 + m02 * d2;
            const float md1 = m01 * d0 + m11 * d1 + m12 * d2;
            const float md2 = m02 * d0 + m12 * d1 + m22 * d2;
            const float q2 = d0 * md0 + d1 * md1 + d2 * md2;
            const float q = sqrtf(q2);
            const float k = q2 < 4.0f && q2 > 0.0f ? amp * jm_cubic_dw(q) / q : 0.0f;
            gx[t] += k * md0;
            gy[t] += k * md1;
            gz[t] += k * md2;
        }
    }
    return jm_normal_from_lanes8(gx, gy, gz, nrm);
}
JM_KERNEL_V4(, int, jm_aniso_normal, jm_aniso_normal_body, (const jm_an_list *l, const float p[3], float nrm[3]), (l, p, nrm))

#include "core/pair16.h"
#ifdef JM_PAIR16
/* Lanes 0-7 vertex p, lanes 8-15 vertex q, each group of 8 kernels in both
 * halves: every lane does what lane t of jm_aniso_normal does, the same
 * IEEE operations (no FMA) in the same order. */
__attribute__((target("avx512f"))) static void normal2_avx512(const jm_an_list *l, const float p[3],
                                                             const float q[3], float np[3], float nq[3])
{
    const __m512 px = jm_pair16_set(p[0], q[0]), py = jm_pair16_set(p[1], q[1]), pz = jm_pair16_set(p[2], q[2]);
    const __m512 zero = _mm512_setzero_ps(), four = _mm512_set1_ps(4.0f);
    __m512 gx = zero, gy = zero, gz = zero;
    const size_t groups = (l->n + 7) / 8;
    for (size_t gi = 0; gi < groups; gi++) {
        const float *b = l->buf + JM_AN_GROUP * gi;
        const __m512 d0 = _mm512_sub_ps(px, jm_pair16_load8(b)), d1 = _mm512_sub_ps(py, jm_pair16_load8(b + 8));
        const __m512 d2 = _mm512_sub_ps(pz, jm_pair16_load8(b + 16));
        const __m512 m00 = jm_pair16_load8(b + 24), m01 = jm_pair16_load8(b + 32), m02 = jm_pair16_load8(b + 40);
        const __m512 m11 = jm_pair16_load8(b + 48), m12 = jm_pair16_load8(b + 56), m22 = jm_pair16_load8(b + 64);
        const __m512 amp = jm_pair16_load8(b + 72);
        const __m512 md0 =
            _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(m00, d0), _mm512_mul_ps(m01, d1)), _mm512_mul_ps(m02, d2));
        const __m512 md1 =
            _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(m01, d0), _mm512_mul_ps(m11, d1)), _mm512_mul_ps(m12, d2));
        const __m512 md2 =
            _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(m02, d0), _mm512_mul_ps(m12, d1)), _mm512_mul_ps(m22, d2));
        const __m512 q2 =
            _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(d0, md0), _mm512_mul_ps(d1, md1)), _mm512_mul_ps(d2, md2));
        const __mmask16 in = _mm512_cmp_ps_mask(q2, four, _CMP_LT_OQ) & _mm512_cmp_ps_mask(q2, zero, _CMP_GT_OQ);
        if (!in) continue; /* every lane adds +0 or -0 to sums never -0 */
        const __m512 qq = _mm512_sqrt_ps(q2), dw = jm_pair16_cubic_dw(qq);
        const __m512 k = _mm512_maskz_div_ps(in, _mm512_mul_ps(amp, dw), qq);
        gx = _mm512_add_ps(gx, _mm512_mul_ps(k, md0));
        gy = _mm512_add_ps(gy, _mm512_mul_ps(k, md1));
        gz = _mm512_add_ps(gz, _mm512_mul_ps(k, md2));
    }
    jm_pair16_normals(gx, gy, gz, np, nq);
}
#endif

void jm_aniso_normals(const jm_an_list *l, const uint32_t *idx, size_t count, const float *pos, float *nrm)
{
    size_t k = 0;
#ifdef JM_PAIR16
    if (jm_cpu_avx512())
        for (; k + 1 < count; k += 2)
            normal2_avx512(l, &pos[3 * (size_t)idx[k]], &pos[3 * (size_t)idx[k + 1]], &nrm[3 * (size_t)idx[k]],
                           &nrm[3 * (size_t)idx[k + 1]]);
#endif
    for (; k < count; k++) jm_aniso_normal(l, &pos[3 * (size_t)idx[k]], &nrm[3 * (size_t)idx[k]]);
}
