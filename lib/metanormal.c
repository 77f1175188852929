/* metanormal.c - metasphere vertex normals blended from every ball and neck within the blend band of each vertex. */
#include "metanormal.h"
#include "cpu.h"
#include <math.h>
#include <string.h>

/* Why every piece: the edge's two pieces (block.c) and the settled set
 * (metavertex.c) know only the pieces that won at a node or beat a vertex.
 * Across a crease, one vertex then blends a piece its neighbour never saw,
 * and the shading steps along the grid (a render at cube r/4 shows the
 * crease as a staircase). Here each piece visits the vertices its box
 * reaches, as in jm_meta_probe, and adds its weighted normal to theirs. */

/* per vertex of capacity: 3 sums, 3 coordinates and 3 sums of a moved
 * one, and its index */
#define PER_VERTEX (9 * sizeof(float) + sizeof(uint32_t))

void jm_mnorm_free(jm_mnorm *m)
{
    jm_free(m->mem, m->visit, m->capvisit * sizeof *m->visit);
    m->visit = NULL;
    m->nvisit = m->capvisit = 0;
    m->visits = 0;
    jm_free(m->mem, m->acc, m->cap * PER_VERTEX);
    m->acc = m->sub = NULL;
    m->moved = NULL;
    m->cap = 0;
}

static int reserve(jm_mnorm *m, size_t n)
{
    if (n <= m->cap) return 1;
    size_t nc = m->cap ? 2 * m->cap : 1024;
    while (nc < n) nc *= 2;
    float *a = jm_alloc(m->mem, nc * PER_VERTEX);
    if (!a) return 0;
    jm_free(m->mem, m->acc, m->cap * PER_VERTEX);
    m->acc = a;
    m->sub = a + 3 * nc;
    m->moved = (uint32_t *)(a + 9 * nc);
    m->cap = nc;
    return 1;
}

/* What every kernel needs: the sorted points (n of them, n >= 8), the
 * sums, the part starts, and the constants. */
typedef struct pass {
    const float *x, *y, *z;
    float *ax, *ay, *az;
    size_t n;
    const uint32_t *ps;
    int np;
    float thr, inv_tau, inv_r;
    float rb2; /* squared: beyond this from its particle a ball is out of the band */
    float *vm; /* the fused pass (jm_meta_normals_probe): the probe's largest values, or NULL */
    float r, rn_probe, rb_probe; /* the probe's reach of a neck from its axis (jm_neck_reach) */
    int clo[3], chi[3]; /* a pass over a few vertices: the parts that hold any */
    jm_mnorm *rec;      /* the fused pass: records its visits here, or NULL */
} pass;

/* the fused pass's visit of a piece, kept for jm_meta_normals_finish (out
 * of memory: it enumerates the pieces again) */
static void record(jm_mnorm *m, const int lo[3], const int hi[3], const float *q, const float *u, float D, float rr2)
{
    if (!m || !m->visits) return;
    if (m->nvisit == m->capvisit) {
        size_t nc = m->capvisit ? 2 * m->capvisit : 256;
        jm_visit *b = jm_realloc(m->mem, m->visit, m->capvisit * sizeof *b, nc * sizeof *b);
        if (!b) {
            m->visits = 0;
            return;
        }
        m->visit = b;
        m->capvisit = nc;
    }
    jm_visit *v = &m->visit[m->nvisit++];
    v->q = q;
    v->u = u;
    v->D = D;
    v->rr2 = rr2;
    memcpy(v->lo, lo, sizeof v->lo);
    memcpy(v->hi, hi, sizeof v->hi);
}

/* The weight of a piece of value v: smoothstep(1 - gap / tau), gap =
 * max(thr - v, 0); 0 (and *ok 0) beyond the band. The SIMD kernels do the
 * same operations lane by lane: the same bits. */
static inline float weight(const pass *P, float v, int *ok)
{
    float g = P->thr - v;
    if (g < 0.0f) g = 0.0f;
    float x = 1.0f - g * P->inv_tau;
    *ok = x > 0.0f;
    return x * x * (3.0f - 2.0f * x);
}

/* Parts lo..hi (per axis) of the sorted points, each vertex once: the
 * parts lo[0]..hi[0] of a row follow one another (x fastest), so their
 * vertices are one range. */
#define FOR_PART_VERTICES(P, lo, hi, s, e, ...)                                                            \
    for (int pk_ = lo[2]; pk_ <= hi[2]; pk_++)                                                           \
        for (int pj_ = lo[1]; pj_ <= hi[1]; pj_++) {                                                     \
            const size_t row_ = ((size_t)pk_ * (P)->np + pj_) * (P)->np;                                 \
            const size_t s = (P)->ps[row_ + lo[0]], e = (P)->ps[row_ + hi[0] + 1];                       \
            __VA_ARGS__                                                                                  \
        }

static void ball_c(const pass *P, const int lo[3], const int hi[3], const float *q)
{
    FOR_PART_VERTICES(P, lo, hi, s, e, {
        for (size_t k = s; k < e; k++) {
            float dx = P->x[k] - q[0], dy = P->y[k] - q[1], dz = P->z[k] - q[2];
            float d2 = dx * dx + dy * dy + dz * dz;
            /* weight 0 there, and below any value the probe keeps: skipped early */
            if (!(d2 < P->rb2)) continue;
            float d = sqrtf(d2);
            const float v = 1.0f - d * P->inv_r;
            if (P->vm && v > P->vm[k]) P->vm[k] = v;
            int ok;
            float w = weight(P, v, &ok);
            if (!ok || !(d > 0.0f)) continue;
            float id = 1.0f / d;
            P->ax[k] += w * (dx * id);
            P->ay[k] += w * (dy * id);
            P->az[k] += w * (dz * id);
        }
    })
}

/* both half-necks of the link from q along u, D long, within rr2 (squared)
 * of its axis */
static void link_c(const pass *P, const int lo[3], const int hi[3], const float *q, const float *u, float D,
                   float rr2, float rrp2)
{
    FOR_PART_VERTICES(P, lo, hi, s0, e, {
        for (size_t k = s0; k < e; k++) {
            float wx = P->x[k] - q[0], wy = P->y[k] - q[1], wz = P->z[k] - q[2];
            float s = wx * u[0] + wy * u[1] + wz * u[2];
            float q2 = wx * wx + wy * wy + wz * wz - s * s;
            if (!(s >= 0.0f && s <= D && q2 < rr2)) continue;
            float sm = D - s, near = s < sm ? s : sm, sg = s <= sm ? 1.0f : -1.0f;
            float t = near * P->inv_r;
            float qq = sqrtf(q2 > 0.0f ? q2 : 0.0f);
            const float v = jm_cos_quarter(t) - qq * P->inv_r;
            if (P->vm && q2 < rrp2 && v > P->vm[k]) P->vm[k] = v;
            int ok;
            float w = weight(P, v, &ok);
            if (!ok || !(qq > 0.0f)) continue;
            /* minus the gradient, times r: away from the axis, tilted
             * along it toward the waist as the neck narrows (jm_prim_eval;
             * a ball's is the unit radial) */
            float sn = sg * jm_sin_quarter(t), iq = 1.0f / qq;
            float ox = sn * u[0] + (wx - s * u[0]) * iq, oy = sn * u[1] + (wy - s * u[1]) * iq,
                  oz = sn * u[2] + (wz - s * u[2]) * iq;
            P->ax[k] += w * ox;
            P->ay[k] += w * oy;
            P->az[k] += w * oz;
        }
    })
}

/* JM_SPLAT_VARIANT (a build option for tests, as splat.c): 0 runs AVX2
 * where the CPU has it, any other value the plain C (the same bits) */
#ifndef JM_SPLAT_VARIANT
#define JM_SPLAT_VARIANT 0
#endif
#if defined(__x86_64__) && defined(__GNUC__) && !defined(JM_NO_CLONES) && JM_SPLAT_VARIANT == 0
#include <immintrin.h>
#include <pthread.h>
#define HAVE_AVX2_NORMALS 1
static int wide;
static pthread_once_t wide_once = PTHREAD_ONCE_INIT;
static void wide_choose(void)
{
    __builtin_cpu_init();
    wide = __builtin_cpu_supports("avx2") != 0;
    if (wide && jm_cpu_avx512()) wide = 2;
}

/* runs of eight sorted points from each row's start (the last shifted
 * back to end at the array's end); lanes outside [s, e) are masked off,
 * so each vertex gets each piece once */
#define FOR_RUNS8(P, lo, hi, k, lanes, ...)                                                                \
    FOR_PART_VERTICES(P, lo, hi, s_, e_, {                                                               \
        for (size_t r_ = s_; r_ < e_; r_ += 8) {                                                         \
            const size_t k = r_ + 8 <= (P)->n ? r_ : (P)->n - 8;                                         \
            const __m256i ix_ = _mm256_add_epi32(_mm256_set1_epi32((int)k), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)); \
            const __m256 lanes = _mm256_castsi256_ps(_mm256_and_si256(                                   \
                _mm256_cmpgt_epi32(ix_, _mm256_set1_epi32((int)r_ - 1)),                                 \
                _mm256_cmpgt_epi32(_mm256_set1_epi32((int)e_), ix_)));                                   \
            __VA_ARGS__                                                                                  \
        }                                                                                                \
    })

#define B8(x) _mm256_set1_ps(x)
__attribute__((target("avx2"))) static inline __m256 weight8(const pass *P, __m256 v, __m256 *ok)
{
    __m256 g = _mm256_max_ps(_mm256_sub_ps(B8(P->thr), v), _mm256_setzero_ps());
    __m256 x = _mm256_sub_ps(B8(1.0f), _mm256_mul_ps(g, B8(P->inv_tau)));
    *ok = _mm256_cmp_ps(x, _mm256_setzero_ps(), _CMP_GT_OQ);
    return _mm256_mul_ps(_mm256_mul_ps(x, x), _mm256_sub_ps(B8(3.0f), _mm256_mul_ps(B8(2.0f), x)));
}

/* acc[k..k+8) += w n where m */
__attribute__((target("avx2"))) static inline void add8(float *a, size_t k, __m256 m, __m256 w, __m256 n)
{
    __m256 old = _mm256_loadu_ps(a + k);
    _mm256_storeu_ps(a + k, _mm256_blendv_ps(old, _mm256_add_ps(old, _mm256_mul_ps(w, n)), m));
}

/* probe: the fused pass (P->vm kept too); a constant where inlined */
__attribute__((target("avx2"), always_inline)) static inline void ball8_(const pass *P, const int lo[3],
                                                                          const int hi[3], const float *q,
                                                                          const int probe)
{
    const __m256 qx = B8(q[0]), qy = B8(q[1]), qz = B8(q[2]), zero = _mm256_setzero_ps();
    FOR_RUNS8(P, lo, hi, k, lanes, {
        __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(P->x + k), qx), dy = _mm256_sub_ps(_mm256_loadu_ps(P->y + k), qy);
        __m256 dz = _mm256_sub_ps(_mm256_loadu_ps(P->z + k), qz);
        __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
        __m256 near = _mm256_and_ps(lanes, _mm256_cmp_ps(d2, B8(P->rb2), _CMP_LT_OQ));
        if (!_mm256_movemask_ps(near)) continue;
        __m256 d = _mm256_sqrt_ps(d2);
        __m256 v = _mm256_sub_ps(B8(1.0f), _mm256_mul_ps(d, B8(P->inv_r)));
        if (probe) {
            __m256 old = _mm256_loadu_ps(P->vm + k);
            _mm256_storeu_ps(P->vm + k, _mm256_blendv_ps(old, _mm256_max_ps(v, old), lanes));
        }
        __m256 ok;
        __m256 w = weight8(P, v, &ok);
        __m256 m = _mm256_and_ps(_mm256_and_ps(ok, near), _mm256_cmp_ps(d, zero, _CMP_GT_OQ));
        if (!_mm256_movemask_ps(m)) continue;
        __m256 id = _mm256_div_ps(B8(1.0f), d);
        add8(P->ax, k, m, w, _mm256_mul_ps(dx, id));
        add8(P->ay, k, m, w, _mm256_mul_ps(dy, id));
        add8(P->az, k, m, w, _mm256_mul_ps(dz, id));
    })
}

__attribute__((target("avx2"), always_inline)) static inline void link8_(const pass *P, const int lo[3],
                                                                          const int hi[3], const float *q,
                                                                          const float *u, float D, float rr2,
                                                                          float rrp2, const int probe)
{
    const __m256 qx = B8(q[0]), qy = B8(q[1]), qz = B8(q[2]), ux = B8(u[0]), uy = B8(u[1]), uz = B8(u[2]);
    const __m256 dd = B8(D), r2 = B8(rr2), zero = _mm256_setzero_ps(), ir = B8(P->inv_r);
    FOR_RUNS8(P, lo, hi, k, lanes, {
        __m256 wx = _mm256_sub_ps(_mm256_loadu_ps(P->x + k), qx), wy = _mm256_sub_ps(_mm256_loadu_ps(P->y + k), qy);
        __m256 wz = _mm256_sub_ps(_mm256_loadu_ps(P->z + k), qz);
        __m256 s = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(wx, ux), _mm256_mul_ps(wy, uy)), _mm256_mul_ps(wz, uz));
        __m256 q2 = _mm256_sub_ps(
            _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(wx, wx), _mm256_mul_ps(wy, wy)), _mm256_mul_ps(wz, wz)),
            _mm256_mul_ps(s, s));
        __m256 in = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(s, zero, _CMP_GE_OQ), _mm256_cmp_ps(s, dd, _CMP_LE_OQ)),
                                  _mm256_cmp_ps(q2, r2, _CMP_LT_OQ));
        in = _mm256_and_ps(in, lanes);
        if (!_mm256_movemask_ps(in)) continue;
        __m256 sm = _mm256_sub_ps(dd, s);
        __m256 nearer = _mm256_cmp_ps(s, sm, _CMP_LT_OQ);
        __m256 near = _mm256_blendv_ps(sm, s, nearer);
        __m256 sg = _mm256_blendv_ps(B8(-1.0f), B8(1.0f), _mm256_cmp_ps(s, sm, _CMP_LE_OQ));
        __m256 t = _mm256_mul_ps(near, ir), t2 = _mm256_mul_ps(t, t);
        __m256 qq = _mm256_sqrt_ps(_mm256_max_ps(q2, zero));
        /* jm_cos_quarter and jm_sin_quarter, term by term */
        __m256 cs = _mm256_sub_ps(B8(1.0f / 40320), _mm256_mul_ps(t2, B8(1.0f / 3628800)));
        cs = _mm256_add_ps(B8(-1.0f / 720), _mm256_mul_ps(t2, cs));
        cs = _mm256_add_ps(B8(1.0f / 24), _mm256_mul_ps(t2, cs));
        cs = _mm256_add_ps(B8(-0.5f), _mm256_mul_ps(t2, cs));
        cs = _mm256_add_ps(B8(1.0f), _mm256_mul_ps(t2, cs));
        __m256 v = _mm256_sub_ps(cs, _mm256_mul_ps(qq, ir));
        if (probe) {
            __m256 keep = _mm256_and_ps(in, _mm256_cmp_ps(q2, B8(rrp2), _CMP_LT_OQ));
            __m256 old = _mm256_loadu_ps(P->vm + k);
            _mm256_storeu_ps(P->vm + k, _mm256_blendv_ps(old, _mm256_max_ps(v, old), keep));
        }
        __m256 ok;
        __m256 w = weight8(P, v, &ok);
        __m256 m = _mm256_and_ps(_mm256_and_ps(in, ok), _mm256_cmp_ps(qq, zero, _CMP_GT_OQ));
        if (!_mm256_movemask_ps(m)) continue;
        __m256 sn = _mm256_add_ps(B8(-1.0f / 5040), _mm256_mul_ps(t2, B8(1.0f / 362880)));
        sn = _mm256_add_ps(B8(1.0f / 120), _mm256_mul_ps(t2, sn));
        sn = _mm256_add_ps(B8(-1.0f / 6), _mm256_mul_ps(t2, sn));
        sn = _mm256_add_ps(B8(1.0f), _mm256_mul_ps(t2, sn));
        sn = _mm256_mul_ps(sg, _mm256_mul_ps(t, sn));
        __m256 iq = _mm256_div_ps(B8(1.0f), qq);
        __m256 ox = _mm256_add_ps(_mm256_mul_ps(sn, ux), _mm256_mul_ps(_mm256_sub_ps(wx, _mm256_mul_ps(s, ux)), iq));
        __m256 oy = _mm256_add_ps(_mm256_mul_ps(sn, uy), _mm256_mul_ps(_mm256_sub_ps(wy, _mm256_mul_ps(s, uy)), iq));
        __m256 oz = _mm256_add_ps(_mm256_mul_ps(sn, uz), _mm256_mul_ps(_mm256_sub_ps(wz, _mm256_mul_ps(s, uz)), iq));
        add8(P->ax, k, m, w, ox);
        add8(P->ay, k, m, w, oy);
        add8(P->az, k, m, w, oz);
    })
}
/* The same kernels in runs of 16 in AVX-512 (where the pass has 16 points
 * or more): each lane does what a lane of ball8_ and link8_ does, the same
 * operations in the same order, so the same bits. */
#define FOR_RUNS16(P, lo, hi, k, lanes, ...)                                                               \
    FOR_PART_VERTICES(P, lo, hi, s_, e_, {                                                               \
        for (size_t r_ = s_; r_ < e_; r_ += 16) {                                                        \
            const size_t k = r_ + 16 <= (P)->n ? r_ : (P)->n - 16;                                       \
            const __m512i ix_ = _mm512_add_epi32(_mm512_set1_epi32((int)k),                              \
                                                 _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)); \
            const __mmask16 lanes = _mm512_cmpgt_epi32_mask(ix_, _mm512_set1_epi32((int)r_ - 1)) &       \
                                    _mm512_cmpgt_epi32_mask(_mm512_set1_epi32((int)e_), ix_);            \
            __VA_ARGS__                                                                                  \
        }                                                                                                \
    })
#define B16(x) _mm512_set1_ps(x)
__attribute__((target("avx512f"))) static inline __m512 weight16(const pass *P, __m512 v, __mmask16 *ok)
{
    __m512 g = _mm512_max_ps(_mm512_sub_ps(B16(P->thr), v), _mm512_setzero_ps());
    __m512 x = _mm512_sub_ps(B16(1.0f), _mm512_mul_ps(g, B16(P->inv_tau)));
    *ok = _mm512_cmp_ps_mask(x, _mm512_setzero_ps(), _CMP_GT_OQ);
    return _mm512_mul_ps(_mm512_mul_ps(x, x), _mm512_sub_ps(B16(3.0f), _mm512_mul_ps(B16(2.0f), x)));
}
__attribute__((target("avx512f"))) static inline void add16(float *a, size_t k, __mmask16 m, __m512 w, __m512 n)
{
    __m512 old = _mm512_loadu_ps(a + k);
    _mm512_storeu_ps(a + k, _mm512_mask_add_ps(old, m, old, _mm512_mul_ps(w, n)));
}
__attribute__((target("avx512f"), always_inline)) static inline void ball16_(const pass *P, const int lo[3],
                                                                              const int hi[3], const float *q,
                                                                              const int probe)
{
    const __m512 qx = B16(q[0]), qy = B16(q[1]), qz = B16(q[2]), zero = _mm512_setzero_ps();
    FOR_RUNS16(P, lo, hi, k, lanes, {
        __m512 dx = _mm512_sub_ps(_mm512_loadu_ps(P->x + k), qx), dy = _mm512_sub_ps(_mm512_loadu_ps(P->y + k), qy);
        __m512 dz = _mm512_sub_ps(_mm512_loadu_ps(P->z + k), qz);
        __m512 d2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)), _mm512_mul_ps(dz, dz));
        __mmask16 near = lanes & _mm512_cmp_ps_mask(d2, B16(P->rb2), _CMP_LT_OQ);
        if (!near) continue;
        __m512 d = _mm512_sqrt_ps(d2);
        __m512 v = _mm512_sub_ps(B16(1.0f), _mm512_mul_ps(d, B16(P->inv_r)));
        if (probe) {
            __m512 old = _mm512_loadu_ps(P->vm + k);
            _mm512_storeu_ps(P->vm + k, _mm512_mask_max_ps(old, lanes, v, old));
        }
        __mmask16 ok;
        __m512 w = weight16(P, v, &ok);
        __mmask16 m = ok & near & _mm512_cmp_ps_mask(d, zero, _CMP_GT_OQ);
        if (!m) continue;
        __m512 id = _mm512_div_ps(B16(1.0f), d);
        add16(P->ax, k, m, w, _mm512_mul_ps(dx, id));
        add16(P->ay, k, m, w, _mm512_mul_ps(dy, id));
        add16(P->az, k, m, w, _mm512_mul_ps(dz, id));
    })
}

__attribute__((target("avx512f"), always_inline)) static inline void link16_(const pass *P, const int lo[3],
                                                                              const int hi[3], const float *q,
                                                                              const float *u, float D, float rr2,
                                                                              float rrp2, const int probe)
{
    const __m512 qx = B16(q[0]), qy = B16(q[1]), qz = B16(q[2]), ux = B16(u[0]), uy = B16(u[1]), uz = B16(u[2]);
    const __m512 dd = B16(D), r2 = B16(rr2), zero = _mm512_setzero_ps(), ir = B16(P->inv_r);
    FOR_RUNS16(P, lo, hi, k, lanes, {
        __m512 wx = _mm512_sub_ps(_mm512_loadu_ps(P->x + k), qx), wy = _mm512_sub_ps(_mm512_loadu_ps(P->y + k), qy);
        __m512 wz = _mm512_sub_ps(_mm512_loadu_ps(P->z + k), qz);
        __m512 s = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(wx, ux), _mm512_mul_ps(wy, uy)), _mm512_mul_ps(wz, uz));
        __m512 q2 = _mm512_sub_ps(
            _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(wx, wx), _mm512_mul_ps(wy, wy)), _mm512_mul_ps(wz, wz)),
            _mm512_mul_ps(s, s));
        __mmask16 in = lanes & _mm512_cmp_ps_mask(s, zero, _CMP_GE_OQ) & _mm512_cmp_ps_mask(s, dd, _CMP_LE_OQ) &
                       _mm512_cmp_ps_mask(q2, r2, _CMP_LT_OQ);
        if (!in) continue;
        __m512 sm = _mm512_sub_ps(dd, s);
        __m512 near = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(s, sm, _CMP_LT_OQ), sm, s);
        __m512 sg = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(s, sm, _CMP_LE_OQ), B16(-1.0f), B16(1.0f));
        __m512 t = _mm512_mul_ps(near, ir), t2 = _mm512_mul_ps(t, t);
        __m512 qq = _mm512_sqrt_ps(_mm512_max_ps(q2, zero));
        /* jm_cos_quarter and jm_sin_quarter, term by term */
        __m512 cs = _mm512_sub_ps(B16(1.0f / 40320), _mm512_mul_ps(t2, B16(1.0f / 3628800)));
        cs = _mm512_add_ps(B16(-1.0f / 720), _mm512_mul_ps(t2, cs));
        cs = _mm512_add_ps(B16(1.0f / 24), _mm512_mul_ps(t2, cs));
        cs = _mm512_add_ps(B16(-0.5f), _mm512_mul_ps(t2, cs));
        cs = _mm512_add_ps(B16(1.0f), _mm512_mul_ps(t2, cs));
        __m512 v = _mm512_sub_ps(cs, _mm512_mul_ps(qq, ir));
        if (probe) {
            __mmask16 keep = in & _mm512_cmp_ps_mask(q2, B16(rrp2), _CMP_LT_OQ);
            __m512 old = _mm512_loadu_ps(P->vm + k);
            _mm512_storeu_ps(P->vm + k, _mm512_mask_max_ps(old, keep, v, old));
        }
        __mmask16 ok;
        __m512 w = weight16(P, v, &ok);
        __mmask16 m = in & ok & _mm512_cmp_ps_mask(qq, zero, _CMP_GT_OQ);
        if (!m) continue;
        __m512 sn = _mm512_add_ps(B16(-1.0f / 5040), _mm512_mul_ps(t2, B16(1.0f / 362880)));
        sn = _mm512_add_ps(B16(1.0f / 120), _mm512_mul_ps(t2, sn));
        sn = _mm512_add_ps(B16(-1.0f / 6), _mm512_mul_ps(t2, sn));
        sn = _mm512_add_ps(B16(1.0f), _mm512_mul_ps(t2, sn));
        sn = _mm512_mul_ps(sg, _mm512_mul_ps(t, sn));
        __m512 iq = _mm512_div_ps(B16(1.0f), qq);
        __m512 ox = _mm512_add_ps(_mm512_mul_ps(sn, ux), _mm512_mul_ps(_mm512_sub_ps(wx, _mm512_mul_ps(s, ux)), iq));
        __m512 oy = _mm512_add_ps(_mm512_mul_ps(sn, uy), _mm512_mul_ps(_mm512_sub_ps(wy, _mm512_mul_ps(s, uy)), iq));
        __m512 oz = _mm512_add_ps(_mm512_mul_ps(sn, uz), _mm512_mul_ps(_mm512_sub_ps(wz, _mm512_mul_ps(s, uz)), iq));
        add16(P->ax, k, m, w, ox);
        add16(P->ay, k, m, w, oy);
        add16(P->az, k, m, w, oz);
    })
}
__attribute__((target("avx512f"))) static void ball16(const pass *P, const int lo[3], const int hi[3], const float *q)
{
    ball16_(P, lo, hi, q, 0);
}
__attribute__((target("avx512f"))) static void ball16p(const pass *P, const int lo[3], const int hi[3], const float *q)
{
    ball16_(P, lo, hi, q, 1);
}
__attribute__((target("avx512f"))) static void link16(const pass *P, const int lo[3], const int hi[3], const float *q,
                                                      const float *u, float D, float rr2)
{
    link16_(P, lo, hi, q, u, D, rr2, 0.0f, 0);
}
__attribute__((target("avx512f"))) static void link16p(const pass *P, const int lo[3], const int hi[3],
                                                       const float *q, const float *u, float D, float rr2, float rrp2)
{
    link16_(P, lo, hi, q, u, D, rr2, rrp2, 1);
}
__attribute__((target("avx2"))) static void ball8(const pass *P, const int lo[3], const int hi[3], const float *q)
{
    ball8_(P, lo, hi, q, 0);
}
__attribute__((target("avx2"))) static void ball8p(const pass *P, const int lo[3], const int hi[3], const float *q)
{
    ball8_(P, lo, hi, q, 1);
}
__attribute__((target("avx2"))) static void link8(const pass *P, const int lo[3], const int hi[3], const float *q,
                                                    const float *u, float D, float rr2)
{
    link8_(P, lo, hi, q, u, D, rr2, 0.0f, 0);
}
__attribute__((target("avx2"))) static void link8p(const pass *P, const int lo[3], const int hi[3], const float *q,
                                                     const float *u, float D, float rr2, float rrp2)
{
    link8_(P, lo, hi, q, u, D, rr2, rrp2, 1);
}
#endif


/* the pieces' weighted gradients onto the vertices, eight at a time
 * where the CPU runs AVX2 (the same bits); the fused pass keeps the
 * probe's largest values on the way */
static void normal_ball(void *ctx, const int lo[3], const int hi[3], const float *q)
{
#ifdef HAVE_AVX2_NORMALS
    if (wide) {
        if (wide == 2 && ((const pass *)ctx)->n >= 16) ball16(ctx, lo, hi, q);
        else ball8(ctx, lo, hi, q);
        return;
    }
#endif
    ball_c(ctx, lo, hi, q);
}
static void normal_link(void *ctx, const int lo[3], const int hi[3], const float *q, const float *u, float D, float rr2)
{
#ifdef HAVE_AVX2_NORMALS
    if (wide) {
        if (wide == 2 && ((const pass *)ctx)->n >= 16) link16(ctx, lo, hi, q, u, D, rr2);
        else link8(ctx, lo, hi, q, u, D, rr2);
        return;
    }
#endif
    link_c(ctx, lo, hi, q, u, D, rr2, 0.0f);
}
static void fused_ball(void *ctx, const int lo[3], const int hi[3], const float *q)
{
    record(((const pass *)ctx)->rec, lo, hi, q, NULL, 0.0f, 0.0f);
#ifdef HAVE_AVX2_NORMALS
    if (wide) {
        if (wide == 2 && ((const pass *)ctx)->n >= 16) ball16p(ctx, lo, hi, q);
        else ball8p(ctx, lo, hi, q);
        return;
    }
#endif
    ball_c(ctx, lo, hi, q);
}
static void fused_link(void *ctx, const int lo[3], const int hi[3], const float *q, const float *u, float D, float rr2)
{
    const pass *P = ctx;
    record(P->rec, lo, hi, q, u, D, rr2);
    /* the probe's reach from the axis (jm_probe_pieces) */
    const float rp = jm_neck_reach(P->r, u[3], P->rn_probe, P->rb_probe);
#ifdef HAVE_AVX2_NORMALS
    if (wide) {
        if (wide == 2 && ((const pass *)ctx)->n >= 16) link16p(ctx, lo, hi, q, u, D, rr2, rp * rp);
        else link8p(ctx, lo, hi, q, u, D, rr2, rp * rp);
        return;
    }
#endif
    link_c(ctx, lo, hi, q, u, D, rr2, rp * rp);
}

/* how far a piece reaches in the band */
static float band_reach(const jm_config *c) { return c->r * (1.0f - (c->threshold - c->mv_tau)) + 1e-3f * c->r; }

/* the pass over a few vertices: a piece's parts clipped to those that
 * hold any (the others would add nothing) */
static int clip(const pass *P, const int lo[3], const int hi[3], int clo[3], int chi[3])
{
    for (int a = 0; a < 3; a++) {
        clo[a] = lo[a] > P->clo[a] ? lo[a] : P->clo[a];
        chi[a] = hi[a] < P->chi[a] ? hi[a] : P->chi[a];
        if (clo[a] > chi[a]) return 0;
    }
    return 1;
}
static void few_ball(void *ctx, const int lo[3], const int hi[3], const float *q)
{
    int l[3], h[3];
    if (clip(ctx, lo, hi, l, h)) normal_ball(ctx, l, h, q);
}
static void few_link(void *ctx, const int lo[3], const int hi[3], const float *q, const float *u, float D, float rr2)
{
    int l[3], h[3];
    if (clip(ctx, lo, hi, l, h)) normal_link(ctx, l, h, q, u, D, rr2);
}

/* the pass over the sorted points x, y, z (n of them, n >= 8) with part
 * starts ps, sums into acc (3 n floats, zeroed here) */
static pass make_pass(const jm_config *c, int B, const float *x, const float *y, const float *z, size_t n,
                      const uint32_t *ps, float *acc)
{
    memset(acc, 0, n * 3 * sizeof(float));
    /* a piece comes within tau of the threshold only within rb of its
     * particle (a ball) or of its axis (a neck): r (1 - (thr - tau)) */
    const float rb = band_reach(c);
    pass P = {x, y, z, acc, acc + n, acc + 2 * n, n, ps, jm_probe_parts(B), c->threshold, 1.0f / c->mv_tau,
              1.0f / c->r, rb * rb, NULL, c->r, 0.0f, 0.0f, {0, 0, 0}, {0, 0, 0}, NULL};
    return P;
}
int jm_meta_normals_probe(const jm_grid *g, const jm_config *c, const jm_hood *hood, jm_probe *pr, jm_mnorm *m, int B,
                          const float *x, const float *y, const float *z, size_t nv, float rb_probe, float rn_probe)
{
#ifdef HAVE_AVX2_NORMALS
    pthread_once(&wide_once, wide_choose);
#endif
    const size_t ns = nv < 8 ? 8 : nv;
    if (!reserve(m, ns)) return 0;
    pass P = make_pass(c, B, pr->px, pr->py, pr->pz, ns, pr->pstart, m->acc);
    P.vm = pr->vmax;
    P.rb_probe = rb_probe;
    P.rn_probe = rn_probe;
    m->nvisit = 0;
    m->visits = 1;
    P.rec = m;
    const float reach = band_reach(c);
    const jm_piece_visitor vis = {reach, reach, fused_ball, fused_link, &P};
    jm_probe_pieces(g, c, hood, B, x, y, z, &vis);
    return 1;
}

int jm_meta_normals_finish(const jm_grid *g, const jm_config *c, const jm_hood *hood, jm_probe *pr, jm_mnorm *m,
                           int B, const float *x, const float *y, const float *z, const float *pos, float *nrm,
                           size_t nv)
{
    if (!nv || !nrm) return 1;
    const size_t ns = nv < 8 ? 8 : nv;
    float *ax = m->acc, *ay = m->acc + ns, *az = m->acc + 2 * ns;
    /* the vertices the settling moved (or the clamp kept off their
     * root's point): their sums again, at where they are now */
    uint32_t *moved = m->moved;
    size_t nm = 0;
    for (size_t w = 0; w < nv; w++) {
        const uint32_t v = pr->order[w];
        if (memcmp(&pos[3 * (size_t)v], &pr->pt[3 * (size_t)v], 3 * sizeof(float)) != 0) moved[nm++] = (uint32_t)w;
    }
    if (nm) {
        const int np = jm_probe_parts(B);
        const size_t parts = (size_t)np * np * np, n2 = nm < 8 ? 8 : nm;
        /* their part starts, where the probe counted (free after its sort) */
        uint32_t *ps = pr->pstart + parts + 1;
        memset(ps, 0, (parts + 1) * sizeof *ps);
        float *sx = m->sub, *sy = sx + n2, *sz = sy + n2, *sacc = sz + n2;
        int clo[3] = {np, np, np}, chi[3] = {-1, -1, -1};
        for (size_t j = 0; j < n2; j++) {
            if (j < nm) {
                const uint32_t v = pr->order[moved[j]], part = pr->part[v];
                ps[part + 1]++;
                const int pc[3] = {(int)(part % (uint32_t)np), (int)(part / (uint32_t)np % (uint32_t)np),
                                   (int)(part / ((uint32_t)np * (uint32_t)np))};
                for (int a = 0; a < 3; a++) {
                    if (pc[a] < clo[a]) clo[a] = pc[a];
                    if (pc[a] > chi[a]) chi[a] = pc[a];
                }
                sx[j] = pos[3 * (size_t)v];
                sy[j] = pos[3 * (size_t)v + 1];
                sz[j] = pos[3 * (size_t)v + 2];
            } else {
                sx[j] = sy[j] = sz[j] = 1e30f; /* fewer than 8: far away dummies */
            }
        }
        for (size_t q = 0; q < parts; q++) ps[q + 1] += ps[q];
        pass P = make_pass(c, B, sx, sy, sz, n2, ps, sacc);
        memcpy(P.clo, clo, sizeof clo);
        memcpy(P.chi, chi, sizeof chi);
        if (m->visits) {
            /* the pieces the first pass visited, with the same parts */
            for (size_t k = 0; k < m->nvisit; k++) {
                const jm_visit *vi = &m->visit[k];
                if (vi->u) few_link(&P, vi->lo, vi->hi, vi->q, vi->u, vi->D, vi->rr2);
                else few_ball(&P, vi->lo, vi->hi, vi->q);
            }
        } else {
            const float reach = band_reach(c);
            const jm_piece_visitor vis = {reach, reach, few_ball, few_link, &P};
            jm_probe_pieces(g, c, hood, B, x, y, z, &vis);
        }
        for (size_t j = 0; j < nm; j++) {
            ax[moved[j]] = P.ax[j];
            ay[moved[j]] = P.ay[j];
            az[moved[j]] = P.az[j];
        }
    }
    /* unit sums in place (a loop the compiler vectorizes: the same
     * roundings), then into the vertices' places */
    float *len = m->sub; /* free again: 6 cap floats */
    for (size_t w = 0; w < nv; w++) {
        const float a0 = ax[w], a1 = ay[w], a2 = az[w];
        const float l = sqrtf(a0 * a0 + a1 * a1 + a2 * a2);
        len[w] = l;
        ax[w] = a0 / l;
        ay[w] = a1 / l;
        az[w] = a2 / l;
    }
    for (size_t w = 0; w < nv; w++) {
        if (!(len[w] > 0.0f)) continue; /* no piece near: the normal found before */
        float *o = &nrm[3 * (size_t)pr->order[w]];
        o[0] = ax[w];
        o[1] = ay[w];
        o[2] = az[w];
    }
    return 1;
}
