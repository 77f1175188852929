/* templates.c - isolated particles meshed as copies of one particle's mesh (the template), translated. */
#include "extract/templates.h"
#include "context.h"
#include "extract/uv.h"

static void template_task(void *arg, size_t k, int worker)
{
    (void)worker;
    jm_frame *job = arg;
    jm_context *ctx = job->ctx;
    const float *c = &job->iso_pos[3 * k];
    float d[3] = {c[0] - ctx->t_origin[0], c[1] - ctx->t_origin[1], c[2] - ctx->t_origin[2]};
    size_t v0 = job->tmpl_v0 + k * ctx->t_nv;
    for (size_t v = 0; v < ctx->t_nv; v++) {
        float *p = ctx->pos + 3 * (v0 + v), *n = ctx->nrm + 3 * (v0 + v);
        for (int a = 0; a < 3; a++) {
            p[a] = ctx->t_pos[3 * v + a] + d[a];
            n[a] = ctx->t_nrm[3 * v + a];
        }
        if (job->c->uv_mode != JM_UV_NONE) jm_uv(job->c, p, n, ctx->uv + 2 * (v0 + v));
    }
    uint32_t *dst = ctx->idx + job->tmpl_i0 + k * ctx->t_ni;
    for (size_t t = 0; t < ctx->t_ni; t++) dst[t] = (uint32_t)(v0 + ctx->t_idx[t]);
}

jm_status jm_frame_templates(jm_frame *f)
{
    jm_context *ctx = f->ctx;
    if (!f->n_isolated) return JM_OK;
    f->tmpl_v0 = ctx->nv;
    f->tmpl_i0 = ctx->ni;
    size_t tv = ctx->nv + f->n_isolated * ctx->t_nv, ti = ctx->ni + f->n_isolated * ctx->t_ni;
    if (tv >= JM_PENDING) return JM_E_TOO_LARGE;
    if (!jm_context_reserve(ctx, tv, ti)) return JM_E_OUT_OF_MEMORY;
    ctx->nv = tv;
    ctx->ni = ti;
    jm_pool_run(ctx->pool, f->n_isolated, 64, template_task, f);
    return JM_OK;
}
