/* cull_check.h - culling tests' shared parts: the same mesh bytes with culling on and off, and a lattice block with holes. */
#ifndef JETMESH_TESTS_CULL_CHECK_H
#define JETMESH_TESTS_CULL_CHECK_H

#include <stddef.h>
#include "../../lib/jetmesh.h"

/**
 * Meshes the count particles xyz with p and culling off (1 thread), then
 * with culling on at 1 and 2 threads. Returns 0 when every culled mesh has
 * the same vertex and triangle counts and the same positions, normals, uvs
 * and indices, byte for byte, and the reference has triangles; *out_triangles
 * gets its triangle count. Otherwise -1, with why in err (naming `what`).
 */
int cull_same_bytes(const char *what, const jm_params *p, const float *xyz, size_t count, size_t *out_triangles,
                    char *err, size_t errsz);

/**
 * A jittered lattice block (24^3 sites, spacing 2r) with a spherical
 * cavity, a perforated wall and a slot, and a lone pair above it: culling
 * next to cavities, thin walls and particles on block faces. Returns the
 * malloc'd positions (*n of them), or NULL for no memory.
 */
float *cull_holed_block(float r, size_t *n);

#endif
