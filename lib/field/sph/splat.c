/* splat.c - SPH field sampling on a block: the kernel splatted row by row in SIMD chosen at run time. */
#include "field/sph/splat.h"
#include "field/sph/cull.h"
#include "core/cubic8.h"
#include "core/round8.h"
#include "core/cpu.h"
#include <math.h>
#include <string.h>

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])
#define INLINE static inline __attribute__((always_inline))

/* row[i] += wgt * (((0.25 A) A) A - (B B) B), A = max(2 - q, 0),
 * B = max(1 - q, 0), q = sqrt((xp[i] - qx)^2 + dyz2) * inv, for i in [a, b) */
INLINE void row_c(float *row, const float *xp, int a, int b, float qx, float dyz2, float inv, float wgt)
{
    for (int i = a; i < b; i++) {
        float dx = xp[i] - qx;
        float q = sqrtf(dx * dx + dyz2) * inv;
        float A = 2.0f - q, B = 1.0f - q;
        A = A > 0.0f ? A : 0.0f;
        B = B > 0.0f ? B : 0.0f;
        float w = 0.25f * A * A * A - B * B * B;
        row[i] = row[i] + wgt * w;
    }
}

/* The partial sums' terms (cull.h, JM_TAN_*): row[i] += max(a1 - b1 s,
 * a2 - b2 s, 0), s = (xp[i] - qx)^2 + dyz2, on the lanes [a, b) */
INLINE void rowp_c(float *row, const float *xp, int a, int b, float qx, float dyz2, const float t[4])
{
    for (int i = a; i < b; i++) {
        float dx = xp[i] - qx;
        float s = dx * dx + dyz2;
        float l1 = t[0] - t[1] * s, l2 = t[2] - t[3] * s;
        float l = l1 > l2 ? l1 : l2;
        row[i] = row[i] + (l > 0.0f ? l : 0.0f);
    }
}

/* What both bodies below start with: xp, the nodes' x continued past n at
 * the spacing h; pad cleared; box, the block's nodes widened by R. */
#define ROWS_SETUP                                                                                         \
    float xp[JM_PAD_MAX];                                                                                  \
    for (int i = 0; i < ns; i++) xp[i] = i < n ? x[i] : x[n - 1] + (float)(i - n + 1) * h;                \
    size_t cells = (size_t)hood->n[0] * hood->n[1] * hood->n[2];                                           \
    memset(pad, 0, (size_t)n * n * ns * sizeof *pad);                                                      \
    const float box[6] = {x[0] - R, x[n - 1] + R, y[0] - R, y[n - 1] + R, z[0] - R, z[n - 1] + R};

/* Whether particle p (at q) counts for the block: inside box, not
 * isolated, and its support R covers some nodes, whose index ranges per
 * axis it then gives. */
INLINE int reaches(const jm_grid *g, uint32_t p, const float *q, const float box[6], const float *x, const float *y,
                   const float *z, int n, float inv_h, float R, int *i0, int *i1, int *j0, int *j1, int *k0, int *k1)
{
    if (q[0] < box[0] || q[0] > box[1] || q[1] < box[2] || q[1] > box[3] || q[2] < box[4] || q[2] > box[5]) return 0;
    if (g->isolated[p]) return 0;
    node_span(x, n, inv_h, q[0] - R, q[0] + R, i0, i1);
    node_span(y, n, inv_h, q[1] - R, q[1] + R, j0, j1);
    node_span(z, n, inv_h, q[2] - R, q[2] + R, k0, k1);
    return *i0 < *i1 && *j0 < *j1 && *k0 < *k1;
}

/* One particle's rows on slab kk (ROWS of SAMPLE_BODY), one at a time:
 * the chord of its support on row jj, from a to e in whole steps of 8
 * (cut to the row's span where SPANNED), given to ROW. */
#define ROWS_ONE(ROW, SPANNED)                                                                                 \
    for (int jj = ja; jj < jb; jj++) {                                                                     \
        const uint8_t *sp = SPANNED ? span + 2 * ((size_t)kk * n + jj) : NULL;                             \
        if (SPANNED && sp[0] >= sp[1]) continue;                                                           \
        float dy = y[jj] - q[1], dyz2 = dy * dy + dz2;                                                     \
        if (dyz2 >= R2) continue;                                                                          \
        float half = sqrtf(R2 - dyz2) * inv_h;                                                             \
        int a = iceil(cx - half), b = ifloor(cx + half) + 1;                                               \
        a = a > i0 ? a : i0;                                                                               \
        b = b < i1 ? b : i1;                                                                               \
        if (a >= b) continue;                                                                              \
        int e = a + ((b - a + 7) & ~7);                                                                    \
        if (SPANNED) {                                                                                     \
            /* the part of the run [a, e) over the span, in whole steps of 8 from a */                     \
            int lo = a > sp[0] ? a : sp[0], hi = e < sp[1] ? e : sp[1];                                    \
            if (lo >= hi) continue;                                                                        \
            a += (lo - a) & ~7;                                                                            \
            e = a + ((hi - a + 7) & ~7);                                                                   \
        }                                                                                                  \
        ROW(slab + (size_t)jj * ns, xp, a, e, qx, dyz2, inv, wgt);                                         \
    }

/* Splats every particle of the hood whose support reaches the block into
 * pad, whose rows are JM_PAD(n) >= n + 7 long, in runs of 8 nodes from the
 * start of the support's chord: one or two vector steps per row (the lanes
 * past the chord add exact zeros: the kernel vanishes beyond its support).
 * ROWS does one particle's rows [ja, jb) of slab kk (ROWS_ONE's, or
 * ROWS_AVX2's: the same rows and runs). */
#define SAMPLE_BODY(ROWS, SPANNED, PREP)                                                                       \
    const int ns = JM_PAD(n);                                                                              \
    const float R = c->support, R2 = R * R, inv = 1.0f / c->sph_h, inv_h = c->inv_h, h = c->h;             \
    ROWS_SETUP                                                                                             \
    jm_span_box sb;                                                                                        \
    if (SPANNED) jm_span_box_of(span, n, &sb);                                                             \
    for (size_t k = 0; k < cells; k++) {                                                                   \
        for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {                           \
            const float *q = GP(g, p);                                                                     \
            int i0, i1, j0, j1, k0, k1;                                                                    \
            if (!reaches(g, p, q, box, x, y, z, n, inv_h, R, &i0, &i1, &j0, &j1, &k0, &k1)) continue;       \
            if (SPANNED) {                                                                                 \
                /* the rows and nodes this particle reaches, cut to the spans' box */                      \
                if (i1 <= sb.i0 || i0 >= sb.i1) continue;                                                  \
                k0 = k0 > sb.k0 ? k0 : sb.k0;                                                              \
                k1 = k1 < sb.k1 ? k1 : sb.k1;                                                              \
                if (k0 >= k1) continue;                                                                    \
            }                                                                                              \
            const float wgt = g->weight[p];                                                                \
            const float qx = q[0], cx = (qx - x[0]) * inv_h;                                               \
            PREP                                                                                           \
            for (int kk = k0; kk < k1; kk++) {                                                             \
                float dz = z[kk] - q[2], dz2 = dz * dz;                                                    \
                float *slab = pad + (size_t)kk * n * ns;                                                   \
                const int ja = SPANNED && sb.j0[kk] > j0 ? sb.j0[kk] : j0;                                 \
                const int jb = SPANNED && sb.j1[kk] < j1 ? sb.j1[kk] : j1;                                 \
                ROWS                                                                                       \
            }                                                                                              \
        }                                                                                                  \
    }

/* The partial sums (see jm_sph_partial): each particle's lower-bound terms
 * (cull.h, JM_TAN_*) on the rows within JM_PART_REACH of its support
 * (dyz2 < Rp^2), there on the window of nodes [ic - K, ic + K] around its
 * own, ic = floor(cx + 1/2), clipped to [i0, i1) (ROWP adds +0 to the other
 * lanes of its steps). Any subset of (particle, node) pairs gives a lower
 * bound (docs/culling.md, 3): the reach and the window are speed only. t[4] = wgt a1,
 * wgt b1 / sph_h^2, wgt a2, wgt b2 / sph_h^2, for s in world units. */
#define PARTIAL_BODY(ROWP, PREP)                                                                               \
    const int ns = JM_PAD(n);                                                                              \
    const float R = c->support, inv = 1.0f / c->sph_h, inv_h = c->inv_h, h = c->h, i2 = inv * inv;          \
    const float Rp = JM_PART_REACH * R, Rp2 = Rp * Rp;                                                     \
    int K = (int)(0.65f * R * inv_h);                                                                      \
    K = K < 0 ? 0 : (K > 7 ? 7 : K);                                                                       \
    (void)span;                                                                                            \
    ROWS_SETUP                                                                                             \
    for (size_t k = 0; k < cells; k++) {                                                                   \
        for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {                           \
            const float *q = GP(g, p);                                                                     \
            int i0, i1, j0, j1, k0, k1;                                                                    \
            if (!reaches(g, p, q, box, x, y, z, n, inv_h, R, &i0, &i1, &j0, &j1, &k0, &k1)) continue;       \
            const float wgt = g->weight[p];                                                                \
            const float t[4] = {wgt * JM_TAN_A1, wgt * JM_TAN_B1 * i2, wgt * JM_TAN_A2, wgt * JM_TAN_B2 * i2}; \
            const float qx = q[0], cx = (qx - x[0]) * inv_h;                                               \
            const int ic = ifloor(cx + 0.5f);                                                              \
            const int a = ic - K > i0 ? ic - K : i0, b = ic + K + 1 < i1 ? ic + K + 1 : i1;                \
            if (a >= b) continue;                                                                          \
            PREP                                                                                           \
            for (int kk = k0; kk < k1; kk++) {                                                             \
                float dz = z[kk] - q[2], dz2 = dz * dz;                                                    \
                if (dz2 >= Rp2) continue;                                                                  \
                float *slab = pad + (size_t)kk * n * ns;                                                   \
                for (int jj = j0; jj < j1; jj++) {                                                         \
                    float dy = y[jj] - q[1], dyz2 = dy * dy + dz2;                                         \
                    if (dyz2 >= Rp2) continue;                                                             \
                    ROWP(slab + (size_t)jj * ns, xp, a, b, qx, dyz2, t);                                   \
                }                                                                                          \
            }                                                                                              \
        }                                                                                                  \
    }

#define SAMPLE_ARGS                                                                                       \
    const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y, const float *z, \
        int n, const uint8_t *span, float *pad

static void sample_c(SAMPLE_ARGS) { SAMPLE_BODY(ROWS_ONE(row_c, 0), 0, ) }
static void sample_c_span(SAMPLE_ARGS) { SAMPLE_BODY(ROWS_ONE(row_c, 1), 1, ) }
static void partial_c(SAMPLE_ARGS) { PARTIAL_BODY(rowp_c, ) } /* exact lanes [a, b) */

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

INLINE void row_sse2(float *row, const float *xp, int a, int b, float qx, float dyz2, float inv, float wgt)
{
    const __m128 vq = _mm_set1_ps(qx), vd = _mm_set1_ps(dyz2), vi = _mm_set1_ps(inv), vw = _mm_set1_ps(wgt);
    const __m128 two = _mm_set1_ps(2.0f), one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps(), quarter = _mm_set1_ps(0.25f);
    for (int i = a; i < b; i += 4) {
        __m128 dx = _mm_sub_ps(_mm_loadu_ps(xp + i), vq);
        __m128 q = _mm_mul_ps(_mm_sqrt_ps(_mm_add_ps(_mm_mul_ps(dx, dx), vd)), vi);
        __m128 A = _mm_max_ps(_mm_sub_ps(two, q), zero);
        __m128 B = _mm_max_ps(_mm_sub_ps(one, q), zero);
        __m128 w = _mm_sub_ps(_mm_mul_ps(_mm_mul_ps(_mm_mul_ps(quarter, A), A), A), _mm_mul_ps(_mm_mul_ps(B, B), B));
        _mm_storeu_ps(row + i, _mm_add_ps(_mm_loadu_ps(row + i), _mm_mul_ps(vw, w)));
    }
}

__attribute__((target("avx2"))) INLINE void row_avx2(float *row, const float *xp, int a, int b, float qx,
                                                     float dyz2, float inv, float wgt)
{
    const __m256 vq = _mm256_set1_ps(qx), vd = _mm256_set1_ps(dyz2), vi = _mm256_set1_ps(inv), vw = _mm256_set1_ps(wgt);
    for (int i = a; i < b; i += 8) {
        __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(xp + i), vq);
        __m256 q = _mm256_mul_ps(_mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), vd)), vi);
        __m256 w = jm_cubic_w8(q);
        _mm256_storeu_ps(row + i, _mm256_add_ps(_mm256_loadu_ps(row + i), _mm256_mul_ps(vw, w)));
    }
}

/* Partial rows (rowp_c's terms): the lanes [a, b) only, the others of each
 * step adding +0 */
INLINE void rowp_sse2(float *row, const float *xp, int a, int b, float qx, float dyz2, const float t[4])
{
    const __m128 vq = _mm_set1_ps(qx), vd = _mm_set1_ps(dyz2), zero = _mm_setzero_ps();
    const __m128 a1 = _mm_set1_ps(t[0]), b1 = _mm_set1_ps(t[1]), a2 = _mm_set1_ps(t[2]), b2 = _mm_set1_ps(t[3]);
    const __m128i vb = _mm_set1_epi32(b), iota = _mm_setr_epi32(0, 1, 2, 3);
    for (int i = a; i < b; i += 4) {
        __m128 dx = _mm_sub_ps(_mm_loadu_ps(xp + i), vq);
        __m128 s = _mm_add_ps(_mm_mul_ps(dx, dx), vd);
        __m128 l = _mm_max_ps(_mm_sub_ps(a1, _mm_mul_ps(b1, s)), _mm_sub_ps(a2, _mm_mul_ps(b2, s)));
        __m128 m = _mm_castsi128_ps(_mm_cmplt_epi32(_mm_add_epi32(_mm_set1_epi32(i), iota), vb));
        _mm_storeu_ps(row + i, _mm_add_ps(_mm_loadu_ps(row + i), _mm_and_ps(m, _mm_max_ps(l, zero))));
    }
}

/* AVX2 rows eight at a time (ROWS_AVX2): the setup ROWS_ONE does per row
 * (dy^2 + dz^2, the chord's half length, its whole steps of 8 and their cut
 * to the span) on eight rows' lanes, with the same IEEE operations (no
 * fused multiply-add in this target) and the same integer steps (round8.h,
 * on the chord ends, well within +-2^31); then row_avx2 on the rows left, in
 * order. The same rows, runs and sums. yp: the block's y padded by 8 lanes
 * (YPAD_AVX2); spr: the slab's spans (2 bytes a row; the buffer holds 16
 * bytes past the last, JM_CULL_SPAN_BYTES) or NULL. */
#define YPAD_AVX2                                                                                          \
    float yp[JM_PAD_MAX + 8];                                                                              \
    for (int t = 0; t < n + 8; t++) yp[t] = t < n ? y[t] : 0.0f;
#define ROWS_AVX2(SPANNED)                                                                                     \
    rows_avx2(slab, ns, yp, xp, SPANNED ? span + 2 * (size_t)kk * n : NULL, ja, jb, q[1], dz2, R2, inv_h, cx, \
              i0, i1, qx, inv, wgt);
__attribute__((target("avx2"))) INLINE void rows_avx2(float *slab, int ns, const float *yp, const float *xp,
                                                      const uint8_t *spr, int ja, int jb, float qy, float dz2,
                                                      float R2, float inv_h, float cx, int i0, int i1, float qx,
                                                      float inv, float wgt)
{
    const __m256 vqy = _mm256_set1_ps(qy), vdz2 = _mm256_set1_ps(dz2), vR2 = _mm256_set1_ps(R2);
    const __m256 vih = _mm256_set1_ps(inv_h), vcx = _mm256_set1_ps(cx);
    const __m256i vi0 = _mm256_set1_epi32(i0), vi1 = _mm256_set1_epi32(i1), one = _mm256_set1_epi32(1);
    const __m256i seven = _mm256_set1_epi32(7), not7 = _mm256_set1_epi32(~7);
    const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m128i split = _mm_setr_epi8(0, 2, 4, 6, 8, 10, 12, 14, 1, 3, 5, 7, 9, 11, 13, 15);
    int A[8], E[8];
    float D[8];
    for (int j = ja; j < jb; j += 8) {
        const __m256 dy = _mm256_sub_ps(_mm256_loadu_ps(yp + j), vqy);
        const __m256 dyz2 = _mm256_add_ps(_mm256_mul_ps(dy, dy), vdz2);
        const __m256 half = _mm256_mul_ps(_mm256_sqrt_ps(_mm256_sub_ps(vR2, dyz2)), vih);
        const __m256 fa = _mm256_sub_ps(vcx, half), fb = _mm256_add_ps(vcx, half);
        __m256i a = jm_iceil8(fa), b = _mm256_add_epi32(jm_ifloor8(fb), one);
        a = _mm256_max_epi32(a, vi0);
        b = _mm256_min_epi32(b, vi1);
        __m256i e = _mm256_add_epi32(a, _mm256_and_si256(_mm256_add_epi32(_mm256_sub_epi32(b, a), seven), not7));
        /* rows in [ja, jb) within the support, with a chord */
        __m256i ok = _mm256_cmpgt_epi32(_mm256_set1_epi32(jb - j), iota);
        ok = _mm256_and_si256(ok, _mm256_castps_si256(_mm256_cmp_ps(dyz2, vR2, _CMP_LT_OQ)));
        ok = _mm256_and_si256(ok, _mm256_cmpgt_epi32(b, a));
        if (spr) {
            const __m128i pr = _mm_shuffle_epi8(_mm_loadu_si128((const __m128i *)(spr + 2 * (size_t)j)), split);
            const __m256i s0 = _mm256_cvtepu8_epi32(pr), s1 = _mm256_cvtepu8_epi32(_mm_srli_si128(pr, 8));
            const __m256i lo = _mm256_max_epi32(a, s0), hi = _mm256_min_epi32(e, s1);
            ok = _mm256_and_si256(ok, _mm256_cmpgt_epi32(hi, lo));
            a = _mm256_add_epi32(a, _mm256_and_si256(_mm256_sub_epi32(lo, a), not7));
            e = _mm256_add_epi32(a, _mm256_and_si256(_mm256_add_epi32(_mm256_sub_epi32(hi, a), seven), not7));
        }
        unsigned m = (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(ok));
        if (!m) continue;
        _mm256_storeu_si256((__m256i *)A, a);
        _mm256_storeu_si256((__m256i *)E, e);
        _mm256_storeu_ps(D, dyz2);
        do {
            const int l = __builtin_ctz(m);
            m &= m - 1;
            row_avx2(slab + (size_t)(j + l) * ns, xp, A[l], E[l], qx, D[l], inv, wgt);
        } while (m);
    }
}

/* AVX-512 full and span rows: runs of 16 nodes, and a last run of 8 in AVX
 * (runs are whole multiples of 8 long), (xp - qx)^2 formed once per particle
 * over the whole padded row (SPREP_AVX512, ns a multiple of 8) and read by
 * each row step (row_avx512d): each lane gets the operations it gets in
 * row_avx2, on the same operands, so the same bits. */
#define SPREP_AVX512                                                                                       \
    float dx2r[JM_PAD_MAX];                                                                                \
    {                                                                                                      \
        int t = 0;                                                                                         \
        for (; t + 16 <= ns; t += 16) {                                                                    \
            const __m512 d = _mm512_sub_ps(_mm512_loadu_ps(xp + t), _mm512_set1_ps(qx));                   \
            _mm512_storeu_ps(dx2r + t, _mm512_mul_ps(d, d));                                               \
        }                                                                                                  \
        if (t < ns) {                                                                                      \
            const __m256 d = _mm256_sub_ps(_mm256_loadu_ps(xp + t), _mm256_set1_ps(qx));                   \
            _mm256_storeu_ps(dx2r + t, _mm256_mul_ps(d, d));                                               \
        }                                                                                                  \
    }                                                                                                      \
    const __m512 svi = _mm512_set1_ps(inv), svw = _mm512_set1_ps(wgt);
#define ROWD_AVX512(row, xp_, a, b, qx_, dyz2, inv_, wgt_) row_avx512d(row, dx2r, a, b, dyz2, svi, svw)
__attribute__((target("avx512f"))) INLINE void row_avx512d(float *row, const float *dx2r, int a, int b, float dyz2,
                                                           __m512 vi, __m512 vw)
{
    const __m512 vd = _mm512_set1_ps(dyz2), two = _mm512_set1_ps(2.0f), one = _mm512_set1_ps(1.0f);
    const __m512 zero = _mm512_setzero_ps(), quarter = _mm512_set1_ps(0.25f);
    int i = a;
    for (; i + 16 <= b; i += 16) {
        __m512 q = _mm512_mul_ps(_mm512_sqrt_ps(_mm512_add_ps(_mm512_loadu_ps(dx2r + i), vd)), vi);
        __m512 A = _mm512_max_ps(_mm512_sub_ps(two, q), zero);
        __m512 B = _mm512_max_ps(_mm512_sub_ps(one, q), zero);
        __m512 w = _mm512_sub_ps(_mm512_mul_ps(_mm512_mul_ps(_mm512_mul_ps(quarter, A), A), A),
                                 _mm512_mul_ps(_mm512_mul_ps(B, B), B));
        _mm512_storeu_ps(row + i, _mm512_add_ps(_mm512_loadu_ps(row + i), _mm512_mul_ps(vw, w)));
    }
    if (i < b) {
        const __m256 hd = _mm256_set1_ps(dyz2), hi = _mm512_castps512_ps256(vi), hw = _mm512_castps512_ps256(vw);
        __m256 q = _mm256_mul_ps(_mm256_sqrt_ps(_mm256_add_ps(_mm256_loadu_ps(dx2r + i), hd)), hi);
        __m256 w = jm_cubic_w8(q);
        _mm256_storeu_ps(row + i, _mm256_add_ps(_mm256_loadu_ps(row + i), _mm256_mul_ps(hw, w)));
    }
}

/* AVX2 partial rows (ROWP_AVX2): a particle's window [a, b) is at most 15
 * nodes, one or two steps of 8, and its (xp - qx)^2 and lane masks are the
 * same on every row: formed once per particle (PREP_AVX2P), each lane then
 * doing rowp_sse2's operations (the same bits); the second step's
 * loads only where the window has one (they stay within the padded row). */
#define PREP_AVX2P                                                                                         \
    const __m256i piota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);                                       \
    const __m256 pq = _mm256_set1_ps(qx);                                                                  \
    const __m256 pdx0 = _mm256_sub_ps(_mm256_loadu_ps(xp + a), pq);                                        \
    const __m256 pdx1 = b - a > 8 ? _mm256_sub_ps(_mm256_loadu_ps(xp + a + 8), pq) : _mm256_setzero_ps(); \
    const __m256 pd0 = _mm256_mul_ps(pdx0, pdx0), pd1 = _mm256_mul_ps(pdx1, pdx1);                        \
    const __m256 pm0 = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(b - a), piota));           \
    const __m256 pm1 = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(b - a - 8), piota));       \
    const __m256 pa1 = _mm256_set1_ps(t[0]), pb1 = _mm256_set1_ps(t[1]), pa2 = _mm256_set1_ps(t[2]);       \
    const __m256 pb2 = _mm256_set1_ps(t[3]);                                                               \
    const int two = b - a > 8;
#define ROWP_AVX2(row, xp_, a_, b_, qx_, dyz2, t_) rowp2_avx2((row) + a, two, pd0, pd1, pm0, pm1, dyz2, pa1, pb1, pa2, pb2)
__attribute__((target("avx2"))) INLINE void rowp_step_avx2(float *row, __m256 dx2, __m256 m, __m256 vd, __m256 a1,
                                                           __m256 b1, __m256 a2, __m256 b2)
{
    const __m256 s = _mm256_add_ps(dx2, vd);
    const __m256 l = _mm256_max_ps(_mm256_sub_ps(a1, _mm256_mul_ps(b1, s)), _mm256_sub_ps(a2, _mm256_mul_ps(b2, s)));
    _mm256_storeu_ps(row, _mm256_add_ps(_mm256_loadu_ps(row), _mm256_and_ps(m, _mm256_max_ps(l, _mm256_setzero_ps()))));
}
__attribute__((target("avx2"))) INLINE void rowp2_avx2(float *row, int two, __m256 d0, __m256 d1, __m256 m0, __m256 m1,
                                                       float dyz2, __m256 a1, __m256 b1, __m256 a2, __m256 b2)
{
    const __m256 vd = _mm256_set1_ps(dyz2);
    rowp_step_avx2(row, d0, m0, vd, a1, b1, a2, b2);
    if (two) rowp_step_avx2(row + 8, d1, m1, vd, a1, b1, a2, b2);
}

/* AVX-512 partial rows in one step: a window is at most 2 K + 1 <= 15
 * nodes (PARTIAL_BODY), so one masked step covers it (masked loads: a window
 * may end within 16 lanes of its row's end), and its mask and (xp - qx)^2
 * are the same on every row of a particle: computed once per particle
 * (PREP_AVX512). Fused multiply-adds: the bound of docs/culling.md, 3, holds for one
 * rounding or two. */
#define PREP_AVX512                                                                                        \
    const __mmask16 pm = (__mmask16)((1u << (b - a)) - 1u);                                                \
    const __m512 pdx = _mm512_sub_ps(_mm512_maskz_loadu_ps(pm, xp + a), _mm512_set1_ps(qx));               \
    const __m512 pdx2 = _mm512_mul_ps(pdx, pdx);                                                           \
    const __m512 pa1 = _mm512_set1_ps(t[0]), pb1 = _mm512_set1_ps(t[1]), pa2 = _mm512_set1_ps(t[2]);       \
    const __m512 pb2 = _mm512_set1_ps(t[3]);
#define ROWP1_AVX512(row, xp_, a_, b_, qx_, dyz2, t_) rowp1_avx512((row) + a, pm, pdx2, dyz2, pa1, pb1, pa2, pb2)
__attribute__((target("avx512f"))) INLINE void rowp1_avx512(float *row, __mmask16 m, __m512 dx2, float dyz2, __m512 a1,
                                                            __m512 b1, __m512 a2, __m512 b2)
{
    const __m512 s = _mm512_add_ps(dx2, _mm512_set1_ps(dyz2));
    const __m512 l = _mm512_max_ps(_mm512_fnmadd_ps(b1, s, a1), _mm512_fnmadd_ps(b2, s, a2));
    _mm512_mask_storeu_ps(row, m, _mm512_add_ps(_mm512_maskz_loadu_ps(m, row), _mm512_max_ps(l, _mm512_setzero_ps())));
}

static void sample_sse2(SAMPLE_ARGS) { SAMPLE_BODY(ROWS_ONE(row_sse2, 0), 0, ) }
static void sample_sse2_span(SAMPLE_ARGS) { SAMPLE_BODY(ROWS_ONE(row_sse2, 1), 1, ) }
static void partial_sse2(SAMPLE_ARGS) { PARTIAL_BODY(rowp_sse2, ) }
__attribute__((target("avx2"))) static void sample_avx2(SAMPLE_ARGS) { YPAD_AVX2 SAMPLE_BODY(ROWS_AVX2(0), 0, ) }
__attribute__((target("avx2"))) static void sample_avx2_span(SAMPLE_ARGS) { YPAD_AVX2 SAMPLE_BODY(ROWS_AVX2(1), 1, ) }
__attribute__((target("avx2"))) static void partial_avx2(SAMPLE_ARGS) { PARTIAL_BODY(ROWP_AVX2, PREP_AVX2P) }
__attribute__((target("avx512f"))) static void sample_avx512(SAMPLE_ARGS) { SAMPLE_BODY(ROWS_ONE(ROWD_AVX512, 0), 0, SPREP_AVX512) }
__attribute__((target("avx512f"))) static void sample_avx512_span(SAMPLE_ARGS) { SAMPLE_BODY(ROWS_ONE(ROWD_AVX512, 1), 1, SPREP_AVX512) }
__attribute__((target("avx512f"))) static void partial_avx512(SAMPLE_ARGS)
{
    PARTIAL_BODY(ROWP1_AVX512, PREP_AVX512)
}

typedef void (*sample_fn)(SAMPLE_ARGS);
/* per level of cpu.h: every node, spans, partial sums */
static const sample_fn chosen[4][3] = {
    {sample_c, sample_c_span, partial_c},
    {sample_sse2, sample_sse2_span, partial_sse2},
    {sample_avx2, sample_avx2_span, partial_avx2},
    {sample_avx512, sample_avx512_span, partial_avx512},
};

void jm_sph_sample(SAMPLE_ARGS)
{
    chosen[jm_cpu_level()][span != NULL](g, c, hood, x, y, z, n, span, pad);
}

void jm_sph_partial(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y,
                    const float *z, int n, float *out)
{
    chosen[jm_cpu_level()][2](g, c, hood, x, y, z, n, NULL, out);
}
#else
void jm_sph_sample(SAMPLE_ARGS)
{
    if (span) sample_c_span(g, c, hood, x, y, z, n, span, pad);
    else sample_c(g, c, hood, x, y, z, n, span, pad);
}

void jm_sph_partial(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y,
                    const float *z, int n, float *out)
{
    partial_c(g, c, hood, x, y, z, n, NULL, out);
}
#endif
