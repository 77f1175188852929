/* draco_bits.h - picks the fewest Draco position bits (from 16) at which no triangle of a mesh collapses. */
#ifndef JETMESH_FORMATS_DRACO_BITS_H
#define JETMESH_FORMATS_DRACO_BITS_H
#include <stddef.h>
#include "../lib/jetmesh.h"

#ifdef __cplusplus
extern "C" {
#endif

#define JMF_DRACO_AUTO_MIN_BITS 16
#define JMF_DRACO_AUTO_MAX_BITS 24

/* The smallest number of position bits in [16, 24] at which no triangle
 * becomes flat after Draco's quantisation (beyond those already flat in
 * float); 24 if none is enough. out_collapsed (may be NULL) gets how many
 * triangles collapse at the bits returned. */
int jmf_draco_auto_position_bits(const jm_mesh *mesh, size_t *out_collapsed);

#ifdef __cplusplus
}
#endif
#endif
