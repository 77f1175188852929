/* cavities.c - removes closed inward-facing shells smaller than a particle (sub-particle bubbles inside bulk fluid). */
#include "post/cavities.h"
#include "post/pieces.h"
#include "extract/compact.h"
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

/*
 * The pieces' signed volumes, summed on the pool's threads in a fixed order
 * that does not depend on their number: the triangles in chunks of
 * VOL_CHUNK; in each chunk, every run of consecutive triangles of one piece
 * (a piece's triangles mostly follow each other) summed in triangle order
 * from 0; the runs' sums added to their pieces' volumes in chunk and run
 * order. A chunk keeps up to VOL_RUNS runs in its slots; one with more (a
 * spray of small pieces) is summed again into a list of its own size.
 */
#define VOL_CHUNK ((size_t)1 << 13)
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

/* The signed volumes of the tetrahedra (o, pa, pb, pc) of triangles t ..
 * t + 3, a . (b x c) / 6 with a = pa - o (and so on) in double: 4 lanes
 * of GCC vectors, each lane the same double operations in the same order
 * on every path (the lanes past b repeat the last triangle) */
typedef double v4d __attribute__((vector_size(32)));
static inline __attribute__((always_inline)) v4d terms4(const vol_job *j, size_t t, size_t b)
{
    v4d c[3][3];
    for (int l = 0; l < 4; l++) {
        const uint32_t *i = j->idx + 3 * (t + (size_t)l < b ? t + (size_t)l : b - 1);
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++) c[k][a][l] = (double)j->pos[3 * (size_t)i[k] + a] - j->o[a];
    }
    const v4d m0 = c[1][1] * c[2][2] - c[1][2] * c[2][1], m1 = c[1][0] * c[2][2] - c[1][2] * c[2][0];
    const v4d m2 = c[1][0] * c[2][1] - c[1][1] * c[2][0];
    return (c[0][0] * m0 - c[0][1] * m1 + c[0][2] * m2) / 6.0;
}

/* chunk k's runs into out (room for cap; the count is returned either way) */
JM_BODY size_t chunk_runs_body(const vol_job *j, size_t k, vol_run *out, size_t cap)
{
    const size_t a = k * VOL_CHUNK, b = a + VOL_CHUNK < j->nt ? a + VOL_CHUNK : j->nt;
    size_t nr = 0;
    uint32_t cur = j->parent[j->idx[3 * a]];
    double acc = 0.0;
    for (size_t t = a; t < b; t += 4) {
        const v4d v = terms4(j, t, b);
        for (int l = 0; l < 4 && t + (size_t)l < b; l++) {
            const uint32_t root = j->parent[j->idx[3 * (t + (size_t)l)]];
            if (root != cur) {
                if (nr < cap) out[nr] = (vol_run){cur, acc};
                nr++;
                cur = root;
                acc = 0.0;
            }
            acc += v[l];
        }
    }
    if (nr < cap) out[nr] = (vol_run){cur, acc};
    return nr + 1;
}
JM_KERNEL_AVX2(static, size_t, chunk_runs, chunk_runs_body, (const vol_job *j, size_t k, vol_run *out, size_t cap), (j, k, out, cap))

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
        /* a drop flag per vertex (in vol): the roots first, then the others
         * from their root's; a whole piece goes, so one corner tells a
         * triangle's */
        for (size_t v = 0; v < n; v++)
            if (parent[v] == v) vol[v] = (vol[v] < 0.0 && -vol[v] < max_volume) ? 1.0 : 0.0;
        for (size_t v = 0; v < n; v++)
            if (parent[v] != v) vol[v] = vol[parent[v]];
        uint8_t *keep = jm_alloc(mem, nt);
        if (keep)
            for (size_t t = 0; t < nt; t++) keep[t] = vol[idx[3 * t]] == 0.0;
        ok = keep && jm_mesh_compact(mem, pos, nrm, uv, idx, nv, ni, keep);
        jm_free(mem, keep, nt);
    }
    if (!roots) jm_free(mem, parent, n * sizeof *parent);
    jm_free(mem, vol, n * sizeof *vol);
    *out_removed = ok ? removed : 0;
    return ok;
}
