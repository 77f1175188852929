/* stitch.c - the blocks' meshes joined: each reference to a vertex owned by another block replaced by its index. */
#include "extract/stitch.h"
#include <string.h>

static void resolve_task(void *arg, size_t p, int worker)
{
    (void)worker;
    jm_frame *job = arg;
    uint32_t owner = job->pend[2 * p], slot = job->pend[2 * p + 1];
    const uint32_t *m = job->bmap[owner];
    /* the first entry not below slot, without a branch per halving (the
     * slots are distinct: the same entry as any binary search) */
    size_t lo = 0, len = job->nbmap[owner];
    while (len > 1) {
        const size_t half = len / 2;
        lo = m[2 * (lo + half - 1)] < slot ? lo + half : lo;
        len -= half;
    }
    if (len == 1 && m[2 * lo] < slot) lo++;
    if (lo < job->nbmap[owner] && m[2 * lo] == slot) {
        job->pend[2 * p] = (uint32_t)(job->vbase[owner] + m[2 * lo + 1]);
    } else {
        job->pend[2 * p] = 0;
        job->failed = 2;
    }
}

#define CHUNK 16384
static void patch_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    jm_frame *job = arg;
    jm_context *ctx = job->ctx;
    size_t a = chunk * CHUNK, b = a + CHUNK < ctx->ni ? a + CHUNK : ctx->ni;
    for (size_t t = a; t < b; t++) {
        uint32_t r = ctx->idx[t];
        if (r & JM_PENDING) ctx->idx[t] = job->pend[2 * (size_t)(r & ~JM_PENDING)];
    }
}

jm_status jm_frame_stitch(jm_frame *f)
{
    jm_context *ctx = f->ctx;
    jm_pool_run(ctx->pool, f->npend, 4096, resolve_task, f);
    if (f->failed) return JM_E_INTERNAL;
    for (size_t b = 0; b < f->bs.count; b++) { /* the owners' maps: done with */
        jm_free(&ctx->mem, f->bmap[b], f->nbmap[b] * 2 * sizeof(uint32_t));
        f->bmap[b] = NULL;
    }
    jm_pool_run(ctx->pool, (ctx->ni + CHUNK - 1) / CHUNK, 1, patch_task, f);
    return JM_OK;
}
