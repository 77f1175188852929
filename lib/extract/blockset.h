/* blockset.h - the frame's active blocks: every block a particle's influence reaches, sorted by key, and the memory estimate. */
#ifndef JETMESH_BLOCKSET_H
#define JETMESH_BLOCKSET_H
#include "extract/block.h"

/* Working memory estimate for a frame of n particles, links metasphere
 * neck links and nblocks blocks on threads workers. */
size_t jm_frame_estimate(const jm_config *c, size_t n, double links, size_t nblocks, int threads);
/* The blocks reached by g's particles not isolated, into bs (sorted keys and
 * their map); out_estimate the frame's memory estimate from an upper bound
 * of the blocks, refused (JM_E_TOO_LARGE) when absurd or over the limit. */
jm_status jm_blocks_build(const jm_config *c, const jm_grid *g, jm_mem *mem, jm_block_set *bs, int threads,
                          size_t *out_estimate);
void jm_blocks_free(jm_block_set *bs, jm_mem *mem);
#endif
