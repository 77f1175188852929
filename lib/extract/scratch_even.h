/* scratch_even.h - the workers' growing scratch evened out after a frame's blocks, so that any worker can take any block. */
#ifndef JETMESH_SCRATCH_EVEN_H
#define JETMESH_SCRATCH_EVEN_H
#include "extract/block.h"

/* After a frame's blocks (n workers' scratch s): every growing buffer
 * grown to the largest any worker needed (scratch_even.c), so that the
 * next frame, its blocks no larger, allocates nothing whichever worker
 * takes which block. 0 if out of memory (the buffers stay valid). */
int jm_scratch_even(jm_scratch *s, int n);
#endif
