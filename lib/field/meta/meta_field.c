/* meta_field.c - the metasphere field's stages: per-block cell lists, splats, vertices as roots settled on the exact surface, the mesh's finish. */
#include "field/meta/meta_field.h"
#include "field/meta/metaroot.h"
#include "field/meta/metasplat.h"
#include "field/meta/metafinish.h"
#include "extract/hood_cells.h"

static int frame_blocks(const jm_config *c, jm_grid *g, jm_mem *mem, jm_block_set *bs)
{
    return jm_block_cells(c, g, mem, bs);
}

/* The sag offset and normals facing their triangles (metafinish.c). */
static int frame_finish(const jm_config *c, jm_mem *mem, jm_pool *pool, float *pos, float *nrm, size_t nv,
                        const uint32_t *idx, size_t ni)
{
    if (!c->compensate && !c->normals) return 1;
    return jm_meta_finish(mem, pool, pos, nrm, nv, idx, ni / 3, c->compensate, c->normals, 0.1f * c->h);
}

static const float *sample(const jm_block_env *env, jm_scratch *s, int n, const uint8_t *span, size_t *stride)
{
    (void)span; /* never culled */
    jm_meta_sample(env->g, env->c, &s->hood, s->x, s->y, s->z, n, s->f, s->win, s->rowstate);
    *stride = (size_t)n;
    return s->f;
}

/* The block's vertices on their edges (metaroot.c): each root for
 * jm_meta_probe (its point, pt), the vertex kept from the nodes */
static void vertices(const jm_block_env *env, jm_scratch *s, jm_bout *out)
{
    jm_roots *r = &s->roots;
    jm_roots_solve(env->g, env->c, r);
    for (size_t v = 0; v < r->n; v++) {
        const float tt = r->t[v], tc = tt < JM_T_MIN ? JM_T_MIN : (tt > 1.0f - JM_T_MIN ? 1.0f - JM_T_MIN : tt);
        const float a[3] = {r->ax[v], r->ay[v], r->az[v]}, ab[3] = {r->bx[v], r->by[v], r->bz[v]};
        float *pt = &s->probe.pt[3 * v], *p = &out->pos[3 * v];
        s->probe.t[v] = tt;
        for (int q = 0; q < 3; q++) {
            pt[q] = a[q] + tt * ab[q];
            p[q] = a[q] + tc * ab[q];
        }
    }
    r->n = 0;
}

/* Every piece checked at every vertex (metaprobe.c), the vertices off the
 * exact surface settled; the normals blended from every piece near each
 * vertex (metanormal.c). */
static int finish(const jm_block_env *env, jm_scratch *s, const float lo[3], const float hi[3], int want_nrm,
                  jm_bout *out)
{
    (void)lo;
    (void)hi;
    const jm_grid *g = env->g;
    const jm_config *c = env->c;
    if (!jm_meta_probe(g, c, &s->hood, &s->probe, want_nrm ? &s->mnorm : NULL, s->B, s->x, s->y, s->z, s->f,
                       out->pos, out->cand, out->nv))
        return 0;
    return !want_nrm ||
           jm_meta_normals_finish(g, c, &s->hood, &s->probe, &s->mnorm, s->B, s->x, s->y, s->z, out->pos, out->nrm,
                                  out->nv);
}

const jm_field_ops jm_meta_field = {
    .frame_blocks = frame_blocks,
    .frame_finish = frame_finish,
    .sample = sample,
    .vertices = vertices,
    .finish = finish,
    .meta = 1,
};
