/* grid.c - the particles sorted into cells with their neighbour data (SPH densities or metasphere links) and isolation. */
#include "grid/grid.h"
#include "grid/cells.h"
#include "grid/density.h"
#include "grid/links.h"
#include "grid/release.h"
#include "core/sort.h"
#include "core/units.h"
#include "field/aniso/anisotropy.h"
#include <math.h>
#include <stdlib.h>

static int cmp_id(const void *a, const void *b, const uint32_t *ids)
{
    uint32_t x = ids[*(const uint32_t *)a], y = ids[*(const uint32_t *)b];
    if (x != y) return x < y ? -1 : 1;
    uint32_t ia = *(const uint32_t *)a, ib = *(const uint32_t *)b;
    return ia < ib ? -1 : ia > ib;
}

/* Stable sort of input indices by id (merge sort; ids may repeat). */
static void sort_by_id(uint32_t *idx, uint32_t *tmp, size_t n, const uint32_t *ids)
{
    if (n < 2) return;
    size_t m = n / 2;
    sort_by_id(idx, tmp, m, ids);
    sort_by_id(idx + m, tmp, n - m, ids);
    size_t i = 0, j = m, k = 0;
    while (i < m && j < n) tmp[k++] = cmp_id(&idx[j], &idx[i], ids) < 0 ? idx[j++] : idx[i++];
    while (i < m) tmp[k++] = idx[i++];
    while (j < n) tmp[k++] = idx[j++];
    memcpy(idx, tmp, n * sizeof *idx);
}

/* ---- the build's passes over all particles or cells, on the pool's
 * threads in chunks; each gives what the serial loop would */
#define PCH ((size_t)1 << 16) /* particles a task of the bounds */
#define PAIR_CH ((size_t)1 << 12) /* cells a task of the pair count (27 look-ups a cell) */

/* Validation and bounds: per chunk the box of its particles (in the
 * library's unit) and the failure of its first bad particle. */
typedef struct {
    const char *base;
    size_t stride, n;
    float unit;
    float *box;    /* per chunk: lo[3], hi[3] */
    jm_status *st; /* per chunk */
} bound_job;

static void bound_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    bound_job *j = arg;
    const size_t a = chunk * PCH, b = a + PCH < j->n ? a + PCH : j->n;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    jm_status st = JM_OK;
    for (size_t i = a; i < b && st == JM_OK; i++) {
        float p[3];
        memcpy(p, j->base + i * j->stride, sizeof p);
        for (int k = 0; k < 3; k++) {
            if (!isfinite(p[k])) { st = JM_E_INVALID_PARTICLE; break; }
            p[k] *= j->unit; /* in the library's unit (units.h) */
            if (!isfinite(p[k])) { st = JM_E_NUMERIC_DOMAIN; break; } /* |x| / 2^unit past FLT_MAX */
            if (p[k] < lo[k]) lo[k] = p[k];
            if (p[k] > hi[k]) hi[k] = p[k];
        }
    }
    memcpy(&j->box[6 * chunk], lo, sizeof lo);
    memcpy(&j->box[6 * chunk + 3], hi, sizeof hi);
    j->st[chunk] = st;
}

/* The particles' box into lo, hi; the first bad particle's failure (in
 * input order), or JM_OK. */
static jm_status bound_all(jm_pool *pool, jm_mem *mem, const char *base, size_t stride, size_t n, float unit,
                           float lo[3], float hi[3])
{
    const size_t nch = (n + PCH - 1) / PCH;
    for (int a = 0; a < 3; a++) lo[a] = INFINITY, hi[a] = -INFINITY;
    if (!nch) return JM_OK;
    float *box = jm_alloc(mem, nch * 6 * sizeof *box);
    jm_status *st = jm_alloc(mem, nch * sizeof *st);
    jm_status r = JM_OK;
    if (!box || !st) r = JM_E_OUT_OF_MEMORY;
    else {
        bound_job j = {base, stride, n, unit, box, st};
        jm_pool_run(pool, nch, 1, bound_task, &j);
        for (size_t k = 0; k < nch && r == JM_OK; k++) {
            r = st[k];
            for (int a = 0; a < 3; a++) {
                if (box[6 * k + a] < lo[a]) lo[a] = box[6 * k + a];
                if (box[6 * k + 3 + a] > hi[a]) hi[a] = box[6 * k + 3 + a];
            }
        }
    }
    jm_free(mem, box, nch * 6 * sizeof *box);
    jm_free(mem, st, nch * sizeof *st);
    return r;
}

/* The neighbour search's pair checks: per chunk of cells, each cell's
 * particles times those of the cells around it (whole numbers: any order
 * of the sums gives the same total below 2^53, and one far over the
 * limit above it). */
typedef struct {
    const jm_grid *g;
    double *part; /* per chunk */
    size_t *most; /* per chunk: the most particles around a cell */
} pair_job;

static void pair_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    pair_job *j = arg;
    const jm_grid *g = j->g;
    const size_t a = chunk * PAIR_CH, b = a + PAIR_CH < g->ncells ? a + PAIR_CH : g->ncells;
    double pairs = 0.0;
    size_t most = 0;
    uint32_t rr[27][2];
    for (size_t ci = a; ci < b; ci++) {
        const int nr = jm_near_ranges(g, ci, rr);
        size_t around = 0;
        for (int k = 0; k < nr; k++) around += rr[k][1] - rr[k][0];
        pairs += (double)(g->cell_start[ci + 1] - g->cell_start[ci]) * (double)around;
        if (around > most) most = around;
    }
    j->part[chunk] = pairs;
    j->most[chunk] = most;
}

static inline int u64_less(const uint64_t *a, const uint64_t *b) { return *a < *b; }
JM_SORT_DEFINE(sort_u64, uint64_t, u64_less)

int jm_grid_isolated(const jm_grid *g, jm_mem *mem, uint32_t *out)
{
    size_t k = 0;
    if (!g->first_rank) {
        for (size_t i = 0; i < g->n; i++)
            if (g->isolated[i]) out[k++] = (uint32_t)i;
        return 1;
    }
    /* (first appearance of the cell, sorted index), sorted: the particles of
     * one cell are in input order in both numberings */
    const size_t bytes = (g->n_isolated ? g->n_isolated : 1) * sizeof(uint64_t);
    uint64_t *pair = jm_alloc(mem, bytes);
    if (!pair) return 0;
    for (size_t ci = 0; ci < g->ncells; ci++)
        for (uint32_t i = g->cell_start[ci]; i < g->cell_start[ci + 1]; i++)
            if (g->isolated[i]) pair[k++] = (uint64_t)g->first_rank[ci] << 32 | i;
    sort_u64(pair, k); /* distinct */
    for (size_t i = 0; i < k; i++) out[i] = (uint32_t)pair[i];
    jm_free(mem, pair, bytes);
    return 1;
}

void jm_grid_free(jm_grid *g, jm_mem *mem)
{
    size_t n = g->n;
    jm_grid_free_released(mem, g->pos, 3 * n * sizeof(float), g->rel[0], g->aligned_min);
    jm_grid_free_released(mem, g->weight, n * sizeof(float), g->rel[1], g->aligned_min);
    jm_free(mem, g->nb_start, (n + 1) * sizeof(uint32_t));
    jm_free(mem, g->nb, g->nb_count * sizeof(uint32_t));
    jm_free(mem, g->nb_owner, g->nb_count * sizeof(uint32_t));
    jm_free(mem, g->nb_dir, g->nb_count * 4 * sizeof(float));
    jm_grid_free_released(mem, g->cell_start, (g->ncells + 1) * sizeof(uint32_t), g->rel[3], g->aligned_min);
    jm_free(mem, g->cell_coord, 3 * g->ncells * sizeof(int32_t));
    jm_free(mem, g->cell_wsum, (g->ncells ? g->ncells : 1) * sizeof *g->cell_wsum);
    jm_free(mem, g->cell_live, (g->ncells ? g->ncells : 1) * sizeof *g->cell_live);
    jm_grid_free_released(mem, g->isolated, n, g->rel[2], g->aligned_min);
    jm_aniso_free(g, mem);
    if (g->cells.keys) jm_hashmap_free(&g->cells, mem);
    jm_grid_free_released(mem, g->dense, (size_t)(g->dense_n[0] * g->dense_n[1] * g->dense_n[2]) * sizeof *g->dense, g->rel[4],
                  g->aligned_min);
    jm_free(mem, g->first_rank, g->ncells * sizeof *g->first_rank);
    jm_free(mem, g->slab_first, (g->slab_n + 1) * sizeof *g->slab_first);
    memset(g, 0, sizeof *g);
}

void jm_grid_drop_coords(jm_grid *g, jm_mem *mem)
{
    jm_free(mem, g->cell_coord, 3 * g->ncells * sizeof(int32_t));
    g->cell_coord = NULL;
}

/* The particles validated and bounded (in the library's unit); the grid's
 * origin, with the lattice's and the cells' coordinates in range. */
static jm_status grid_bounds(jm_grid *g, jm_pool *pool, jm_mem *mem, const jm_config *c, const char *base,
                             size_t stride, float lo[3], float hi[3])
{
    const jm_status vs = bound_all(pool, mem, base, stride, g->n, c->unit_in, lo, hi);
    if (vs != JM_OK) return vs;
    for (int a = 0; a < 3; a++) {
        /* lattice node coordinates must stay within +-2^30 cubes */
        if (fabsf(lo[a]) * c->inv_h > 1e9f || fabsf(hi[a]) * c->inv_h > 1e9f) return JM_E_TOO_LARGE;
        g->lo[a] = lo[a];
        g->hi[a] = hi[a];
        g->origin[a] = (int64_t)floorf(lo[a] * g->inv_cell) - 4;
        if ((int64_t)floorf(hi[a] * g->inv_cell) + 4 - g->origin[a] >= JM_KEY_MAX) return JM_E_TOO_LARGE;
    }
    return g->n ? jm_unit_check(c, lo, hi, jm_unit_reach(c)) : JM_OK;
}

/* The processing order: by id where the particles have ids (*order then
 * holds it), else the input's (*order stays NULL). */
static jm_status id_order(jm_mem *mem, const jm_particles *in, uint32_t **order)
{
    const size_t n = in->count;
    *order = NULL;
    if (!in->ids || n < 2) return JM_OK;
    uint32_t *o = jm_alloc(mem, n * sizeof *o);
    if (!o) return JM_E_OUT_OF_MEMORY;
    for (size_t i = 0; i < n; i++) o[i] = (uint32_t)i;
    uint32_t *tmp = jm_alloc(mem, n * sizeof *tmp);
    if (!tmp) { jm_free(mem, o, n * sizeof *o); return JM_E_OUT_OF_MEMORY; }
    sort_by_id(o, tmp, n, in->ids);
    jm_free(mem, tmp, n * sizeof *tmp);
    *order = o;
    return JM_OK;
}

/* Bounded work: the neighbour search checks every particle of a cell
 * against those of the 27 cells around it; refused before it starts when
 * that is beyond JM_MAX_PAIR_CHECKS (a frame of duplicates, or a radius far
 * too large, would otherwise take hours). *most: the most particles around
 * a cell (the densities' buffers). */
static jm_status pair_check(const jm_grid *g, jm_mem *mem, jm_pool *pool, size_t *most)
{
    const size_t nch = (g->ncells + PAIR_CH - 1) / PAIR_CH;
    double *part = jm_alloc(mem, (nch ? nch : 1) * (sizeof *part + sizeof(size_t))), pairs = 0.0;
    if (!part) return JM_E_OUT_OF_MEMORY;
    pair_job pj = {g, part, (size_t *)(part + (nch ? nch : 1))};
    jm_pool_run(pool, nch, 1, pair_task, &pj);
    *most = 0;
    for (size_t k = 0; k < nch; k++) {
        pairs += part[k];
        if (pj.most[k] > *most) *most = pj.most[k];
    }
    jm_free(mem, part, (nch ? nch : 1) * (sizeof *part + sizeof(size_t)));
    return pairs > JM_MAX_PAIR_CHECKS(g->n) ? JM_E_TOO_DENSE : JM_OK;
}

/* The neighbour data: SPH densities, or metasphere links; isolation
 * within 2 supports (SPH) or the link distance, at least 2.6 r. */
static jm_status neighbours(jm_grid *g, jm_mem *mem, jm_pool *pool, const jm_config *c, size_t most,
                            size_t *refused)
{
    jm_nb_job job = {g, c, 1, 0, NULL, NULL, NULL, 0, mem};
    float iso;
    if (c->field == JM_FIELD_SPH) iso = 2.0f * c->support;
    else iso = fmaxf(c->link, 2.6f * c->r);
    job.iso2 = iso * iso;
    job.range = (int)ceilf(iso / c->cell);
    if (c->field == JM_FIELD_SPH) return jm_grid_densities(&job, pool, most);
    return jm_grid_links(&job, pool, refused);
}

jm_status jm_grid_build(jm_grid *g, jm_mem *mem, jm_pool *pool, const jm_config *c, const jm_particles *in)
{
    memset(g, 0, sizeof *g);
    size_t refused = 0; /* the memory a refusal over the limit would have needed */
    size_t n = in->count;
    size_t stride = in->stride ? in->stride : 3 * sizeof(float);
    if (n > UINT32_MAX / 2) return JM_E_TOO_LARGE;
    if (stride < 3 * sizeof(float)) return JM_E_INVALID_ARGUMENT;
    g->n = n;
    g->cell = c->cell;
    g->inv_cell = 1.0f / c->cell;
    const char *base = (const char *)in->xyz;
    float lo[3], hi[3];
    jm_status st = grid_bounds(g, pool, mem, c, base, stride, lo, hi);
    if (st != JM_OK) return st;
    uint32_t *order;
    st = id_order(mem, in, &order);
    if (st != JM_OK) return st;
    st = jm_grid_cells(g, mem, pool, c, base, stride, order, lo, hi);
    jm_free(mem, order, (n ? n : 1) * sizeof *order);
    size_t most = 0;
    if (st == JM_OK) st = pair_check(g, mem, pool, &most);
    if (st == JM_OK) st = neighbours(g, mem, pool, c, most, &refused);
    if (st != JM_OK) {
        jm_grid_free(g, mem);
        g->refused_bytes = refused;
        return st;
    }
    for (size_t i = 0; i < n; i++) g->n_isolated += g->isolated[i];
    return JM_OK;
}
