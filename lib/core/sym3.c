/* sym3.c - eigen-decomposition of symmetric 3x3 matrices (cyclic Jacobi rotations), one at a time or eight in AVX-512 lanes. */
#include "core/sym3.h"
#include "core/cpu.h"
#include <math.h>

static void sym3_order(double m[3][3], double v[3][3], double val[3], double vec[9]);

void jm_sym3_eigen(const double a[6], double val[3], double vec[9])
{
    double m[3][3] = {{a[0], a[1], a[2]}, {a[1], a[3], a[4]}, {a[2], a[4], a[5]}};
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double scale = fabs(a[0]) + fabs(a[3]) + fabs(a[5]) + fabs(a[1]) + fabs(a[2]) + fabs(a[4]);
    /* cyclic sweeps over (0,1), (0,2), (1,2); converges quadratically: a
     * handful of sweeps reach double precision */
    for (int sweep = 0; sweep < 32; sweep++) {
        double off = fabs(m[0][1]) + fabs(m[0][2]) + fabs(m[1][2]);
        if (!(off > 1e-15 * scale)) break;
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                if (m[p][q] == 0.0) continue;
                /* the rotation that zeroes m[p][q] (Golub & Van Loan, sym.schur2) */
                double theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
                double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; k++) { /* m = m J */
                    double mkp = m[k][p], mkq = m[k][q];
                    m[k][p] = c * mkp - s * mkq;
                    m[k][q] = s * mkp + c * mkq;
                }
                for (int k = 0; k < 3; k++) { /* m = J^T m */
                    double mpk = m[p][k], mqk = m[q][k];
                    m[p][k] = c * mpk - s * mqk;
                    m[q][k] = s * mpk + c * mqk;
                }
                m[p][q] = m[q][p] = 0.0;
                for (int k = 0; k < 3; k++) { /* v = v J */
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    sym3_order(m, v, val, vec);
}

/* the diagonal of m in descending order and v's columns alike (an even
 * permutation or a sign flip keeps det +1) */
static void sym3_order(double m[3][3], double v[3][3], double val[3], double vec[9])
{
    int o[3] = {0, 1, 2};
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2 - i; j++)
            if (m[o[j]][o[j]] < m[o[j + 1]][o[j + 1]]) {
                int t = o[j];
                o[j] = o[j + 1];
                o[j + 1] = t;
            }
    for (int k = 0; k < 3; k++) {
        val[k] = m[o[k]][o[k]];
        for (int r = 0; r < 3; r++) vec[3 * r + k] = v[r][o[k]];
    }
    double det = vec[0] * (vec[4] * vec[8] - vec[5] * vec[7]) - vec[1] * (vec[3] * vec[8] - vec[5] * vec[6]) +
                 vec[2] * (vec[3] * vec[7] - vec[4] * vec[6]);
    if (det < 0.0)
        for (int r = 0; r < 3; r++) vec[3 * r + 2] = -vec[3 * r + 2];
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SYM3_SIMD 1
/* Eight matrices in the lanes of AVX-512 doubles: lane i does the
 * operations jm_sym3_eigen does on a[i], in the same order (IEEE division
 * and square root round exactly, no FMA), its sweeps stopping when its own
 * would and a rotation skipped where its own skips (the lane keeps its
 * values), so the same bits. */
__attribute__((target("avx512f"))) static void eigen8_avx512(int n, const double (*a)[6], double (*val)[3],
                                                            double (*vec)[9])
{
    double in[6][8];
    for (int e = 0; e < 6; e++)
        for (int i = 0; i < 8; i++) in[e][i] = a[i < n ? i : 0][e];
    __m512d m[3][3], v[3][3];
    static const int at[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) {
            m[r][k] = _mm512_loadu_pd(in[at[r][k]]);
            v[r][k] = _mm512_set1_pd(r == k ? 1.0 : 0.0);
        }
#define ABS(x) _mm512_abs_pd(x)
    const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0), two = _mm512_set1_pd(2.0);
    const __m512d scale = _mm512_add_pd(
        _mm512_add_pd(_mm512_add_pd(_mm512_add_pd(_mm512_add_pd(ABS(m[0][0]), ABS(m[1][1])), ABS(m[2][2])),
                                    ABS(m[0][1])),
                      ABS(m[0][2])),
        ABS(m[1][2]));
    const __m512d tol = _mm512_mul_pd(_mm512_set1_pd(1e-15), scale);
    __mmask8 run = 0xFF;
    for (int sweep = 0; sweep < 32; sweep++) {
        const __m512d off = _mm512_add_pd(_mm512_add_pd(ABS(m[0][1]), ABS(m[0][2])), ABS(m[1][2]));
        run = _mm512_mask_cmp_pd_mask(run, off, tol, _CMP_GT_OQ);
        if (!run) break;
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                const __mmask8 k = _mm512_mask_cmp_pd_mask(run, m[p][q], zero, _CMP_NEQ_UQ);
                if (!k) continue;
                const __m512d theta = _mm512_div_pd(_mm512_sub_pd(m[q][q], m[p][p]), _mm512_mul_pd(two, m[p][q]));
                const __m512d sg = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(theta, zero, _CMP_GE_OQ),
                                                        _mm512_set1_pd(-1.0), one);
                const __m512d t = _mm512_div_pd(
                    sg, _mm512_add_pd(ABS(theta), _mm512_sqrt_pd(_mm512_add_pd(_mm512_mul_pd(theta, theta), one))));
                const __m512d c = _mm512_div_pd(one, _mm512_sqrt_pd(_mm512_add_pd(_mm512_mul_pd(t, t), one)));
                const __m512d s = _mm512_mul_pd(t, c);
                for (int r = 0; r < 3; r++) { /* m = m J */
                    const __m512d mp = m[r][p], mq = m[r][q];
                    m[r][p] = _mm512_mask_sub_pd(mp, k, _mm512_mul_pd(c, mp), _mm512_mul_pd(s, mq));
                    m[r][q] = _mm512_mask_add_pd(mq, k, _mm512_mul_pd(s, mp), _mm512_mul_pd(c, mq));
                }
                for (int r = 0; r < 3; r++) { /* m = J^T m */
                    const __m512d mp = m[p][r], mq = m[q][r];
                    m[p][r] = _mm512_mask_sub_pd(mp, k, _mm512_mul_pd(c, mp), _mm512_mul_pd(s, mq));
                    m[q][r] = _mm512_mask_add_pd(mq, k, _mm512_mul_pd(s, mp), _mm512_mul_pd(c, mq));
                }
                m[p][q] = _mm512_mask_mov_pd(m[p][q], k, zero);
                m[q][p] = _mm512_mask_mov_pd(m[q][p], k, zero);
                for (int r = 0; r < 3; r++) { /* v = v J */
                    const __m512d vp = v[r][p], vq = v[r][q];
                    v[r][p] = _mm512_mask_sub_pd(vp, k, _mm512_mul_pd(c, vp), _mm512_mul_pd(s, vq));
                    v[r][q] = _mm512_mask_add_pd(vq, k, _mm512_mul_pd(s, vp), _mm512_mul_pd(c, vq));
                }
            }
    }
#undef ABS
    double om[3][3][8], ov[3][3][8];
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) {
            _mm512_storeu_pd(om[r][k], m[r][k]);
            _mm512_storeu_pd(ov[r][k], v[r][k]);
        }
    for (int i = 0; i < n; i++) {
        double mi[3][3], vi[3][3];
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++) {
                mi[r][k] = om[r][k][i];
                vi[r][k] = ov[r][k][i];
            }
        sym3_order(mi, vi, val[i], vec[i]);
    }
}
#endif

void jm_sym3_eigen_n(int n, const double (*a)[6], double (*val)[3], double (*vec)[9])
{
#ifdef SYM3_SIMD
    if (jm_cpu_avx512()) {
        for (int i = 0; i < n; i += 8) eigen8_avx512(n - i < 8 ? n - i : 8, a + i, val + i, vec + i);
        return;
    }
#endif
    for (int i = 0; i < n; i++) jm_sym3_eigen(a[i], val[i], vec[i]);
}
