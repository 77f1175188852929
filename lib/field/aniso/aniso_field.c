/* aniso_field.c - the anisotropic SPH field's stages: per-particle kernels, the kernels reaching each block, culling, splats, normals. */
#include "field/aniso/aniso_field.h"
#include "field/aniso/aniso_boxes.h"
#include "field/aniso/aniso_cull.h"
#include "field/aniso/aniso_normals.h"
#include "field/aniso/aniso_splat.h"
#include "field/sph/cull.h"
#include "field/vertex_parts.h"

/* The kernels (anisotropy.c): the band reaches as far as this frame's do. */
static jm_status frame_grid(jm_grid *g, jm_mem *mem, jm_pool *pool, const jm_config **c, jm_config *own)
{
    const jm_status s = jm_aniso_build(g, mem, pool, *c);
    if (s != JM_OK) return s;
    *own = **c;
    if (g->an_reach > own->influence) own->influence = g->an_reach;
    *c = own;
    return JM_OK;
}

static int drop_coords(const jm_config *c, jm_grid *g, jm_mem *mem, jm_block_set *bs)
{
    (void)c;
    (void)bs;
    jm_grid_drop_coords(g, mem); /* read no more */
    return 1;
}

/* The kernels reaching the block (and the normals' part boxes, a hundredth
 * of a support wider), looked at from here on. */
static int block_prepare(const jm_block_env *env, jm_scratch *s, const float lo[3], const float hi[3])
{
    return jm_aniso_candidates(env->g, &s->hood, lo, hi, 0.02f * env->c->support, &s->an_cand);
}

static int outside(const jm_block_env *env, jm_scratch *s, const float lo[3], const float hi[3], size_t *inner)
{
    return jm_aniso_block_outside(env->g, env->c, &s->an_cand, lo, hi, inner);
}

/* Boxes of 3 x 3 x 3 nodes where they apply (aniso_boxes.c), else partial
 * sums in a block a third full or more (aniso_cull.c). */
static int inside(const jm_block_env *env, jm_scratch *s, size_t inner, const float lo[3], const float hi[3],
                  float *proof)
{
    const jm_config *c = env->c;
    const int n = s->B + 1;
    if (jm_aniso_boxes_apply(c, inner, lo, hi)) {
        *proof = jm_aniso_boxes(env->g, c, &s->an_cand, s->x, s->y, s->z, n, s->boxes, s->part);
        return 1;
    }
    if (!jm_sph_block_full(c, inner, lo, hi)) return 0;
    jm_aniso_partial(env->g, c, &s->an_cand, s->x, s->y, s->z, n, s->part);
    *proof = c->threshold;
    return 1;
}

static const float *sample(const jm_block_env *env, jm_scratch *s, int n, const uint8_t *span, size_t *stride)
{
    jm_aniso_sample(env->g, env->c, &s->an_cand, s->x, s->y, s->z, n, span, s->pad);
    *stride = JM_PAD(n);
    return s->pad;
}

/* The kernels' normals at a part's vertices from the kernels near it, each
 * vertex settled onto the surface along its edge (aniso_normals.c: the
 * block's fallback normals are the edges' directions). */
static int part_normals(const jm_block_env *env, jm_scratch *s, const float plo[3], const float phi[3],
                        const uint32_t *order, uint32_t n, jm_bout *out)
{
    jm_aniso_gather(env->g, &s->an_cand, plo, phi, &s->an_list);
    if (s->an_list.n == SIZE_MAX) return 0;
    jm_aniso_normals(&s->an_list, env->c->threshold, env->c->h, order, n, out->pos, out->nrm);
    return 1;
}

/* The kernels' normals at the block's vertices, part by part
 * (vertex_parts.h); the vertices settle whether or not normals are wanted
 * (the surface is the same either way). */
static int finish(const jm_block_env *env, jm_scratch *s, const float lo[3], const float hi[3], int want_nrm,
                  jm_bout *out)
{
    (void)want_nrm;
    if (!out->nv) return 1;
    return jm_vertex_parts_normals(env, s, lo, hi, out, part_normals);
}

const jm_field_ops jm_aniso_field = {
    .frame_grid = frame_grid,
    .frame_blocks = drop_coords,
    .block_prepare = block_prepare,
    .outside = outside,
    .inside = inside,
    .sample = sample,
    .finish = finish,
};
