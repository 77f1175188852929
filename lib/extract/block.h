/* block.h - meshes one block of the lattice: sample, march, weld, normals, UVs. */
#ifndef JETMESH_BLOCK_H
#define JETMESH_BLOCK_H
#include "field/field.h"
#include "field/sph/sph_normals.h"
#include "field/aniso/anisotropy.h"
#include "field/meta/metaprobe.h"
#include "field/meta/metanormal.h"
#include "field/meta/metaroot.h"

/* What one block produced. Vertex refs in tri: an owned vertex's local index,
 * or JM_PENDING | k for the k-th (owner block, owner slot) pair in pend. */
#define JM_PENDING 0x80000000u
/* Interpolation parameters are kept this far from the edge ends, so no two
 * vertices meet at a lattice node (no zero-area triangles). */
#define JM_T_MIN 0.01f
typedef struct jm_bout {
    float *pos, *nrm, *uv;
    uint32_t *cand;           /* metasphere: 2 candidate pieces per vertex */
    size_t nv, capv;
    uint32_t *tri;
    size_t ni, capt;          /* indices (3 per triangle) */
    uint32_t *pend;           /* 2 per pending vertex */
    size_t np, capp;
    uint32_t *bmap;           /* 2 per owned vertex on a min face: slot, local index */
    size_t nb, capb;
    size_t cells;
    double t_field, t_extract, t_attr; /* thread milliseconds */
    int failed;               /* 1: allocation failed, 2: stitching impossible */
} jm_bout;

/* Scratch memory of one worker. */
typedef struct jm_scratch {
    int B;
    float *f;                 /* (B+1)^3 node values */
    uint8_t *in;              /* (B+1)^3 inside flags */
    uint32_t *win;            /* (B+1)^3 metasphere winning pieces */
    float *pad;               /* (B+1)^2 * JM_PAD(B+1) padded field rows */
    uint8_t *rowstate;        /* (B+1)^2 rows: 0 all out, 1 all in, 2 mixed */
    uint32_t *vt;             /* (B+1)^3 * 7 vertex refs */
    uint32_t *touched;
    size_t ntouched;
    float *x, *y, *z;         /* node coordinates */
    jm_hood hood;
    jm_soa soa;               /* sph: particles near a part of the block, for normals */
    uint32_t *order;          /* sph: vertices sorted by part of the block */
    size_t cap_order;
    jm_an_list an_list;       /* sph anisotropic: particles near a part, for normals */
    jm_an_cand an_cand;       /* sph anisotropic: the kernels reaching the block */
    jm_roots roots;           /* metasphere: the vertices' edges and pieces, solved at once */
    jm_probe probe;           /* metasphere: the vertices' edges, checked on every piece */
    jm_mnorm mnorm;           /* metasphere: the vertices' crease normals (metanormal.h) */
    float *part;              /* sph culling: (B+1)^2 * JM_PAD(B+1) partial sums (splat.h) */
    uint8_t *span;            /* sph culling: 2 per node row, the nodes to sample (cull.h) */
    void *boxes;              /* sph culling: the box pass's work (inside_boxes.h) */
} jm_scratch;

typedef struct jm_block_set {
    size_t count;
    uint64_t *key;            /* sorted block keys */
    jm_hashmap map;           /* key -> index */
    int64_t origin[3];        /* block coordinate of relative zero */
    uint32_t *cell_start;     /* metasphere: count + 1, each block's first in cells */
    uint32_t *cells;          /* the cells that reach each block (hood_cells.c) */
    size_t ncells;
} jm_block_set;


struct jm_field_ops;
typedef struct jm_block_env {
    const jm_grid *g;
    const jm_config *c;
    const jm_block_set *blocks;
    jm_mem *mem;
    const struct jm_field_ops *field; /* the frame's field (field_ops.h) */
} jm_block_env;

int jm_scratch_init(jm_scratch *s, int B);
size_t jm_scratch_bytes(int B); /* heap bytes of one scratch */
void jm_scratch_free(jm_scratch *s);
void jm_bout_reset(jm_bout *o);
void jm_bout_free(jm_bout *o, jm_mem *mem);

/* Meshes block index b into out (out reset first). */
void jm_block_mesh(const jm_block_env *env, size_t b, jm_scratch *s, jm_bout *out);

#endif
