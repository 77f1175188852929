/* inside_boxes.c - SPH nodes proven inside a box of 3 x 3 x 3 nodes at a time: each particle's tangent line at the box's centre node. */
#include "field/sph/inside_boxes.h"
#include "core/cpu.h"
#include <math.h>
#include <stddef.h>
#include <string.h>

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])
#define LANES 16 /* box centres a row: n <= 33 nodes give at most 16 boxes */
#define ROWS 11  /* rows along y and z: n <= 33 nodes give at most 11 */

/* W(sqrt s) and its derivative in s (the kernel's shape, cull.h). */
static double shape_ds(double s)
{
    const double q = sqrt(s);
    if (q < 1e-12) return -1.5; /* W = 1 - 1.5 s + 0.75 s^1.5 near 0 */
    double a = 2.0 - q, b = 1.0 - q;
    a = a > 0.0 ? a : 0.0;
    b = b > 0.0 ? b : 0.0;
    return (-0.75 * a * a + 3.0 * b * b) / (2.0 * q);
}

void jm_box_lines(float a[JM_BOX_BINS], float b[JM_BOX_BINS], double inv_sph_h2)
{
    for (int k = 0; k < JM_BOX_BINS; k++) {
        double ak = 0.0, bk = 0.0; /* the last bin: the zero line */
        if (k < JM_BOX_BINS - 1) {
            const double sk = (k + 0.5) / JM_BOX_BINS_PER_S, d = shape_ds(sk);
            ak = jm_cull_kernel(sqrt(sk)) - d * sk - JM_BOX_LOWER;
            bk = -d;
        }
        a[k] = (float)ak;
        b[k] = (float)(bk * inv_sph_h2);
    }
}

int jm_sph_boxes_apply(const jm_config *c, size_t inner, const float lo[3], const float hi[3])
{
    return c->h <= JM_BOX_MAX_H * c->sph_h && jm_block_filled(c, inner, lo, hi, JM_BOX_FILL);
}

/* E2 >= e0^2 + e1^2 + e2^2 as a float, and the factors 2 e_a */
static void box_consts(const double e[3], float *E2, float te[3])
{
    *E2 = jm_float_up(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    for (int a = 0; a < 3; a++) te[a] = jm_float_up(2.0 * e[a]);
}

float jm_sph_box_threshold(const jm_config *c, const jm_hood *h)
{
    const double u = 0x1p-24, m = (double)h->live;
    if (!(c->threshold > 0.0f) || m >= 1e5) return INFINITY;
    return jm_float_up(((double)c->threshold + 26.0 * u * h->wsum) / (1.0 - m * u));
}

/* What both variants share: the centres, the extents, the particles'
 * filter box, each particle's rows of box centres within the reach. Along
 * x a row's 16 lanes hold boxes of stride 2 (centres 1, 3, .., 2 nb - 1;
 * the lanes cost the same used or not, and a node between two boxes gets
 * the better bound); the rows tile y and z with stride 3 (centres 1, 4, ..,
 * at most n - 1), as many rows as boxes of the same reach need, 2.25
 * times fewer than stride 2. */
typedef struct {
    int nb;                        /* boxes along x: centres 1, 3, .., 2 nb - 1 */
    int nr;                        /* rows along y and along z: centres 1, 4, .. (clipped to n - 1) */
    float xc[LANES], yc[ROWS], zc[ROWS];
    float E2, te[3];
    float lo[3], hi[3];            /* particles outside add to no row */
    float Rp, Rp2, inv3h;
    float M, Gt;                   /* |a - b (s + E2)| and |b v_a| for any term (docs/culling.md, 3b) */
} box_setup;

static void setup(const jm_config *c, const float *x, const float *y, const float *z, int n, box_setup *b)
{
    b->nb = n / 2;
    b->nr = (n + 2) / 3;
    for (int i = 0; i < LANES; i++) b->xc[i] = x[2 * i + 1 < n ? 2 * i + 1 : n - 1];
    for (int i = 0; i < ROWS; i++) {
        const int r = 3 * i + 1 < n ? 3 * i + 1 : n - 1;
        b->yc[i] = y[r];
        b->zc[i] = z[r];
    }
    const double e[3] = {jm_box_extent(x, n, 2, b->nb), jm_box_extent(y, n, 3, b->nr), jm_box_extent(z, n, 3, b->nr)};
    box_consts(e, &b->E2, b->te);
    double M = 0.0, Gt = 0.0;
    for (int k = 0; k < JM_BOX_BINS - 1; k++) { /* the last bin adds exact zeros */
        const double shi = (k + 1) / (double)c->box_bin * (1.0 + 1e-6), bk = c->box_b[k];
        M = fmax(M, fabs((double)c->box_a[k]) + bk * (shi + b->E2));
        Gt = fmax(Gt, bk * sqrt(shi));
    }
    b->M = (float)(M * (1.0 + 1e-6));
    b->Gt = (float)(Gt * (1.0 + 1e-6));
    b->Rp = JM_BOX_REACH * c->support;
    b->Rp2 = b->Rp * b->Rp;
    b->inv3h = 1.0f / (3.0f * c->h);
    b->lo[0] = b->xc[0] - b->Rp - c->h;
    b->hi[0] = b->xc[b->nb - 1] + b->Rp + c->h;
    b->lo[1] = b->yc[0] - b->Rp - c->h;
    b->hi[1] = b->yc[b->nr - 1] + b->Rp + c->h;
    b->lo[2] = b->zc[0] - b->Rp - c->h;
    b->hi[2] = b->zc[b->nr - 1] + b->Rp + c->h;
}

/* particle q's rows of centres within the reach: [*j0, *j1) x [*k0, *k1) */
static inline int rows_of(const box_setup *b, const float *q, int *j0, int *j1, int *k0, int *k1)
{
    if (q[0] < b->lo[0] || q[0] > b->hi[0] || q[1] < b->lo[1] || q[1] > b->hi[1] || q[2] < b->lo[2] || q[2] > b->hi[2])
        return 0;
    *k0 = iceil((q[2] - b->Rp - b->zc[0]) * b->inv3h);
    *k1 = ifloor((q[2] + b->Rp - b->zc[0]) * b->inv3h) + 1;
    *j0 = iceil((q[1] - b->Rp - b->yc[0]) * b->inv3h);
    *j1 = ifloor((q[1] + b->Rp - b->yc[0]) * b->inv3h) + 1;
    *k0 = *k0 < 0 ? 0 : *k0;
    *j0 = *j0 < 0 ? 0 : *j0;
    *k1 = *k1 > b->nr ? b->nr : *k1;
    *j1 = *j1 > b->nr ? b->nr : *j1;
    return *k0 < *k1 && *j0 < *j1;
}

/* The accumulators: per row of box centres (bk, bj), L (the lines at s +
 * E2) and G (w b v, per axis), 16 lanes. */
typedef struct {
    float L[ROWS][ROWS][LANES], G[3][ROWS][ROWS][LANES];
    float W[ROWS][ROWS]; /* the weights of the particles a row got */
    int m[ROWS][ROWS];   /* and their count */
    float X[ROWS][ROWS][JM_PAD_MAX]; /* spread: the bounds along x */
} box_acc;

size_t jm_box_work_bytes(void) { return sizeof(box_acc); }

/* Each node the best of its boxes' bounds: V = L - sum_a te_a |G_a| less
 * its rounding (docs/culling.md, 3b); along x node i in boxes (i - 1) / 2 and i / 2
 * (clipped to [0, nb)), along y and z in row i / 3 alone. */
JM_BODY void spread_body(box_acc *A, const box_setup *b, int n, float *out)
{
    const int nb = b->nb, nr = b->nr, ns = JM_PAD(n);
    const double u = 0x1p-24, te = (double)b->te[0] + b->te[1] + b->te[2];
    float(*X)[ROWS][JM_PAD_MAX] = A->X;
    for (int bk = 0; bk < nr; bk++)
        for (int bj = 0; bj < nr; bj++) {
            const double mb = A->m[bk][bj];
            const float err = (float)(1.02 * u * A->W[bk][bj] * ((mb + 16.0) * b->M + te * (mb + 8.0) * b->Gt) * (1.0 + 1e-6));
            float v[LANES];
            for (int i = 0; i < LANES; i++) {
                const float t = A->L[bk][bj][i] - (b->te[0] * fabsf(A->G[0][bk][bj][i]) + b->te[1] * fabsf(A->G[1][bk][bj][i]) +
                                                   b->te[2] * fabsf(A->G[2][bk][bj][i]));
                v[i] = t - (err + fabsf(t) * 0x1p-21f);
            }
            /* along x: node 2 t + 1 in box t alone, node 2 t in boxes t - 1 and t */
            float *r = X[bk][bj];
            r[0] = v[0];
            for (int t = 0; t < nb; t++) {
                r[2 * t + 1] = v[t];
                if (2 * t + 2 < n) r[2 * t + 2] = t + 1 < nb && v[t + 1] > v[t] ? v[t + 1] : v[t];
            }
        }
    for (int k = 0; k < n; k++)
        for (int j = 0; j < n; j++) memcpy(out + ((size_t)k * n + j) * ns, X[k / 3][j / 3], (size_t)n * sizeof *out);
}
JM_KERNEL_512(static, void, spread, spread_body, (box_acc *A, const box_setup *b, int n, float *out), (A, b, n, out))

/* Every particle of the hood (not isolated, within the setup's box): PREP
 * once, then ROW(L, G0, G1, G2, vy, vz, dyz2) on each row of box centres
 * within the reach, whose count and weight sum it adds to. */
#define BOX_LOOP(PREP, ROW)                                                                                \
    box_setup b;                                                                                       \
    setup(c, x, y, z, n, &b);                                                                          \
    box_acc *A = work;                                                                                 \
    memset(A, 0, offsetof(box_acc, X));                                                                \
    const size_t cells = (size_t)hood->n[0] * hood->n[1] * hood->n[2];                                 \
    for (size_t k = 0; k < cells; k++)                                                                 \
        for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {                       \
            const float *q = GP(g, p);                                                                 \
            int j0, j1, k0, k1;                                                                        \
            if (!rows_of(&b, q, &j0, &j1, &k0, &k1) || g->isolated[p]) continue;                       \
            const float w = g->weight[p];                                                              \
            PREP                                                                                       \
            for (int bk = k0; bk < k1; bk++) {                                                         \
                const float vz = b.zc[bk] - q[2], dz2 = vz * vz;                                       \
                if (dz2 >= b.Rp2) continue;                                                            \
                for (int bj = j0; bj < j1; bj++) {                                                     \
                    const float vy = b.yc[bj] - q[1], dyz2 = vy * vy + dz2;                            \
                    if (dyz2 >= b.Rp2) continue;                                                       \
                    A->W[bk][bj] += w;                                                                 \
                    A->m[bk][bj]++;                                                                    \
                    ROW(A->L[bk][bj], A->G[0][bk][bj], A->G[1][bk][bj], A->G[2][bk][bj], vy, vz, dyz2); \
                }                                                                                      \
            }                                                                                          \
        }                                                                                              \
    spread(A, &b, n, out);

#define PREP_C                                                                                             \
    float dx[LANES], dx2[LANES];                                                                       \
    for (int i = 0; i < LANES; i++) {                                                                  \
        dx[i] = b.xc[i] - q[0];                                                                        \
        dx2[i] = dx[i] * dx[i];                                                                        \
    }
#define ROW_C(L, G0, G1, G2, vy, vz, dyz2)                                                                 \
    for (int i = 0; i < LANES; i++) {                                                                  \
        const float s = dx2[i] + dyz2, sb = s * c->box_bin;                                            \
        const int kk = (int)(sb < top ? sb : top);                                                     \
        const float wb = w * c->box_b[kk];                                                             \
        L[i] = L[i] + w * (c->box_a[kk] - c->box_b[kk] * (s + b.E2));                                  \
        G0[i] = G0[i] + wb * dx[i];                                                                    \
        G1[i] = G1[i] + wb * vy;                                                                       \
        G2[i] = G2[i] + wb * vz;                                                                       \
    }
static void boxes_c(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y,
                    const float *z, int n, void *work, float *out)
{
    const float top = (float)(JM_BOX_BINS - 1);
    BOX_LOOP(PREP_C, ROW_C)
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
/* The same terms 16 box centres at a time, the lines picked by a permute
 * from the 32 bins, fused multiply-adds (the bound holds for one rounding
 * or two, docs/culling.md, 3b). */
#define PREP_AVX512                                                                                        \
    const __m512 vw = _mm512_set1_ps(w), vE2 = _mm512_set1_ps(b.E2);                                   \
    const __m512 dx = _mm512_sub_ps(_mm512_loadu_ps(b.xc), _mm512_set1_ps(q[0]));                      \
    const __m512 dx2 = _mm512_mul_ps(dx, dx);
#define ROW_AVX512(L, G0, G1, G2, vy, vz, dyz2)                                                            \
    do {                                                                                               \
        const __m512 s = _mm512_add_ps(dx2, _mm512_set1_ps(dyz2));                                     \
        const __m512i kk = _mm512_cvttps_epi32(_mm512_min_ps(_mm512_mul_ps(s, vbin), vtop));           \
        const __m512 a = _mm512_permutex2var_ps(A0, kk, A1), bb = _mm512_permutex2var_ps(B0, kk, B1);  \
        const __m512 l = _mm512_fnmadd_ps(bb, _mm512_add_ps(s, vE2), a);                               \
        const __m512 wb = _mm512_mul_ps(vw, bb);                                                       \
        _mm512_storeu_ps(L, _mm512_fmadd_ps(vw, l, _mm512_loadu_ps(L)));                               \
        _mm512_storeu_ps(G0, _mm512_fmadd_ps(wb, dx, _mm512_loadu_ps(G0)));                            \
        _mm512_storeu_ps(G1, _mm512_fmadd_ps(wb, _mm512_set1_ps(vy), _mm512_loadu_ps(G1)));            \
        _mm512_storeu_ps(G2, _mm512_fmadd_ps(wb, _mm512_set1_ps(vz), _mm512_loadu_ps(G2)));            \
    } while (0)
__attribute__((target("avx512f"))) static void boxes_avx512(const jm_grid *g, const jm_config *c, const jm_hood *hood,
                                                            const float *x, const float *y, const float *z, int n,
                                                            void *work, float *out)
{
    const __m512 A0 = _mm512_loadu_ps(c->box_a), A1 = _mm512_loadu_ps(c->box_a + 16);
    const __m512 B0 = _mm512_loadu_ps(c->box_b), B1 = _mm512_loadu_ps(c->box_b + 16);
    const __m512 vbin = _mm512_set1_ps(c->box_bin), vtop = _mm512_set1_ps((float)(JM_BOX_BINS - 1));
    BOX_LOOP(PREP_AVX512, ROW_AVX512)
}

/* The same terms in two halves of 8 lanes (AVX2 with FMA, AMD Zen 2 and
 * the like): the line of each lane's bin picked from the 32 bins by four
 * permutes of 8 and two blends on the bin's bits 3 and 4 (the sign bit of
 * the bin shifted left by 28 and 27), cheaper than gathers. */
__attribute__((target("avx2,fma"))) static inline __m256 lut32_avx2(const __m256 t[4], __m256i k, __m256 m3, __m256 m4)
{
    const __m256 lo = _mm256_blendv_ps(_mm256_permutevar8x32_ps(t[0], k), _mm256_permutevar8x32_ps(t[1], k), m3);
    const __m256 hi = _mm256_blendv_ps(_mm256_permutevar8x32_ps(t[2], k), _mm256_permutevar8x32_ps(t[3], k), m3);
    return _mm256_blendv_ps(lo, hi, m4);
}
__attribute__((target("avx2,fma"))) static inline float min8_avx2(__m256 v)
{
    __m128 m = _mm_min_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_min_ss(m, _mm_shuffle_ps(m, m, 1)));
}
/* Lanes whose bin is the last one (the zero line: a = b = 0) add exact
 * zeros to their accumulators: they are left out, the same sums. A lane
 * with fl(dx^2 bin) >= 31 is such a lane on every row (fl(fl(dx^2 + dyz^2)
 * bin) is monotone in dyz^2 >= 0); the others of a particle (|dx| < 1.97
 * sph_h) are at most 8 consecutive lanes while the boxes' stride 2h is at
 * least 0.5 sph_h (h <= JM_BOX_MAX_H sph_h keeps it near that): one window
 * of 8 lanes from the first of them (at most from lane 8), else the two
 * halves. On a row, a window whose lanes all reach the last bin (decided
 * by its least dx^2 for all eight) is skipped too. */
#define PREP_AVX2                                                                                          \
    const __m256 vw = _mm256_set1_ps(w), vE2 = _mm256_set1_ps(b.E2), q0 = _mm256_set1_ps(q[0]);        \
    __m256 wdx[2], wdx2[2];                                                                            \
    float wmin[2];                                                                                     \
    int woff[2], nwin = 0;                                                                             \
    {                                                                                                  \
        const __m256 da = _mm256_sub_ps(_mm256_loadu_ps(b.xc), q0);                                    \
        const __m256 db = _mm256_sub_ps(_mm256_loadu_ps(b.xc + 8), q0);                                \
        const unsigned live =                                                                          \
            (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(_mm256_mul_ps(_mm256_mul_ps(da, da), vbin), vtop, _CMP_LT_OQ)) | \
            (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(_mm256_mul_ps(_mm256_mul_ps(db, db), vbin), vtop, _CMP_LT_OQ)) << 8; \
        if (live) {                                                                                    \
            nwin = jm_box_windows(live, woff);                                                         \
            for (int ww = 0; ww < nwin; ww++) {                                                        \
                wdx[ww] = _mm256_sub_ps(_mm256_loadu_ps(b.xc + woff[ww]), q0);                         \
                wdx2[ww] = _mm256_mul_ps(wdx[ww], wdx[ww]);                                            \
                wmin[ww] = min8_avx2(wdx2[ww]);                                                        \
            }                                                                                          \
        }                                                                                              \
    }
#define ROW_AVX2(L, G0, G1, G2, vy, vz, dyz2)                                                              \
    do {                                                                                               \
        const __m256 vyz = _mm256_set1_ps(dyz2), vvy = _mm256_set1_ps(vy), vvz = _mm256_set1_ps(vz);  \
        for (int hh = 0; hh < nwin; hh++) {                                                            \
            if ((wmin[hh] + dyz2) * c->box_bin >= top) continue; /* every lane's bin the zero line */  \
            const __m256 s = _mm256_add_ps(wdx2[hh], vyz);                                             \
            const __m256i kk = _mm256_cvttps_epi32(_mm256_min_ps(_mm256_mul_ps(s, vbin), vtop));       \
            const __m256 m3 = _mm256_castsi256_ps(_mm256_slli_epi32(kk, 28));                          \
            const __m256 m4 = _mm256_castsi256_ps(_mm256_slli_epi32(kk, 27));                          \
            const __m256 a = lut32_avx2(TA, kk, m3, m4), bb = lut32_avx2(TB, kk, m3, m4);              \
            const __m256 l = _mm256_fnmadd_ps(bb, _mm256_add_ps(s, vE2), a);                           \
            const __m256 wb = _mm256_mul_ps(vw, bb);                                                   \
            const int o = woff[hh];                                                                    \
            float *l8 = (L) + o, *g0 = (G0) + o, *g1 = (G1) + o, *g2 = (G2) + o;                       \
            _mm256_storeu_ps(l8, _mm256_fmadd_ps(vw, l, _mm256_loadu_ps(l8)));                         \
            _mm256_storeu_ps(g0, _mm256_fmadd_ps(wb, wdx[hh], _mm256_loadu_ps(g0)));                   \
            _mm256_storeu_ps(g1, _mm256_fmadd_ps(wb, vvy, _mm256_loadu_ps(g1)));                       \
            _mm256_storeu_ps(g2, _mm256_fmadd_ps(wb, vvz, _mm256_loadu_ps(g2)));                       \
        }                                                                                              \
    } while (0)
__attribute__((target("avx2,fma"))) static void boxes_avx2(const jm_grid *g, const jm_config *c, const jm_hood *hood,
                                                           const float *x, const float *y, const float *z, int n,
                                                           void *work, float *out)
{
    __m256 TA[4], TB[4];
    for (int i = 0; i < 4; i++) {
        TA[i] = _mm256_loadu_ps(c->box_a + 8 * i);
        TB[i] = _mm256_loadu_ps(c->box_b + 8 * i);
    }
    const float top = (float)(JM_BOX_BINS - 1);
    const __m256 vbin = _mm256_set1_ps(c->box_bin), vtop = _mm256_set1_ps(top);
    BOX_LOOP(PREP_AVX2, ROW_AVX2)
}
#endif

/* Which path runs: cpu.h's level (AVX2 comes with FMA there) */
int jm_box_path(void)
{
    const int level = jm_cpu_level();
    return level >= JM_CPU_AVX512 ? JM_BOX_AVX512 : level >= JM_CPU_AVX2 ? JM_BOX_AVX2 : JM_BOX_C;
}

void jm_sph_boxes(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y,
                  const float *z, int n, void *work, float *out)
{
    switch (jm_box_path()) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    case JM_BOX_AVX512: boxes_avx512(g, c, hood, x, y, z, n, work, out); return;
    case JM_BOX_AVX2: boxes_avx2(g, c, hood, x, y, z, n, work, out); return;
#endif
    default: boxes_c(g, c, hood, x, y, z, n, work, out);
    }
}
