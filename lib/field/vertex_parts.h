/* vertex_parts.h - a block's vertices sorted into parts about a support wide, so that normals gather only the particles near each part. */
#ifndef JETMESH_VERTEX_PARTS_H
#define JETMESH_VERTEX_PARTS_H
#include "extract/block.h"

/* The block [lo, hi] cut into S^3 parts about a support wide (S from 1 to
 * 4): out's vertices listed part by part in s->order, part q's from
 * start[q] to start[q + 1]. Returns S, 0 if out of memory. */
int jm_vertex_parts(const jm_config *c, jm_scratch *s, const float lo[3], const float hi[3], const jm_bout *out,
                    uint32_t start[65]);
/* Part q's box [plo, phi], a hundredth of the support wider on each side
 * (a vertex of the part lies within the part up to rounding). */
void jm_vertex_part_box(const jm_config *c, int S, int q, const float lo[3], const float hi[3], float plo[3],
                        float phi[3]);
#endif
