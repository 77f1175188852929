/* links.h - the metasphere grid's links: every pair of particles closer than the link distance, counted then written. */
#ifndef JETMESH_LINKS_H
#define JETMESH_LINKS_H
#include "grid/near.h"

/* g's links (nb_start, nb, nb_owner, nb_dir) and isolated particles; a
 * refusal over the memory limit sets *refused to the bytes it needed. */
jm_status jm_grid_links(jm_nb_job *job, jm_pool *pool, size_t *refused);
#endif
