/* metavertex.h - metasphere vertices: every piece near a point, settling onto the exact surface, blended normals. */
#ifndef JETMESH_METAVERTEX_H
#define JETMESH_METAVERTEX_H
#include "field.h"
#include <math.h>

/* Fills the metasphere's vertex constants of c (the reach of the pieces,
 * the blend width of the normals, the tolerance of the check); called by
 * jm_config_resolve. */
void jm_metavertex_config(jm_config *c);

/* The vertex on edge a + t ab found from the pieces won at the edge's two
 * nodes (cand) at parameter t, where the piece `win` gives the value there:
 * checks every piece near that point and, while one beats the candidates by
 * more than the tolerance (a third piece winning mid-edge), refines again
 * on the edge with those pieces added. fa: field minus threshold at a.
 * Returns the settled t; nrm (may be NULL) gets the normal there: the
 * pieces within the blend width of the maximum, their outward normals
 * weighted by how close they come to it. */
float jm_meta_settle(const jm_grid *g, const jm_config *c, const jm_hood *hood, const uint32_t cand[2], uint32_t win,
                     const float a[3], const float ab[3], float fa, float t, float nrm[3]);

/* Normals are blended across a crease: a piece gap below the leading one
 * (at most c->mv_tau) weighs smoothstep(1 - gap / mv_tau), the leading one
 * 1: the direction of the gradient of a smooth maximum of the pieces,
 * continuous wherever the leading piece changes (C1: weight 1 where two
 * pieces meet, 0 with a flat tangent at the band's edge). jm_meta_normals
 * applies the same rule to every piece near every vertex. */
static inline float jm_meta_weight(const jm_config *c, float gap)
{
    if (!(gap < c->mv_tau)) return 0.0f;
    const float x = 1.0f - (gap > 0.0f ? gap : 0.0f) / c->mv_tau;
    return x * x * (3.0f - 2.0f * x);
}

/* The normal of n pieces meeting near a point (values v, unit normals
 * nk): the leading piece's plus each other's by jm_meta_weight,
 * normalised. */
void jm_meta_blend(const jm_config *c, int n, const float *v, const float (*nk)[3], float out[3]);

/* The blended normal at p, a point on the surface next to piece `win`. */
void jm_meta_normal(const jm_grid *g, const jm_config *c, const jm_hood *hood, uint32_t win, const float p[3],
                    float nrm[3]);

/* The stitched mesh's last pass (pos, nrm: nv vertices; idx: nt
 * triangles): compensate moves every vertex outward by the estimated chord
 * sag of its triangles (at most max_sag); facing pulls a normal that points away from one of
 * its triangles toward theirs. 0 if out of memory. */
int jm_meta_finish(jm_mem *mem, float *pos, float *nrm, size_t nv, const uint32_t *idx, size_t nt, int compensate,
                   int facing, float max_sag);
#endif
