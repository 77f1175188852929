/* sweep.h - the frame's blocks meshed in batches on the pool's threads, each batch's outputs copied into the mesh. */
#ifndef JETMESH_SWEEP_H
#define JETMESH_SWEEP_H
#include "frame.h"

/* Every block of f in z order (their keys), f->slots at a time: the
 * context's mesh holds their vertices and triangles, the references to
 * vertices of later blocks pending (f->pend) until jm_frame_stitch. Where
 * nothing after the sweep reads the particles, the grid is given back
 * behind it, so that the peak holds the mesh and a band of the grid. */
jm_status jm_frame_sweep(jm_frame *f);
#endif
