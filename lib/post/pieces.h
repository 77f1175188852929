/* pieces.h - the connected pieces of a triangle mesh, by union-find: each vertex's root is the smallest vertex of its piece. */
#ifndef JETMESH_PIECES_H
#define JETMESH_PIECES_H
#include "core/internal.h"

/* parent[v] (n entries) gets the smallest vertex of v's piece: the vertices
 * joined by the nt triangles idx[3 t .. 3 t + 2]. The result does not
 * depend on the order of the unions, so not on the pool's threads either
 * (NULL or one thread, or a small mesh: the plain serial pass). */
void jm_mesh_pieces(jm_pool *pool, uint32_t *parent, const uint32_t *idx, size_t n, size_t nt);

/* The same threads' union-find for any other sets (particle_groups.c):
 * with parent[x] = x to start, jm_pieces_unite joins the sets of a and b
 * (from any thread, at once) and jm_pieces_find gives x's root; a set's
 * root is its smallest element whatever the order of the unions. */
void jm_pieces_unite(uint32_t *parent, uint32_t a, uint32_t b);
uint32_t jm_pieces_find(uint32_t *parent, uint32_t x);
#endif
