/* metaprobe.c - every metasphere piece evaluated at a block's vertices: those off the exact surface settled again. */
#include "field/meta/metaprobe.h"
#include "field/meta/metapieces.h"
#include "field/meta/metanormal.h"
#include "field/meta/metavertex.h"
#include "extract/tables.h"
#include "core/cpu.h"
#include "core/skew.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A vertex is refined onto the surface of the two pieces that won at its
 * edge's nodes. A third piece can still win in the middle of the edge (a
 * ball or half-neck bulging between two nodes won by others), and Newton
 * steps across the kink where the two pieces meet can stop short: either
 * way the vertex lies off the surface (0.8 % of the jet's vertices, up to
 * 0.33 r inside). Checking each vertex against the pieces near it one by
 * one costs more than the rest of the mesh; here every piece is splatted
 * onto the block's vertices instead, as the field is onto its nodes: the
 * vertices sorted into parts of PART^3 cubes, each piece (both half-necks
 * of a link at once) visits the parts its box reaches and evaluates their
 * vertices four (AVX2: eight) at a time, keeping the largest value at each
 * (about a ninth of the work of checking the vertices one by one). Where that value is off the threshold by more
 * than c->mv_check the vertex is settled again on every piece near it
 * (jm_meta_settle: about 1.2 % of the jet's vertices), so every vertex
 * ends within that of the exact surface. */

#define PART JM_PROBE_PART
/* block.c's JM_T_MIN: vertices are kept this far (of the edge) from nodes */
#define T_MIN 0.01f

/* Grows the k arrays *a[i] (elements of esz[i] bytes), one block whose
 * first array is *a[0] (skew.h), from oldn to newn elements, counted in m
 * (a failure leaves them as they were, so the counts and the capacities
 * stay in step). */
static int grow_all(jm_mem *m, void **a[], const size_t *esz, int k, size_t oldn, size_t newn)
{
    void *b = jm_alloc_lasting(m, jm_skew_bytes(esz, k, newn));
    if (!b) return 0;
    for (int i = 0; i < k; i++) {
        void *nw = jm_skew_at(b, esz, i, newn);
        if (*a[i]) memcpy(nw, *a[i], oldn * esz[i]);
        *a[i] = nw;
    }
    return 1;
}

/* gives back the block of k arrays of n elements that starts at p */
static void free_all(jm_mem *m, void *p, const size_t *esz, int k, size_t n)
{
    if (p) jm_free(m, p, jm_skew_bytes(esz, k, n));
}

/* the per-vertex arrays (slot, t, part, pt) and the sorted ones (order,
 * px, py, pz, vmax) */
static const size_t vert_esz[4] = {sizeof(uint32_t), sizeof(float), sizeof(uint32_t), 3 * sizeof(float)};
static const size_t sort_esz[5] = {sizeof(uint32_t), sizeof(float), sizeof(float), sizeof(float), sizeof(float)};

int jm_probe_grow(jm_probe *pr, size_t v)
{
    size_t nc = pr->cap ? 2 * pr->cap : 1024;
    while (nc <= v) nc *= 2;
    void **a[4] = {(void **)&pr->slot, (void **)&pr->t, (void **)&pr->part, (void **)&pr->pt};
    void *old = pr->slot;
    if (!grow_all(pr->mem, a, vert_esz, 4, pr->cap, nc)) return 0;
    free_all(pr->mem, old, vert_esz, 4, pr->cap);
    pr->cap = nc;
    return 1;
}

void jm_probe_free(jm_probe *pr)
{
    jm_mem *m = pr->mem;
    free_all(m, pr->slot, vert_esz, 4, pr->cap);
    free_all(m, pr->order, sort_esz, 5, pr->capw);
    jm_free(m, pr->pstart, pr->capp * sizeof(uint32_t));
    memset(pr, 0, sizeof *pr);
    pr->mem = m;
}

static int reserve(jm_probe *pr, size_t n, size_t parts)
{
    if (n > pr->capw) {
        size_t nc = pr->capw ? 2 * pr->capw : 1024;
        while (nc < n) nc *= 2;
        void **a[5] = {(void **)&pr->order, (void **)&pr->px, (void **)&pr->py, (void **)&pr->pz, (void **)&pr->vmax};
        void *old = pr->order;
        if (!grow_all(pr->mem, a, sort_esz, 5, pr->capw, nc)) return 0;
        free_all(pr->mem, old, sort_esz, 5, pr->capw);
        pr->capw = nc;
    }
    /* the parts' starts, then four counts (cursors) per part */
    if (5 * parts + 1 > pr->capp) {
        uint32_t *q = jm_realloc_lasting(pr->mem, pr->pstart, pr->capp * sizeof *q, (5 * parts + 1) * sizeof *q);
        if (!q) return 0;
        pr->pstart = q;
        pr->capp = 5 * parts + 1;
    }
    return 1;
}

int jm_probe_match(jm_probe *pr, const jm_probe *o)
{
    if (o->cap > pr->cap && !jm_probe_grow(pr, o->cap - 1)) return 0;
    if (o->capw > pr->capw && !reserve(pr, o->capw, 0)) return 0;
    if (o->capp > pr->capp) {
        uint32_t *q = jm_realloc_lasting(pr->mem, pr->pstart, pr->capp * sizeof *q, o->capp * sizeof *q);
        if (!q) return 0;
        pr->pstart = q;
        pr->capp = o->capp;
    }
    return 1;
}

/* The sorted points (n of them, n >= 4) and their largest values. */
typedef struct rows {
    const float *x, *y, *z;
    float *v;
    size_t n;
} rows;

/* The parts lo..hi (per axis; np a side, vertices ps[part] to
 * ps[part + 1]; the parts lo[0]..hi[0] of a row follow one another, x
 * fastest, so their vertices are one range) visited in runs of W vertices
 * from the start of each row's range (the last shifted back to end at the
 * array's end: a run reaching into other vertices gives them their true
 * values, which changes nothing). */
#define FOR_RUNS(W, ps, np, lo, hi, n, k, ...)                                                             \
    for (int pk_ = lo[2]; pk_ <= hi[2]; pk_++)                                                           \
        for (int pj_ = lo[1]; pj_ <= hi[1]; pj_++) {                                                     \
            const size_t row_ = ((size_t)pk_ * (np) + pj_) * (np);                                       \
            const size_t end_ = ps[row_ + hi[0] + 1];                                                    \
            for (size_t s_ = ps[row_ + lo[0]]; s_ < end_; s_ += (W)) {                                   \
                const size_t k = s_ + (W) <= (n) ? s_ : (n) - (W);                                       \
                __VA_ARGS__                                                                              \
            }                                                                                            \
        }

/* Four vertices at a time: the piece's value at each, kept where it beats
 * the largest so far (the same float operations in the SSE2 and the plain
 * C versions: the same bits). Ball: 1 - |p - q| / r. Half-neck along u
 * from q, half its link long: cos(s / r) - |p - q - s u| / r for
 * s = (p - q).u in [0, half] and |p - q - s u| < rr, nothing elsewhere
 * (within the reach of its box, as the node splat). */
#ifdef __SSE2__
#include <emmintrin.h>
#define HAVE_SSE2_PROBE 1
typedef __m128 vf;
#define V1(x) _mm_set1_ps(x)
#define VLD(p) _mm_loadu_ps(p)
#define VADD _mm_add_ps
#define VSUB _mm_sub_ps
#define VMUL _mm_mul_ps
static void splat_ball4(const rows *R, const uint32_t *ps, int np, const int lo[3], const int hi[3], const float *q,
                       float inv_r)
{
    const float *restrict X = R->x, *restrict Y = R->y, *restrict Z = R->z;
    float *restrict V = R->v;
    const vf qx = V1(q[0]), qy = V1(q[1]), qz = V1(q[2]), ir = V1(inv_r), one = V1(1.0f);
    FOR_RUNS(4, ps, np, lo, hi, R->n, k, {
        vf dx = VSUB(VLD(X + k), qx), dy = VSUB(VLD(Y + k), qy), dz = VSUB(VLD(Z + k), qz);
        vf d2 = VADD(VADD(VMUL(dx, dx), VMUL(dy, dy)), VMUL(dz, dz));
        vf v = VSUB(one, VMUL(_mm_sqrt_ps(d2), ir));
        _mm_storeu_ps(V + k, _mm_max_ps(v, VLD(V + k)));
    })
}
static void splat_link4(const rows *R, const uint32_t *ps, int np, const int lo[3], const int hi[3], const float *q,
                       const float *u, float D, float rr2, float inv_r)
{
    const float *restrict X = R->x, *restrict Y = R->y, *restrict Z = R->z;
    float *restrict V = R->v;
    const vf qx = V1(q[0]), qy = V1(q[1]), qz = V1(q[2]), ux = V1(u[0]), uy = V1(u[1]), uz = V1(u[2]);
    const vf dd = V1(D), r2 = V1(rr2), ir = V1(inv_r), zero = _mm_setzero_ps();
    FOR_RUNS(4, ps, np, lo, hi, R->n, k, {
        vf wx = VSUB(VLD(X + k), qx), wy = VSUB(VLD(Y + k), qy), wz = VSUB(VLD(Z + k), qz);
        vf s = VADD(VADD(VMUL(wx, ux), VMUL(wy, uy)), VMUL(wz, uz));
        vf q2 = VSUB(VADD(VADD(VMUL(wx, wx), VMUL(wy, wy)), VMUL(wz, wz)), VMUL(s, s));
        vf ok = _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(s, zero), _mm_cmple_ps(s, dd)), _mm_cmplt_ps(q2, r2));
        if (!_mm_movemask_ps(ok)) continue;
        /* the nearer end's half-neck */
        vf t = VMUL(_mm_min_ps(s, VSUB(dd, s)), ir), t2 = VMUL(t, t);
        /* jm_cos_quarter, term by term */
        vf cs = VSUB(V1(1.0f / 40320), VMUL(t2, V1(1.0f / 3628800)));
        cs = VADD(V1(-1.0f / 720), VMUL(t2, cs));
        cs = VADD(V1(1.0f / 24), VMUL(t2, cs));
        cs = VADD(V1(-0.5f), VMUL(t2, cs));
        cs = VADD(V1(1.0f), VMUL(t2, cs));
        vf v = VSUB(cs, VMUL(_mm_sqrt_ps(_mm_max_ps(q2, zero)), ir));
        vf old = VLD(V + k);
        _mm_storeu_ps(V + k, _mm_or_ps(_mm_and_ps(ok, _mm_max_ps(v, old)), _mm_andnot_ps(ok, old)));
    })
}
#if defined(__x86_64__) && defined(__GNUC__) && !defined(JM_NO_CLONES)
#include <immintrin.h>
#define HAVE_AVX2_PROBE 1
/* the same operations eight vertices at a time */
__attribute__((target("avx2"))) static void splat_ball8(const rows *R, const uint32_t *ps, int np, const int lo[3],
                                                          const int hi[3], const float *q, float inv_r)
{
    const float *restrict X = R->x, *restrict Y = R->y, *restrict Z = R->z;
    float *restrict V = R->v;
    const __m256 qx = _mm256_set1_ps(q[0]), qy = _mm256_set1_ps(q[1]), qz = _mm256_set1_ps(q[2]);
    const __m256 ir = _mm256_set1_ps(inv_r), one = _mm256_set1_ps(1.0f);
    FOR_RUNS(8, ps, np, lo, hi, R->n, k, {
        __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(X + k), qx), dy = _mm256_sub_ps(_mm256_loadu_ps(Y + k), qy);
        __m256 dz = _mm256_sub_ps(_mm256_loadu_ps(Z + k), qz);
        __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
        __m256 v = _mm256_sub_ps(one, _mm256_mul_ps(_mm256_sqrt_ps(d2), ir));
        _mm256_storeu_ps(V + k, _mm256_max_ps(v, _mm256_loadu_ps(V + k)));
    })
}
__attribute__((target("avx2"))) static void splat_link8(const rows *R, const uint32_t *ps, int np, const int lo[3],
                                                          const int hi[3], const float *q, const float *u, float D,
                                                          float rr2, float inv_r)
{
    const float *restrict X = R->x, *restrict Y = R->y, *restrict Z = R->z;
    float *restrict V = R->v;
    const __m256 qx = _mm256_set1_ps(q[0]), qy = _mm256_set1_ps(q[1]), qz = _mm256_set1_ps(q[2]);
    const __m256 ux = _mm256_set1_ps(u[0]), uy = _mm256_set1_ps(u[1]), uz = _mm256_set1_ps(u[2]);
    const __m256 dd = _mm256_set1_ps(D), r2 = _mm256_set1_ps(rr2), ir = _mm256_set1_ps(inv_r);
    const __m256 zero = _mm256_setzero_ps();
    FOR_RUNS(8, ps, np, lo, hi, R->n, k, {
        __m256 wx = _mm256_sub_ps(_mm256_loadu_ps(X + k), qx), wy = _mm256_sub_ps(_mm256_loadu_ps(Y + k), qy);
        __m256 wz = _mm256_sub_ps(_mm256_loadu_ps(Z + k), qz);
        __m256 s = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(wx, ux), _mm256_mul_ps(wy, uy)), _mm256_mul_ps(wz, uz));
        __m256 q2 = _mm256_sub_ps(
            _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(wx, wx), _mm256_mul_ps(wy, wy)), _mm256_mul_ps(wz, wz)),
            _mm256_mul_ps(s, s));
        __m256 ok = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(s, zero, _CMP_GE_OQ), _mm256_cmp_ps(s, dd, _CMP_LE_OQ)),
                                  _mm256_cmp_ps(q2, r2, _CMP_LT_OQ));
        if (!_mm256_movemask_ps(ok)) continue;
        __m256 t = _mm256_mul_ps(_mm256_min_ps(s, _mm256_sub_ps(dd, s)), ir), t2 = _mm256_mul_ps(t, t);
        __m256 cs = _mm256_sub_ps(_mm256_set1_ps(1.0f / 40320), _mm256_mul_ps(t2, _mm256_set1_ps(1.0f / 3628800)));
        cs = _mm256_add_ps(_mm256_set1_ps(-1.0f / 720), _mm256_mul_ps(t2, cs));
        cs = _mm256_add_ps(_mm256_set1_ps(1.0f / 24), _mm256_mul_ps(t2, cs));
        cs = _mm256_add_ps(_mm256_set1_ps(-0.5f), _mm256_mul_ps(t2, cs));
        cs = _mm256_add_ps(_mm256_set1_ps(1.0f), _mm256_mul_ps(t2, cs));
        __m256 v = _mm256_sub_ps(cs, _mm256_mul_ps(_mm256_sqrt_ps(_mm256_max_ps(q2, zero)), ir));
        __m256 old = _mm256_loadu_ps(V + k);
        _mm256_storeu_ps(V + k, _mm256_blendv_ps(old, _mm256_max_ps(v, old), ok));
    })
}
#endif
#endif
/* plain C, four at a time as above */
static void splat_ball(const rows *R, const uint32_t *ps, int np, const int lo[3], const int hi[3], const float *q,
                       float inv_r)
{
    FOR_RUNS(4, ps, np, lo, hi, R->n, k, {
        for (int l = 0; l < 4; l++) {
            float dx = R->x[k + l] - q[0], dy = R->y[k + l] - q[1], dz = R->z[k + l] - q[2];
            float v = 1.0f - sqrtf(dx * dx + dy * dy + dz * dz) * inv_r;
            if (v > R->v[k + l]) R->v[k + l] = v;
        }
    })
}
static void splat_link(const rows *R, const uint32_t *ps, int np, const int lo[3], const int hi[3], const float *q,
                       const float *u, float D, float rr2, float inv_r)
{
    FOR_RUNS(4, ps, np, lo, hi, R->n, k, {
        for (int l = 0; l < 4; l++) {
            float wx = R->x[k + l] - q[0], wy = R->y[k + l] - q[1], wz = R->z[k + l] - q[2];
            float s = wx * u[0] + wy * u[1] + wz * u[2];
            float q2 = wx * wx + wy * wy + wz * wz - s * s;
            if (!(s >= 0.0f && s <= D && q2 < rr2)) continue;
            float sn = s < D - s ? s : D - s;
            float v = jm_cos_quarter(sn * inv_r) - sqrtf(q2 > 0.0f ? q2 : 0.0f) * inv_r;
            if (v > R->v[k + l]) R->v[k + l] = v;
        }
    })
}


/* node and direction of a vertex slot, and its edge a + t ab */
static void edge_of(uint32_t slot, size_t sn, const float *x, const float *y, const float *z, int ijk[3], float a[3],
                    float ab[3])
{
    size_t node = slot / 7;
    const int *d = jm_dir[slot % 7];
    ijk[0] = (int)(node % sn);
    ijk[1] = (int)((node / sn) % sn);
    ijk[2] = (int)(node / (sn * sn));
    a[0] = x[ijk[0]];
    a[1] = y[ijk[1]];
    a[2] = z[ijk[2]];
    ab[0] = x[ijk[0] + d[0]] - a[0];
    ab[1] = y[ijk[1] + d[1]] - a[1];
    ab[2] = z[ijk[2] + d[2]] - a[2];
}

/* the probe's pieces: the largest value at each vertex */
typedef struct probe_ctx {
    const rows *R;
    const uint32_t *ps;
    int np;
    float inv_r;
    int level; /* cpu.h's: eight vertices at a time from AVX2, four from SSE2 */
} probe_ctx;
static void probe_ball(void *ctx, const int lo[3], const int hi[3], const float *q)
{
    const probe_ctx *k = ctx;
#ifdef HAVE_AVX2_PROBE
    if (k->level >= JM_CPU_AVX2) {
        splat_ball8(k->R, k->ps, k->np, lo, hi, q, k->inv_r);
        return;
    }
#endif
#ifdef HAVE_SSE2_PROBE
    if (k->level >= JM_CPU_SSE2) {
        splat_ball4(k->R, k->ps, k->np, lo, hi, q, k->inv_r);
        return;
    }
#endif
    splat_ball(k->R, k->ps, k->np, lo, hi, q, k->inv_r);
}
static void probe_link(void *ctx, const int lo[3], const int hi[3], const float *q, const float *u, float D, float rr2)
{
    const probe_ctx *k = ctx;
#ifdef HAVE_AVX2_PROBE
    if (k->level >= JM_CPU_AVX2) {
        splat_link8(k->R, k->ps, k->np, lo, hi, q, u, D, rr2, k->inv_r);
        return;
    }
#endif
#ifdef HAVE_SSE2_PROBE
    if (k->level >= JM_CPU_SSE2) {
        splat_link4(k->R, k->ps, k->np, lo, hi, q, u, D, rr2, k->inv_r);
        return;
    }
#endif
    splat_link(k->R, k->ps, k->np, lo, hi, q, u, D, rr2, k->inv_r);
}

int jm_meta_probe(const jm_grid *g, const jm_config *c, const jm_hood *hood, jm_probe *pr, struct jm_mnorm *m, int B,
                  const float *x, const float *y, const float *z, const float *f, float *pos, const uint32_t *cand,
                  size_t nv)
{
    if (!nv) return 1;
    /* parts of 4 cubes a side, 2 where the block is crowded (the tunnels
     * of bulk fluid, JM_PROBE_CROWDED vertices or more; a jet's blocks hold
     * a few hundred): smaller parts visit fewer vertices there */
    pr->pc = nv >= JM_PROBE_CROWDED ? 2 : 4;
    const int np = jm_probe_parts(B, pr->pc);
    const size_t parts = (size_t)np * np * np, sn = (size_t)B + 1, ns = nv < 8 ? 8 : nv;
    if (!reserve(pr, ns, parts)) return 0;
    const float thr = c->threshold, tol = c->mv_check, inv_r = 1.0f / c->r;
    /* below any value that counts */
    const float level = thr - 2.0f * tol;

    /* counting sort of the vertices by part, counted in four interleaved
     * sets (vertex v in set v % 4: neighbours, often of one part, do not
     * wait on each other's count); within a part the order does not
     * matter (each vertex gets its own maximum) */
    uint32_t *ps = pr->pstart, *cnt = ps + parts + 1;
    const int sh = pr->pc == 2 ? 1 : 2;
    for (size_t v = 0; v < nv; v++) {
        const uint32_t ijk = pr->part[v];
        pr->part[v] = (((ijk >> 16 >> sh) * (uint32_t)np + ((ijk >> 8 & 255) >> sh)) * (uint32_t)np) + ((ijk & 255) >> sh);
    }
    memset(cnt, 0, 4 * parts * sizeof *cnt);
    for (size_t v = 0; v < nv; v++) cnt[(v & 3) * parts + pr->part[v]]++;
    uint32_t acc = 0;
    for (size_t q = 0; q < parts; q++) {
        ps[q] = acc;
        for (size_t k = 0; k < 4; k++) {
            const uint32_t m = cnt[k * parts + q];
            cnt[k * parts + q] = acc;
            acc += m;
        }
    }
    ps[parts] = acc;
    for (size_t v = 0; v < nv; v++) {
        size_t w = cnt[(v & 3) * parts + pr->part[v]]++;
        pr->order[w] = (uint32_t)v;
        pr->px[w] = pr->pt[3 * v];
        pr->py[w] = pr->pt[3 * v + 1];
        pr->pz[w] = pr->pt[3 * v + 2];
        pr->vmax[w] = level;
    }
    for (size_t w = nv; w < ns; w++) {
        /* fewer than 8 vertices: far away dummies */
        pr->px[w] = pr->py[w] = pr->pz[w] = 1e30f;
        pr->vmax[w] = level;
    }

    /* every piece onto the vertices of the parts its box reaches: a ball
     * exceeds `level` only within r (1 - level) of its centre, a neck
     * within as much of its axis; and up to pi/2 r along its axis a
     * half-neck beats its own ball only closer than r to the axis (see
     * field.c), where that ball holds the value */
    const rows R = {pr->px, pr->py, pr->pz, pr->vmax, ns};
    const float slack = 1e-3f * c->r, rb = c->r * (1.0f - level) + slack;
    const float rn = fminf(rb, 1.02f * c->r + slack);
    if (m) {
        /* the normals' pass, which reaches further (metanormal.h) */
        if (!jm_meta_normals_probe(g, c, hood, pr, m, B, x, y, z, nv, rb, rn)) return 0;
    } else {
        probe_ctx pc = {&R, ps, np, inv_r, jm_cpu_level()};
        const jm_piece_visitor vis = {rb, rn, probe_ball, probe_link, &pc};
        jm_probe_pieces(g, c, hood, B, pr->pc, x, y, z, &vis);
    }

    /* the vertices off the surface, settled again on every piece there */
    for (size_t w = 0; w < nv; w++) {
        const float vm = pr->vmax[w];
        if (vm <= thr + tol && vm >= thr - tol) continue;
        const uint32_t v = pr->order[w], *cv = &cand[2 * (size_t)v];
        int ijk[3];
        float a[3], ab[3];
        edge_of(pr->slot[v], sn, x, y, z, ijk, a, ab);
        const float fa = f[((size_t)ijk[2] * sn + (size_t)ijk[1]) * sn + (size_t)ijk[0]] - thr;
        /* a piece on the surface at the root: near_scan starts there */
        const uint32_t win = cv[0] != UINT32_MAX ? cv[0] : cv[1];
        float *pv = &pos[3 * (size_t)v];
        float tt = jm_meta_settle(g, c, hood, cv, win, a, ab, fa, pr->t[v]);
        float tc = tt < T_MIN ? T_MIN : (tt > 1.0f - T_MIN ? 1.0f - T_MIN : tt);
        for (int q = 0; q < 3; q++) pv[q] = a[q] + tc * ab[q];
    }
    return 1;
}
