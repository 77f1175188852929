/* metaroot.h - a block's metasphere vertices on their lattice edges, 8 at a time: each piece's crossing in closed form (a ball) or by bracketed Newton steps (a half-neck). */
#ifndef JETMESH_METAROOT_H
#define JETMESH_METAROOT_H
#include "field/field.h"

/* A block's vertices as the marching finds them: each one's edge a + t ab
 * (t in [0, 1]), the field minus the threshold at a, the linear estimate t
 * from the node values, and the pieces won at the edge's nodes (c0 at a,
 * c1 at b; UINT32_MAX where a node was clamped). jm_roots_solve puts each
 * vertex's root in t. Worker scratch: lasting arrays (internal.h). */
typedef struct jm_roots {
    jm_mem *mem;
    size_t n, cap;
    float *ax, *ay, *az, *bx, *by, *bz, *fa, *t;
    uint32_t *c0, *c1;
    uint32_t *list; /* the solver's work lists */
} jm_roots;

/* Room for one more vertex (0 if out of memory). */
int jm_roots_grow(jm_roots *r);
/* Appends a vertex (0 if out of memory). */
static inline int jm_roots_add(jm_roots *r, const float a[3], const float ab[3], float fa, float t, const uint32_t c[2])
{
    if (r->n == r->cap && !jm_roots_grow(r)) return 0;
    const size_t k = r->n++;
    r->ax[k] = a[0], r->ay[k] = a[1], r->az[k] = a[2];
    r->bx[k] = ab[0], r->by[k] = ab[1], r->bz[k] = ab[2];
    r->fa[k] = fa, r->t[k] = t, r->c0[k] = c[0], r->c1[k] = c[1];
    return 1;
}

/* The crossing of the surface of each vertex's two pieces on its edge, into
 * t. The surface of their maximum leaves the inside node's piece where
 * that piece's own surface does (a ball's crossing in closed form, a
 * half-neck's by Newton steps bracketed by the edge), unless the other
 * piece holds that point, whose crossing beyond it then is the vertex. A
 * piece winning nowhere at the nodes but mid-edge is the probe's
 * (metaprobe.c) to catch. Eight vertices a step, each lane the same float
 * operations whatever the CPU: the same bits. */
void jm_roots_solve(const jm_grid *g, const jm_config *c, jm_roots *r);

/* r's capacity grown to at least o's (0 if out of memory); freed. */
int jm_roots_match(jm_roots *r, const jm_roots *o);
void jm_roots_free(jm_roots *r);
#endif
