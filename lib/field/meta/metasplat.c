/* metasplat.c - the metasphere sampled on a block's nodes: every ball and half-neck splatted onto the node rows it reaches, rows no piece reaches left unwritten. */
#include "field/meta/metasplat.h"
#include "core/cpu.h"
#include <math.h>
#include <string.h>

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])

/* Both pieces are splatted in runs of 4 nodes (AVX2: 8) from the start of
 * their span (the last run shifted back to end at the row's end; n >= 9),
 * the nodes of a run past the span masked: beyond a ball's reach the ball
 * is under the floor and beyond a half-neck's box the neck under its own
 * ball, but only to rounding (at a neck's end, across its axis, the two are
 * equal), so an unmasked run's width would decide a few ties. Every path
 * does the same float operations in the same order: the same bits. */
#ifdef __SSE2__
#include <emmintrin.h>
#define HAVE_SPLAT4 1
typedef __m128 vf;
#define V1(x) _mm_set1_ps(x)
#define VLD(p) _mm_loadu_ps(p)
#define VADD _mm_add_ps
#define VSUB _mm_sub_ps
#define VMUL _mm_mul_ps
#define VSQRT _mm_sqrt_ps
#define VMAX0(x) _mm_max_ps(x, _mm_setzero_ps()) /* x > 0 ? x : 0 (NaN-free here) */
/* row, wrow = v, id where v > row, for the nodes a .. a + 3 within [i0, i1) */
static inline __attribute__((always_inline)) void keep_max(float *row, uint32_t *wrow, vf v, uint32_t id, int a,
                                                           int i0, int i1)
{
    const __m128i k = _mm_add_epi32(_mm_set1_epi32(a), _mm_setr_epi32(0, 1, 2, 3));
    const __m128 in = _mm_castsi128_ps(
        _mm_and_si128(_mm_cmpgt_epi32(k, _mm_set1_epi32(i0 - 1)), _mm_cmplt_epi32(k, _mm_set1_epi32(i1))));
    vf old = _mm_loadu_ps(row), m = _mm_and_ps(_mm_cmpgt_ps(v, old), in);
    _mm_storeu_ps(row, _mm_or_ps(_mm_and_ps(m, v), _mm_andnot_ps(m, old)));
    __m128i w = _mm_loadu_si128((const __m128i *)wrow), mi = _mm_castps_si128(m);
    __m128i idv = _mm_set1_epi32((int)id);
    _mm_storeu_si128((__m128i *)wrow, _mm_or_si128(_mm_and_si128(mi, idv), _mm_andnot_si128(mi, w)));
}
static inline __attribute__((always_inline)) void ball_run4(float *row, uint32_t *wrow, const float *x, float qx,
                                                            float dyz2, float inv_r, uint32_t id, int a, int i0, int i1)
{
    vf dx = VSUB(VLD(x), V1(qx));
    vf v = VSUB(V1(1.0f), VMUL(VSQRT(VADD(VMUL(dx, dx), V1(dyz2))), V1(inv_r)));
    keep_max(row, wrow, v, id, a, i0, i1);
}
static inline __attribute__((always_inline)) void neck_run4(float *row, uint32_t *wrow, const float *x, float qx,
                                                            float u0, float syz, float wyz2, float half, float inv_r,
                                                            float floor_v, uint32_t id, int a, int i0, int i1)
{
    vf wx = VSUB(VLD(x), V1(qx));
    vf s = VADD(VMUL(wx, V1(u0)), V1(syz));
    vf q2 = VSUB(VADD(VMUL(wx, wx), V1(wyz2)), VMUL(s, s));
    vf t = VMUL(s, V1(inv_r)), t2 = VMUL(t, t);
    /* jm_cos_quarter, term by term */
    vf cs = VSUB(V1(1.0f / 40320), VMUL(t2, V1(1.0f / 3628800)));
    cs = VADD(V1(-1.0f / 720), VMUL(t2, cs));
    cs = VADD(V1(1.0f / 24), VMUL(t2, cs));
    cs = VADD(V1(-0.5f), VMUL(t2, cs));
    cs = VADD(V1(1.0f), VMUL(t2, cs));
    vf v = VSUB(cs, VMUL(VSQRT(VMAX0(q2)), V1(inv_r)));
    vf ok = _mm_and_ps(_mm_cmpge_ps(s, _mm_setzero_ps()), _mm_cmple_ps(s, V1(half)));
    v = _mm_or_ps(_mm_and_ps(ok, v), _mm_andnot_ps(ok, V1(floor_v)));
    keep_max(row, wrow, v, id, a, i0, i1);
}
#endif
/* the same in plain C */
static inline void keep_max_c(float *row, uint32_t *wrow, const float *v, uint32_t id, int a, int i0, int i1)
{
    for (int l = 0; l < 4; l++) {
        int m = v[l] > row[l] && a + l >= i0 && a + l < i1;
        row[l] = m ? v[l] : row[l];
        wrow[l] = m ? id : wrow[l];
    }
}
static inline void ball_run4c(float *row, uint32_t *wrow, const float *x, float qx, float dyz2, float inv_r, uint32_t id,
                              int a, int i0, int i1)
{
    float v[4];
    for (int l = 0; l < 4; l++) {
        float dx = x[l] - qx;
        v[l] = 1.0f - sqrtf(dx * dx + dyz2) * inv_r;
    }
    keep_max_c(row, wrow, v, id, a, i0, i1);
}
static inline void neck_run4c(float *row, uint32_t *wrow, const float *x, float qx, float u0, float syz, float wyz2,
                              float half, float inv_r, float floor_v, uint32_t id, int a, int i0, int i1)
{
    float v[4];
    for (int l = 0; l < 4; l++) {
        float wx = x[l] - qx;
        float s = wx * u0 + syz;
        float q2 = wx * wx + wyz2 - s * s;
        float t = jm_cos_quarter(s * inv_r) - sqrtf(q2 > 0.0f ? q2 : 0.0f) * inv_r;
        v[l] = s >= 0.0f && s <= half ? t : floor_v;
    }
    keep_max_c(row, wrow, v, id, a, i0, i1);
}

/* a row no piece has reached yet: at the floor, no winner */
static inline void floor_row(float *row, uint32_t *wrow, int n, float floor_v)
{
    for (int i = 0; i < n; i++) {
        row[i] = floor_v;
        wrow[i] = UINT32_MAX;
    }
}

/* Row (k, j) reached by a piece for the first time: it and the rows next
 * to it not yet written go to the floor (a cube reads its four rows) */
static void first_touch(float *f, uint32_t *win, uint8_t *rows, int n, int k, int j, float floor_v)
{
    for (int dk = k > 0 ? -1 : 0; dk <= (k < n - 1 ? 1 : 0); dk++)
        for (int dj = j > 0 ? -1 : 0; dj <= (j < n - 1 ? 1 : 0); dj++) {
            const size_t r = (size_t)(k + dk) * n + (size_t)(j + dj);
            if (rows[r] != JM_ROW_UNSET) continue;
            floor_row(f + r * n, win + r * n, n, floor_v);
            rows[r] = JM_ROW_FLOOR;
        }
    rows[(size_t)k * n + j] = JM_ROW_SPLAT;
}

/* the splat over every piece, in runs of 4: SSE2 (any x86-64) and plain C */
#ifdef HAVE_SPLAT4
#define MS_W 4
#define MS_NAME splat4
#define MS_ATTR
#define MS_BALL ball_run4
#define MS_NECK neck_run4
#include "field/meta/metasplat_rows.h"
#endif
#define MS_W 4
#define MS_NAME splat4c
#define MS_ATTR
#define MS_BALL ball_run4c
#define MS_NECK neck_run4c
#include "field/meta/metasplat_rows.h"

/* where the level is AVX2 or more (cpu.h) */
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define HAVE_SPLAT8 1
#define AVX2 __attribute__((target("avx2")))
/* the runs of 4 above on 8 lanes: the same operations lane by lane */
AVX2 static inline __attribute__((always_inline)) void keep_max8(float *row, uint32_t *wrow, __m256 v, uint32_t id,
                                                                 int a, int i0, int i1)
{
    const __m256i k = _mm256_add_epi32(_mm256_set1_epi32(a), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256 in = _mm256_castsi256_ps(_mm256_and_si256(_mm256_cmpgt_epi32(k, _mm256_set1_epi32(i0 - 1)),
                                                           _mm256_cmpgt_epi32(_mm256_set1_epi32(i1), k)));
    const __m256 old = _mm256_loadu_ps(row), m = _mm256_and_ps(_mm256_cmp_ps(v, old, _CMP_GT_OQ), in);
    _mm256_storeu_ps(row, _mm256_blendv_ps(old, v, m));
    const __m256 w = _mm256_loadu_ps((const float *)wrow);
    _mm256_storeu_ps((float *)wrow, _mm256_blendv_ps(w, _mm256_castsi256_ps(_mm256_set1_epi32((int)id)), m));
}
AVX2 static inline __attribute__((always_inline)) void ball_run8(float *row, uint32_t *wrow, const float *x, float qx,
                                                                 float dyz2, float inv_r, uint32_t id, int a, int i0,
                                                                 int i1)
{
    const __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(x), _mm256_set1_ps(qx));
    const __m256 d = _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_set1_ps(dyz2)));
    keep_max8(row, wrow, _mm256_sub_ps(_mm256_set1_ps(1.0f), _mm256_mul_ps(d, _mm256_set1_ps(inv_r))), id, a, i0, i1);
}
AVX2 static inline __attribute__((always_inline)) void neck_run8(float *row, uint32_t *wrow, const float *x, float qx,
                                                                 float u0, float syz, float wyz2, float half,
                                                                 float inv_r, float floor_v, uint32_t id, int a,
                                                                 int i0, int i1)
{
#define B8 _mm256_set1_ps
    const __m256 wx = _mm256_sub_ps(_mm256_loadu_ps(x), B8(qx));
    const __m256 s = _mm256_add_ps(_mm256_mul_ps(wx, B8(u0)), B8(syz));
    const __m256 q2 = _mm256_sub_ps(_mm256_add_ps(_mm256_mul_ps(wx, wx), B8(wyz2)), _mm256_mul_ps(s, s));
    const __m256 t = _mm256_mul_ps(s, B8(inv_r)), t2 = _mm256_mul_ps(t, t);
    __m256 cs = _mm256_sub_ps(B8(1.0f / 40320), _mm256_mul_ps(t2, B8(1.0f / 3628800)));
    cs = _mm256_add_ps(B8(-1.0f / 720), _mm256_mul_ps(t2, cs));
    cs = _mm256_add_ps(B8(1.0f / 24), _mm256_mul_ps(t2, cs));
    cs = _mm256_add_ps(B8(-0.5f), _mm256_mul_ps(t2, cs));
    cs = _mm256_add_ps(B8(1.0f), _mm256_mul_ps(t2, cs));
    __m256 v = _mm256_sub_ps(cs, _mm256_mul_ps(_mm256_sqrt_ps(_mm256_max_ps(q2, _mm256_setzero_ps())), B8(inv_r)));
    const __m256 ok = _mm256_and_ps(_mm256_cmp_ps(s, _mm256_setzero_ps(), _CMP_GE_OQ), _mm256_cmp_ps(s, B8(half), _CMP_LE_OQ));
    v = _mm256_blendv_ps(B8(floor_v), v, ok);
#undef B8
    keep_max8(row, wrow, v, id, a, i0, i1);
}
#define MS_W 8
#define MS_NAME splat8
#define MS_ATTR AVX2
#define MS_BALL ball_run8
#define MS_NECK neck_run8
#include "field/meta/metasplat_rows.h"
#endif

void jm_meta_sample(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y,
                    const float *z, int n, float *f, uint32_t *win, uint8_t *rows)
{
    memset(rows, JM_ROW_UNSET, (size_t)n * n);
    const int level = jm_cpu_level();
#ifdef HAVE_SPLAT8
    if (level >= JM_CPU_AVX2) {
        splat8(g, c, hood, x, y, z, n, f, win, rows);
        return;
    }
#endif
#ifdef HAVE_SPLAT4
    if (level >= JM_CPU_SSE2) {
        splat4(g, c, hood, x, y, z, n, f, win, rows);
        return;
    }
#endif
    splat4c(g, c, hood, x, y, z, n, f, win, rows);
}
