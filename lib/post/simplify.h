/* simplify.h - simplification to a geometric error with meshoptimizer, checked closed and manifold. */
#ifndef JETMESH_SIMPLIFY_H
#define JETMESH_SIMPLIFY_H
#include "post/post_mesh.h"

/* Simplifies m to the geometric error c->simplify_error (world units) with
 * meshoptimizer (simplify.c), compacting the vertex arrays; keeps the input
 * where the result would not be closed and manifold. */
jm_status jm_simplify_mesh(jm_mem *mem, const jm_config *c, jm_post_mesh *m);
#endif
