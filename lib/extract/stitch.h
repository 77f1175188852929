/* stitch.h - the blocks' meshes joined: each reference to a vertex owned by another block replaced by its index. */
#ifndef JETMESH_STITCH_H
#define JETMESH_STITCH_H
#include "frame.h"

/* After jm_frame_sweep: every pending reference resolved through its owner
 * block's map (JM_E_INTERNAL where one is missing), the maps freed. */
jm_status jm_frame_stitch(jm_frame *f);
#endif
