/* frame.h - the context and one frame's state, shared by the pipeline (mesh.c) and the stages it calls. */
#ifndef JETMESH_FRAME_H
#define JETMESH_FRAME_H
#include "extract/block.h"
#include "post/post_mesh.h"
#include <stdatomic.h>

struct jm_context {
    jm_params params; /* with defaults filled in */
    jm_config cfg;
    jm_pool *pool;
    int threads;
    jm_mem mem;
    jm_scratch *scratch;
    int nscratch;
    size_t scratch_cap; /* jm_scratch structs allocated */
    jm_bout *bouts;
    size_t nbouts;
    /* the last mesh */
    float *pos, *nrm, *uv;
    size_t capv;
    uint32_t *idx;
    size_t capi;
    size_t nv, ni;
    /* the sphere template (isolated particles) */
    int have_tmpl;
    float *t_pos, *t_nrm;
    uint32_t *t_idx;
    size_t t_nv, t_ni;
    float t_origin[3];
    jm_post_scratch post; /* post-processing arrays (post_mesh.h) */
};

/* Whether the mesh is post-processed (smoothing, simplification), which reads the particles */
static inline int jm_frame_post(const jm_config *c)
{
    return c->smooth_iters || c->smooth_normal_iters || c->simplify_error > 0.0f;
}

/* Whether a frame gives its particles back behind the block sweep: isotropic
 * SPH with no post-processing (nothing after the sweep reads the particles;
 * the anisotropic kernels and the post-processing do) */
static inline int jm_frame_releases_grid(const jm_config *c)
{
    return c->field == JM_FIELD_SPH && !c->aniso && !jm_frame_post(c);
}

/* One frame on its way through the stages (mesh.c: run). */
typedef struct jm_frame {
    jm_context *ctx;
    const jm_config *c;    /* the frame's configuration: the context's, or cfg */
    jm_config cfg;         /* anisotropic: c with the band as wide as the kernels reach */
    jm_stats *st;
    const struct jm_field_ops *field; /* the frame's field (field_ops.h) */
    jm_grid g;
    jm_block_set bs;
    jm_block_env env;
    size_t nb, slots;      /* blocks (at least 1) and block outputs per batch */
    size_t first;          /* first block of the batch */
    size_t *vbase;         /* per block: first global vertex */
    uint32_t **bmap;       /* per block: sorted (slot, local) pairs */
    uint32_t *nbmap;
    size_t *slot_vbase, *slot_ibase, *slot_pbase;
    uint32_t *pend;        /* global pending pairs */
    size_t npend, cappend;
    atomic_int failed;     /* 1 memory, 2 internal; set by any worker */
    size_t n_isolated;     /* the grid's isolated particles (kept when it goes) */
    uint32_t *iso;         /* sorted indices of isolated particles, input order */
    float *iso_pos;        /* and their positions (the sweep may release the grid's) */
    uint32_t *roots;       /* the cavity pass's pieces, for smoothing (roots_n entries) */
    size_t roots_n;
    int roots_ok;          /* roots are the final mesh's pieces */
    size_t tmpl_v0, tmpl_i0;
    /* thread milliseconds of the blocks' stages, and wall milliseconds */
    double tf, te, ta, t_blocks, t_stitch;
} jm_frame;
#endif
