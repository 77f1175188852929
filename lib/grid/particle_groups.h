/* particle_groups.h - particles grouped by connectivity: two closer than a distance are of one group. */
#ifndef JETMESH_PARTICLE_GROUPS_H
#define JETMESH_PARTICLE_GROUPS_H
#include "core/internal.h"

/* parent[i] (n entries) gets the smallest index of point i's group, the n
 * points pos[3 i .. 3 i + 2] (finite) joined wherever two lie closer than
 * d (their squared distance in float below d * d). Union-find over cells
 * of edge d on the pool's threads: the same result for any thread count. */
jm_status jm_particle_groups(jm_mem *mem, jm_pool *pool, const float *pos, size_t n, float d, uint32_t *parent);
#endif
