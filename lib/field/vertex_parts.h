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
/* Normals part by part: for each part holding vertices, part() gathers the
 * field near the part's box [plo, phi] and writes the normals of its n
 * vertices order[0..n); 0 when it runs out of memory. Returns 1, or 0 when
 * the parts or a part() do. */
typedef int (*jm_part_normals_fn)(const jm_block_env *env, jm_scratch *s, const float plo[3], const float phi[3],
                                  const uint32_t *order, uint32_t n, jm_bout *out);
int jm_vertex_parts_normals(const jm_block_env *env, jm_scratch *s, const float lo[3], const float hi[3], jm_bout *out,
                            jm_part_normals_fn part);
#endif
