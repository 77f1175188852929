/* field_ops.h - one interface per field: what the pipeline and the block meshing ask of SPH, anisotropic SPH or the metasphere. */
#ifndef JETMESH_FIELD_OPS_H
#define JETMESH_FIELD_OPS_H
#include "extract/block.h"

/* A field's stages, chosen once per frame (jm_field_ops_of); the block's
 * are called once per block, never per node or vertex. NULL: nothing to do. */
typedef struct jm_field_ops {
    /* -- per frame */
    /* After the grid: the field's own per-particle data (the anisotropic
     * kernels); *c may be replaced by own, a copy whose band reaches as far
     * as the kernels. */
    jm_status (*frame_grid)(jm_grid *g, jm_mem *mem, jm_pool *pool, const jm_config **c, jm_config *own);
    /* After the blocks are known: what the blocks read of the grid's cells
     * (the metasphere's per-block cell lists; the others drop the cells'
     * coordinates). 0 if out of memory. */
    int (*frame_blocks)(const jm_config *c, jm_grid *g, jm_mem *mem, jm_block_set *bs);
    /* The stitched mesh's last pass (the metasphere's sag and normals).
     * 0 if out of memory. */
    int (*frame_finish)(const jm_config *c, jm_mem *mem, jm_pool *pool, float *pos, float *nrm, size_t nv,
                        const uint32_t *idx, size_t ni);
    /* -- per block (lo, hi: the block's box; s: the worker's scratch) */
    /* After the hood: what the block looks at (the kernels reaching it). */
    int (*block_prepare)(const jm_block_env *env, jm_scratch *s, const float lo[3], const float hi[3]);
    /* Outside test (culling only): 1 when the block is proven to hold no
     * inside node; *inner gets the particles well inside it. */
    int (*outside)(const jm_block_env *env, jm_scratch *s, const float lo[3], const float hi[3], size_t *inner);
    /* Inside proof (culling only): 0 where the block is too empty to try;
     * else lower bounds of the field into s->part and the value above which
     * a bound proves its node inside, in *proof. */
    int (*inside)(const jm_block_env *env, jm_scratch *s, size_t inner, const float lo[3], const float hi[3],
                  float *proof);
    /* The field on the block's n^3 nodes (only the rows' spans given by
     * span, if not NULL): node (i, j, k) at [(k n + j) *stride + i]. */
    const float *(*sample)(const jm_block_env *env, jm_scratch *s, int n, const uint8_t *span, size_t *stride);
    /* After the cubes are marched: the vertices' positions where they were
     * left to the field (the metasphere's roots), still in the extraction. */
    void (*vertices)(const jm_block_env *env, jm_scratch *s, jm_bout *out);
    /* The vertices' normals (want_nrm) and whatever else the field settles
     * at them. 0 if out of memory. */
    int (*finish)(const jm_block_env *env, jm_scratch *s, const float lo[3], const float hi[3], int want_nrm,
                  jm_bout *out);
    /* The metasphere: sample leaves the rows it never reached marked in
     * s->rowstate, and the edges' vertices are roots solved by vertices. */
    int meta;
} jm_field_ops;

/* The field of configuration c: SPH, anisotropic SPH or the metasphere. */
const jm_field_ops *jm_field_ops_of(const jm_config *c);
#endif
