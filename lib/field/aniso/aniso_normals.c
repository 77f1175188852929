/* aniso_normals.c - unit normals of the anisotropic SPH field at mesh vertices, each vertex settled onto the surface by a Newton step, two at a time (AVX-512) or one (C). */
#include "field/aniso/aniso_normals.h"
#include "extract/block.h" /* JM_T_MIN */
#include "core/cpu.h"
#include <math.h>

/* The one-at-a-time loop is built for x86-64-v4 and AVX2 machines and for
 * any x86-64 (JM_KERNEL_V4, cpu.h): the same bits. */

/*
 * Issue 31. The marching places a vertex where the line between two nodes'
 * values crosses the threshold. Flattened kernels bend the field between
 * nodes more than round ones, most along the tetrahedra's long diagonals,
 * so that error hangs on where the lattice falls and a moving input
 * shimmers. The normal's pass sums the field's gradient at the vertex
 * anyway; its value beside it costs one more kernel term, and one Newton
 * step along the vertex's edge, t + (phi - threshold) / (-grad phi . e),
 * takes the vertex onto the surface to second order. The vertex stays
 * within its edge (JM_T_MIN from either node), so no shell of the marching
 * can turn inside out, and moves at most a quarter cube: where the edge
 * runs nearly along the surface the step means little. (Figures: the man
 * page's anisotropic section, `jetmesh bench --flicker`.)
 */
#define AN_STEP_MAX 0.25f /* the most a vertex moves, in cubes */

/* From the 8 lanes of the gradient (gx, gy, gz) and of the value (vl), each
 * summed in lane order: the outward unit normal at p into nrm; p, a vertex
 * on the lattice edge (cube h) whose unit direction from its inside to its
 * outside node nrm holds on entry, moved along it by one Newton step onto
 * the level thr, at most AN_STEP_MAX h and kept within the edge. Both
 * untouched (returns 0) where the gradient vanishes or is not finite. */
static inline int lanes_settle(const float *gx, const float *gy, const float *gz, const float *vl, float thr, float h,
                               float p[3], float nrm[3])
{
    float o[3] = {0, 0, 0}, v = 0.0f;
    for (int l = 0; l < 8; l++) {
        o[0] -= gx[l];
        o[1] -= gy[l];
        o[2] -= gz[l];
        v += vl[l];
    }
    const float len = sqrtf(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
    if (!(len > 0.0f) || !isfinite(len)) return 0;
    const float e[3] = {nrm[0], nrm[1], nrm[2]};
    for (int a = 0; a < 3; a++) nrm[a] = o[a] / len;
    /* the step along e: the field falls along it near the root (-grad phi .
     * e = o . e > 0; where it does not, the vertex stays) */
    const float oe = o[0] * e[0] + o[1] * e[1] + o[2] * e[2];
    if (!(oe > 0.0f)) return 1;
    float s = (v - thr) / oe;
    const float smax = AN_STEP_MAX * h;
    s = s > smax ? smax : (s < -smax ? -smax : s);
    /* within the edge: along its steepest axis q, between the nodes */
    int q = 0;
    for (int a = 1; a < 3; a++)
        if (fabsf(e[a]) > fabsf(e[q])) q = a;
    const double x = (double)p[q] / h, u = x - floor(x); /* 0 to 1 between the nodes along q */
    const double lo = JM_T_MIN, hi = 1.0 - JM_T_MIN;
    double u1 = u + (double)s * e[q] / h;
    if (u1 < lo) s = (float)((lo - u) * h / e[q]);
    else if (u1 > hi) s = (float)((hi - u) * h / e[q]);
    if (!(isfinite(s))) return 1;
    for (int a = 0; a < 3; a++) p[a] += s * e[a];
    return 1;
}

JM_BODY int jm_aniso_normal_body(const jm_an_list *l, float thr, float h, float p[3], float nrm[3])
{
    /* grad phi = sum amp w'(q) / q M d and phi = sum amp w(q), with q =
     * sqrt(d^T M d); 8 lanes summed in a fixed order */
    float gx[8] = {0}, gy[8] = {0}, gz[8] = {0}, vl[8] = {0};
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
            vl[t] += amp * jm_cubic_w(q); /* +0 past the support */
        }
    }
    return lanes_settle(gx, gy, gz, vl, thr, h, p, nrm);
}
JM_KERNEL_V4(, int, jm_aniso_normal, jm_aniso_normal_body,
             (const jm_an_list *l, float thr, float h, float p[3], float nrm[3]), (l, thr, h, p, nrm))

#include "core/pair16.h"
#ifdef JM_PAIR16
/* Lanes 0-7 vertex p, lanes 8-15 vertex q, each group of 8 kernels in both
 * halves: every lane does what lane t of jm_aniso_normal does, the same
 * IEEE operations (no FMA) in the same order. */
__attribute__((target("avx512f"))) static void normal2_avx512(const jm_an_list *l, float thr, float h, float p[3],
                                                             float q[3], float np[3], float nq[3])
{
    const __m512 px = jm_pair16_set(p[0], q[0]), py = jm_pair16_set(p[1], q[1]), pz = jm_pair16_set(p[2], q[2]);
    const __m512 zero = _mm512_setzero_ps(), four = _mm512_set1_ps(4.0f);
    __m512 gx = zero, gy = zero, gz = zero, vl = zero;
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
        const __mmask16 near = _mm512_cmp_ps_mask(q2, four, _CMP_LT_OQ);
        if (!near) continue; /* every lane adds +0 or -0 to sums never -0 */
        const __mmask16 in = near & _mm512_cmp_ps_mask(q2, zero, _CMP_GT_OQ);
        const __m512 qq = _mm512_sqrt_ps(q2), dw = jm_pair16_cubic_dw(qq);
        vl = _mm512_add_ps(vl, _mm512_mul_ps(amp, jm_pair16_cubic_w(qq)));
        const __m512 k = _mm512_maskz_div_ps(in, _mm512_mul_ps(amp, dw), qq);
        gx = _mm512_add_ps(gx, _mm512_mul_ps(k, md0));
        gy = _mm512_add_ps(gy, _mm512_mul_ps(k, md1));
        gz = _mm512_add_ps(gz, _mm512_mul_ps(k, md2));
    }
    float sx[16], sy[16], sz[16], sv[16];
    _mm512_storeu_ps(sx, gx);
    _mm512_storeu_ps(sy, gy);
    _mm512_storeu_ps(sz, gz);
    _mm512_storeu_ps(sv, vl);
    lanes_settle(sx, sy, sz, sv, thr, h, p, np);
    lanes_settle(sx + 8, sy + 8, sz + 8, sv + 8, thr, h, q, nq);
}
#endif

void jm_aniso_normals(const jm_an_list *l, float thr, float h, const uint32_t *idx, size_t count, float *pos,
                      float *nrm)
{
    size_t k = 0;
#ifdef JM_PAIR16
    if (jm_cpu_avx512())
        for (; k + 1 < count; k += 2)
            normal2_avx512(l, thr, h, &pos[3 * (size_t)idx[k]], &pos[3 * (size_t)idx[k + 1]],
                           &nrm[3 * (size_t)idx[k]], &nrm[3 * (size_t)idx[k + 1]]);
#endif
    for (; k < count; k++) jm_aniso_normal(l, thr, h, &pos[3 * (size_t)idx[k]], &nrm[3 * (size_t)idx[k]]);
}
