/* metaroot.h - a metasphere vertex on its lattice edge: each piece's crossing in closed form (a ball) or by bracketed Newton steps (a half-neck). */
#ifndef JETMESH_METAROOT_H
#define JETMESH_METAROOT_H
#include "field.h"

/* The crossing of the surface of the two pieces won at the edge's nodes
 * (cand[0] at a, cand[1] at b; UINT32_MAX where a node was clamped) on the
 * edge a + t ab, t in [0, 1]; fa: the field minus the threshold at a, t0
 * the linear estimate from the node values. The surface of their maximum
 * leaves the inside node's piece where that piece's own surface does (a
 * ball's crossing in closed form, a half-neck's by Newton steps bracketed
 * by the edge), unless the other piece holds that point, whose crossing
 * beyond it then is the vertex. A piece winning nowhere at the nodes but
 * mid-edge is the probe's (metaprobe.c) to catch. */
float jm_meta_root(const jm_grid *g, const jm_config *c, const uint32_t cand[2], const float a[3], const float ab[3],
                   float fa, float t0);
#endif
