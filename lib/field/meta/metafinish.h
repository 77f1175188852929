/* metafinish.h - the stitched metasphere mesh's last pass: chord-sag compensation, normals kept facing their triangles. */
#ifndef JETMESH_METAFINISH_H
#define JETMESH_METAFINISH_H
#include "core/internal.h"

/* The stitched mesh's last pass (pos, nrm: nv vertices; idx: nt
 * triangles): compensate moves every vertex outward by the estimated chord
 * sag of its triangles (at most max_sag); facing pulls a normal that points
 * away from one of its triangles toward theirs. The passes over every
 * triangle run on the pool's threads (NULL: the caller's), the same bits
 * for any number. 0 if out of memory. */
int jm_meta_finish(jm_mem *mem, jm_pool *pool, float *pos, float *nrm, size_t nv, const uint32_t *idx, size_t nt,
                   int compensate, int facing, float max_sag);
#endif
