/* smooth_scratch.c - the smoothing stages' shared services: passes over chunks on the pool, and the working arrays kept from frame to frame. */
#include "post/smooth.h"

#include <string.h>

void sm_run_ranges(jm_pool *pool, size_t nchunks, jm_task_fn fn, void *arg)
{
    /* each thread one contiguous range, the same every pass: the lines a
     * thread wrote stay in its cache for the next pass (chunks handed out
     * as they come made 2 threads no faster than one); any split gives the
     * same result */
    const size_t t = (size_t)jm_pool_threads(pool);
    jm_pool_run(pool, nchunks, (nchunks + t - 1) / t, fn, arg);
}

void sm_run_swap(jm_pool *pool, sm_job *job, jm_task_fn fn, void *arg, float **src, float **dst)
{
    job->src = *src;
    job->dst = *dst;
    sm_run_ranges(pool, job->nchunks, fn, arg);
    float *t = *src;
    *src = *dst;
    *dst = t;
}

void *sm_scratch(jm_post_scratch *s, jm_mem *mem, int k, size_t bytes)
{
    if (bytes == 0) bytes = 1;
    if (s->bytes[k] >= bytes) return s->p[k];
    size_t want = bytes + bytes / 4;
    jm_free(mem, s->p[k], s->bytes[k]);
    s->p[k] = jm_alloc_lasting(mem, want);
    s->bytes[k] = s->p[k] ? want : 0;
    return s->p[k];
}

void jm_post_scratch_free(jm_post_scratch *s, jm_mem *mem)
{
    for (int k = 0; k < JM_POST_BUFS; k++) jm_free(mem, s->p[k], s->bytes[k]);
    memset(s, 0, sizeof *s);
}
