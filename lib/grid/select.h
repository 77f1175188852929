/* select.h - the particles a frame meshes: inside the particle box, in groups of at least min_piece_particles. */
#ifndef JETMESH_SELECT_H
#define JETMESH_SELECT_H
#include "core/internal.h"

/* Whether configuration c leaves any particle out. */
int jm_select_on(const jm_config *c);

/* The particles c's selection leaves out (jetmesh.h, "Selection and
 * clipping", steps 1 and 2): *out_skip gets n flags (1: left out), from
 * mem (free with n bytes), or NULL when the selection is off; *out_kept
 * the count kept. JM_E_INVALID_PARTICLE for a coordinate that is not
 * finite; memory errors. */
jm_status jm_select(jm_mem *mem, jm_pool *pool, const jm_config *c, const jm_particles *in, uint8_t **out_skip,
                    size_t *out_kept);

/* The kept particles copied (xyz, and ids when in has them) into *out,
 * whose arrays come from mem (freed with jm_select_free_copy). */
jm_status jm_select_copy(jm_mem *mem, const jm_particles *in, const uint8_t *skip, size_t kept, jm_particles *out);
void jm_select_free_copy(jm_mem *mem, jm_particles *p);
#endif
