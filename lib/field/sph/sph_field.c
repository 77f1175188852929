/* sph_field.c - the isotropic SPH field's stages: culling by bounds, sampling by splats, normals from the gathered particles. */
#include "field/sph/sph_field.h"
#include "field/sph/cull.h"
#include "field/sph/inside_boxes.h"
#include "field/sph/splat.h"
#include "field/vertex_parts.h"

static int drop_coords(const jm_config *c, jm_grid *g, jm_mem *mem, jm_block_set *bs)
{
    (void)c;
    (void)bs;
    jm_grid_drop_coords(g, mem); /* read no more */
    return 1;
}

static int outside(const jm_block_env *env, jm_scratch *s, const float lo[3], const float hi[3], size_t *inner)
{
    return jm_sph_block_outside(env->g, env->c, &s->hood, lo, hi, inner);
}

/* A block a third full of fluid or more: boxes of 3 x 3 x 3 nodes on a fine
 * lattice (inside_boxes.c), else partial sums (cull.c). */
static int inside(const jm_block_env *env, jm_scratch *s, size_t inner, const float lo[3], const float hi[3],
                  float *proof)
{
    const jm_config *c = env->c;
    const int n = s->B + 1;
    if (!jm_sph_block_full(c, inner, lo, hi)) return 0;
    if (jm_sph_boxes_apply(c, inner, lo, hi)) { /* JM_BOX_FILL full, fine lattice */
        *proof = jm_sph_box_threshold(c, &s->hood);
        jm_sph_boxes(env->g, c, &s->hood, s->x, s->y, s->z, n, s->boxes, s->part);
    } else {
        *proof = jm_sph_partial_threshold(c, &s->hood);
        jm_sph_partial(env->g, c, &s->hood, s->x, s->y, s->z, n, s->part);
    }
    return 1;
}

static const float *sample(const jm_block_env *env, jm_scratch *s, int n, const uint8_t *span, size_t *stride)
{
    jm_sph_sample(env->g, env->c, &s->hood, s->x, s->y, s->z, n, span, s->pad);
    *stride = JM_PAD(n);
    return s->pad;
}

/* SPH normals of a part's vertices from the particles near it. */
static int part_normals(const jm_block_env *env, jm_scratch *s, const float plo[3], const float phi[3],
                        const uint32_t *order, uint32_t n, jm_bout *out)
{
    jm_sph_gather(env->g, env->c, &s->hood, plo, phi, &s->soa);
    if (s->soa.n == SIZE_MAX) return 0;
    jm_sph_normals(env->c, &s->soa, order, n, out->pos, out->nrm);
    return 1;
}

/* SPH normals of the block's vertices, part by part (vertex_parts.h). */
static int finish(const jm_block_env *env, jm_scratch *s, const float lo[3], const float hi[3], int want_nrm,
                  jm_bout *out)
{
    if (!want_nrm || !out->nv) return 1;
    return jm_vertex_parts_normals(env, s, lo, hi, out, part_normals);
}

const jm_field_ops jm_sph_field = {
    .frame_blocks = drop_coords,
    .outside = outside,
    .inside = inside,
    .sample = sample,
    .finish = finish,
};
