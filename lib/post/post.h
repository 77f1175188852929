/* post.h - post-processing of an extracted mesh: bounded smoothing, normal smoothing, simplification. */
#ifndef JETMESH_POST_H
#define JETMESH_POST_H
#include "core/internal.h"

/* The context's output arrays, edited in place. Vertices [0, nv_lattice) and
 * indices [0, ni_lattice) come from the lattice; the rest are sphere
 * templates of isolated particles, which smoothing leaves alone. */
typedef struct jm_post_mesh {
    float *pos, *nrm, *uv;
    uint32_t *idx;
    size_t nv, ni;
    size_t nv_lattice, ni_lattice;
    const uint32_t *roots; /* NULL, or each vertex's piece as jm_mesh_pieces gives it */
} jm_post_mesh;

/* Working arrays of the post-processing, kept by the context from frame to
 * frame (fresh memory costs a page fault per 4 KiB on first touch). */
#define JM_POST_BUFS 14
typedef struct jm_post_scratch {
    void *p[JM_POST_BUFS];
    size_t bytes[JM_POST_BUFS];
} jm_post_scratch;
void jm_post_scratch_free(jm_post_scratch *s, jm_mem *mem);

/* Smooths the lattice part of m (smooth.c): c->smooth_iters steps of
 * Laplacian smoothing, every vertex's move along its raw normal bounded,
 * with the enclosed volume of every connected piece restored, normals from
 * the new surface, then c->smooth_normal_iters iterations of normal
 * smoothing and fresh UVs. Deterministic for any thread count. */
jm_status jm_smooth_mesh(jm_mem *mem, jm_pool *pool, jm_post_scratch *scratch, const jm_config *c, jm_post_mesh *m);

/* Simplifies m to the geometric error c->simplify_error (world units) with
 * meshoptimizer (simplify.c), compacting the vertex arrays; keeps the input
 * where the result would not be closed and manifold. */
jm_status jm_simplify_mesh(jm_mem *mem, const jm_config *c, jm_post_mesh *m);
#endif
