/* pieces.h - the connected pieces of a triangle mesh, by union-find: each vertex's root is the smallest vertex of its piece. */
#ifndef JETMESH_PIECES_H
#define JETMESH_PIECES_H
#include "internal.h"

/* parent[v] (n entries) gets the smallest vertex of v's piece: the vertices
 * joined by the nt triangles idx[3 t .. 3 t + 2]. The result does not
 * depend on the order of the unions, so not on the pool's threads either
 * (NULL or one thread, or a small mesh: the plain serial pass). */
void jm_mesh_pieces(jm_pool *pool, uint32_t *parent, const uint32_t *idx, size_t n, size_t nt);
#endif
