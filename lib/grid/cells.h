/* cells.h - the grid's cells: numbered (dense index or hash map), in key order for SPH, and the particles placed by a counting sort. */
#ifndef JETMESH_CELLS_H
#define JETMESH_CELLS_H
#include "grid/grid.h"

/* g's cells from its g->n particles (at base, stride bytes apart, in the
 * order `order` or the input's; their box lo, hi in the library's unit):
 * cell_start, cell_coord, pos and isolated (all 0). The caller frees g on
 * failure. */
jm_status jm_grid_cells(jm_grid *g, jm_mem *mem, jm_pool *pool, const jm_config *c, const char *base, size_t stride,
                        const uint32_t *order, const float lo[3], const float hi[3]);
#endif
