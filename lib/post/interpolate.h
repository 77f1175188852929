/* interpolate.h - per-particle values carried onto mesh vertices on a pool's threads (jm_context_interpolate). */
#ifndef JETMESH_INTERPOLATE_H
#define JETMESH_INTERPOLATE_H
#include "core/internal.h"

/* The argument checks jm_interpolate_attributes and jm_context_interpolate
 * share: JM_OK, or JM_E_INVALID_ARGUMENT; *out_total gets the components
 * over all attributes. */
jm_status jm_interp_check(const jm_particles *in, const float *positions, size_t nv, const jm_attribute *attrs,
                          size_t na, size_t *out_total);

/* jm_interpolate_attributes' weights and fallback for nv vertices (world
 * units), in float lanes on the pool's threads (interpolate.c). c: the
 * context's configuration (in its unit of length, c->unit_in); skip (NULL:
 * none) marks the particles to leave out (1), as the selection left them
 * out of the mesh. Arguments already checked (jm_interp_check). */
jm_status jm_interp_run(jm_mem *mem, jm_pool *pool, const jm_config *c, const uint8_t *skip, const jm_particles *in,
                        const float *positions, size_t nv, jm_attribute *attrs, size_t na);
#endif
