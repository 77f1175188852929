/* clip.h - the mesh clip box: triangles with a corner outside removed, or the vertices outside clamped onto the box. */
#ifndef JETMESH_CLIP_H
#define JETMESH_CLIP_H
#include "core/internal.h"

/* Applies c's clip box (c->clip: 1 remove, 2 clamp; jetmesh.h, "Selection
 * and clipping", step 4) to the mesh, in place, in order (positions in
 * units, as c's box); nrm and uv recomputed for clamped vertices (the
 * arrays exist for every vertex). 0 if out of memory (the mesh unchanged). */
int jm_clip_mesh(jm_mem *mem, jm_pool *pool, const jm_config *c, float *pos, float *nrm, float *uv, uint32_t *idx,
                 size_t *nv, size_t *ni);
#endif
