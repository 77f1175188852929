/* stitch.h - the blocks' meshes joined: each reference to a vertex owned by another block replaced by its index. */
#ifndef JETMESH_STITCH_H
#define JETMESH_STITCH_H
#include "frame.h"

/* A pending pair (frame.h) the sweep's copy already resolved: its first
 * entry is the vertex's index. */
#define JM_RESOLVED UINT32_MAX

/* After jm_frame_sweep: every pending reference the sweep left resolved
 * through its owner block's map (JM_E_INTERNAL where one is missing). */
jm_status jm_frame_stitch(jm_frame *f);

/* The local index that a block's map (n sorted (slot, local) pairs) gives
 * slot, or UINT32_MAX if it has none. */
uint32_t jm_stitch_find(const uint32_t *map, size_t n, uint32_t slot);
#endif
