/* aniso_boxes.c - anisotropic SPH nodes proven inside a box of 3 x 3 x 3 nodes at a time: each kernel's tangent line in q^2 at the box's centre node. */
/* Why a node whose bound exceeds the returned level samples above the
 * threshold: docs/culling.md, part B.
 *
 * Layout as inside_boxes.c: along x 16 lanes of box centres of stride 2
 * (nodes 1, 3, ..), along y and z rows of stride 3 (nodes 1, 4, ..); a
 * kernel adds to the rows of centres within JM_AN_BOX_REACH of its box's
 * half sides, and the AVX2 path to the lanes within it along x (any subset
 * of terms is a bound; outside its ellipsoid a lane takes the zero line). */
#include "field/aniso/aniso_boxes.h"
#include "field/aniso/aniso_cull.h"
#include "field/sph/cull.h"
#include "field/sph/inside_boxes.h"
#include <math.h>
#include <pthread.h>
#include <stddef.h>
#include <string.h>

#ifndef JM_AN_CULL_BREAK
#define JM_AN_CULL_BREAK 0
#endif
#define AN(g, i) (&(g)->an[JM_AN_STRIDE * (size_t)(i)])
#define LANES 16
#define ROWS 11

int jm_aniso_boxes_apply(const jm_config *c, size_t inner, const float lo[3], const float hi[3])
{
    return c->h <= JM_BOX_MAX_H * c->sph_h && jm_block_filled(c, inner, lo, hi, JM_AN_BOX_FILL);
}

/* W(sqrt s) and its derivative in s */
static double shape(double s) { return jm_cull_kernel(sqrt(s)); }
static double shape_ds(double s)
{
    const double q = sqrt(s);
    if (q < 1e-12) return -1.5;
    double a = 2.0 - q, b = 1.0 - q;
    a = a > 0.0 ? a : 0.0;
    b = b > 0.0 ? b : 0.0;
    return (-0.75 * a * a + 3.0 * b * b) / (2.0 * q);
}

static float lines_a[JM_AN_BOX_BINS], lines_b[JM_AN_BOX_BINS];
static pthread_once_t lines_once = PTHREAD_ONCE_INIT;
static void lines_init(void)
{
    for (int k = 0; k < JM_AN_BOX_BINS - 1; k++) {
        const double sk = (k + 0.5) / JM_AN_BOX_BINS_PER_S, d = shape_ds(sk);
        const double ak = shape(sk) - d * sk, bk = -d;
        float a = (float)ak, b = (float)bk;
        if ((double)a > ak) a = nextafterf(a, -INFINITY);
        if ((double)b < bk) b = nextafterf(b, INFINITY);
        lines_a[k] = a;
        lines_b[k] = b;
    }
    lines_a[JM_AN_BOX_BINS - 1] = lines_b[JM_AN_BOX_BINS - 1] = 0.0f;
}

void jm_aniso_box_lines(float a[JM_AN_BOX_BINS], float b[JM_AN_BOX_BINS])
{
    pthread_once(&lines_once, lines_init);
    memcpy(a, lines_a, sizeof lines_a);
    memcpy(b, lines_b, sizeof lines_b);
}

/* The accumulators, as inside_boxes.c's: per row of
 * box centres L and G (16 lanes), the amp sum W and count m of the
 * kernels it got, and the nodes' bounds along x. */
typedef struct {
    float L[ROWS][ROWS][LANES], G[3][ROWS][ROWS][LANES];
    float W[ROWS][ROWS];
    int m[ROWS][ROWS];
    float X[ROWS][ROWS][JM_PAD_MAX];
} an_box_acc;

size_t jm_aniso_box_work_bytes(void) { return sizeof(an_box_acc); }

typedef struct {
    int nb, nr;
    float xc[LANES], yc[ROWS], zc[ROWS];
    double E[3];
    float te[3];
    float inv3h;
    double ML, GB, bmax, kappa;
    double S, Kmax, trmax; /* the kernels' amp sum, largest K and trace */
    size_t m;              /* and count */
} an_box_setup;

/* Each node the best of its boxes' bounds (part 3's error off each box). */
static void spread(an_box_acc *A, const an_box_setup *b, int n, float *out)
{
    const int nb = b->nb, nr = b->nr, ns = JM_PAD(n);
    const double u = 0x1p-24, te = (double)b->te[0] + b->te[1] + b->te[2];
    const double cl = 45.0 * b->kappa * b->bmax, cg = 7.0 + 28.0 * sqrt(b->kappa);
    for (int bk = 0; bk < nr; bk++)
        for (int bj = 0; bj < nr; bj++) {
            const double mb = A->m[bk][bj];
            const float err =
                (float)(1.02 * u * A->W[bk][bj] * (b->ML * (mb + 5.0) + cl + te * b->GB * (2.01 * mb + cg)) * (1.0 + 1e-6));
            float v[LANES];
            for (int i = 0; i < LANES; i++) {
                const float t = A->L[bk][bj][i] - (b->te[0] * fabsf(A->G[0][bk][bj][i]) +
                                                   b->te[1] * fabsf(A->G[1][bk][bj][i]) +
                                                   b->te[2] * fabsf(A->G[2][bk][bj][i]));
                v[i] = t - (err + fabsf(t) * 0x1p-21f);
            }
            /* along x: node 2 t + 1 in box t alone, node 2 t in boxes t - 1 and t */
            float *r = A->X[bk][bj];
            r[0] = v[0];
            for (int t = 0; t < nb; t++) {
                r[2 * t + 1] = v[t];
                if (2 * t + 2 < n) r[2 * t + 2] = t + 1 < nb && v[t + 1] > v[t] ? v[t + 1] : v[t];
            }
        }
    for (int k = 0; k < n; k++)
        for (int j = 0; j < n; j++) memcpy(out + ((size_t)k * n + j) * ns, A->X[k / 3][j / 3], (size_t)n * sizeof *out);
}

/* Every kernel of the block (the splat's filter) whose box holds rows of
 * box centres: PREP once, then ROW(L, G0, G1, G2, B, C, Py, Pz) on each such
 * row (B = m01 vy + m02 vz, C = (m11 vy + 2 m12 vz) vy + m22 vz vz, Py and
 * Pz the rest of (M v)_y and (M v)_z; the splat's order for s), rows whose
 * ellipse misses the centres' line past the zero bin skipped; W, m, S and
 * the sizes part 3 needs summed on the way. */
#define AN_BOX_LOOP(PREP, ROW)                                                                                 \
    for (size_t ci = 0; ci < cand->n; ci++) {                                                              \
        const float *a = AN(g, cand->idx[ci]);                                                             \
        if (a[0] + a[10] < lo[0] || a[0] - a[10] > hi[0] || a[1] + a[11] < lo[1] || a[1] - a[11] > hi[1] ||  \
            a[2] + a[12] < lo[2] || a[2] - a[12] > hi[2])                                                  \
            continue;                                                                                      \
        const float m00 = a[3], m01 = a[4], m02 = a[5], m11 = a[6], m12 = a[7], m22 = a[8], amp = a[9];     \
        S += amp;                                                                                          \
        m++;                                                                                               \
        const double Kd = ((double)m00 * b.E[0] * b.E[0] + (double)m11 * b.E[1] * b.E[1] +                  \
                           (double)m22 * b.E[2] * b.E[2] +                                                 \
                           2.0 * (fabs((double)m01) * b.E[0] * b.E[1] + fabs((double)m02) * b.E[0] * b.E[2] + \
                                  fabs((double)m12) * b.E[1] * b.E[2])) *                                  \
                          (1.0 + 1e-9);                                                                    \
        /* tests/t_aniso_cull_broken.sh: boxes bounded as if a third as                                 \
         * large must fail test_aniso_cull */                                                              \
        const float K = jm_float_up(JM_AN_CULL_BREAK == 3 ? 0.3 * Kd : Kd);                                \
        Kmax = Kd > Kmax ? Kd : Kmax;                                                                      \
        const double tr = (double)m00 + m11 + m22;                                                         \
        trmax = tr > trmax ? tr : trmax;                                                                   \
        const float rz = reach * a[12], ry = reach * a[11];                                                \
        int k0 = iceil((a[2] - rz - b.zc[0]) * b.inv3h), k1 = ifloor((a[2] + rz - b.zc[0]) * b.inv3h) + 1;   \
        int j0 = iceil((a[1] - ry - b.yc[0]) * b.inv3h), j1 = ifloor((a[1] + ry - b.yc[0]) * b.inv3h) + 1;   \
        k0 = k0 < 0 ? 0 : k0;                                                                              \
        j0 = j0 < 0 ? 0 : j0;                                                                              \
        k1 = k1 > b.nr ? b.nr : k1;                                                                        \
        j1 = j1 > b.nr ? b.nr : j1;                                                                        \
        if (k0 >= k1 || j0 >= j1) continue;                                                                \
        const float cx = a[0];                                                                             \
        PREP                                                                                               \
        for (int bk = k0; bk < k1; bk++) {                                                                 \
            const float vz = b.zc[bk] - a[2];                                                              \
            for (int bj = j0; bj < j1; bj++) {                                                             \
                const float vy = b.yc[bj] - a[1];                                                          \
                const float B = m01 * vy + m02 * vz, C = (m11 * vy + 2.0f * m12 * vz) * vy + m22 * vz * vz; \
                if (!(B * B - m00 * (C - zero_s) > 0.0f)) continue;                                        \
                const float Py = m11 * vy + m12 * vz, Pz = m12 * vy + m22 * vz;                            \
                A->W[bk][bj] += amp;                                                                       \
                A->m[bk][bj]++;                                                                            \
                ROW(A->L[bk][bj], A->G[0][bk][bj], A->G[1][bk][bj], A->G[2][bk][bj], B, C, Py, Pz);       \
            }                                                                                              \
        }                                                                                                  \
    }

#define PREP_C
#define ROW_C(L, G0, G1, G2, B, C, Py, Pz)                                                                     \
    for (int i = 0; i < LANES; i++) {                                                                      \
        const float vx = b.xc[i] - cx;                                                                     \
        float s = (m00 * vx + 2.0f * B) * vx + C;                                                          \
        s = s > 0.0f ? s : 0.0f;                                                                           \
        const float sb = s * bin;                                                                          \
        const int k = (int)(sb < top ? sb : top);                                                          \
        const float wb = amp * lines_b[k];                                                                 \
        L[i] = L[i] + amp * (lines_a[k] - lines_b[k] * (s + K));                                           \
        G0[i] = G0[i] + wb * (m00 * vx + B);                                                               \
        G1[i] = G1[i] + wb * (m01 * vx + Py);                                                              \
        G2[i] = G2[i] + wb * (m02 * vx + Pz);                                                              \
    }

/* One path's function around the kernel loop: its accumulators, and the
 * sums into the caller's setup. */
#define AN_BOX_HEAD                                                                                            \
    const an_box_setup b = *bp;                                                                            \
    const jm_an_cand *cand = in->cand;                                                                     \
    const float *lo = in->lo, *hi = in->hi;                                                                \
    const float top = (float)(JM_AN_BOX_BINS - 1), bin = (float)JM_AN_BOX_BINS_PER_S;                       \
    const float zero_s = top / bin, reach = JM_AN_BOX_REACH;                                      \
    double S = 0.0, Kmax = 0.0, trmax = 0.0;                                                               \
    size_t m = 0;
#define AN_BOX_TAIL                                                                                            \
    (void)top;                                                                                             \
    (void)bin;                                                                                             \
    bp->S = S;                                                                                             \
    bp->m = m;                                                                                             \
    bp->Kmax = Kmax;                                                                                       \
    bp->trmax = trmax;
#define AN_BOX_ARGS const jm_grid *g, const an_jm_box_in *in, an_box_setup *bp, an_box_acc *A

typedef struct {
    const jm_an_cand *cand;
    const float *lo, *hi;
} an_jm_box_in;

static void boxes_c(AN_BOX_ARGS)
{
    AN_BOX_HEAD
    AN_BOX_LOOP(PREP_C, ROW_C)
    AN_BOX_TAIL
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define AN_BOX_SIMD 1
/* The same terms 16 centres at a time (AVX-512) or in windows of 8 (AVX2
 * with FMA), the lines picked from the 32 bins by permutes, fused
 * multiply-adds (part 3 counts roundings: a fused one rounds less). */
#define SETUP_AVX512                                                                                           \
    const __m512 A0 = _mm512_loadu_ps(lines_a), A1 = _mm512_loadu_ps(lines_a + 16);                      \
    const __m512 B0 = _mm512_loadu_ps(lines_b), B1 = _mm512_loadu_ps(lines_b + 16);                      \
    const __m512 vbin = _mm512_set1_ps(bin), vtop = _mm512_set1_ps(top), z16 = _mm512_setzero_ps();
#define PREP_AVX512                                                                                            \
    const __m512 vx = _mm512_sub_ps(_mm512_loadu_ps(b.xc), _mm512_set1_ps(cx));                           \
    const __m512 vamp = _mm512_set1_ps(amp), vK = _mm512_set1_ps(K), v00 = _mm512_set1_ps(m00);           \
    const __m512 v01 = _mm512_set1_ps(m01), v02 = _mm512_set1_ps(m02);
#define ROW_AVX512(L, G0, G1, G2, B, C, Py, Pz)                                                                \
    do {                                                                                                   \
        const __m512 vB = _mm512_set1_ps(B);                                                               \
        __m512 s = _mm512_fmadd_ps(_mm512_fmadd_ps(v00, vx, _mm512_set1_ps(2.0f * B)), vx, _mm512_set1_ps(C)); \
        s = _mm512_max_ps(s, z16);                                                                         \
        const __m512i kk = _mm512_cvttps_epi32(_mm512_min_ps(_mm512_mul_ps(s, vbin), vtop));               \
        const __m512 la = _mm512_permutex2var_ps(A0, kk, A1), lb = _mm512_permutex2var_ps(B0, kk, B1);     \
        const __m512 l = _mm512_fnmadd_ps(lb, _mm512_add_ps(s, vK), la);                                   \
        const __m512 wb = _mm512_mul_ps(vamp, lb);                                                         \
        _mm512_storeu_ps(L, _mm512_fmadd_ps(vamp, l, _mm512_loadu_ps(L)));                                 \
        _mm512_storeu_ps(G0, _mm512_fmadd_ps(wb, _mm512_fmadd_ps(v00, vx, vB), _mm512_loadu_ps(G0)));      \
        _mm512_storeu_ps(G1, _mm512_fmadd_ps(wb, _mm512_fmadd_ps(v01, vx, _mm512_set1_ps(Py)), _mm512_loadu_ps(G1))); \
        _mm512_storeu_ps(G2, _mm512_fmadd_ps(wb, _mm512_fmadd_ps(v02, vx, _mm512_set1_ps(Pz)), _mm512_loadu_ps(G2))); \
    } while (0)
__attribute__((target("avx512f"))) static void boxes_avx512(AN_BOX_ARGS)
{
    AN_BOX_HEAD
    SETUP_AVX512
    AN_BOX_LOOP(PREP_AVX512, ROW_AVX512)
    AN_BOX_TAIL
}

/* 32 bins in four registers of 8: four permutes and two blends on the
 * bin's bits 3 and 4 */
__attribute__((target("avx2,fma"))) static inline __m256 lut32(const __m256 t[4], __m256i k)
{
    const __m256 m3 = _mm256_castsi256_ps(_mm256_slli_epi32(k, 28)), m4 = _mm256_castsi256_ps(_mm256_slli_epi32(k, 27));
    const __m256 l = _mm256_blendv_ps(_mm256_permutevar8x32_ps(t[0], k), _mm256_permutevar8x32_ps(t[1], k), m3);
    const __m256 h = _mm256_blendv_ps(_mm256_permutevar8x32_ps(t[2], k), _mm256_permutevar8x32_ps(t[3], k), m3);
    return _mm256_blendv_ps(l, h, m4);
}
/* A kernel's lanes in reach (|vx| within its box's half side: the others
 * lie past its ellipsoid on every row, on the zero line, adding nothing)
 * are one window of 8 from the first of them (at most from lane 8) when
 * they span under 8 lanes, else both halves. */
#define SETUP_AVX2                                                                                             \
    __m256 TA[4], TB[4];                                                                                   \
    for (int t = 0; t < 4; t++) {                                                                          \
        TA[t] = _mm256_loadu_ps(lines_a + 8 * t);                                                          \
        TB[t] = _mm256_loadu_ps(lines_b + 8 * t);                                                          \
    }                                                                                                      \
    const __m256 vbin = _mm256_set1_ps(bin), vtop = _mm256_set1_ps(top), z8 = _mm256_setzero_ps();
#define PREP_AVX2                                                                                              \
    const __m256 vamp = _mm256_set1_ps(amp), vK = _mm256_set1_ps(K), v00 = _mm256_set1_ps(m00);           \
    const __m256 v01 = _mm256_set1_ps(m01), v02 = _mm256_set1_ps(m02), vcx = _mm256_set1_ps(cx);          \
    __m256 wvx[2];                                                                                         \
    int woff[2], nwin = 0;                                                                                 \
    {                                                                                                      \
        const __m256 half = _mm256_set1_ps(reach * a[10]);                                                 \
        const __m256 da = _mm256_sub_ps(_mm256_loadu_ps(b.xc), vcx), db = _mm256_sub_ps(_mm256_loadu_ps(b.xc + 8), vcx); \
        const __m256 sign = _mm256_set1_ps(-0.0f);                                                         \
        const unsigned live =                                                                              \
            (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(_mm256_andnot_ps(sign, da), half, _CMP_LE_OQ)) |    \
            (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(_mm256_andnot_ps(sign, db), half, _CMP_LE_OQ)) << 8; \
        if (live) {                                                                                        \
            nwin = jm_box_windows(live, woff);                                                             \
            for (int ww = 0; ww < nwin; ww++) wvx[ww] = _mm256_sub_ps(_mm256_loadu_ps(b.xc + woff[ww]), vcx); \
        }                                                                                                  \
    }                                                                                                      \
    if (!nwin) continue;
#define ROW_AVX2(L, G0, G1, G2, B, C, Py, Pz)                                                                  \
    do {                                                                                                   \
        const __m256 vB = _mm256_set1_ps(B), v2B = _mm256_set1_ps(2.0f * B), vC = _mm256_set1_ps(C);      \
        const __m256 vPy = _mm256_set1_ps(Py), vPz = _mm256_set1_ps(Pz);                                  \
        for (int hh = 0; hh < nwin; hh++) {                                                                \
            const __m256 vx = wvx[hh];                                                                     \
            __m256 s = _mm256_max_ps(_mm256_fmadd_ps(_mm256_fmadd_ps(v00, vx, v2B), vx, vC), z8);          \
            const __m256i kk = _mm256_cvttps_epi32(_mm256_min_ps(_mm256_mul_ps(s, vbin), vtop));           \
            const __m256 la = lut32(TA, kk), lb = lut32(TB, kk);                                           \
            const __m256 l = _mm256_fnmadd_ps(lb, _mm256_add_ps(s, vK), la);                               \
            const __m256 wb = _mm256_mul_ps(vamp, lb);                                                     \
            const int o = woff[hh];                                                                        \
            float *l8 = (L) + o, *g0 = (G0) + o, *g1 = (G1) + o, *g2 = (G2) + o;                           \
            _mm256_storeu_ps(l8, _mm256_fmadd_ps(vamp, l, _mm256_loadu_ps(l8)));                           \
            _mm256_storeu_ps(g0, _mm256_fmadd_ps(wb, _mm256_fmadd_ps(v00, vx, vB), _mm256_loadu_ps(g0)));  \
            _mm256_storeu_ps(g1, _mm256_fmadd_ps(wb, _mm256_fmadd_ps(v01, vx, vPy), _mm256_loadu_ps(g1))); \
            _mm256_storeu_ps(g2, _mm256_fmadd_ps(wb, _mm256_fmadd_ps(v02, vx, vPz), _mm256_loadu_ps(g2))); \
        }                                                                                                  \
    } while (0)
__attribute__((target("avx2,fma"))) static void boxes_avx2(AN_BOX_ARGS)
{
    AN_BOX_HEAD
    SETUP_AVX2
    AN_BOX_LOOP(PREP_AVX2, ROW_AVX2)
    AN_BOX_TAIL
}
#endif

float jm_aniso_boxes(const jm_grid *g, const jm_config *c, const jm_an_cand *cand, const float *x, const float *y,
                     const float *z, int n, void *work, float *out)
{
    pthread_once(&lines_once, lines_init);
    an_box_setup b;
    b.nb = n / 2;
    b.nr = (n + 2) / 3;
    for (int i = 0; i < LANES; i++) b.xc[i] = x[2 * i + 1 < n ? 2 * i + 1 : n - 1];
    for (int i = 0; i < ROWS; i++) {
        const int r = 3 * i + 1 < n ? 3 * i + 1 : n - 1;
        b.yc[i] = y[r];
        b.zc[i] = z[r];
    }
    b.E[0] = jm_box_extent(x, n, 2, b.nb);
    b.E[1] = jm_box_extent(y, n, 3, b.nr);
    b.E[2] = jm_box_extent(z, n, 3, b.nr);
    for (int a = 0; a < 3; a++) b.te[a] = jm_float_up(2.0 * b.E[a]);
    b.inv3h = 1.0f / (3.0f * c->h);
    b.kappa = (double)c->an_kr * c->an_kr;
    an_box_acc *A = work;
    memset(A, 0, offsetof(an_box_acc, X));
    const float lo[3] = {x[0], y[0], z[0]}, hi[3] = {x[n - 1], y[n - 1], z[n - 1]};
    const an_jm_box_in in = {cand, lo, hi};
    switch (jm_box_path()) {
#ifdef AN_BOX_SIMD
    case JM_BOX_AVX512: boxes_avx512(g, &in, &b, A); break;
    case JM_BOX_AVX2: boxes_avx2(g, &in, &b, A); break;
#endif
    default: boxes_c(g, &in, &b, A);
    }
    const double S = b.S, Kmax = b.Kmax, trmax = b.trmax;
    const size_t m = b.m;
    /* the sizes of the terms (part 3) */
    double ML = 0.0, bmax = 0.0;
    for (int k = 0; k < JM_AN_BOX_BINS - 1; k++) {
        const double shi = (k + 1) / JM_AN_BOX_BINS_PER_S * (1.0 + 1e-6);
        ML = fmax(ML, fabs((double)lines_a[k]) + lines_b[k] * (shi + Kmax));
        bmax = fmax(bmax, lines_b[k]);
    }
    b.ML = ML * (1.0 + 1e-6);
    b.bmax = bmax;
    b.GB = bmax * sqrt(trmax) * (1.0 + 1e-6);
    spread(A, &b, n, out);
    const double u = 0x1p-24, thr = c->threshold;
    if (!(thr > 0.0) || m >= 100000) return INFINITY;
    return jm_float_up(thr / (1.0 - (double)m * u) + (18.0 + 15.0 * b.kappa) * u * S);
}
