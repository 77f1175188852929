/* cellbins.c - points binned into cubic cells: a counting sort by cell, the cells found by their coordinates. */
#include "grid/cellbins.h"
#include <string.h>

jm_status jm_cellbins_build(jm_cellbins *b, jm_mem *mem, const float *pos, size_t n, float cell)
{
    memset(b, 0, sizeof *b);
    b->n = n;
    b->inv = 1.0f / cell;
    if (n == 0) return JM_OK;
    if (n > UINT32_MAX - 1) return JM_E_TOO_LARGE;
    int64_t hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    for (int k = 0; k < 3; k++) b->lo[k] = INT64_MAX;
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            const int64_t c = jm_cellbins_coord(b, pos[3 * i + k]);
            if (c < b->lo[k]) b->lo[k] = c;
            if (c > hi[k]) hi[k] = c;
        }
    double box = 1.0;
    for (int k = 0; k < 3; k++) {
        b->span[k] = hi[k] - b->lo[k];
        if (b->span[k] >= JM_KEY_MAX - 1) return JM_E_TOO_LARGE;
        box *= (double)(b->span[k] + 1);
    }
    uint32_t *cellof = jm_alloc(mem, n * sizeof *cellof);
    if (!cellof) return JM_E_OUT_OF_MEMORY;
    jm_status s = JM_OK;
    /* a dense index where the box of cells is no more than 4 a point */
    if (box <= 4.0 * (double)n + 4096.0) {
        b->ndense = (size_t)box;
        b->dense = jm_alloc(mem, b->ndense * sizeof *b->dense);
        if (!b->dense) s = JM_E_OUT_OF_MEMORY;
        else memset(b->dense, 0xff, b->ndense * sizeof *b->dense);
    } else {
        s = jm_hashmap_init(&b->map, mem, n < 64 ? 64 : n);
    }
    for (size_t i = 0; s == JM_OK && i < n; i++) {
        int64_t q[3];
        for (int k = 0; k < 3; k++) q[k] = jm_cellbins_coord(b, pos[3 * i + k]) - b->lo[k];
        uint32_t *v = b->dense ? &b->dense[((size_t)q[2] * (size_t)(b->span[1] + 1) + (size_t)q[1]) *
                                               (size_t)(b->span[0] + 1) + (size_t)q[0]]
                               : jm_hashmap_upsert(&b->map, jm_key3(q[0], q[1], q[2]));
        if (*v == UINT32_MAX) *v = (uint32_t)b->ncells++;
        cellof[i] = *v;
    }
    if (s == JM_OK) {
        b->start = jm_calloc(mem, b->ncells + 1, sizeof *b->start);
        b->items = jm_alloc(mem, n * sizeof *b->items);
        b->coord = jm_alloc(mem, 3 * b->ncells * sizeof *b->coord);
        if (!b->start || !b->items || !b->coord) s = JM_E_OUT_OF_MEMORY;
    }
    if (s == JM_OK) {
        for (size_t i = 0; i < n; i++) b->start[cellof[i] + 1]++;
        for (size_t c = 0; c < b->ncells; c++) b->start[c + 1] += b->start[c];
        /* a counting sort: stable, so index order within a cell */
        for (size_t i = 0; i < n; i++) b->items[b->start[cellof[i]]++] = (uint32_t)i;
        for (size_t c = b->ncells; c > 0; c--) b->start[c] = b->start[c - 1];
        b->start[0] = 0;
        for (size_t c = 0; c < b->ncells; c++) {
            const float *p = pos + 3 * (size_t)b->items[b->start[c]];
            for (int k = 0; k < 3; k++) b->coord[3 * c + k] = (int32_t)(jm_cellbins_coord(b, p[k]) - b->lo[k]);
        }
    }
    jm_free(mem, cellof, n * sizeof *cellof);
    return s;
}

void jm_cellbins_free(jm_cellbins *b, jm_mem *mem)
{
    if (b->map.keys) jm_hashmap_free(&b->map, mem);
    jm_free(mem, b->dense, b->ndense * sizeof *b->dense);
    jm_free(mem, b->start, (b->ncells + 1) * sizeof *b->start);
    jm_free(mem, b->items, b->n * sizeof *b->items);
    jm_free(mem, b->coord, 3 * b->ncells * sizeof *b->coord);
    memset(b, 0, sizeof *b);
}
