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

#endif
