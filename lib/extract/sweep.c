/* sweep.c - the frame's blocks meshed in batches on the pool's threads, each batch's outputs copied into the mesh. */
#include "extract/sweep.h"
#include "context.h"
#include "grid/release.h"
#include <string.h>

static void block_task(void *arg, size_t i, int worker)
{
    jm_frame *job = arg;
    jm_block_mesh(&job->env, job->first + i, &job->ctx->scratch[worker], &job->ctx->bouts[i]);
}

static void copy_task(void *arg, size_t i, int worker)
{
    (void)worker;
    jm_frame *job = arg;
    jm_context *ctx = job->ctx;
    jm_bout *o = &ctx->bouts[i];
    size_t vb = job->slot_vbase[i], ib = job->slot_ibase[i], pb = job->slot_pbase[i];
    if (o->nv) { /* (a block without vertices may never have allocated) */
        memcpy(ctx->pos + 3 * vb, o->pos, o->nv * 3 * sizeof(float));
        memcpy(ctx->nrm + 3 * vb, o->nrm, o->nv * 3 * sizeof(float));
        memcpy(ctx->uv + 2 * vb, o->uv, o->nv * 2 * sizeof(float));
    }
    uint32_t *dst = ctx->idx + ib;
    for (size_t t = 0; t < o->ni; t++) {
        uint32_t r = o->tri[t];
        dst[t] = (r & JM_PENDING) ? (JM_PENDING | (uint32_t)(pb + (r & ~JM_PENDING))) : (uint32_t)(vb + r);
    }
    if (o->np) memcpy(job->pend + 2 * pb, o->pend, o->np * 2 * sizeof(uint32_t));
    size_t b = job->first + i;
    if (o->nb) {
        uint32_t *m = jm_alloc(&ctx->mem, o->nb * 2 * sizeof(uint32_t));
        if (!m) { job->failed = 1; return; }
        memcpy(m, o->bmap, o->nb * 2 * sizeof(uint32_t));
        job->bmap[b] = m;
        job->nbmap[b] = (uint32_t)o->nb;
    }
}

/* The batch of m blocks from first: meshed, their outputs counted and
 * copied after the nv vertices and ni indices already there; then, where
 * the frame releases its grid, the particles no later block reads given back. */
static jm_status sweep_batch(jm_frame *f, size_t first, size_t m, size_t *nv_io, size_t *ni_io)
{
    jm_context *ctx = f->ctx;
    const jm_config *c = f->c;
    size_t nv = *nv_io, ni = *ni_io;
    f->first = first;
    double ta0 = jm_now_ms();
    jm_pool_run(ctx->pool, m, 1, block_task, f);
    double ta1 = jm_now_ms();
    f->t_blocks += ta1 - ta0;
    size_t np = f->npend;
    for (size_t i = 0; i < m; i++) {
        jm_bout *o = &ctx->bouts[i];
        if (o->failed) return o->failed == 1 ? JM_E_OUT_OF_MEMORY : JM_E_INTERNAL;
        f->st->cells += o->cells;
        f->tf += o->t_field;
        f->te += o->t_extract;
        f->ta += o->t_attr;
        f->vbase[first + i] = nv;
        f->slot_vbase[i] = nv;
        f->slot_ibase[i] = ni;
        f->slot_pbase[i] = np;
        nv += o->nv;
        ni += o->ni;
        np += o->np;
    }
    if (nv >= JM_PENDING || np >= JM_PENDING) return JM_E_TOO_LARGE;
    if (!jm_context_reserve(ctx, nv, ni)) return JM_E_OUT_OF_MEMORY;
    if (np > f->cappend) {
        size_t nc = f->cappend ? f->cappend * 2 : 4096;
        while (nc < np) nc *= 2;
        uint32_t *p = jm_realloc(&ctx->mem, f->pend, f->cappend * 2 * sizeof(uint32_t), nc * 2 * sizeof(uint32_t));
        if (!p) return JM_E_OUT_OF_MEMORY;
        f->pend = p;
        f->cappend = nc;
    }
    f->npend = np;
    ctx->nv = *nv_io = nv;
    ctx->ni = *ni_io = ni;
    jm_pool_run(ctx->pool, m, 1, copy_task, f);
    if (f->failed) return JM_E_OUT_OF_MEMORY;
    if (jm_frame_releases_grid(c) && first + m < f->bs.count) {
        /* the blocks left lie at the next one's z or above (its low
         * nodes as block.c places them); their hoods start at a cell z
         * of at least this one's: every cell below (one more to spare)
         * is done */
        int64_t kz = (int64_t)(f->bs.key[first + m] >> (2 * JM_KEY_BITS)) + f->bs.origin[2];
        float zlo = (float)((double)(kz * c->block) * (double)c->h);
        jm_grid_release_below(&f->g, &ctx->mem, jm_hood_cell_lo(&f->g, c, zlo) - 1);
    }
    f->t_stitch += jm_now_ms() - ta1;
    return JM_OK;
}

jm_status jm_frame_sweep(jm_frame *f)
{
    size_t nv = 0, ni = 0;
    for (size_t first = 0; first < f->bs.count; first += f->slots) {
        const size_t m = f->bs.count - first < f->slots ? f->bs.count - first : f->slots;
        const jm_status s = sweep_batch(f, first, m, &nv, &ni);
        if (s != JM_OK) return s;
    }
    return JM_OK;
}
