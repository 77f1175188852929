/* metaprobe.h - every metasphere piece evaluated at a block's vertices: a third piece beating the surface, crease normals. */
#ifndef JETMESH_METAPROBE_H
#define JETMESH_METAPROBE_H
#include "field/field.h"

/* A block's metasphere vertices as the probe needs them (worker scratch,
 * grown with realloc like the rest of the scratch). Per vertex, in block
 * order: its edge (node * 7 + direction, as the block's vertex slots) and
 * the root its edge's two pieces gave (before the clamp to [0.01, 0.99]).
 * The rest is the probe's own: the vertices' points sorted by part of the
 * block (PART^3 cubes) and the largest piece value found at each. */
typedef struct jm_probe {
    jm_mem *mem;          /* the context's counts (alloc.c); kept by jm_probe_free */
    size_t cap;
    uint32_t *slot;
    float *t;
    uint32_t *part;       /* per vertex: its node (jm_probe_add), then its part */
    int pc;               /* the block's parts: pc cubes a side */
    float *pt;            /* per vertex: its root's point (3 floats) */
    size_t capw;          /* sorted arrays: vertices + 4 */
    uint32_t *order;      /* sorted position -> vertex */
    float *px, *py, *pz;  /* the vertices' points */
    float *vmax;          /* the largest value of a piece there */
    size_t capp;
    uint32_t *pstart;     /* parts + 1: first sorted position of each part; then 4 parts of counts */
} jm_probe;

/* parts are pc cubes a side (a block's choice, jm_meta_probe: the
 * pieces' boxes cover the vertices of a crowded block more closely in
 * smaller parts; no value depends on it): a block of B cubes has
 * jm_probe_parts(B, pc) a side, and node (i, j, k) lies in part
 * jm_probe_part(np, pc, i, j, k) */
static inline int jm_probe_parts(int B, int pc) { return (B + pc - 1) / pc; }
/* a block of at least this many vertices is crowded: parts of 2 cubes */
#define JM_PROBE_CROWDED 700
static inline uint32_t jm_probe_part(int np, int pc, int i, int j, int k)
{
    return (uint32_t)(((k / pc) * np + j / pc) * np + i / pc);
}

/* the parts [lo, hi] (per axis) holding the cubes that meet the box
 * [blo, bhi] (nodes x0 + i h); 0 if none. The boxes are wider than the
 * pieces by a thousandth of r, far more than the rounding here (doubles). */
static inline int jm_probe_dfloor(double x)
{
    int t = (int)x;
    return t - (x < (double)t);
}
static inline int jm_probe_part_span(const float x0[3], int B, int pc, double inv_h, const float blo[3],
                                     const float bhi[3], int lo[3], int hi[3])
{
    for (int a = 0; a < 3; a++) {
        double f0 = ((double)blo[a] - (double)x0[a]) * inv_h, f1 = ((double)bhi[a] - (double)x0[a]) * inv_h;
        if (f1 < 0.0 || f0 >= (double)B) return 0;
        /* the cubes holding the box's ends, and all between */
        int c0 = f0 < 0.0 ? 0 : jm_probe_dfloor(f0), c1 = f1 >= (double)B ? B - 1 : jm_probe_dfloor(f1);
        lo[a] = c0 / pc;
        hi[a] = c1 / pc;
    }
    return 1;
}

/* Room for vertex v (0 if out of memory). */
int jm_probe_grow(jm_probe *pr, size_t v);

/* Records vertex v: its edge slot, its edge's first node (i | j << 8 | k
 * << 16: jm_meta_probe turns it into the part), the root t on its edge and
 * the root's point p (0 if out of memory). */
static inline int jm_probe_add(jm_probe *pr, size_t v, uint32_t slot, uint32_t ijk, float t, const float p[3])
{
    if (v >= pr->cap && !jm_probe_grow(pr, v)) return 0;
    pr->slot[v] = slot;
    pr->part[v] = ijk;
    pr->t[v] = t;
    pr->pt[3 * v] = p[0];
    pr->pt[3 * v + 1] = p[1];
    pr->pt[3 * v + 2] = p[2];
    return 1;
}
void jm_probe_free(jm_probe *pr);
/* pr's capacities grown to at least o's (0 if out of memory). */
int jm_probe_match(jm_probe *pr, const jm_probe *o);

/* The block's vertices (nv of them: pos, the edge pieces cand; B cubes a
 * side with node coordinates x, y, z and node
 * values f) checked against every piece of the field: where the largest
 * piece value at a vertex's root is off the threshold by more than
 * c->mv_tol (a third piece winning mid-edge, or a refinement stopped
 * short), the vertex is settled again on every piece near it
 * (jm_meta_settle). With m (normals wanted), the splat is the normals'
 * (jm_meta_normals_probe, which sums them on the way) and
 * jm_meta_normals_finish comes after; without, the probe's own. 0 if out
 * of memory. */
struct jm_mnorm;
int jm_meta_probe(const jm_grid *g, const jm_config *c, const jm_hood *hood, jm_probe *pr, struct jm_mnorm *m, int B,
                  const float *x, const float *y, const float *z, const float *f, float *pos, const uint32_t *cand,
                  size_t nv);
#endif
