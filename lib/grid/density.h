/* density.h - the SPH grid's densities: each particle's kernel sum over the cells around it, 16 lanes at a time, and isolation. */
#ifndef JETMESH_DENSITY_H
#define JETMESH_DENSITY_H
#include "grid/near.h"

/* g->weight (1 / density), the cells' census (cell_wsum, cell_live) and the
 * isolated particles of job->g; most: the most particles around a cell. */
jm_status jm_grid_densities(jm_nb_job *job, jm_pool *pool, size_t most);
#endif
