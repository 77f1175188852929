/* metafinish.c - the stitched metasphere mesh's last pass: chord-sag compensation, normals kept facing their triangles. */
#include "field/meta/metafinish.h"
#include "field/meta/metafinish16.h"
#include "core/cpu.h"
#include <math.h>
#include <string.h>

/* Sag: a triangle whose corners lie on a curved surface cuts inside it by,
 * on average over its area, sum over its edges of k_e l_e^2 / 24 (k_e the
 * normal curvature along edge e; exact for a sphere), and k_e l_e^2 = dn . dp
 * with the field's unit normals n. Moving every vertex outward by the
 * area-weighted mean of that sag over its triangles makes the mesh straddle
 * the surface instead of being inscribed in it, so areas and volumes come
 * out unbiased.
 *
 * Facing: where the surface bends or creases more sharply than the cubes
 * can follow (the tunnels and saddles between densely packed particles), a
 * triangle may stand almost across the surface, and the field's normal at a
 * corner then points away from it (a renderer shades that corner from
 * behind). Such a vertex's normal is turned toward its triangles until it
 * faces them all (see face_normals), after the sag has moved the vertices. */
/* a corner faces its triangle above this cosine (see face_normals) */
#define COS_MIN JM_FINISH_COS_MIN
/* Per-triangle kernels of the passes over every triangle, with the same
 * float operations in the SSE2 and the plain C versions (the same bits):
 * a point's coordinates in a vector's first three lanes. */
#ifdef __SSE2__
#include <emmintrin.h>
static inline __m128 ld3(const float *p)
{
    return _mm_movelh_ps(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)p)), _mm_load_ss(p + 2));
}
/* a[0] += x, a[1] += y */
static inline void add2(float *a, float x, float y)
{
    const __m128 s = _mm_add_ps(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)a)), _mm_unpacklo_ps(_mm_set_ss(x), _mm_set_ss(y)));
    _mm_storel_epi64((__m128i *)a, _mm_castps_si128(s));
}
/* u x w, each lane as the plain C cross product computes it */
static inline __m128 cross3(__m128 u, __m128 w)
{
    const __m128 u1 = _mm_shuffle_ps(u, u, _MM_SHUFFLE(3, 0, 2, 1)), w2 = _mm_shuffle_ps(w, w, _MM_SHUFFLE(3, 1, 0, 2));
    const __m128 u2 = _mm_shuffle_ps(u, u, _MM_SHUFFLE(3, 1, 0, 2)), w1 = _mm_shuffle_ps(w, w, _MM_SHUFFLE(3, 0, 2, 1));
    return _mm_sub_ps(_mm_mul_ps(u1, w2), _mm_mul_ps(u2, w1));
}
/* s + m0 + m1 + m2 (first lanes), left to right as in C */
static inline __m128 sum3(__m128 s, __m128 m)
{
    s = _mm_add_ss(s, m);
    s = _mm_add_ss(s, _mm_shuffle_ps(m, m, 1));
    return _mm_add_ss(s, _mm_shuffle_ps(m, m, 2));
}
static inline float dot3(__m128 a, __m128 b)
{
    const __m128 m = _mm_mul_ps(a, b);
    return _mm_cvtss_f32(_mm_add_ss(_mm_add_ss(m, _mm_shuffle_ps(m, m, 1)), _mm_shuffle_ps(m, m, 2)));
}
/* the triangle's chord sag (x24, see above) and its normal's length (x2
 * area); its normal (x2 area, the same bits as folds' unmoved one) in out */
static inline float tri_sag(const float *restrict P, const float *restrict N, const uint32_t *vi, float *len, float *out)
{
    const __m128 p0 = ld3(P + 3 * (size_t)vi[0]), p1 = ld3(P + 3 * (size_t)vi[1]), p2 = ld3(P + 3 * (size_t)vi[2]);
    const __m128 n0 = ld3(N + 3 * (size_t)vi[0]), n1 = ld3(N + 3 * (size_t)vi[1]), n2 = ld3(N + 3 * (size_t)vi[2]);
    const __m128 e1 = _mm_sub_ps(p1, p0), e2 = _mm_sub_ps(p2, p1), e3 = _mm_sub_ps(p0, p2);
    const __m128 cr = cross3(e3, e1);
    *len = sqrtf(dot3(cr, cr));
    _mm_storeu_ps(out, cr);
    const __m128 m1 = _mm_mul_ps(_mm_sub_ps(n1, n0), e1), m2 = _mm_mul_ps(_mm_sub_ps(n2, n1), e2),
                 m3 = _mm_mul_ps(_mm_sub_ps(n0, n2), e3);
    __m128 s = _mm_add_ss(m1, _mm_shuffle_ps(m1, m1, 1));
    s = _mm_add_ss(s, _mm_shuffle_ps(m1, m1, 2));
    return _mm_cvtss_f32(sum3(sum3(s, m2), m3));
}
/* bit k set where corner k's normal does not face the triangle: cosine
 * above COS_MIN, without the square root */
static inline int facing_away(const float *restrict N, const uint32_t *vi, __m128 cr)
{
    const __m128 lim2 = _mm_set1_ps(COS_MIN * COS_MIN * dot3(cr, cr));
    /* the three corners' dots in three lanes: products transposed, then
     * (x + y) + z */
    const __m128 ma = _mm_mul_ps(ld3(N + 3 * (size_t)vi[0]), cr), mb = _mm_mul_ps(ld3(N + 3 * (size_t)vi[1]), cr),
                 mc = _mm_mul_ps(ld3(N + 3 * (size_t)vi[2]), cr);
    const __m128 lo = _mm_unpacklo_ps(ma, mb), hi = _mm_unpackhi_ps(ma, mb);
    const __m128 d = _mm_add_ps(_mm_add_ps(_mm_shuffle_ps(lo, mc, _MM_SHUFFLE(3, 0, 1, 0)),
                                           _mm_shuffle_ps(lo, mc, _MM_SHUFFLE(3, 1, 3, 2))),
                                _mm_shuffle_ps(hi, mc, _MM_SHUFFLE(3, 2, 1, 0)));
    const __m128 ok = _mm_and_ps(_mm_cmpgt_ps(d, _mm_setzero_ps()), _mm_cmpgt_ps(_mm_mul_ps(d, d), lim2));
    return ~_mm_movemask_ps(ok) & 7;
}
/* the same, the triangle's normal (x2 area) computed from P, or read from cr */
static inline int corners_away(const float *restrict P, const float *restrict N, const uint32_t *vi)
{
    const __m128 p0 = ld3(P + 3 * (size_t)vi[0]), p1 = ld3(P + 3 * (size_t)vi[1]), p2 = ld3(P + 3 * (size_t)vi[2]);
    return facing_away(N, vi, cross3(_mm_sub_ps(p0, p2), _mm_sub_ps(p1, p0)));
}
static inline int stored_away(const float *restrict N, const uint32_t *vi, const float *cr)
{
    return facing_away(N, vi, _mm_loadu_ps(cr));
}
/* Whether triangle v, its vertices moved by D along their normals N, turns
 * its normal (x2 area) against its own at positions P; the moved one into
 * moved where not NULL (4 floats: the same bits as corners_away computes
 * at the moved positions but for the sign of a zero, which the tests do
 * not see, as p0 - p2 is -(p2 - p0) exactly). */
static inline int folds(const float *restrict P, const float *restrict N, const float *restrict D, const uint32_t *v,
                        float *moved)
{
    __m128 p[3], q[3];
    for (int k = 0; k < 3; k++) {
        p[k] = ld3(P + 3 * (size_t)v[k]);
        q[k] = _mm_add_ps(p[k], _mm_mul_ps(_mm_set1_ps(D[v[k]]), ld3(N + 3 * (size_t)v[k])));
    }
    const __m128 c0 = cross3(_mm_sub_ps(p[1], p[0]), _mm_sub_ps(p[2], p[0]));
    const __m128 c1 = cross3(_mm_sub_ps(q[1], q[0]), _mm_sub_ps(q[2], q[0]));
    if (moved) _mm_storeu_ps(moved, c1);
    return dot3(c0, c1) < 0.0f;
}
#else
static inline void add2(float *a, float x, float y)
{
    a[0] += x;
    a[1] += y;
}
static inline float tri_sag(const float *restrict P, const float *restrict N, const uint32_t *vi, float *len, float *out)
{
    float p[3][3], n[3][3], e1[3], e2[3], e3[3];
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 3; a++) p[k][a] = P[3 * (size_t)vi[k] + a], n[k][a] = N[3 * (size_t)vi[k] + a];
    for (int a = 0; a < 3; a++) {
        e1[a] = p[1][a] - p[0][a];
        e2[a] = p[2][a] - p[1][a];
        e3[a] = p[0][a] - p[2][a];
    }
    const float cr[3] = {e3[1] * e1[2] - e3[2] * e1[1], e3[2] * e1[0] - e3[0] * e1[2],
                         e3[0] * e1[1] - e3[1] * e1[0]};
    *len = sqrtf(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    memcpy(out, cr, sizeof cr);
    return (n[1][0] - n[0][0]) * e1[0] + (n[1][1] - n[0][1]) * e1[1] + (n[1][2] - n[0][2]) * e1[2] +
           (n[2][0] - n[1][0]) * e2[0] + (n[2][1] - n[1][1]) * e2[1] + (n[2][2] - n[1][2]) * e2[2] +
           (n[0][0] - n[2][0]) * e3[0] + (n[0][1] - n[2][1]) * e3[1] + (n[0][2] - n[2][2]) * e3[2];
}
static inline int stored_away(const float *restrict N, const uint32_t *vi, const float *cr)
{
    const float lim2 = COS_MIN * COS_MIN * (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    int away = 0;
    for (int k = 0; k < 3; k++) {
        const float *n = N + 3 * (size_t)vi[k];
        const float d = n[0] * cr[0] + n[1] * cr[1] + n[2] * cr[2];
        away |= !(d > 0.0f && d * d > lim2) << k;
    }
    return away;
}
static inline int corners_away(const float *restrict P, const float *restrict N, const uint32_t *vi)
{
    const float *p0 = P + 3 * (size_t)vi[0], *p1 = P + 3 * (size_t)vi[1], *p2 = P + 3 * (size_t)vi[2];
    const float e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const float e3[3] = {p0[0] - p2[0], p0[1] - p2[1], p0[2] - p2[2]};
    const float cr[3] = {e3[1] * e1[2] - e3[2] * e1[1], e3[2] * e1[0] - e3[0] * e1[2],
                         e3[0] * e1[1] - e3[1] * e1[0]};
    return stored_away(N, vi, cr);
}
static int folds(const float *restrict P, const float *restrict N, const float *restrict D, const uint32_t *v,
                 float *moved)
{
    float p[3][3], q[3][3];
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 3; a++) {
            p[k][a] = P[3 * (size_t)v[k] + a];
            q[k][a] = p[k][a] + D[v[k]] * N[3 * (size_t)v[k] + a];
        }
    float u[3], w[3], x[3], y[3], c0[3];
    for (int a = 0; a < 3; a++) {
        u[a] = p[1][a] - p[0][a], w[a] = p[2][a] - p[0][a];
        x[a] = q[1][a] - q[0][a], y[a] = q[2][a] - q[0][a];
    }
    c0[0] = u[1] * w[2] - u[2] * w[1];
    c0[1] = u[2] * w[0] - u[0] * w[2];
    c0[2] = u[0] * w[1] - u[1] * w[0];
    const float c1[3] = {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
    if (moved) memcpy(moved, c1, sizeof c1);
    return c0[0] * c1[0] + c0[1] * c1[1] + c0[2] * c1[2] < 0.0f;
}
#endif

/* the capacity of the lists of triangles the fold rounds keep; past it
 * they fall back to every triangle (the same result); small while a test
 * forces a CPU level (cpu.h), so that the fallback runs too */
#define FINISH_LIST(nt) (jm_cpu_forced() ? (size_t)16 : (nt) / 8 + 64)
/* rounds that halve the offsets of a folded triangle's vertices before
 * they are zeroed */
#define FOLD_HALVINGS 4
/* Which vertices have a corner that does not face its triangle: flag[v]
 * set (flag: nv bytes, zeroed by the caller), their count returned. The
 * triangles listed in tl (nl of them), or every triangle when tl is NULL,
 * are tested at P. */
static size_t flag_away(const float *restrict P, const float *restrict N, const uint32_t *idx, const uint32_t *tl,
                        size_t nl, uint8_t *flag)
{
    size_t bad = 0;
    for (size_t j = 0; j < nl; j++) {
        const size_t t = tl ? tl[j] : j;
        const uint32_t *vi = idx + 3 * t;
        const int away = corners_away(P, N, vi);
        if (!away) continue;
        for (int k = 0; k < 3; k++) {
            if ((away >> k & 1) && !flag[vi[k]]) {
                flag[vi[k]] = 1;
                bad++;
            }
        }
    }
    return bad;
}

/* Normals facing their triangles: each of the bad vertices flagged by
 * flag_away (a corner whose cosine between the vertex normal and the
 * triangle's does not exceed COS_MIN) gathers its triangles' unit normals,
 * and its normal is pushed toward those it fails (by their sum,
 * renormalised) until it faces all of them, keeping the best of a few steps
 * (a fan folded over itself may have no normal facing every triangle). */
static size_t mark_triangles(jm_pool *pool, const uint32_t *idx, size_t nt, const uint8_t *mark, uint64_t *bits);
static int face_normals(jm_mem *mem, jm_pool *pool, const float *restrict P, float *restrict N, size_t nv,
                        const uint32_t *idx, size_t nt, const uint8_t *flag, size_t bad, uint64_t *tbits,
                        uint32_t *slot)
{
    if (!bad) return 1;
    /* the flagged vertices' triangles: (slot, unit normal) for each corner
     * at one, then sorted by slot (slot: nv entries of the caller's
     * scratch, not a fresh array: on a big frame new pages cost more than
     * this pass) */
    size_t cap = 8 * bad, np = 0;
    uint32_t *who = jm_alloc(mem, bad * sizeof *who);
    uint32_t *start = jm_calloc(mem, bad + 1, sizeof *start);
    float *pair = jm_alloc(mem, 3 * cap * sizeof *pair), *fn = NULL;
    uint32_t *pslot = jm_alloc(mem, cap * sizeof *pslot);
    int ok = who && start && pair && pslot;
    if (ok) {
        size_t b = 0;
        for (size_t i = 0; i < nv; i++) {
            slot[i] = flag[i] ? (uint32_t)b : UINT32_MAX;
            if (flag[i]) who[b++] = (uint32_t)i;
        }
        (void)mark_triangles(pool, idx, nt, flag, tbits);
        for (size_t w = 0; w < (nt + 63) / 64 && ok; w++)
            for (uint64_t tb = tbits[w]; tb && ok; tb &= tb - 1) {
                const size_t t = 64 * w + (size_t)__builtin_ctzll(tb);
                const uint32_t vi[3] = {idx[3 * t], idx[3 * t + 1], idx[3 * t + 2]};
                const float *p0 = P + 3 * (size_t)vi[0], *p1 = P + 3 * (size_t)vi[1], *p2 = P + 3 * (size_t)vi[2];
                const float e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
                const float e3[3] = {p0[0] - p2[0], p0[1] - p2[1], p0[2] - p2[2]};
                float cr[3] = {e3[1] * e1[2] - e3[2] * e1[1], e3[2] * e1[0] - e3[0] * e1[2], e3[0] * e1[1] - e3[1] * e1[0]};
                float len = sqrtf(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
                for (int a = 0; a < 3; a++) cr[a] = len > 0.0f ? cr[a] / len : 0.0f;
                for (int k = 0; k < 3; k++) {
                    if (!flag[vi[k]]) continue;
                    if (np == cap) {
                        float *q = jm_realloc(mem, pair, 3 * cap * sizeof *pair, 6 * cap * sizeof *pair);
                        if (q) pair = q;
                        uint32_t *u = q ? jm_realloc(mem, pslot, cap * sizeof *pslot, 2 * cap * sizeof *pslot) : NULL;
                        if (!u) {
                            if (q) pair = jm_realloc(mem, pair, 6 * cap * sizeof *pair, 3 * cap * sizeof *pair);
                            ok = 0;
                            break;
                        }
                        pslot = u;
                        cap *= 2;
                    }
                    pslot[np] = slot[vi[k]];
                    memcpy(pair + 3 * np++, cr, sizeof cr);
                    start[slot[vi[k]] + 1]++;
                }
            }
    }
    if (ok) {
        for (size_t k = 0; k < bad; k++) start[k + 1] += start[k];
        fn = jm_alloc(mem, 3 * np * sizeof *fn);
        ok = fn != NULL;
    }
    if (ok) {
        /* slot's triangles in order: fill with slot[] reused as cursors */
        for (size_t k = 0; k < bad; k++) slot[k] = start[k];
        for (size_t j = 0; j < np; j++) memcpy(fn + 3 * (size_t)slot[pslot[j]]++, pair + 3 * j, 3 * sizeof *fn);
        for (size_t k = 0; k < bad; k++) {
            float *nn = N + 3 * (size_t)who[k], cur[3] = {nn[0], nn[1], nn[2]}, best[3] = {nn[0], nn[1], nn[2]};
            float best_min = -2.0f;
            for (int it = 0; it < 8; it++) {
                float worst = 2.0f, push[3] = {0, 0, 0};
                for (uint32_t j = start[k]; j < start[k + 1]; j++) {
                    const float *f = fn + 3 * (size_t)j;
                    float d = cur[0] * f[0] + cur[1] * f[1] + cur[2] * f[2];
                    if (d < worst) worst = d;
                    if (!(d > COS_MIN))
                        for (int a = 0; a < 3; a++) push[a] += f[a];
                }
                if (worst > best_min) {
                    best_min = worst;
                    memcpy(best, cur, sizeof cur);
                }
                if (worst > COS_MIN) break;
                float l = 0.0f;
                for (int a = 0; a < 3; a++) {
                    cur[a] += push[a];
                    l += cur[a] * cur[a];
                }
                l = sqrtf(l);
                if (!(l > 0.0f)) break;
                for (int a = 0; a < 3; a++) cur[a] /= l;
            }
            memcpy(nn, best, sizeof best);
        }
    }
    jm_free(mem, fn, 3 * np * sizeof *fn);
    jm_free(mem, pair, 3 * cap * sizeof *pair);
    jm_free(mem, pslot, cap * sizeof *pslot);
    jm_free(mem, start, (bad + 1) * sizeof *start);
    jm_free(mem, who, bad * sizeof *who);
    return ok;
}

/* The passes over every triangle run in chunks on the pool's threads,
 * each triangle's result kept apart (its sag and area, its fold and facing
 * bits); the sums over a vertex's triangles and the rounds' bookkeeping
 * then run in triangle order on one thread, so the result does not depend
 * on the threads. */
#define FIN_CHUNK ((size_t)4096) /* triangles a task: a multiple of 16 */
typedef struct fin {
    const float *P, *N, *D;
    const uint32_t *idx;
    size_t nt;
    int facing, lanes;  /* lanes: 16 (AVX-512), 8 (AVX2) or 1 a pass */
    float *as, *area;   /* per triangle of the wave: its sag times its area / 24, its area */
    size_t wave;        /* the first chunk of the wave (sag_offsets) */
    uint32_t *bits;     /* round 0, per 16 triangles t0 + l: bit l set where it
                           folds, bit 16 + l where a corner faces away */
} fin;

/* The triangles with a marked vertex, as bits (one per triangle, 64 a
 * word), found in chunks on the pool's threads: the lists are then read
 * off the bits in triangle order on one thread. */
typedef struct marked {
    const uint32_t *idx;
    size_t nt;
    const uint8_t *mark;
    uint64_t *bits;
} marked;

static void marked_task(void *arg, size_t k, int worker)
{
    (void)worker;
    const marked *M = arg;
    const size_t t0 = k * FIN_CHUNK, t1 = t0 + FIN_CHUNK < M->nt ? t0 + FIN_CHUNK : M->nt;
    for (size_t w = t0 / 64; w * 64 < t1; w++) {
        uint64_t b = 0;
        const size_t e = (w + 1) * 64 < t1 ? (w + 1) * 64 : t1;
        for (size_t t = w * 64; t < e; t++) {
            const uint32_t *v = M->idx + 3 * t;
            b |= (uint64_t)(M->mark[v[0]] | M->mark[v[1]] | M->mark[v[2]]) << (t - w * 64);
        }
        M->bits[w] = b;
    }
}

/* bits (nt / 64 + 1 words) set for the triangles with a marked vertex (mark:
 * 0 or 1); their count */
static size_t mark_triangles(jm_pool *pool, const uint32_t *idx, size_t nt, const uint8_t *mark, uint64_t *bits)
{
    marked M = {idx, nt, mark, bits};
    jm_pool_run(pool, (nt + FIN_CHUNK - 1) / FIN_CHUNK, 1, marked_task, &M);
    size_t n = 0;
    for (size_t w = 0; w < (nt + 63) / 64; w++) n += (size_t)__builtin_popcountll(bits[w]);
    return n;
}

static void sag_task(void *arg, size_t k, int worker)
{
    (void)worker;
    const fin *F = arg;
    k += F->wave;
    const size_t t1 = (k + 1) * FIN_CHUNK < F->nt ? (k + 1) * FIN_CHUNK : F->nt, b = F->wave * FIN_CHUNK;
    float *as = F->as - b, *area = F->area - b; /* (indexed by triangle) */
    size_t t = k * FIN_CHUNK;
    for (; F->lanes == 16 && t + 16 <= t1; t += 16) jm_finish_sag16(F->P, F->N, F->idx, t, as + t, area + t);
    for (; F->lanes >= 8 && t + 8 <= t1; t += 8) jm_finish_sag8(F->P, F->N, F->idx, t, as + t, area + t);
    for (; t < t1; t++) {
        float len, cr[4];
        const float sag = tri_sag(F->P, F->N, F->idx + 3 * t, &len, cr);
        area[t] = 0.5f * len;
        as[t] = area[t] * sag * (1.0f / 24.0f);
    }
}

static void fold0_task(void *arg, size_t k, int worker)
{
    (void)worker;
    const fin *F = arg;
    const size_t t1 = (k + 1) * FIN_CHUNK < F->nt ? (k + 1) * FIN_CHUNK : F->nt;
    size_t t = k * FIN_CHUNK;
    for (size_t w = t / 16; w <= (t1 - 1) / 16; w++) F->bits[w] = 0;
    for (; F->lanes == 16 && t + 16 <= t1; t += 16)
        F->bits[t / 16] = jm_finish_fold16(F->P, F->N, F->D, F->idx, t, F->facing);
    for (; F->lanes >= 8 && t + 8 <= t1; t += 8)
        F->bits[t / 16] |= jm_finish_fold8(F->P, F->N, F->D, F->idx, t, F->facing) << (t % 16);
    for (; t < t1; t++) {
        const uint32_t *v = F->idx + 3 * t;
        float moved[4];
        const uint32_t f = (uint32_t)folds(F->P, F->N, F->D, v, moved);
        const uint32_t away = (uint32_t)(F->facing && stored_away(F->N, v, moved));
        F->bits[t / 16] |= (f | away << 16) << (t % 16);
    }
}

/* The passes over every vertex, each vertex on its own: in chunks on the
 * pool's threads. */
#define VTX_CHUNK ((size_t)8192)
typedef struct vtx_job {
    const float *A; /* per vertex: sag * area, area */
    float *D;
    float *pos;
    const float *nrm;
    size_t nv;
    float max_sag;
} vtx_job;

static void offset_task(void *arg, size_t k, int worker)
{
    (void)worker;
    const vtx_job *V = arg;
    const size_t e = (k + 1) * VTX_CHUNK < V->nv ? (k + 1) * VTX_CHUNK : V->nv;
    for (size_t i = k * VTX_CHUNK; i < e; i++) {
        float d = V->A[2 * i + 1] > 0.0f ? V->A[2 * i] / V->A[2 * i + 1] : 0.0f;
        /* where the normals turn across a triangle more than a curved
         * surface could (creases and folds finer than the cubes), the
         * estimate means nothing: at most a tenth of a cube */
        V->D[i] = d > V->max_sag ? V->max_sag : (d < -V->max_sag ? -V->max_sag : d);
    }
}

/* each vertex moved by D along its normal */
static void move_task(void *arg, size_t k, int worker)
{
    (void)worker;
    const vtx_job *V = arg;
    const size_t e = (k + 1) * VTX_CHUNK < V->nv ? (k + 1) * VTX_CHUNK : V->nv;
    for (size_t i = k * VTX_CHUNK; i < e; i++)
        for (int a = 0; a < 3; a++) V->pos[3 * i + a] += V->D[i] * V->nrm[3 * i + a];
}

/* Each vertex's offset D along its normal: the area-weighted mean sag of
 * its triangles, at most max_sag either way. */
static int sag_offsets(jm_mem *mem, jm_pool *pool, fin *F, float *A, float *D, size_t nv, float max_sag)
{
    /* in waves of 4 chunks a thread: the triangles' sags on the threads,
     * then added to their vertices in triangle order */
    const size_t nt = F->nt, nch = (nt + FIN_CHUNK - 1) / FIN_CHUNK, per = 4 * (size_t)jm_pool_threads(pool);
    const size_t bytes = 2 * per * FIN_CHUNK * sizeof(float);
    F->as = jm_alloc(mem, bytes);
    if (!F->as) return 0;
    F->area = F->as + per * FIN_CHUNK;
    memset(A, 0, 2 * nv * sizeof(float));
    for (F->wave = 0; F->wave < nch; F->wave += per) {
        const size_t m = nch - F->wave < per ? nch - F->wave : per, b = F->wave * FIN_CHUNK;
        jm_pool_run(pool, m, 1, sag_task, F);
        const size_t e = (F->wave + m) * FIN_CHUNK < nt ? (F->wave + m) * FIN_CHUNK : nt;
        for (size_t t = b; t < e; t++) {
            const uint32_t *vi = F->idx + 3 * t;
            for (int k = 0; k < 3; k++) add2(A + 2 * (size_t)vi[k], F->as[t - b], F->area[t - b]);
        }
    }
    jm_free(mem, F->as, bytes);
    F->as = F->area = NULL;
    vtx_job V = {A, D, NULL, NULL, nv, max_sag};
    jm_pool_run(pool, (nv + VTX_CHUNK - 1) / VTX_CHUNK, 1, offset_task, &V);
    return 1;
}

/* The fold rounds' lists: watch (the triangles of the rounds after the
 * first), awl (those the first found with a corner away) and hit (the
 * vertices a round flags) */
typedef struct rounds {
    uint32_t *watch, *awl, *hit;
    size_t capw, nw, na;
    int listed;
    uint64_t *tbits; /* nt / 64 + 1: the triangles with a marked vertex */
} rounds;

/* No triangle folds over: a triangle whose normal, its vertices moved,
 * would point against its own before has its vertices' offsets halved
 * (zeroed after FOLD_HALVINGS rounds), until none does. Each zeroing round
 * zeroes a vertex of every folded triangle and a triangle of unmoved
 * vertices is not folded, so the rounds end. After the first round (every
 * triangle), a round tests only the triangles with a vertex the round
 * before halved (halved[v], that round's number plus one): any other keeps
 * the offsets with which it was last found not folded (a folded triangle
 * has all three halved). They are among the triangles with a changed
 * vertex (watch), which the facing pass needs too. The first round also
 * finds the triangles with a corner away from their moved normal (awl),
 * which the facing pass tests again at the final positions. */
static int fold_rounds(jm_mem *mem, jm_pool *pool, fin *F, float *D, uint8_t *changed, uint32_t *halved,
                       size_t nv, rounds *R)
{
    const size_t nt = F->nt;
    const uint32_t *idx = F->idx;
    const size_t nw = (nt + 15) / 16;
    F->bits = jm_alloc(mem, (nw + 1) * sizeof *F->bits);
    if (!F->bits) return 0;
    F->D = D;
    jm_pool_run(pool, (nt + FIN_CHUNK - 1) / FIN_CHUNK, 1, fold0_task, F);
    memset(changed, 0, nv);
    memset(halved, 0, nv * sizeof *halved);
    for (uint32_t round = 0, all = 1;; round++) {
        size_t folded = 0, fresh = 0, nh = 0;
        /* round 0: the triangles its bits mark, in order; then the watched
         * ones (or all) tested */
        const size_t count = round ? (all ? nt : R->nw) : nw;
        for (size_t j = 0; j < count; j++) {
            uint32_t m = 1;
            size_t t = all ? j : R->watch[j];
            if (!round) {
                m = F->bits[j];
                t = 16 * j;
            }
            if (round) {
                const uint32_t *v = idx + 3 * t;
                /* (round + 1: halved last round and listed again in this one) */
                if ((halved[v[0]] < round) & (halved[v[1]] < round) & (halved[v[2]] < round)) continue;
            }
            for (uint32_t any = round ? 1 : (m | m >> 16) & 0xffffu; any; any &= any - 1) {
                const int l = round ? 0 : __builtin_ctz(any);
                const uint32_t *v = idx + 3 * (t + (size_t)l);
                if (!round && (m >> (16 + l) & 1)) {
                    if (R->na < R->capw) R->awl[R->na++] = (uint32_t)(t + (size_t)l);
                    else R->listed = 0;
                }
                if (round ? !folds(F->P, F->N, D, v, NULL) : !(m >> l & 1)) continue;
                /* a folded triangle's vertices: changed, and listed once */
                for (int k = 0; k < 3; k++) {
                    fresh += !changed[v[k]];
                    changed[v[k]] = 1;
                    if (halved[v[k]] != round + 1) {
                        halved[v[k]] = round + 1;
                        R->hit[nh++] = v[k];
                    }
                }
                folded++;
            }
        }
        if (!folded) {
            /* watch lists every triangle with a changed vertex unless it
             * overflowed (none changed when the first round ends it) */
            if (all && round) R->listed = 0;
            break;
        }
        for (size_t h = 0; h < nh; h++) D[R->hit[h]] = round < FOLD_HALVINGS ? 0.5f * D[R->hit[h]] : 0.0f;
        if (!fresh) continue;
        R->nw = 0, all = 0; /* too many to list: every triangle */
        if (mark_triangles(pool, idx, nt, changed, R->tbits) > R->capw) all = 1;
        else
            for (size_t w = 0; w < (nt + 63) / 64; w++)
                for (uint64_t b = R->tbits[w]; b; b &= b - 1) R->watch[R->nw++] = (uint32_t)(64 * w + (size_t)__builtin_ctzll(b));
    }
    jm_free(mem, F->bits, (nw + 1) * sizeof *F->bits);
    F->bits = NULL;
    return 1;
}

int jm_meta_finish(jm_mem *mem, jm_pool *pool, float *pos, float *nrm, size_t nv, const uint32_t *idx, size_t nt,
                   int compensate, int facing, float max_sag)
{
    /* per vertex: sag * area, area; then each vertex's offset D; once D
     * is found, the first nv bytes are the flags of the facing, the next
     * nv those of the vertices the fold rounds changed, and from byte 4 nv
     * the round that last halved each vertex (plus one) */
    float *acc = jm_alloc(mem, (3 * nv + 1) * sizeof(float));
    if (!acc) return 0;
    float *D = acc + 2 * nv;
    uint8_t *flag = (uint8_t *)acc, *changed = (uint8_t *)acc + nv;
    uint32_t *halved = (uint32_t *)(void *)(acc + nv);
    /* 16 triangles a pass where the CPU can (metafinish16.c), else 8
     * (metafinish8.c): the same bits as one at a time */
    fin F = {pos, nrm, NULL, idx, nt, facing, jm_finish16_ok() ? 16 : (jm_finish8_ok() ? 8 : 1), NULL, NULL, 0, NULL};
    rounds R = {NULL, NULL, NULL, FINISH_LIST(nt), 0, 0, 1, NULL};
    const size_t tbsz = (nt / 64 + 1) * sizeof *R.tbits;
    R.tbits = jm_alloc(mem, tbsz);
    int ok = R.tbits != NULL;
    if (ok && compensate) {
        R.watch = jm_alloc(mem, (2 * R.capw + nv) * sizeof *R.watch);
        ok = R.watch != NULL;
        if (ok) {
            R.awl = R.watch + R.capw;
            R.hit = R.awl + R.capw;
            ok = sag_offsets(mem, pool, &F, acc, D, nv, max_sag) && fold_rounds(mem, pool, &F, D, changed, halved, nv, &R);
        }
        if (ok) {
            vtx_job V = {NULL, D, pos, nrm, nv, 0.0f};
            jm_pool_run(pool, (nv + VTX_CHUNK - 1) / VTX_CHUNK, 1, move_task, &V);
        }
    }
    if (ok && facing) {
        /* every triangle's facing at the moved positions: where the rounds
         * listed them, those the first round found away and are unchanged
         * (the others, unchanged, face) and those with a changed vertex */
        size_t bad;
        memset(flag, 0, nv);
        if (compensate && R.listed)
            bad = flag_away(pos, nrm, idx, R.awl, R.na, flag) + flag_away(pos, nrm, idx, R.watch, R.nw, flag);
        else bad = flag_away(pos, nrm, idx, NULL, nt, flag);
        /* D is spent (added to pos above): its room holds the slots */
        ok = face_normals(mem, pool, pos, nrm, nv, idx, nt, flag, bad, R.tbits, (uint32_t *)(void *)D);
    }
    jm_free(mem, R.tbits, tbsz);
    jm_free(mem, R.watch, (2 * R.capw + nv) * sizeof *R.watch);
    jm_free(mem, acc, (3 * nv + 1) * sizeof(float));
    return ok;
}
