/* metavertex.h - metasphere vertices: every piece near a point, settling onto the exact surface. */
#ifndef JETMESH_METAVERTEX_H
#define JETMESH_METAVERTEX_H
#include "field/field.h"
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
 * Returns the settled t. */
float jm_meta_settle(const jm_grid *g, const jm_config *c, const jm_hood *hood, const uint32_t cand[2], uint32_t win,
                     const float a[3], const float ab[3], float fa, float t);

/* The stitched mesh's last pass (pos, nrm: nv vertices; idx: nt
 * triangles): compensate moves every vertex outward by the estimated chord
 * sag of its triangles (at most max_sag); facing pulls a normal that points
 * away from one of its triangles toward theirs. The passes over every
 * triangle run on the pool's threads (NULL: the caller's), the same bits
 * for any number. 0 if out of memory. */
int jm_meta_finish(jm_mem *mem, jm_pool *pool, float *pos, float *nrm, size_t nv, const uint32_t *idx, size_t nt,
                   int compensate, int facing, float max_sag);
#endif
