/* compact.h - a mesh's arrays compacted in place: the triangles not kept removed, then the vertices no triangle uses. */
#ifndef JETMESH_COMPACT_H
#define JETMESH_COMPACT_H
#include "core/internal.h"

/* Keeps the triangles t with keep_tri[t] != 0 (of *ni / 3) and the
 * vertices they use, both in their order; pos (3 a vertex), nrm (3) and uv
 * (2, both may be NULL) and idx compacted in place, *nv and *ni updated.
 * 0 if out of memory (the mesh unchanged). */
int jm_mesh_compact(jm_mem *mem, float *pos, float *nrm, float *uv, uint32_t *idx, size_t *nv, size_t *ni,
                    const uint8_t *keep_tri);
#endif
