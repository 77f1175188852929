/* grid.h - particles sorted into cells, with neighbour data: densities, links, isolation. */
#ifndef JETMESH_GRID_H
#define JETMESH_GRID_H
#include "core/internal.h"
#include "jetmesh_testing.h" /* jm_testing_grid_mode, defined in grid/release.c */

/* Builds g from the particles (validating them). */
jm_status jm_grid_build(jm_grid *g, jm_mem *mem, jm_pool *pool, const jm_config *c,
                        const jm_particles *in);
void jm_grid_free(jm_grid *g, jm_mem *mem);
/* Frees the cells' coordinates (12 bytes a cell), which only the building
 * of the grid, the kernels and the blocks read: the field and the later
 * stages find cells by their coordinates, never the reverse. */
void jm_grid_drop_coords(jm_grid *g, jm_mem *mem);
/* The isolated particles' sorted indices (g->n_isolated of them) in the
 * order of their cells' first appearance, then of the sorted order: the
 * same particles in the same order whichever way the cells are numbered. */
int jm_grid_isolated(const jm_grid *g, jm_mem *mem, uint32_t *out); /* 0: out of memory */
/* Cell index of absolute cell coordinates, or UINT32_MAX if empty/out of range. */
static inline uint32_t jm_grid_cell(const jm_grid *g, int64_t x, int64_t y, int64_t z)
{
    if (g->dense) {
        x -= g->dense_lo[0];
        y -= g->dense_lo[1];
        z -= g->dense_lo[2];
        if ((uint64_t)x >= (uint64_t)g->dense_n[0] || (uint64_t)y >= (uint64_t)g->dense_n[1] ||
            (uint64_t)z >= (uint64_t)g->dense_n[2])
            return UINT32_MAX;
        return g->dense[((size_t)z * (size_t)g->dense_n[1] + (size_t)y) * (size_t)g->dense_n[0] + (size_t)x];
    }
    x -= g->origin[0];
    y -= g->origin[1];
    z -= g->origin[2];
    if (x < 0 || y < 0 || z < 0 || x >= JM_KEY_MAX || y >= JM_KEY_MAX || z >= JM_KEY_MAX) return UINT32_MAX;
    return jm_hashmap_get(&g->cells, jm_key3(x, y, z));
}
#endif
