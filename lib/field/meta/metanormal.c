/* metanormal.c - metasphere vertex normals blended from every ball and neck within the blend band of each vertex. */
#include "field/meta/metanormal.h"
#include "field/meta/metapieces.h"
#include "core/cpu.h"
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
    float *a = jm_alloc_lasting(m->mem, nc * PER_VERTEX);
    if (!a) return 0;
    jm_free(m->mem, m->acc, m->cap * PER_VERTEX);
    m->acc = a;
    m->sub = a + 3 * nc;
    m->moved = (uint32_t *)(a + 9 * nc);
    m->cap = nc;
    return 1;
}

int jm_mnorm_match(jm_mnorm *m, const jm_mnorm *o)
{
    if (!reserve(m, o->cap)) return 0;
    if (o->capvisit > m->capvisit) {
        jm_visit *b = jm_realloc_lasting(m->mem, m->visit, m->capvisit * sizeof *b, o->capvisit * sizeof *b);
        if (!b) return 0;
        m->visit = b;
        m->capvisit = o->capvisit;
    }
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
    int wide;           /* 0 plain C, 1 AVX2, 2 AVX-512 (cpu.h's level) */
} pass;

/* the fused pass's visit of a piece, kept for jm_meta_normals_finish (out
 * of memory: it enumerates the pieces again) */
static void record(jm_mnorm *m, const int lo[3], const int hi[3], const float *q, const float *u, float D, float rr2)
{
    if (!m || !m->visits) return;
    if (m->nvisit == m->capvisit) {
        size_t nc = m->capvisit ? 2 * m->capvisit : 256;
        jm_visit *b = jm_realloc_lasting(m->mem, m->visit, m->capvisit * sizeof *b, nc * sizeof *b);
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

#if defined(__x86_64__) && defined(__GNUC__) && !defined(JM_NO_CLONES)
#include <immintrin.h>
#define HAVE_AVX2_NORMALS 1

/* The kernels in runs of 8 (AVX2) and of 16 (AVX-512, where the pass
 * has 16 points or more), written once in metanormal_simd.h: each lane does
 * the plain C's operations, the same bits at both widths. */
#define VT8 __m256
#define MT8 __m256
#define TGT8 "avx2"
#define PFX8 _mm256
#define B8(x) _mm256_set1_ps(x)
#define LANES8(k, s, e)                                                                                    \
    _mm256_castsi256_ps(_mm256_and_si256(                                                                \
        _mm256_cmpgt_epi32(_mm256_add_epi32(_mm256_set1_epi32((int)(k)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)), \
                           _mm256_set1_epi32((int)(s) - 1)),                                             \
        _mm256_cmpgt_epi32(_mm256_set1_epi32((int)(e)),                                                  \
                           _mm256_add_epi32(_mm256_set1_epi32((int)(k)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)))))
#define CMP8(a, b, op) _mm256_cmp_ps(a, b, op)
#define AND8(a, b) _mm256_and_ps(a, b)
#define ANY8(m) _mm256_movemask_ps(m)
#define SEL8(m, a, b) _mm256_blendv_ps(a, b, m)
#define KEEPMAX8(old, m, v) _mm256_blendv_ps(old, _mm256_max_ps(v, old), m)
#define ADDM8(old, m, x) _mm256_blendv_ps(old, _mm256_add_ps(old, x), m)
#define W 8
#include "field/meta/metanormal_simd.h"
#undef W

#define VT16 __m512
#define MT16 __mmask16
#define TGT16 "avx512f"
#define PFX16 _mm512
#define B16(x) _mm512_set1_ps(x)
#define LANES16(k, s, e)                                                                                   \
    (_mm512_cmpgt_epi32_mask(_mm512_add_epi32(_mm512_set1_epi32((int)(k)), _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)), \
                             _mm512_set1_epi32((int)(s) - 1)) &                                          \
     _mm512_cmpgt_epi32_mask(_mm512_set1_epi32((int)(e)),                                                \
                             _mm512_add_epi32(_mm512_set1_epi32((int)(k)), _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15))))
#define CMP16(a, b, op) _mm512_cmp_ps_mask(a, b, op)
#define AND16(a, b) ((__mmask16)((a) & (b)))
#define ANY16(m) (m)
#define SEL16(m, a, b) _mm512_mask_blend_ps(m, a, b)
#define KEEPMAX16(old, m, v) _mm512_mask_max_ps(old, m, v, old)
#define ADDM16(old, m, x) _mm512_mask_add_ps(old, m, old, x)
#define W 16
#include "field/meta/metanormal_simd.h"
#undef W
/* 16 lanes where the CPU has AVX-512 and the pass has 16 points or more */
static inline int use16(const void *ctx) { return ((const pass *)ctx)->wide == 2 && ((const pass *)ctx)->n >= 16; }
#endif


/* the pieces' weighted gradients onto the vertices, eight at a time
 * where the CPU runs AVX2 (the same bits); the fused pass keeps the
 * probe's largest values on the way */
static void normal_ball(void *ctx, const int lo[3], const int hi[3], const float *q)
{
#ifdef HAVE_AVX2_NORMALS
    if (((const pass *)ctx)->wide) {
        if (use16(ctx)) ball16(ctx, lo, hi, q);
        else ball8(ctx, lo, hi, q);
        return;
    }
#endif
    ball_c(ctx, lo, hi, q);
}
static void normal_link(void *ctx, const int lo[3], const int hi[3], const float *q, const float *u, float D, float rr2)
{
#ifdef HAVE_AVX2_NORMALS
    if (((const pass *)ctx)->wide) {
        if (use16(ctx)) link16(ctx, lo, hi, q, u, D, rr2);
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
    if (((const pass *)ctx)->wide) {
        if (use16(ctx)) ball16p(ctx, lo, hi, q);
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
    if (((const pass *)ctx)->wide) {
        if (use16(ctx)) link16p(ctx, lo, hi, q, u, D, rr2, rp * rp);
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
static pass make_pass(const jm_config *c, int np, const float *x, const float *y, const float *z, size_t n,
                      const uint32_t *ps, float *acc)
{
    memset(acc, 0, n * 3 * sizeof(float));
    /* a piece comes within tau of the threshold only within rb of its
     * particle (a ball) or of its axis (a neck): r (1 - (thr - tau)) */
    const float rb = band_reach(c);
    pass P = {x, y, z, acc, acc + n, acc + 2 * n, n, ps, np, c->threshold, 1.0f / c->mv_tau,
              1.0f / c->r, rb * rb, NULL, c->r, 0.0f, 0.0f, {0, 0, 0}, {0, 0, 0}, NULL, 0};
    const int level = jm_cpu_level();
    P.wide = level >= JM_CPU_AVX512 ? 2 : level >= JM_CPU_AVX2;
    return P;
}
int jm_meta_normals_probe(const jm_grid *g, const jm_config *c, const jm_hood *hood, jm_probe *pr, jm_mnorm *m, int B,
                          const float *x, const float *y, const float *z, size_t nv, float rb_probe, float rn_probe)
{
    const size_t ns = nv < 8 ? 8 : nv;
    if (!reserve(m, ns)) return 0;
    pass P = make_pass(c, jm_probe_parts(B, pr->pc), pr->px, pr->py, pr->pz, ns, pr->pstart, m->acc);
    P.vm = pr->vmax;
    P.rb_probe = rb_probe;
    P.rn_probe = rn_probe;
    m->nvisit = 0;
    m->visits = 1;
    P.rec = m;
    const float reach = band_reach(c);
    const jm_piece_visitor vis = {reach, reach, fused_ball, fused_link, &P};
    jm_probe_pieces(g, c, hood, B, pr->pc, x, y, z, &vis);
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
        const int np = jm_probe_parts(B, pr->pc);
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
        pass P = make_pass(c, np, sx, sy, sz, n2, ps, sacc);
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
            jm_probe_pieces(g, c, hood, B, pr->pc, x, y, z, &vis);
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
