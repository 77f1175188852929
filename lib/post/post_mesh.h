/* post_mesh.h - the mesh the post-processing (smoothing, simplification) edits, and its working arrays kept across frames. */
#ifndef JETMESH_POST_MESH_H
#define JETMESH_POST_MESH_H
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
#define JM_POST_BUFS 16
typedef struct jm_post_scratch {
    void *p[JM_POST_BUFS];
    size_t bytes[JM_POST_BUFS];
} jm_post_scratch;
#endif
