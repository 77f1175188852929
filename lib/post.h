/* post.h - post-processing of an extracted mesh: feature-weighted smoothing, normal smoothing, simplification. */
#ifndef JETMESH_POST_H
#define JETMESH_POST_H
#include "internal.h"

/* The context's output arrays, edited in place. Vertices [0, nv_lattice) and
 * indices [0, ni_lattice) come from the lattice; the rest are sphere
 * templates of isolated particles, which smoothing leaves alone. */
typedef struct jm_post_mesh {
    float *pos, *nrm, *uv;
    uint32_t *idx;
    size_t nv, ni;
    size_t nv_lattice, ni_lattice;
} jm_post_mesh;

/* Smooths the lattice part of m (smooth.c): c->smooth_iters iterations of
 * feature-weighted Laplacian smoothing with the enclosed volume of every
 * connected piece restored, normals from the new surface, then
 * c->smooth_normal_iters iterations of normal smoothing and fresh UVs.
 * Deterministic for any thread count. */
jm_status jm_smooth_mesh(jm_mem *mem, jm_pool *pool, const jm_config *c, const jm_grid *g, jm_post_mesh *m);

/* Simplifies m to the geometric error c->simplify_error (world units) with
 * meshoptimizer (simplify.c), compacting the vertex arrays; keeps the input
 * where the result would not be closed and manifold. */
jm_status jm_simplify_mesh(jm_mem *mem, const jm_config *c, jm_post_mesh *m);
#endif
