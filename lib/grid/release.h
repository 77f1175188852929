/* release.h - the SPH grid's arrays on whole pages, given back behind the block sweep, and freed as counted. */
#ifndef JETMESH_RELEASE_H
#define JETMESH_RELEASE_H
#include "grid/grid.h"

/* SPH grids are numbered in key order, and can be released. */
int jm_grid_keyed(const jm_config *c);
/* An array of a grid: where it can be released and spans a page at least,
 * aligned to the page and advised huge (g->aligned_min set). */
void *jm_grid_alloc(const jm_config *c, jm_grid *g, jm_mem *mem, size_t bytes);
/* Frees an array of `bytes` (as counted when taken) of which rel were
 * released; aligned_min: as in jm_grid. */
void jm_grid_free_released(jm_mem *mem, void *p, size_t bytes, size_t rel, size_t aligned_min);
/* SPH grids (cells in key order): gives back the memory of the particles
 * of every cell whose z coordinate is below cz, and of those cells' index
 * entries: nothing may read them afterwards (the block sweep, which runs in
 * z order, calls it behind itself). Pages whole inside the released ranges
 * go back to the system and out of the count; the grid is freed as usual.
 * Any other grid: nothing. */
void jm_grid_release_below(jm_grid *g, jm_mem *mem, int64_t cz);
#endif
