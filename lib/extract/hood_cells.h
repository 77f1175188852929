/* hood_cells.h - the cells that reach each block, listed once a frame: a metasphere block's hood is filled from its list. */
#ifndef JETMESH_HOOD_CELLS_H
#define JETMESH_HOOD_CELLS_H
#include "extract/block.h"

/* The cells with a particle not isolated whose influence reaches each block
 * of bs (cell_start, cells; the grid's cell coordinates still there): 0 if
 * out of memory. */
int jm_block_cells(const jm_config *c, const jm_grid *g, jm_mem *mem, jm_block_set *bs);
/* jm_hood_build from a block's listed cells: the cells around the box
 * [lo, hi] not listed hold no particle that reaches it but isolated ones
 * (which the metasphere's splats skip): their ranges are empty. */
int jm_hood_build_listed(jm_hood *hood, const jm_grid *g, const jm_config *c, const float lo[3], const float hi[3],
                         const uint32_t *cells, size_t ncells);
#endif
