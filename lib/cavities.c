/* cavities.c - removes closed inward-facing shells smaller than a particle (sub-particle bubbles inside bulk fluid). */
#include "cavities.h"
#include "pieces.h"
#include <string.h>

/*
 * Where the particles of bulk fluid are packed a little unevenly, the SPH
 * colour field can dip below the threshold inside the liquid and the mesh
 * gets a tiny closed shell there, facing inward: a bubble smaller than one
 * particle, which no simulation resolves (the dam-break frame of the demo
 * has one of 0.08 particle volumes). The metasphere on bulk fluid leaves
 * such shells between balls that do not touch. They are invisible from
 * outside but count as components, spoil genus and volume, and trouble
 * every tool downstream. A cavity of a particle's volume or more (a real
 * bubble, or a hollow in the particle data) is kept.
 */

/* The signed volume of the tetrahedron (o, pa, pb, pc): a . (b x c) / 6
 * with a = pa - o (and so on) in double, the SSE2 version doing the same
 * operations on pairs of lanes (the same bits; variant 1 of
 * t_splat_variants.sh builds the plain one). */
#if defined(__SSE2__) && JM_SPLAT_VARIANT != 1
#include <emmintrin.h>
static inline double volume_term(const float *pa, const float *pb, const float *pc, const double o[3])
{
    const __m128d o01 = _mm_loadu_pd(o), o2 = _mm_set_sd(o[2]);
    /* (x, y) and z of each corner, less o */
    const __m128d a01 = _mm_sub_pd(_mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)pa))), o01);
    const __m128d b01 = _mm_sub_pd(_mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)pb))), o01);
    const __m128d c01 = _mm_sub_pd(_mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)pc))), o01);
    const __m128d a2 = _mm_sub_sd(_mm_cvtss_sd(_mm_setzero_pd(), _mm_load_ss(pa + 2)), o2);
    const __m128d b2 = _mm_sub_sd(_mm_cvtss_sd(_mm_setzero_pd(), _mm_load_ss(pb + 2)), o2);
    const __m128d c2 = _mm_sub_sd(_mm_cvtss_sd(_mm_setzero_pd(), _mm_load_ss(pc + 2)), o2);
    /* (b1 c2 - b2 c1, b0 c2 - b2 c0) */
    const __m128d b2b2 = _mm_unpacklo_pd(b2, b2), c2c2 = _mm_unpacklo_pd(c2, c2);
    const __m128d m = _mm_sub_pd(_mm_mul_pd(_mm_shuffle_pd(b01, b01, 1), c2c2), _mm_mul_pd(b2b2, _mm_shuffle_pd(c01, c01, 1)));
    /* (a0 m0, a1 m1), then b0 c1 - b1 c0 */
    const __m128d am = _mm_mul_pd(a01, m);
    const __m128d bc = _mm_mul_pd(b01, _mm_shuffle_pd(c01, c01, 1));
    const double m2 = _mm_cvtsd_f64(_mm_sub_sd(bc, _mm_unpackhi_pd(bc, bc)));
    const double s = _mm_cvtsd_f64(_mm_sub_sd(am, _mm_unpackhi_pd(am, am))) + _mm_cvtsd_f64(a2) * m2;
    return s / 6.0;
}
#else
static inline double volume_term(const float *pa, const float *pb, const float *pc, const double o[3])
{
    double a[3], b[3], c[3];
    for (int k = 0; k < 3; k++) {
        a[k] = pa[k] - o[k];
        b[k] = pb[k] - o[k];
        c[k] = pc[k] - o[k];
    }
    return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
            a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
}
#endif

/*
 * The pieces' signed volumes, summed on the pool's threads in a fixed order
 * that does not depend on their number: the triangles in chunks of
 * VOL_CHUNK; in each chunk, every run of consecutive triangles of one piece
 * (a piece's triangles mostly follow each other) summed in triangle order
 * from 0; the runs' sums added to their pieces' volumes in chunk and run
 * order. A chunk keeps up to VOL_RUNS runs in its slots; one with more (a
 * spray of small pieces) is summed again into a list of its own size.
 */
#define VOL_CHUNK ((size_t)1 << 15)
#define VOL_RUNS 256
typedef struct {
    uint32_t root;
    double sum;
} vol_run;
typedef struct {
    jm_mem *mem;
    const float *pos;
    const uint32_t *idx, *parent;
    size_t nt;
    double o[3];
    vol_run *slots;  /* VOL_RUNS a chunk */
    vol_run **big;   /* per chunk: its own list when it has more runs */
    size_t *nruns;   /* per chunk */
    int failed;
} vol_job;

/* chunk k's runs into out (room for cap; the count is returned either way) */
static size_t chunk_runs(const vol_job *j, size_t k, vol_run *out, size_t cap)
{
    const size_t a = k * VOL_CHUNK, b = a + VOL_CHUNK < j->nt ? a + VOL_CHUNK : j->nt;
    size_t nr = 0;
    uint32_t cur = j->parent[j->idx[3 * a]];
    double acc = 0.0;
    for (size_t t = a; t < b; t++) {
        const uint32_t *i = j->idx + 3 * t;
        const uint32_t root = j->parent[i[0]];
        if (root != cur) {
            if (nr < cap) out[nr] = (vol_run){cur, acc};
            nr++;
            cur = root;
            acc = 0.0;
        }
        acc += volume_term(j->pos + 3 * (size_t)i[0], j->pos + 3 * (size_t)i[1], j->pos + 3 * (size_t)i[2], j->o);
    }
    if (nr < cap) out[nr] = (vol_run){cur, acc};
    return nr + 1;
}

static void vol_task(void *arg, size_t k, int worker)
{
    (void)worker;
    vol_job *j = arg;
    j->nruns[k] = chunk_runs(j, k, j->slots + k * VOL_RUNS, VOL_RUNS);
}

static void vol_big_task(void *arg, size_t k, int worker)
{
    (void)worker;
    vol_job *j = arg;
    if (j->nruns[k] <= VOL_RUNS) return;
    j->big[k] = jm_alloc(j->mem, j->nruns[k] * sizeof(vol_run));
    if (!j->big[k]) { __atomic_store_n(&j->failed, 1, __ATOMIC_RELAXED); return; }
    chunk_runs(j, k, j->big[k], j->nruns[k]);
}

int jm_piece_volumes(jm_mem *mem, jm_pool *pool, const float *pos, const uint32_t *idx, size_t nt,
                     const uint32_t *parent, double *vol)
{
    const size_t nch = (nt + VOL_CHUNK - 1) / VOL_CHUNK;
    /* about the first vertex (translation-invariant for a closed shell;
     * near the mesh for precision) */
    vol_job j = {mem, pos, idx, parent, nt, {pos[0], pos[1], pos[2]}, NULL, NULL, NULL, 0};
    j.slots = jm_alloc(mem, nch * VOL_RUNS * sizeof *j.slots);
    j.big = jm_calloc(mem, nch, sizeof *j.big);
    j.nruns = jm_alloc(mem, nch * sizeof *j.nruns);
    int ok = j.slots && j.big && j.nruns;
    if (ok) {
        jm_pool_run(pool, nch, 1, vol_task, &j);
        jm_pool_run(pool, nch, 1, vol_big_task, &j);
        ok = !j.failed;
    }
    if (ok)
        for (size_t k = 0; k < nch; k++) {
            const vol_run *r = j.nruns[k] > VOL_RUNS ? j.big[k] : j.slots + k * VOL_RUNS;
            for (size_t q = 0; q < j.nruns[k]; q++) vol[r[q].root] += r[q].sum;
        }
    if (j.big)
        for (size_t k = 0; k < nch; k++)
            if (j.big[k]) jm_free(mem, j.big[k], j.nruns[k] * sizeof(vol_run));
    jm_free(mem, j.slots, nch * VOL_RUNS * sizeof *j.slots);
    jm_free(mem, j.big, nch * sizeof *j.big);
    jm_free(mem, j.nruns, nch * sizeof *j.nruns);
    return ok;
}

int jm_drop_small_cavities(jm_mem *mem, jm_pool *pool, float *pos, float *nrm, float *uv, uint32_t *idx, size_t *nv,
                           size_t *ni, double max_volume, uint32_t *roots, size_t *out_removed)
{
    size_t n = *nv, nt = *ni / 3;
    *out_removed = 0;
    if (n == 0 || nt == 0) return 1;
    uint32_t *parent = roots ? roots : jm_alloc(mem, n * sizeof *parent);
    double *vol = jm_calloc(mem, n, sizeof *vol);
    int ok = parent && vol;
    if (ok) {
        jm_mesh_pieces(pool, parent, idx, n, nt);
        ok = jm_piece_volumes(mem, pool, pos, idx, nt, parent, vol);
    }
    if (!ok) {
        if (!roots) jm_free(mem, parent, n * sizeof *parent);
        jm_free(mem, vol, n * sizeof *vol);
        return 0;
    }
    size_t removed = 0;
    for (size_t v = 0; v < n; v++)
        if (parent[v] == v && vol[v] < 0.0 && -vol[v] < max_volume) removed++;
    if (removed) {
        /* new index of each kept vertex (UINT32_MAX: dropped); keep order */
        uint32_t *map = parent; /* reused after the roots are read */
        size_t k = 0;
        /* a drop flag per vertex: the roots first, then the others from
         * their root's */
        for (size_t v = 0; v < n; v++)
            if (parent[v] == v) vol[v] = (vol[v] < 0.0 && -vol[v] < max_volume) ? 1.0 : 0.0;
        for (size_t v = 0; v < n; v++)
            if (parent[v] != v) vol[v] = vol[parent[v]];
        for (size_t v = 0; v < n; v++) {
            if (vol[v] != 0.0) {
                map[v] = UINT32_MAX;
                continue;
            }
            map[v] = (uint32_t)k;
            if (k != v) {
                memmove(pos + 3 * k, pos + 3 * v, 3 * sizeof *pos);
                if (nrm) memmove(nrm + 3 * k, nrm + 3 * v, 3 * sizeof *nrm);
                if (uv) memmove(uv + 2 * k, uv + 2 * v, 2 * sizeof *uv);
            }
            k++;
        }
        size_t kt = 0;
        for (size_t t = 0; t < nt; t++) {
            uint32_t a = map[idx[3 * t]];
            if (a == UINT32_MAX) continue; /* a whole component goes: one corner tells */
            idx[3 * kt] = a;
            idx[3 * kt + 1] = map[idx[3 * t + 1]];
            idx[3 * kt + 2] = map[idx[3 * t + 2]];
            kt++;
        }
        *nv = k;
        *ni = 3 * kt;
    }
    if (!roots) jm_free(mem, parent, n * sizeof *parent);
    jm_free(mem, vol, n * sizeof *vol);
    *out_removed = removed;
    return 1;
}
