/* hood_cells.c - the cells that reach each block, listed once a frame: a metasphere block's hood is filled from its list instead of looking up every cell around it. */
#include "extract/hood_cells.h"
#include <math.h>
#include <string.h>

/* The block range of cell ci along each axis, as jm_blocks_build (blockset.c)
 * puts its blocks in the set: the blocks its particles' influence reaches */
static void cell_blocks(const jm_config *c, const jm_grid *g, const jm_block_set *bs, size_t ci, int64_t lo[3],
                        int64_t hi[3])
{
    const double BW = (double)c->block * c->h;
    for (int a = 0; a < 3; a++) {
        double cl = (double)g->cell_coord[3 * ci + a] * g->cell;
        lo[a] = (int64_t)floor((cl - c->influence) / BW) - bs->origin[a];
        hi[a] = (int64_t)floor((cl + g->cell + c->influence) / BW) - bs->origin[a];
        if (lo[a] < 0) lo[a] = 0;
    }
}

int jm_block_cells(const jm_config *c, const jm_grid *g, jm_mem *mem, jm_block_set *bs)
{
    bs->cell_start = jm_calloc(mem, bs->count + 1, sizeof *bs->cell_start);
    if (!bs->cell_start) return 0;
    /* twice over the cells with a particle not isolated (those that made
     * the blocks): count, then place (each list in cell order) */
    for (int pass = 0; pass < 2; pass++) {
        for (size_t ci = 0; ci < g->ncells; ci++) {
            int any = 0;
            for (uint32_t p = g->cell_start[ci]; p < g->cell_start[ci + 1] && !any; p++) any = !g->isolated[p];
            if (!any) continue;
            int64_t lo[3], hi[3];
            cell_blocks(c, g, bs, ci, lo, hi);
            for (int64_t z = lo[2]; z <= hi[2]; z++)
                for (int64_t y = lo[1]; y <= hi[1]; y++)
                    for (int64_t x = lo[0]; x <= hi[0]; x++) {
                        const uint32_t b = jm_hashmap_get(&bs->map, jm_key3(x, y, z));
                        if (b == UINT32_MAX) continue; /* (past the set's span) */
                        if (pass) bs->cells[bs->cell_start[b + 1]++] = (uint32_t)ci;
                        else bs->cell_start[b + 1]++;
                    }
        }
        if (pass) break;
        for (size_t b = 0; b < bs->count; b++) bs->cell_start[b + 1] += bs->cell_start[b];
        bs->ncells = bs->cell_start[bs->count];
        bs->cells = jm_alloc(mem, (bs->ncells ? bs->ncells : 1) * sizeof *bs->cells);
        if (!bs->cells) return 0;
        /* start[b + 1] becomes block b's cursor, from start[b] */
        for (size_t b = bs->count; b > 0; b--) bs->cell_start[b] = bs->cell_start[b - 1];
    }
    return 1;
}

int jm_hood_build_listed(jm_hood *hood, const jm_grid *g, const jm_config *c, const float lo[3], const float hi[3],
                         const uint32_t *cells, size_t ncells)
{
    if (!jm_hood_size(hood, g, c, lo, hi)) return 0;
    const size_t total = (size_t)hood->n[0] * (size_t)hood->n[1] * (size_t)hood->n[2];
    memset(hood->range, 0, 2 * total * sizeof *hood->range);
    hood->particles = 0;
    hood->live = 0;
    hood->wsum = 0.0;
    for (size_t k = 0; k < ncells; k++) {
        const uint32_t ci = cells[k];
        int64_t x[3];
        int in = 1;
        for (int a = 0; a < 3; a++) {
            x[a] = (int64_t)g->cell_coord[3 * (size_t)ci + a] - hood->c0[a];
            in &= x[a] >= 0 && x[a] < hood->n[a];
        }
        if (!in) continue;
        const size_t h = ((size_t)x[2] * (size_t)hood->n[1] + (size_t)x[1]) * (size_t)hood->n[0] + (size_t)x[0];
        hood->range[2 * h] = g->cell_start[ci];
        hood->range[2 * h + 1] = g->cell_start[ci + 1];
        hood->particles += g->cell_start[ci + 1] - g->cell_start[ci];
    }
    return 1;
}
