/* metanormal.h - metasphere vertex normals blended from every ball and neck within the blend band of each vertex. */
#ifndef JETMESH_METANORMAL_H
#define JETMESH_METANORMAL_H
#include "field/meta/metaprobe.h"

/* A piece's visit in the first pass, replayed for the moved vertices: the
 * pieces jm_probe_pieces gives, with their parts, in its order (u NULL: a
 * ball). */
typedef struct jm_visit {
    const float *q, *u;
    float D, rr2;
    int lo[3], hi[3];
} jm_visit;

/* Per-worker scratch of the normals (grown like the probe's). */
typedef struct jm_mnorm {
    jm_mem *mem;   /* the context's counts (alloc.c); kept by jm_mnorm_free */
    size_t cap;
    float *acc;    /* 3 * cap: the weighted sums, in the probe's sorted order */
    float *sub;    /* 6 * cap: the moved vertices' points and sums */
    uint32_t *moved; /* cap: their sorted positions */
    jm_visit *visit; /* the first pass's visits (nvisit of capvisit) */
    size_t nvisit, capvisit;
    int visits;    /* 1: visit holds this block's (0: enumerate again) */
} jm_mnorm;
void jm_mnorm_free(jm_mnorm *m);
/* m's capacities grown to at least o's (0 if out of memory). */
int jm_mnorm_match(jm_mnorm *m, const jm_mnorm *o);

/* The metasphere is the union of its pieces (balls and half-necks), so it
 * has a crease wherever two of them meet at an angle. A vertex's normal is
 * the normalised sum of minus the gradients of every piece whose value at
 * the vertex comes within c->mv_tau of the threshold, each weighted by
 * smoothstep(1 - gap / mv_tau) (gap: how far its value lies below the
 * threshold, 0 for a piece at or above it): the direction of the gradient
 * of a smooth maximum of the pieces, continuous across every crease.
 * Every piece is splatted onto the block's vertices as jm_meta_probe
 * splats them (its sorted points pr), so no piece
 * near a vertex is left out, and neighbouring vertices blend the same
 * pieces: the crease is shaded as a fillet about mv_tau r wide on each
 * side, with no step where the pieces blended would change from vertex to
 * vertex.
 *
 * In two steps, one pass over the pieces in all for most blocks:
 * jm_meta_normals_probe is jm_meta_probe's splat (called by it, on the
 * roots it sorted; rb_probe and rn_probe its reach, at most the band's:
 * c->mv_tau >= 2 c->mv_check) and sums every vertex's normal at its root
 * on the way, as it keeps the largest value there; after the settling,
 * jm_meta_normals_finish sums again, in a pass over only them, the
 * vertices that no longer lie at their root (settled, or clamped on their
 * edge), replaying the pieces the first pass visited (jm_visit; it
 * enumerates them again if that list ran out of memory), and writes the
 * normals (nrm: nv in block order). A vertex's sum has the same terms in
 * the same order either way, so the bits are those of one pass at the
 * final points. 0 if out of memory. */
int jm_meta_normals_probe(const jm_grid *g, const jm_config *c, const jm_hood *hood, jm_probe *pr, jm_mnorm *m, int B,
                          const float *x, const float *y, const float *z, size_t nv, float rb_probe, float rn_probe);
int jm_meta_normals_finish(const jm_grid *g, const jm_config *c, const jm_hood *hood, jm_probe *pr, jm_mnorm *m,
                           int B, const float *x, const float *y, const float *z, const float *pos, float *nrm,
                           size_t nv);
#endif
