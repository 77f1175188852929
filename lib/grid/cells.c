/* cells.c - the grid's cells: numbered (dense index or hash map), in key order for SPH, and the particles placed by a counting sort. */
#include "grid/cells.h"
#include "grid/near.h"
#include "grid/release.h"
#include "core/sort.h"

/* particles from which placement runs as two halves on two threads (below,
 * the halves' start-up costs more than they save) */
#define PLACE_SPLIT ((size_t)1 << 13)

/* Placement: particle k (input order, or order[k]) into the next free
 * place of its cell, cells filled in input order. On two threads or more,
 * the first half of the particles fills each cell from its start upwards
 * and the second half, taken backwards, from its end downwards: each cell
 * gets the same particles in the same order as from one pass. */
typedef struct {
    jm_grid *g;
    const char *base;
    size_t stride, n;
    float unit;
    const uint32_t *order, *pcell;
    uint32_t *count; /* 4 a cell: [0] the upward cursor, [1] the downward one */
} place_job;

/* particle k into its cell: at the upward cursor (up) or below the downward one */
static inline void place_one(const place_job *j, size_t k, int up)
{
    float p[3];
    load_units(p, j->base + (size_t)(j->order ? j->order[k] : k) * j->stride, j->unit);
    /* its cell, as the first pass found it */
    const uint32_t ci = j->pcell ? j->pcell[k] : *dense_slot(j->g, p);
    memcpy(GP(j->g, up ? j->count[4 * ci]++ : --j->count[4 * ci + 1]), p, sizeof p);
}

/* half 0: the first half upwards; 1: the second half downwards, backwards */
static void place_task(void *arg, size_t half, int worker)
{
    (void)worker;
    const place_job *j = arg;
    if (half == 0)
        for (size_t k = 0; k < j->n / 2; k++) place_one(j, k, 1);
    else
        for (size_t k = j->n; k-- > j->n / 2;) place_one(j, k, 0);
}

typedef struct {
    uint64_t key;
    uint32_t id;
} key_id;

static inline int key_less(const key_id *a, const key_id *b) { return a->key < b->key; }
JM_SORT_DEFINE(sort_key_id, key_id, key_less)

/* Renumbers the cells of the first pass (count: 4 entries a cell, the count
 * then the absolute coordinates; numbered by first appearance) in key
 * order, z slowest: the dense index or the map's values, pcell (map only)
 * and count follow; g->first_rank keeps each cell's old number and
 * g->slab_first where each z begins. */
static jm_status key_order(jm_grid *g, jm_mem *mem, uint32_t **count, size_t *count_cap, size_t ncells,
                           uint32_t *pcell, size_t n)
{
    uint32_t *rank = jm_alloc(mem, ncells * sizeof *rank); /* new number -> old */
    if (!rank) return JM_E_OUT_OF_MEMORY;
    uint32_t next = 0;
    if (g->dense) { /* z, y, x: the index is laid out in key order */
        const size_t box = (size_t)(g->dense_n[0] * g->dense_n[1] * g->dense_n[2]);
        for (size_t i = 0; i < box; i++)
            if (g->dense[i] != UINT32_MAX) {
                rank[next] = g->dense[i];
                g->dense[i] = next++;
            }
    } else {
        key_id *k = jm_alloc(mem, ncells * sizeof *k);
        if (!k) { jm_free(mem, rank, ncells * sizeof *rank); return JM_E_OUT_OF_MEMORY; }
        for (size_t i = 0; i < ncells; i++) {
            const uint32_t *e = *count + 4 * i;
            k[i].key = jm_key3((int64_t)(int32_t)e[1] - g->origin[0], (int64_t)(int32_t)e[2] - g->origin[1],
                               (int64_t)(int32_t)e[3] - g->origin[2]);
            k[i].id = (uint32_t)i;
        }
        sort_key_id(k, ncells); /* keys are distinct */
        uint32_t *to = (uint32_t *)k; /* old number -> new, in place of the pairs' first half */
        for (size_t i = 0; i < ncells; i++) rank[i] = k[i].id;
        for (size_t i = 0; i < ncells; i++) to[rank[i]] = (uint32_t)i;
        for (size_t s = 0; s < g->cells.cap; s++)
            if (g->cells.keys[s] != JM_HASH_EMPTY) g->cells.vals[s] = to[g->cells.vals[s]];
        for (size_t i = 0; i < n; i++) pcell[i] = to[pcell[i]];
        jm_free(mem, k, ncells * sizeof *k);
    }
    uint32_t *c2 = jm_alloc(mem, 4 * ncells * sizeof *c2);
    if (!c2) { jm_free(mem, rank, ncells * sizeof *rank); return JM_E_OUT_OF_MEMORY; }
    for (size_t i = 0; i < ncells; i++) memcpy(c2 + 4 * i, *count + 4 * (size_t)rank[i], 4 * sizeof *c2);
    jm_free(mem, *count, *count_cap * 4 * sizeof **count);
    *count = c2;
    *count_cap = ncells;
    g->first_rank = rank;
    /* each cell z's first cell */
    const int64_t z0 = (int32_t)c2[3], z1 = (int32_t)c2[4 * (ncells - 1) + 3];
    g->slab_z0 = z0;
    g->slab_n = (size_t)(z1 - z0 + 1);
    g->slab_first = jm_alloc(mem, (g->slab_n + 1) * sizeof *g->slab_first);
    if (!g->slab_first) return JM_E_OUT_OF_MEMORY;
    size_t ci = 0;
    for (size_t j = 0; j <= g->slab_n; j++) {
        while (ci < ncells && (int64_t)(int32_t)c2[4 * ci + 3] < z0 + (int64_t)j) ci++;
        g->slab_first[j] = (uint32_t)ci;
    }
    return JM_OK;
}

/* A growing per-cell table: 4 entries a cell, the count then the absolute
 * coordinates, cells numbered in order of first appearance. */
typedef struct {
    uint32_t *count;
    size_t cap, ncells;
    uint32_t *pcell; /* hash map only: each particle's cell */
} cell_table;

/* The cells' index: where the particles' box holds no more cells than there
 * are particles (bulk fluid: 8 particles a cell at rest), a dense index over
 * that box (at most 4 bytes a particle, one load a look-up); else a hash
 * map, with each particle's cell kept for the placement (a dense index
 * answers again in one load). Either numbers the cells alike, in order of
 * first appearance, and answers every look-up alike. */
static jm_status cell_index(jm_grid *g, jm_mem *mem, const jm_config *c, const float lo[3], const float hi[3],
                            cell_table *t)
{
    const size_t n = g->n;
    double box = 1.0;
    int64_t clo[3] = {0, 0, 0};
    for (int a = 0; a < 3 && n; a++) {
        clo[a] = (int64_t)floorf(lo[a] * g->inv_cell);
        box *= (double)((int64_t)floorf(hi[a] * g->inv_cell) - clo[a] + 1);
    }
    jm_status st;
    if (n && box <= (double)n + 64.0) {
        for (int a = 0; a < 3; a++) {
            g->dense_lo[a] = clo[a];
            g->dense_n[a] = (int64_t)floorf(hi[a] * g->inv_cell) - clo[a] + 1;
        }
        g->dense = jm_grid_alloc(c, g, mem, (size_t)box * sizeof *g->dense);
        if (!g->dense) return JM_E_OUT_OF_MEMORY;
        memset(g->dense, 0xff, (size_t)box * sizeof *g->dense);
        return JM_OK;
    }
    st = jm_hashmap_init(&g->cells, mem, n / 2 + 16);
    if (st != JM_OK) return st;
    t->pcell = jm_alloc(mem, (n ? n : 1) * sizeof *t->pcell);
    return t->pcell ? JM_OK : JM_E_OUT_OF_MEMORY;
}

/* Each particle's cell numbered in order of first appearance and counted;
 * the hash map grown as needed. */
static jm_status number_cells(jm_grid *g, jm_mem *mem, const jm_config *c, const char *base, size_t stride,
                              const uint32_t *order, cell_table *t)
{
    for (size_t k = 0; k < g->n; k++) {
        float p[3];
        load_units(p, base + (size_t)(order ? order[k] : k) * stride, c->unit_in);
        int64_t cx = (int64_t)floorf(p[0] * g->inv_cell) - g->origin[0];
        int64_t cy = (int64_t)floorf(p[1] * g->inv_cell) - g->origin[1];
        int64_t cz = (int64_t)floorf(p[2] * g->inv_cell) - g->origin[2];
        uint32_t *v;
        if (g->dense) {
            v = dense_slot(g, p);
        } else {
            if (g->cells.count * 2 + 2 > g->cells.cap) {
                /* rehash into a bigger table */
                jm_hashmap big;
                jm_status st = jm_hashmap_init(&big, mem, g->cells.cap);
                if (st != JM_OK) return st;
                for (size_t s = 0; s < g->cells.cap; s++)
                    if (g->cells.keys[s] != JM_HASH_EMPTY) *jm_hashmap_upsert(&big, g->cells.keys[s]) = g->cells.vals[s];
                jm_hashmap_free(&g->cells, mem);
                g->cells = big;
            }
            v = jm_hashmap_upsert(&g->cells, jm_key3(cx, cy, cz));
        }
        if (*v == UINT32_MAX) {
            if (t->ncells == t->cap) {
                size_t nc = t->cap ? t->cap * 2 : 256;
                uint32_t *bigger = jm_realloc(mem, t->count, t->cap * 4 * sizeof *t->count, nc * 4 * sizeof *t->count);
                if (!bigger) return JM_E_OUT_OF_MEMORY;
                t->count = bigger;
                t->cap = nc;
            }
            uint32_t *e = t->count + 4 * t->ncells;
            e[0] = 0;
            e[1] = (uint32_t)(cx + g->origin[0]);
            e[2] = (uint32_t)(cy + g->origin[1]);
            e[3] = (uint32_t)(cz + g->origin[2]);
            *v = (uint32_t)t->ncells++;
        }
        t->count[4 * *v]++;
        if (t->pcell) t->pcell[k] = *v;
    }
    g->ncells = t->ncells;
    return JM_OK;
}

/* The cells' starts and coordinates, and the particles placed in them. */
static jm_status place_all(jm_grid *g, jm_mem *mem, jm_pool *pool, const jm_config *c, const char *base,
                           size_t stride, const uint32_t *order, cell_table *t)
{
    const size_t n = g->n, ncells = g->ncells;
    uint32_t *count = t->count;
    const size_t start_bytes = (ncells + 1) * sizeof *g->cell_start, pos_bytes = (n ? 3 * n : 1) * sizeof(float);
    g->cell_start = jm_grid_alloc(c, g, mem, start_bytes);
    g->cell_coord = jm_alloc(mem, (ncells ? 3 * ncells : 1) * sizeof *g->cell_coord);
    g->pos = jm_grid_alloc(c, g, mem, pos_bytes);
    g->isolated = jm_grid_alloc(c, g, mem, n ? n : 1);
    if (g->isolated) memset(g->isolated, 0, n ? n : 1);
    if (!g->cell_start || !g->cell_coord || !g->pos || !g->isolated) return JM_E_OUT_OF_MEMORY;
    uint32_t acc = 0;
    for (size_t ci = 0; ci < ncells; ci++) {
        g->cell_start[ci] = acc;
        acc += count[4 * ci];
        count[4 * ci] = g->cell_start[ci]; /* becomes the fill cursor */
        for (int a = 0; a < 3; a++) g->cell_coord[3 * ci + a] = (int32_t)count[4 * ci + 1 + a];
    }
    g->cell_start[ncells] = acc;
    place_job pj = {g, base, stride, n, c->unit_in, order, t->pcell, count};
    if (jm_pool_threads(pool) >= 2 && n >= PLACE_SPLIT) {
        for (size_t ci = 0; ci < ncells; ci++) count[4 * ci + 1] = g->cell_start[ci + 1]; /* coordinates copied */
        jm_pool_run(pool, 2, 1, place_task, &pj);
    } else {
        for (size_t k = 0; k < n; k++) place_one(&pj, k, 1);
    }
    return JM_OK;
}

jm_status jm_grid_cells(jm_grid *g, jm_mem *mem, jm_pool *pool, const jm_config *c, const char *base, size_t stride,
                        const uint32_t *order, const float lo[3], const float hi[3])
{
    cell_table t = {NULL, 0, 0, NULL};
    jm_status st = cell_index(g, mem, c, lo, hi, &t);
    if (st == JM_OK) st = number_cells(g, mem, c, base, stride, order, &t);
    /* SPH: the cells in key order (z slowest), so that the particles lie in
     * memory slab by slab, as the blocks are swept, and the sweep can give
     * them back behind it (jm_grid_release_below). Every sum over particles
     * enumerates cells by their coordinates and a cell's particles in input
     * order, so the numbering changes no value; the isolated particles keep
     * the input's order through first_rank (jm_grid_isolated). */
    if (st == JM_OK && jm_grid_keyed(c) && t.ncells) st = key_order(g, mem, &t.count, &t.cap, t.ncells, t.pcell, g->n);
    if (st == JM_OK) st = place_all(g, mem, pool, c, base, stride, order, &t);
    jm_free(mem, t.count, t.cap * 4 * sizeof *t.count);
    jm_free(mem, t.pcell, (g->n ? g->n : 1) * sizeof *t.pcell);
    return st;
}
