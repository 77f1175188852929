/* aniso_splat.c - the anisotropic SPH field on a block: kernels splatted row by row (AVX-512/AVX2/SSE2/C), every node, spans or partial sums. */
#include "field/aniso/aniso_splat.h"
#include "field/sph/cull.h"
#include "core/round8.h"
#include "core/cpu.h"
#include <math.h>
#include <string.h>

#define AN(g, i) (&(g)->an[JM_AN_STRIDE * (size_t)(i)])
#ifndef JM_AN_CULL_BREAK
#define JM_AN_CULL_BREAK 0
#endif
#define INLINE static inline __attribute__((always_inline))

/* row[i] += amp w(sqrt(max((m00 dx + 2B) dx + C, 0))), dx = xp[i] - cx, for
 * i in [a, b). The full rows take b - a a multiple of 8 (lanes past the
 * chord add exact zeros); the partial rows (rowp) add +0 on the lanes of
 * their last step past b. Plain C, SSE2, AVX2 and AVX-512 do the same IEEE
 * operations in the same order on each lane. */
#define AN_ROW_ARGS float *restrict row, const float *restrict xp, int a, int b, float cx, float m00, float B2, float C, float amp
INLINE void an_row_c(AN_ROW_ARGS)
{
    for (int i = a; i < b; i++) {
        const float dx = xp[i] - cx;
        float q2 = (m00 * dx + B2) * dx + C;
        q2 = q2 > 0.0f ? q2 : 0.0f;
        const float q = sqrtf(q2);
        float A = 2.0f - q, Bq = 1.0f - q;
        A = A > 0.0f ? A : 0.0f;
        Bq = Bq > 0.0f ? Bq : 0.0f;
        row[i] = row[i] + amp * (0.25f * A * A * A - Bq * Bq * Bq);
    }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define AN_SIMD 1

/* the term of 4, 8 or 16 lanes: V the vector type, P its intrinsics' prefix */
#define AN_TERM(V, P, x)                                                                              \
    ({                                                                                                \
        V dx_ = P##_sub_ps(x, P##_set1_ps(cx));                                                       \
        V q2_ = P##_add_ps(P##_mul_ps(P##_add_ps(P##_mul_ps(P##_set1_ps(m00), dx_), P##_set1_ps(B2)), dx_), \
                           P##_set1_ps(C));                                                           \
        V q_ = P##_sqrt_ps(P##_max_ps(q2_, P##_setzero_ps()));                                        \
        V A_ = P##_max_ps(P##_sub_ps(P##_set1_ps(2.0f), q_), P##_setzero_ps());                       \
        V B_ = P##_max_ps(P##_sub_ps(P##_set1_ps(1.0f), q_), P##_setzero_ps());                       \
        V w_ = P##_sub_ps(P##_mul_ps(P##_mul_ps(P##_mul_ps(P##_set1_ps(0.25f), A_), A_), A_),        \
                          P##_mul_ps(P##_mul_ps(B_, B_), B_));                                        \
        P##_mul_ps(P##_set1_ps(amp), w_);                                                             \
    })

INLINE void an_row_sse2(AN_ROW_ARGS)
{
    for (int i = a; i < b; i += 4)
        _mm_storeu_ps(row + i, _mm_add_ps(_mm_loadu_ps(row + i), AN_TERM(__m128, _mm, _mm_loadu_ps(xp + i))));
}

__attribute__((target("avx2"))) INLINE void an_row_avx2(AN_ROW_ARGS)
{
    for (int i = a; i < b; i += 8)
        _mm256_storeu_ps(row + i,
                         _mm256_add_ps(_mm256_loadu_ps(row + i), AN_TERM(__m256, _mm256, _mm256_loadu_ps(xp + i))));
}

/* runs of 16 lanes, then a last run of 8 in AVX */
__attribute__((target("avx512f"))) INLINE void an_row_avx512(AN_ROW_ARGS)
{
    int i = a;
    for (; i + 16 <= b; i += 16)
        _mm512_storeu_ps(row + i,
                         _mm512_add_ps(_mm512_loadu_ps(row + i), AN_TERM(__m512, _mm512, _mm512_loadu_ps(xp + i))));
    if (i < b)
        _mm256_storeu_ps(row + i,
                         _mm256_add_ps(_mm256_loadu_ps(row + i), AN_TERM(__m256, _mm256, _mm256_loadu_ps(xp + i))));
}

INLINE void an_rowp_sse2(AN_ROW_ARGS)
{
    const __m128i vb = _mm_set1_epi32(b), iota = _mm_setr_epi32(0, 1, 2, 3);
    for (int i = a; i < b; i += 4) {
        __m128 m = _mm_castsi128_ps(_mm_cmplt_epi32(_mm_add_epi32(_mm_set1_epi32(i), iota), vb));
        __m128 t = AN_TERM(__m128, _mm, _mm_loadu_ps(xp + i));
        _mm_storeu_ps(row + i, _mm_add_ps(_mm_loadu_ps(row + i), _mm_and_ps(m, t)));
    }
}

__attribute__((target("avx2"))) INLINE void an_rowp_avx2(AN_ROW_ARGS)
{
    const __m256i vb = _mm256_set1_epi32(b), iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    for (int i = a; i < b; i += 8) {
        __m256 m = _mm256_castsi256_ps(_mm256_cmpgt_epi32(vb, _mm256_add_epi32(_mm256_set1_epi32(i), iota)));
        __m256 t = AN_TERM(__m256, _mm256, _mm256_loadu_ps(xp + i));
        _mm256_storeu_ps(row + i, _mm256_add_ps(_mm256_loadu_ps(row + i), _mm256_and_ps(m, t)));
    }
}

__attribute__((target("avx512f"))) INLINE void an_rowp_avx512(AN_ROW_ARGS)
{
    for (int i = a; i < b; i += 16) {
        const __mmask16 m = b - i >= 16 ? (__mmask16)0xFFFF : (__mmask16)((1u << (b - i)) - 1u);
        __m512 t = AN_TERM(__m512, _mm512, _mm512_maskz_loadu_ps(m, xp + i));
        _mm512_mask_storeu_ps(row + i, m, _mm512_add_ps(_mm512_maskz_loadu_ps(m, row + i), t));
    }
}
#endif

typedef void (*an_row_fn)(AN_ROW_ARGS);

#define AN_SAMPLE_ARGS                                                                                       \
    const jm_grid *g, const jm_config *c, const jm_an_cand *cand, const float *x, const float *y, const float *z, \
        int n, const uint8_t *span, float *pad

/* The rows of one slab: for r < nr (row jj = j0 + r, dy = y[jj] - cy) the
 * row's B and C (q^2 = m00 dx^2 + 2 B dx + C along it) and the run of nodes
 * [ia[r], ib[r]) to splat (empty where there is none). The chord where q^2 < lim (4, or the inner ellipsoid's 4 rho^2
 * for the partial sums) comes from the spacing, with slack nodes of slack
 * each side (0.01 for the full chord: its ends are good to about 1e-5 nodes
 * unless the row barely touches the ellipsoid, where w is under 1e-12
 * anyway; 0 for the inner one), clipped to [0, n). AN_FULL and AN_SPAN
 * round the run up to whole steps of 8 from the chord's start; AN_SPAN then
 * keeps the part over the row's span (spr: 2 bytes a row from row j0), in
 * whole steps of 8 from there (so the run's lanes over a span are computed
 * as in AN_FULL, and none past the run is). A branch-free loop the compiler
 * vectorizes; each lane does the operations of one row alone, so the same
 * bits as row by row. */
typedef struct an_slab {
    float cy, m00, m01, m11, Bz, Cy, Cz, lim, ccx, sc, slack;
} an_slab;
enum { AN_FULL, AN_SPAN, AN_PART };
#define AN_ROWS_ARGS                                                                                          \
    const an_slab *s, const float *restrict y, int j0, int nr, int n, const int mode, const uint8_t *spr,     \
        float *restrict Bv, float *restrict Cv, int *restrict ia, int *restrict ib
INLINE void an_rows(AN_ROWS_ARGS)
{
    for (int r = 0; r < nr; r++) {
        const float dy = y[j0 + r] - s->cy;
        const float B = s->m01 * dy + s->Bz, C = (s->m11 * dy + s->Cy) * dy + s->Cz;
        const float disc = B * B - s->m00 * C + s->lim;
        const int ok = disc > 0.0f;
        const float sq = sqrtf(ok ? disc : 0.0f);
        const float lo = ok ? s->ccx - (B + sq) * s->sc - s->slack : 0.0f;
        const float hi = ok ? s->ccx + (sq - B) * s->sc + s->slack : -1.0f;
        int i0 = iceil(lo), i1 = ifloor(hi) + 1;
        i0 = i0 > 0 ? i0 : 0;
        i1 = i1 < n ? i1 : n;
        int keep = i0 < i1, e = i1;
        if (mode != AN_PART) e = i0 + ((i1 - i0 + 7) & ~7);
        if (mode == AN_SPAN) {
            const int a = i0 > spr[2 * r] ? i0 : spr[2 * r], b = e < spr[2 * r + 1] ? e : spr[2 * r + 1];
            keep = keep && a < b;
            i0 += (a - i0) & ~7;
            e = i0 + ((b - i0 + 7) & ~7);
        }
        Bv[r] = B;
        Cv[r] = C;
        ia[r] = i0;
        ib[r] = keep ? e : i0;
    }
}

typedef void (*an_rows_fn)(AN_ROWS_ARGS);

#ifdef AN_SIMD
/* an_rows on 8 rows at a time, in AVX2 (the compiler leaves the loop above
 * scalar there): the same operations on each lane, integers included
 * (round8.h); yp holds y continued past n and spr 16 bytes past its last
 * row (JM_CULL_SPAN_BYTES): the rows past nr are computed and ignored */
__attribute__((target("avx2"))) INLINE void an_rows_avx2(AN_ROWS_ARGS)
{
    const float *yp = y;
    const __m256 cy = _mm256_set1_ps(s->cy), m00 = _mm256_set1_ps(s->m00), m01 = _mm256_set1_ps(s->m01);
    const __m256 m11 = _mm256_set1_ps(s->m11), Bz = _mm256_set1_ps(s->Bz), Cy = _mm256_set1_ps(s->Cy);
    const __m256 Cz = _mm256_set1_ps(s->Cz), lim = _mm256_set1_ps(s->lim), ccx = _mm256_set1_ps(s->ccx);
    const __m256 sc = _mm256_set1_ps(s->sc), slack = _mm256_set1_ps(s->slack), zero = _mm256_setzero_ps();
    const __m256i vn = _mm256_set1_epi32(n), izero = _mm256_setzero_si256(), one = _mm256_set1_epi32(1);
    const __m256i seven = _mm256_set1_epi32(7), not7 = _mm256_set1_epi32(~7);
    const __m128i split = _mm_setr_epi8(0, 2, 4, 6, 8, 10, 12, 14, 1, 3, 5, 7, 9, 11, 13, 15);
    for (int r = 0; r < nr; r += 8) {
        const __m256 dy = _mm256_sub_ps(_mm256_loadu_ps(yp + j0 + r), cy);
        const __m256 B = _mm256_add_ps(_mm256_mul_ps(m01, dy), Bz);
        const __m256 C = _mm256_add_ps(_mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(m11, dy), Cy), dy), Cz);
        const __m256 disc = _mm256_add_ps(_mm256_sub_ps(_mm256_mul_ps(B, B), _mm256_mul_ps(m00, C)), lim);
        const __m256 ok = _mm256_cmp_ps(disc, zero, _CMP_GT_OQ);
        const __m256 sq = _mm256_sqrt_ps(_mm256_and_ps(ok, disc));
        __m256 lo = _mm256_sub_ps(_mm256_sub_ps(ccx, _mm256_mul_ps(_mm256_add_ps(B, sq), sc)), slack);
        __m256 hi = _mm256_add_ps(_mm256_add_ps(ccx, _mm256_mul_ps(_mm256_sub_ps(sq, B), sc)), slack);
        lo = _mm256_and_ps(ok, lo);
        hi = _mm256_blendv_ps(_mm256_set1_ps(-1.0f), hi, ok);
        /* iceil and ifloor (field.h), lane by lane (round8.h) */
        __m256i i0 = jm_iceil8(lo), i1 = jm_ifloor8(hi);
        i0 = _mm256_max_epi32(i0, izero);
        i1 = _mm256_min_epi32(_mm256_add_epi32(i1, one), vn);
        __m256i e = i1;
        if (mode != AN_PART)
            e = _mm256_add_epi32(i0, _mm256_and_si256(_mm256_add_epi32(_mm256_sub_epi32(i1, i0), seven), not7));
        if (mode == AN_SPAN) {
            const __m128i pr = _mm_shuffle_epi8(_mm_loadu_si128((const __m128i *)(spr + 2 * (size_t)r)), split);
            const __m256i s0 = _mm256_cvtepu8_epi32(pr), s1 = _mm256_cvtepu8_epi32(_mm_srli_si128(pr, 8));
            const __m256i a = _mm256_max_epi32(i0, s0), b = _mm256_min_epi32(e, s1);
            const __m256i keep = _mm256_and_si256(_mm256_cmpgt_epi32(i1, i0), _mm256_cmpgt_epi32(b, a));
            i0 = _mm256_add_epi32(i0, _mm256_and_si256(_mm256_sub_epi32(a, i0), not7));
            e = _mm256_add_epi32(i0, _mm256_and_si256(_mm256_add_epi32(_mm256_sub_epi32(b, i0), seven), not7));
            e = _mm256_blendv_epi8(i0, e, keep);
        }
        _mm256_storeu_ps(Bv + r, B);
        _mm256_storeu_ps(Cv + r, C);
        _mm256_storeu_si256((__m256i *)(ia + r), i0);
        /* no chord: i1 <= i0 gives e <= i0 in every mode, an empty run */
        _mm256_storeu_si256((__m256i *)(ib + r), e);
    }
}
#endif

/* The sampling loop, inlined into each variant with its row function and
 * mode: AN_FULL every node; AN_SPAN the same runs cut to the spans, in whole
 * steps of 8 from the run's start (so the run's lanes over a span are
 * computed as in AN_FULL, and none past the run is); AN_PART the partial
 * sums: the same slabs, rows and row terms, on the rows that cut the inner
 * ellipsoid q < 2 JM_AN_PART_REACH only its chord there, which lies within
 * the full chord (docs/culling.md, A.3). */
INLINE void an_sample(AN_SAMPLE_ARGS, an_row_fn row_fn, const int mode, an_rows_fn rows_fn)
{
    const int ns = JM_PAD(n);
    const float inv_h = c->inv_h, h = c->h;
    const float rho2 = JM_AN_PART_REACH * JM_AN_PART_REACH, inner4 = 4.0f * rho2;
    float xp[JM_PAD_MAX], yp[JM_PAD_MAX], Bv[JM_PAD_MAX], Cv[JM_PAD_MAX];
    int ia[JM_PAD_MAX], ib[JM_PAD_MAX];
    for (int i = 0; i < ns; i++) xp[i] = i < n ? x[i] : x[n - 1] + (float)(i - n + 1) * h;
    for (int i = 0; i < ns; i++) yp[i] = i < n ? y[i] : y[n - 1] + (float)(i - n + 1) * h;
    memset(pad, 0, (size_t)n * n * ns * sizeof *pad);
    jm_span_box sb;
    if (mode == AN_SPAN) {
        jm_span_box_of(span, n, &sb);
        if (sb.k0 >= sb.k1) return;
    }
    for (size_t ci = 0; ci < cand->n; ci++) {
        const float *a = AN(g, cand->idx[ci]);
        const float cx = a[0], cy = a[1], cz = a[2];
        if (cx + a[10] < x[0] || cx - a[10] > x[n - 1] || cy + a[11] < y[0] || cy - a[11] > y[n - 1] ||
            cz + a[12] < z[0] || cz - a[12] > z[n - 1])
            continue;
        /* spans: a kernel whose box, a node wider, misses the spans' nodes
         * adds to no span (its chords lie within its box and a hundredth of
         * a node) */
        if (mode == AN_SPAN && (cx + a[10] + h < x[sb.i0] || cx - a[10] - h > x[sb.i1 - 1])) continue;
        const float m00 = a[3], m01 = a[4], m02 = a[5], m11 = a[6], m12 = a[7], m22 = a[8];
        /* tests/t_aniso_cull_broken.sh: partial sums above the full ones
         * must fail test_aniso_cull */
        const float amp = JM_AN_CULL_BREAK == 2 && mode == AN_PART ? 1.4f * a[9] : a[9];
        /* in a slab dz the rows dy cut the ellipsoid where
         * Py dy^2 + 2 Qy dz dy + Rz dz^2 < 4 (x eliminated) */
        const float i00 = 1.0f / m00, sc = inv_h * i00, four00 = 4.0f * m00;
        const float Py = m11 - m01 * m01 * i00, Qy = m12 - m01 * m02 * i00, Rz = m22 - m02 * m02 * i00;
        const float iPy = 1.0f / Py, ccx = (cx - x[0]) * inv_h, ccy = (cy - y[0]) * inv_h;
        an_slab sl = {cy, m00, m01, m11, 0.0f, 0.0f, 0.0f, four00, ccx, sc, 0.01f};
        if (mode == AN_PART) {
            sl.lim = four00 * rho2;
            sl.slack = 0.0f;
        }
        int k0, k1;
        node_span(z, n, inv_h, cz - a[12], cz + a[12], &k0, &k1);
        if (mode == AN_SPAN) {
            k0 = k0 > sb.k0 ? k0 : sb.k0;
            k1 = k1 < sb.k1 ? k1 : sb.k1;
        }
        for (int kk = k0; kk < k1; kk++) {
            const float dz = z[kk] - cz;
            const float qd = Qy * dz, dy_disc = qd * qd - Py * (Rz * dz * dz - 4.0f);
            if (!(dy_disc > 0.0f)) continue;
            const float sy = sqrtf(dy_disc);
            /* the rows, as the chords: indices from the spacing, a
             * hundredth of a node of slack */
            int j0 = iceil(ccy + (-qd - sy) * iPy * inv_h - 0.01f), j1 = ifloor(ccy + (sy - qd) * iPy * inv_h + 0.01f) + 1;
            j0 = j0 > 0 ? j0 : 0;
            j1 = j1 < n ? j1 : n;
            if (mode == AN_PART) {
                /* only the rows cutting the inner ellipsoid */
                const float di = qd * qd - Py * (Rz * dz * dz - inner4);
                if (!(di > 0.0f)) continue;
                const float si = sqrtf(di);
                const int ja = iceil(ccy + (-qd - si) * iPy * inv_h), jb = ifloor(ccy + (si - qd) * iPy * inv_h) + 1;
                j0 = ja > j0 ? ja : j0;
                j1 = jb < j1 ? jb : j1;
            }
            if (mode == AN_SPAN) {
                /* the rows holding a span (each row's terms are its own) */
                j0 = j0 > sb.j0[kk] ? j0 : sb.j0[kk];
                j1 = j1 < sb.j1[kk] ? j1 : sb.j1[kk];
            }
            if (j0 >= j1) continue;
            sl.Bz = m02 * dz;
            sl.Cy = 2.0f * m12 * dz;
            sl.Cz = m22 * dz * dz;
            rows_fn(&sl, yp, j0, j1 - j0, n, mode, mode == AN_SPAN ? span + 2 * ((size_t)kk * n + j0) : NULL, Bv,
                    Cv, ia, ib);
            float *slab = pad + (size_t)kk * n * ns;
            for (int r = 0; r < j1 - j0; r++)
                if (ia[r] < ib[r])
                    row_fn(slab + (size_t)(j0 + r) * ns, xp, ia[r], ib[r], cx, m00, 2.0f * Bv[r], Cv[r], amp);
        }
    }
}

static void an_sample_c(AN_SAMPLE_ARGS) { an_sample(g, c, cand, x, y, z, n, span, pad, an_row_c, AN_FULL, an_rows); }
static void an_span_c(AN_SAMPLE_ARGS) { an_sample(g, c, cand, x, y, z, n, span, pad, an_row_c, AN_SPAN, an_rows); }
static void an_part_c(AN_SAMPLE_ARGS) { an_sample(g, c, cand, x, y, z, n, span, pad, an_row_c, AN_PART, an_rows); }
#ifdef AN_SIMD
static void an_sample_sse2(AN_SAMPLE_ARGS) { an_sample(g, c, cand, x, y, z, n, span, pad, an_row_sse2, AN_FULL, an_rows); }
static void an_span_sse2(AN_SAMPLE_ARGS) { an_sample(g, c, cand, x, y, z, n, span, pad, an_row_sse2, AN_SPAN, an_rows); }
static void an_part_sse2(AN_SAMPLE_ARGS) { an_sample(g, c, cand, x, y, z, n, span, pad, an_rowp_sse2, AN_PART, an_rows); }
#define AN_VARIANT(NAME, TARGET, ROW, MODE)                                                                 \
    __attribute__((target(TARGET))) static void NAME(AN_SAMPLE_ARGS)                                        \
    {                                                                                                       \
        an_sample(g, c, cand, x, y, z, n, span, pad, ROW, MODE, an_rows_avx2);                                            \
    }
AN_VARIANT(an_sample_avx2, "avx2", an_row_avx2, AN_FULL)
AN_VARIANT(an_span_avx2, "avx2", an_row_avx2, AN_SPAN)
AN_VARIANT(an_part_avx2, "avx2", an_rowp_avx2, AN_PART)
AN_VARIANT(an_sample_avx512, "avx512f", an_row_avx512, AN_FULL)
AN_VARIANT(an_span_avx512, "avx512f", an_row_avx512, AN_SPAN)
AN_VARIANT(an_part_avx512, "avx512f", an_rowp_avx512, AN_PART)
#endif

typedef void (*an_sample_fn)(AN_SAMPLE_ARGS);
/* per level of cpu.h: every node, spans, partial sums */
static const an_sample_fn an_chosen[4][3] = {
    {an_sample_c, an_span_c, an_part_c},
#ifdef AN_SIMD
    {an_sample_sse2, an_span_sse2, an_part_sse2},
    {an_sample_avx2, an_span_avx2, an_part_avx2},
    {an_sample_avx512, an_span_avx512, an_part_avx512},
#endif
};

void jm_aniso_sample(AN_SAMPLE_ARGS)
{
    an_chosen[jm_cpu_level()][span != NULL](g, c, cand, x, y, z, n, span, pad);
}

void jm_aniso_partial(const jm_grid *g, const jm_config *c, const jm_an_cand *cand, const float *x, const float *y,
                      const float *z, int n, float *out)
{
    an_chosen[jm_cpu_level()][2](g, c, cand, x, y, z, n, NULL, out);
}
