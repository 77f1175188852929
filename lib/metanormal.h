/* metanormal.h - metasphere vertex normals blended from every ball and neck within the blend band of each vertex. */
#ifndef JETMESH_METANORMAL_H
#define JETMESH_METANORMAL_H
#include "metaprobe.h"

/* Per-worker scratch of jm_meta_normals (grown like the probe's). */
typedef struct jm_mnorm {
    jm_mem *mem;   /* the context's counts (alloc.c); kept by jm_mnorm_free */
    size_t cap;
    float *acc;    /* 3 * cap: the weighted sums, in the probe's sorted order */
} jm_mnorm;
void jm_mnorm_free(jm_mnorm *m);

/* The metasphere is the union of its pieces (balls and half-necks), so it
 * has a crease wherever two of them meet at an angle. A vertex's normal is
 * the normalised sum of minus the gradients of every piece whose value at
 * the vertex comes within c->mv_tau of the threshold, each weighted by
 * smoothstep(1 - gap / mv_tau) (gap: how far its value lies below the
 * threshold, 0 for a piece at or above it): the direction of the gradient
 * of a smooth maximum of the pieces, continuous across every crease. Every piece is splatted onto the block's
 * vertices as jm_meta_probe splats them (its sorted points pr, after the
 * probe and the settling: the points are refreshed from pos), so no piece
 * near a vertex is left out, and neighbouring vertices blend the same
 * pieces: the crease is shaded as a fillet about mv_tau r wide on each
 * side, with no step where the pieces blended would change from vertex to
 * vertex. nrm: nv normals in block order. 0 if out of memory. */
int jm_meta_normals(const jm_grid *g, const jm_config *c, const jm_hood *hood, jm_probe *pr, jm_mnorm *m, int B,
                    const float *x, const float *y, const float *z, const float *pos, float *nrm, size_t nv);
#endif
