/* interpolate.c - per-particle values carried onto mesh vertices: vertices bucketed by cell, each bucket gathering its particles once, summed in 8 float lanes on the pool's threads. */
#include "post/interpolate.h"
#include "core/cpu.h"
#include "core/cubic8.h"
#include "grid/cellbins.h"
#include <string.h>

/*
 * The weights of jm_interpolate_attributes (attributes.c),
 *     a(v) = sum_j a_j W(|v - c_j|, h) / sum_j W(|v - c_j|, h)
 * over the particles within the support 2h of v, the nearest particle's
 * values where none is in reach. That one sums every vertex alone over the
 * 27 cells around it, in double precision on one thread: 1.4 times the
 * meshing's own time on a 6,859-particle frame (issue 32). Here:
 *  - the particles are binned once into cells of edge 2h, their positions
 *    (in the library's unit) and values copied in cell order;
 *  - the vertices are bucketed by cells of edge 2h too (one serial pass):
 *    a bucket gathers once, in groups of 8, the particles within 2h of its
 *    vertices' box;
 *  - every vertex of the bucket sums those groups in 8 float lanes (lane l
 *    takes the gathered particles l, l + 8, ...), the lanes added in a
 *    fixed tree at the end; the hand-written AVX2 loop skips the groups
 *    with no particle in reach, whose lanes would add zeros (the same
 *    bits as the plain loop);
 *  - the buckets go to the pool's threads.
 * A vertex's sums depend only on its bucket's gathered particles, and the
 * buckets only on the vertex positions: the same bits for any thread count.
 * Finer buckets (edge h) gather fewer particles a vertex but gather four
 * times as often, which costs more in all.
 */

typedef struct {
    float *buf; /* groups of 8: x, y, z, then the T components, 8 lanes each */
    size_t cap; /* groups */
} ip_worker;

typedef struct {
    jm_mem *mem;
    const jm_config *c;
    const jm_particles *in;
    const uint8_t *skip;
    const float *vpos;
    jm_attribute *attr;
    size_t nv, na;
    int T;
    float unit_in, inv_h, R2, invC, margin;
    /* the particles by cell */
    jm_cellbins bins;
    float *bpos, *bval; /* 3 and T floats per binned particle, in bins order */
    uint32_t *from;     /* the input index of each kept particle (bins.items' numbers) */
    size_t nb;
    /* the vertices by bucket (cells of edge 2h) */
    uint32_t *order;    /* the vertices by bucket */
    uint32_t *bstart;   /* nbuckets + 1 starts in order */
    size_t nbuckets;
    ip_worker *w;
    int nw;
    int failed;
} ip_job;

jm_status jm_interp_check(const jm_particles *in, const float *positions, size_t nv, const jm_attribute *attrs,
                          size_t na, size_t *out_total)
{
    size_t total = 0;
    *out_total = 0;
    if (!in || (nv && !positions) || (na && !attrs) || (in->count && !in->xyz) || in->count > UINT32_MAX - 1)
        return JM_E_INVALID_ARGUMENT;
    if (in->stride && in->stride < 3 * sizeof(float)) return JM_E_INVALID_ARGUMENT;
    for (size_t a = 0; a < na; a++) {
        const jm_attribute *at = &attrs[a];
        if (at->components < 1 || at->components > 16 || (in->count && !at->particle_values) ||
            (nv && !at->vertex_values))
            return JM_E_INVALID_ARGUMENT;
        total += (size_t)at->components;
    }
    if (total > 64) return JM_E_INVALID_ARGUMENT;
    *out_total = total;
    return JM_OK;
}

static const float *pos_of(const jm_particles *p, size_t i)
{
    size_t stride = p->stride ? p->stride : 3 * sizeof(float);
    return (const float *)(const void *)((const char *)p->xyz + i * stride);
}

static int64_t cell_of(float x, float inv)
{
    return (int64_t)floorf(x * inv);
}

/* The particles not skipped, binned by cell (cellbins.h: input order
 * within a cell), their positions in units and values copied in that order. */
static jm_status bins_build(ip_job *j)
{
    const jm_particles *in = j->in;
    const size_t n = in->count;
    size_t kept = 0;
    for (size_t i = 0; i < n; i++) {
        const float *x = pos_of(in, i);
        for (int k = 0; k < 3; k++)
            if (!isfinite(x[k])) return JM_E_INVALID_PARTICLE;
        kept += !(j->skip && j->skip[i]);
    }
    j->nb = kept;
    if (!kept) return JM_OK;
    float *upos = jm_alloc(j->mem, 3 * kept * sizeof *upos);
    uint32_t *from = j->from = jm_alloc(j->mem, kept * sizeof *from);
    jm_status s = upos && from ? JM_OK : JM_E_OUT_OF_MEMORY;
    for (size_t i = 0, k = 0; s == JM_OK && i < n; i++) {
        if (j->skip && j->skip[i]) continue;
        const float *x = pos_of(in, i);
        for (int a = 0; a < 3; a++) upos[3 * k + a] = x[a] * j->unit_in;
        from[k++] = (uint32_t)i;
    }
    if (s == JM_OK) s = jm_cellbins_build(&j->bins, j->mem, upos, kept, j->c->support);
    if (s == JM_OK) {
        j->bpos = jm_alloc(j->mem, 3 * kept * sizeof *j->bpos);
        j->bval = jm_alloc(j->mem, (size_t)j->T * kept * sizeof *j->bval);
        if (!j->bpos || !j->bval) s = JM_E_OUT_OF_MEMORY;
    }
    for (size_t q = 0; s == JM_OK && q < kept; q++) {
        const uint32_t k = j->bins.items[q];
        const size_t i = from[k];
        memcpy(j->bpos + 3 * q, upos + 3 * (size_t)k, 3 * sizeof *j->bpos);
        float *o = j->bval + (size_t)j->T * q;
        for (size_t a = 0; a < j->na; a++) {
            const size_t nc = (size_t)j->attr[a].components;
            memcpy(o, j->attr[a].particle_values + i * nc, nc * sizeof *o);
            o += nc;
        }
    }
    jm_free(j->mem, upos, 3 * kept * sizeof *upos);
    return s;
}

/* Buckets the vertices by cells of edge 2h: order gets
 * the vertices bucket by bucket (buckets in order of first appearance,
 * vertex order within), bstart the buckets' starts. JM_E_INVALID_ARGUMENT for
 * a coordinate that is not finite. */
static jm_status bucket_vertices(ip_job *j)
{
    const float inv = j->invC;
    int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    for (size_t v = 0; v < j->nv; v++)
        for (int k = 0; k < 3; k++) {
            const float x = j->vpos[3 * v + k] * j->unit_in;
            if (!isfinite(x)) return JM_E_INVALID_ARGUMENT;
            const int64_t c = cell_of(x, inv);
            if (c < lo[k]) lo[k] = c;
            if (c > hi[k]) hi[k] = c;
        }
    for (int k = 0; k < 3; k++)
        if (hi[k] - lo[k] >= JM_KEY_MAX - 1) return JM_E_TOO_LARGE;
    jm_hashmap map;
    memset(&map, 0, sizeof map);
    uint32_t *bof = jm_alloc(j->mem, j->nv * sizeof *bof);
    j->order = jm_alloc(j->mem, j->nv * sizeof *j->order);
    jm_status s = bof && j->order ? jm_hashmap_init(&map, j->mem, j->nv / 8 + 64) : JM_E_OUT_OF_MEMORY;
    size_t nb = 0;
    for (size_t v = 0; s == JM_OK && v < j->nv; v++) {
        int64_t q[3];
        for (int k = 0; k < 3; k++) q[k] = cell_of(j->vpos[3 * v + k] * j->unit_in, inv) - lo[k];
        uint32_t *b = jm_hashmap_upsert(&map, jm_key3(q[0], q[1], q[2]));
        if (*b == UINT32_MAX) *b = (uint32_t)nb++;
        bof[v] = *b;
        if (2 * map.count + 1 > map.cap) { /* grow: the map was sized for 8 vertices a bucket */
            jm_hashmap big;
            s = jm_hashmap_init(&big, j->mem, 2 * map.count);
            for (size_t i = 0; s == JM_OK && i < map.cap; i++)
                if (map.keys[i] != JM_HASH_EMPTY) *jm_hashmap_upsert(&big, map.keys[i]) = map.vals[i];
            jm_hashmap_free(&map, j->mem);
            map = big;
        }
    }
    if (s == JM_OK) {
        j->bstart = jm_calloc(j->mem, nb + 1, sizeof *j->bstart);
        if (!j->bstart) s = JM_E_OUT_OF_MEMORY;
    }
    if (s == JM_OK) {
        j->nbuckets = nb;
        for (size_t v = 0; v < j->nv; v++) j->bstart[bof[v] + 1]++;
        for (size_t b = 0; b < nb; b++) j->bstart[b + 1] += j->bstart[b];
        for (size_t v = 0; v < j->nv; v++) j->order[j->bstart[bof[v]]++] = (uint32_t)v;
        for (size_t b = nb; b > 0; b--) j->bstart[b] = j->bstart[b - 1];
        j->bstart[0] = 0;
    }
    if (map.keys) jm_hashmap_free(&map, j->mem);
    jm_free(j->mem, bof, j->nv * sizeof *bof);
    return s;
}

/* The bucket's particles within reach of its box [lo, hi] (units), in groups
 * of 8 (the last padded with weightless particles far away); the count of
 * groups, or SIZE_MAX when out of memory. */
static size_t gather(const ip_job *j, ip_worker *w, const float lo[3], const float hi[3])
{
    const size_t stride = (size_t)(3 + j->T) * 8;
    int64_t c0[3], c1[3];
    for (int k = 0; k < 3; k++) {
        c0[k] = jm_cellbins_coord(&j->bins, lo[k] - j->margin) - j->bins.lo[k];
        c1[k] = jm_cellbins_coord(&j->bins, hi[k] + j->margin) - j->bins.lo[k];
        if (c0[k] < 0) c0[k] = 0;
        if (c1[k] > j->bins.span[k]) c1[k] = j->bins.span[k];
        if (c0[k] > c1[k]) return 0;
    }
    float blo[3], bhi[3];
    for (int k = 0; k < 3; k++) {
        blo[k] = lo[k] - j->margin;
        bhi[k] = hi[k] + j->margin;
    }
    size_t n = 0;
    for (int64_t z = c0[2]; z <= c1[2]; z++)
        for (int64_t y = c0[1]; y <= c1[1]; y++)
            for (int64_t x = c0[0]; x <= c1[0]; x++) {
                const uint32_t cell = jm_cellbins_find(&j->bins, x, y, z);
                if (cell == UINT32_MAX) continue;
                const uint32_t p0 = j->bins.start[cell], p1 = j->bins.start[cell + 1];
                if ((n + (p1 - p0)) / 8 >= w->cap) {
                    size_t nc = w->cap ? 2 * w->cap : 64;
                    while ((n + (p1 - p0)) / 8 >= nc) nc *= 2;
                    float *b = jm_realloc(j->mem, w->buf, w->cap * stride * sizeof *b, nc * stride * sizeof *b);
                    if (!b) return SIZE_MAX;
                    w->buf = b;
                    w->cap = nc;
                }
                /* every particle written to the next slot, which moves on
                 * only for those in the box: no branch to mispredict */
                for (uint32_t p = p0; p < p1; p++) {
                    const float *q = j->bpos + 3 * (size_t)p;
                    const int keep = (q[0] >= blo[0]) & (q[0] <= bhi[0]) & (q[1] >= blo[1]) & (q[1] <= bhi[1]) &
                                     (q[2] >= blo[2]) & (q[2] <= bhi[2]);
                    float *g = w->buf + (n / 8) * stride + (n & 7);
                    g[0] = q[0];
                    g[8] = q[1];
                    g[16] = q[2];
                    const float *v = j->bval + (size_t)j->T * p;
                    for (int c = 0; c < j->T; c++) g[24 + 8 * c] = v[c];
                    n += (size_t)keep;
                }
            }
    for (size_t m = n; m & 7; m++) {
        float *g = w->buf + (m / 8) * stride + (m & 7);
        g[0] = g[8] = g[16] = 1e30f;
        for (int c = 0; c < j->T; c++) g[24 + 8 * c] = 0.0f;
    }
    return (n + 7) / 8;
}

/* The sum of 8 lanes in a fixed tree: (l + l4) for l < 4, then (l + l2)
 * for l < 2, then the two; the AVX2 path adds the same pairs. */
static inline float lanes8(const float *a)
{
    const float t0 = a[0] + a[4], t1 = a[1] + a[5], t2 = a[2] + a[6], t3 = a[3] + a[7];
    return (t0 + t2) + (t1 + t3);
}

/* One vertex's weight sum (out[0]) and weighted sums (out[1 .. T]): lane
 * l of every group of 8 summed in lane l (the weight 0 out of reach), the
 * lanes then added by lanes8. Plain C, built for AVX2 machines and any
 * x86-64 (the same bits). */
JM_BODY void sum_plain_body(const float *g, size_t groups, int T, const float p[3], float R2, float inv,
                                     float *out)
{
    const size_t stride = (size_t)(3 + T) * 8;
    float sw8[8] = {0}, acc8[64 * 8];
    memset(acc8, 0, (size_t)T * 8 * sizeof *acc8);
    for (size_t k = 0; k < groups; k++) {
        const float *b = g + k * stride;
        float w[8];
        for (int l = 0; l < 8; l++) {
            const float dx = p[0] - b[l], dy = p[1] - b[8 + l], dz = p[2] - b[16 + l];
            const float d2 = dx * dx + dy * dy + dz * dz;
            w[l] = d2 < R2 ? jm_cubic_w(sqrtf(d2) * inv) : 0.0f;
            sw8[l] += w[l];
        }
        for (int c = 0; c < T; c++)
            for (int l = 0; l < 8; l++) acc8[8 * c + l] += w[l] * b[24 + 8 * c + l];
    }
    out[0] = lanes8(sw8);
    for (int c = 0; c < T; c++) out[1 + c] = lanes8(acc8 + 8 * c);
}
JM_KERNEL_AVX2(static, void, sum_plain, sum_plain_body, (const float *g, size_t groups, int T, const float p[3], float R2, float inv, float *out), (g, groups, T, p, R2, inv, out))

#ifdef JM_CUBIC8
/* lanes8 of a register */
__attribute__((target("avx2"), always_inline)) static inline float lanes8_avx2(__m256 v)
{
    const __m128 t = _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1)); /* t0..t3 */
    const __m128 u = _mm_add_ps(t, _mm_movehl_ps(t, t));                                  /* t0+t2, t1+t3 */
    return _mm_cvtss_f32(_mm_add_ss(u, _mm_shuffle_ps(u, u, 1)));
}

/* sum_plain by hand in AVX2: the same operations per lane, no FMA; a group
 * with no lane in reach (all weights 0, adding zeros) skipped. */
__attribute__((target("avx2"))) static void sum_avx2(const float *g, size_t groups, int T, const float p[3], float R2,
                                                     float inv, float *out)
{
    const __m256 px = _mm256_set1_ps(p[0]), py = _mm256_set1_ps(p[1]), pz = _mm256_set1_ps(p[2]);
    const __m256 r2 = _mm256_set1_ps(R2), vinv = _mm256_set1_ps(inv);
    const size_t stride = (size_t)(3 + T) * 8;
    __m256 sw = _mm256_setzero_ps(), a0 = sw, a1 = sw, a2 = sw, acc[64];
    if (T != 3)
        for (int c = 0; c < T; c++) acc[c] = sw;
    for (size_t k = 0; k < groups; k++) {
        const float *b = g + k * stride;
        const __m256 dx = _mm256_sub_ps(px, _mm256_loadu_ps(b)), dy = _mm256_sub_ps(py, _mm256_loadu_ps(b + 8));
        const __m256 dz = _mm256_sub_ps(pz, _mm256_loadu_ps(b + 16));
        const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
        const __m256 in = _mm256_cmp_ps(d2, r2, _CMP_LT_OQ);
        if (_mm256_testz_ps(in, in)) continue;
        const __m256 w = _mm256_and_ps(in, jm_cubic_w8(_mm256_mul_ps(_mm256_sqrt_ps(d2), vinv)));
        sw = _mm256_add_ps(sw, w);
        if (T == 3) { /* velocities: the sums in registers */
            a0 = _mm256_add_ps(a0, _mm256_mul_ps(w, _mm256_loadu_ps(b + 24)));
            a1 = _mm256_add_ps(a1, _mm256_mul_ps(w, _mm256_loadu_ps(b + 32)));
            a2 = _mm256_add_ps(a2, _mm256_mul_ps(w, _mm256_loadu_ps(b + 40)));
            continue;
        }
        for (int c = 0; c < T; c++) acc[c] = _mm256_add_ps(acc[c], _mm256_mul_ps(w, _mm256_loadu_ps(b + 24 + 8 * c)));
    }
    out[0] = lanes8_avx2(sw);
    if (T == 3) {
        out[1] = lanes8_avx2(a0);
        out[2] = lanes8_avx2(a1);
        out[3] = lanes8_avx2(a2);
        return;
    }
    for (int c = 0; c < T; c++) out[1 + c] = lanes8_avx2(acc[c]);
}
#endif

/* Binned particle p, if nearer x (units) than *best (ties: the first in
 * input order), by the double distances of attributes.c (the same order:
 * units are world times a power of two). */
static inline void consider(const ip_job *j, const float *x, size_t p, double *bd, uint32_t *best)
{
    const float *q = j->bpos + 3 * p;
    const double ex = (double)x[0] - q[0], ey = (double)x[1] - q[1], ez = (double)x[2] - q[2];
    const double d = ex * ex + ey * ey + ez * ez;
    const uint32_t i = j->from[j->bins.items[p]];
    if (*best == UINT32_MAX || d < *bd || (d == *bd && i < *best)) {
        *bd = d;
        *best = i;
    }
}

static void nearest_in_cell(const ip_job *j, const float *x, int64_t cx, int64_t cy, int64_t cz, double *bd,
                            uint32_t *best)
{
    const uint32_t cell = jm_cellbins_find(&j->bins, cx, cy, cz);
    if (cell == UINT32_MAX) return;
    for (uint32_t p = j->bins.start[cell]; p < j->bins.start[cell + 1]; p++) consider(j, x, p, bd, best);
}

/* No particle in reach: the nearest one's values (the first in input
 * order on a tie), over shells of cells around x's cell (units) until no
 * farther shell can hold a nearer one (a shell of slack for the cells'
 * roundings), or over every particle once the shells would visit more
 * cells than there are particles (cells far smaller than the spacing). */
static void nearest(const ip_job *j, const float *x, size_t v)
{
    const jm_cellbins *b = &j->bins;
    int64_t c[3], kmax = 0;
    for (int a = 0; a < 3; a++) {
        c[a] = jm_cellbins_coord(b, x[a]) - b->lo[a];
        /* the farthest cell of the particles' range on this axis */
        const int64_t d0 = c[a] < 0 ? -c[a] : c[a], d1 = b->span[a] > c[a] ? b->span[a] - c[a] : c[a] - b->span[a];
        if (d0 > kmax) kmax = d0;
        if (d1 > kmax) kmax = d1;
    }
    const double C = (double)j->c->support;
    uint32_t best = UINT32_MAX;
    double bd = INFINITY;
    double cells = 0.0;
    for (int64_t k = 0; k <= kmax; k++) {
        if (best != UINT32_MAX && k >= 2 && bd < ((double)(k - 1) * C) * ((double)(k - 1) * C)) break;
        const double side = 2.0 * (double)k + 1.0;
        cells += side * side * side - (side - 2.0) * (side - 2.0) * (side - 2.0) * (k > 0);
        if (cells > (double)j->nb) { /* every particle: the same minimum */
            for (size_t q = 0; q < j->nb; q++) consider(j, x, q, &bd, &best);
            break;
        }
        for (int64_t dz = -k; dz <= k; dz++)
            for (int64_t dy = -k; dy <= k; dy++) {
                const int rim = dz == -k || dz == k || dy == -k || dy == k;
                for (int64_t dx = -k; dx <= k; dx += rim ? 1 : 2 * k)
                    nearest_in_cell(j, x, c[0] + dx, c[1] + dy, c[2] + dz, &bd, &best);
            }
    }
    for (size_t a = 0; a < j->na; a++) {
        const size_t nc = (size_t)j->attr[a].components;
        memcpy(j->attr[a].vertex_values + v * nc, j->attr[a].particle_values + (size_t)best * nc, nc * sizeof(float));
    }
}

static void bucket_task(void *arg, size_t r, int worker)
{
    ip_job *j = arg;
    ip_worker *w = &j->w[worker];
    const uint32_t v0 = j->bstart[r], v1 = j->bstart[r + 1];
    float lo[3], hi[3];
    for (int k = 0; k < 3; k++) lo[k] = hi[k] = j->vpos[3 * (size_t)j->order[v0] + k] * j->unit_in;
    for (uint32_t i = v0 + 1; i < v1; i++)
        for (int k = 0; k < 3; k++) {
            const size_t v = j->order[i];
            const float x = j->vpos[3 * (size_t)v + k] * j->unit_in;
            if (x < lo[k]) lo[k] = x;
            if (x > hi[k]) hi[k] = x;
        }
    const size_t groups = j->nb ? gather(j, w, lo, hi) : 0;
    if (groups == SIZE_MAX) {
        __atomic_store_n(&j->failed, 1, __ATOMIC_RELAXED);
        return;
    }
#ifdef JM_CUBIC8
    const int avx2 = jm_cpu_avx2();
#endif
    for (uint32_t i = v0; i < v1; i++) {
        const size_t v = j->order[i];
        const float *xw = j->vpos + 3 * v;
        const float x[3] = {xw[0] * j->unit_in, xw[1] * j->unit_in, xw[2] * j->unit_in};
        float sums[65];
#ifdef JM_CUBIC8
        if (avx2) sum_avx2(w->buf, groups, j->T, x, j->R2, j->inv_h, sums);
        else
#endif
            sum_plain(w->buf, groups, j->T, x, j->R2, j->inv_h, sums);
        if (!(sums[0] > 0.0f)) {
            nearest(j, x, v);
            continue;
        }
        const float *acc = sums + 1;
        for (size_t a = 0; a < j->na; a++) {
            const int nc = j->attr[a].components;
            float *out = j->attr[a].vertex_values + v * (size_t)nc;
            for (int cc = 0; cc < nc; cc++) out[cc] = *acc++ / sums[0];
        }
    }
}

static void job_free(ip_job *j)
{
    for (int k = 0; j->w && k < j->nw; k++)
        jm_free(j->mem, j->w[k].buf, j->w[k].cap * (size_t)(3 + j->T) * 8 * sizeof(float));
    jm_free(j->mem, j->w, (size_t)j->nw * sizeof *j->w);
    jm_free(j->mem, j->bstart, (j->nbuckets + 1) * sizeof *j->bstart);
    jm_free(j->mem, j->order, j->nv * sizeof *j->order);
    jm_cellbins_free(&j->bins, j->mem);
    jm_free(j->mem, j->from, j->nb * sizeof *j->from);
    jm_free(j->mem, j->bpos, 3 * j->nb * sizeof *j->bpos);
    jm_free(j->mem, j->bval, (size_t)j->T * j->nb * sizeof *j->bval);
}

jm_status jm_interp_run(jm_mem *mem, jm_pool *pool, const jm_config *c, const uint8_t *skip, const jm_particles *in,
                        const float *positions, size_t nv, jm_attribute *attrs, size_t na)
{
    size_t total = 0;
    jm_status s = jm_interp_check(in, positions, nv, attrs, na, &total);
    if (s != JM_OK) return s;
    if (nv == 0 || na == 0) return JM_OK;
    if (nv > UINT32_MAX - 1) return JM_E_TOO_LARGE; /* the buckets number vertices in 32 bits */
    ip_job j;
    memset(&j, 0, sizeof j);
    j.mem = mem;
    j.c = c;
    j.in = in;
    j.skip = skip;
    j.vpos = positions;
    j.attr = attrs;
    j.nv = nv;
    j.na = na;
    j.T = (int)total;
    j.unit_in = c->unit_in;
    j.inv_h = 1.0f / c->sph_h;
    j.R2 = c->support * c->support;
    j.invC = 1.0f / c->support;
    /* the gathered box reaches a hair past the support: every particle
     * the weights can reach is in it, whatever the roundings */
    j.margin = c->support * 1.001f;
    s = bins_build(&j);
    if (s == JM_OK && j.nb == 0) { /* no particle: zeros, as attributes.c gives */
        for (size_t a = 0; a < na; a++)
            memset(attrs[a].vertex_values, 0, nv * (size_t)attrs[a].components * sizeof(float));
        job_free(&j);
        return JM_OK;
    }
    if (s == JM_OK) s = bucket_vertices(&j);
    if (s == JM_OK) {
        j.nw = jm_pool_threads(pool);
        j.w = jm_calloc(mem, (size_t)j.nw, sizeof *j.w);
        if (!j.w) s = JM_E_OUT_OF_MEMORY;
    }
    if (s == JM_OK) {
        jm_pool_run(pool, j.nbuckets, 4, bucket_task, &j);
        if (j.failed) s = JM_E_OUT_OF_MEMORY;
    }
    job_free(&j);
    return s;
}
