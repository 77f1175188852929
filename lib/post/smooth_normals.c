/* smooth_normals.c - the smoothed mesh's normals, normal smoothing over neighbours facing the same side, and fresh UVs. */
#include "post/smooth.h"
#include "extract/uv.h"

/* Each normal: the fan's area vector of the smoothed surface (job->src)
 * made unit, or the field's normal where the fan has no area. */
JM_BODY void fan_normal_task_body(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    const size_t a = chunk * SM_CH, b = sm_chunk_end(job->nv, chunk);
    size_t k = sm_lower_bound(job->f.big, job->f.nbig, a);
    for (size_t v = a; v < b; v++) {
        const v4f n = sm_fan_area(job, job->src, v, &k);
        const float l = sqrtf(sm_dot3(n, n));
        if (l > 0.0f) sm_store3(&job->m->nrm[3 * v], n / l);
    }
}
JM_KERNEL_AVX2(static, void, fan_normal_task, fan_normal_task_body, (void *arg, size_t chunk, int worker), (arg, chunk, worker))

/* Normal smoothing's neighbours, chosen once from the normals before its
 * first step (job->src, 4 floats per vertex): one counts when it faces
 * the same side as the vertex (never across a thin sheet or a droplet:
 * its other side faces away), the product summed ((x + y) + z) > 0. Per
 * vertex of up to 8 its row of nb8 with the others replaced by the -0
 * sentinel (into nc8, no longer needed); per big vertex a flag per fan
 * entry (job->bflag), its row all sentinels; 1 / (1 + the number counted)
 * in inv (no longer needed). */
typedef struct nm_job {
    sm_job *s;
    uint8_t *bflag;
} nm_job;

JM_BODY void nmask_task_body(void *arg, size_t chunk, int worker)
{
    (void)worker;
    nm_job *nj = arg;
    sm_job *job = nj->s;
    const float *S = job->src;
    const uint32_t *deg = job->f.deg, *nb8 = job->f.nb8, sent = 2 * (uint32_t)job->nv;
    uint32_t *nm8 = job->f.nc8;
    const size_t a = chunk * SM_CH, b = sm_chunk_end(job->nv, chunk);
    size_t bk = sm_lower_bound(job->f.big, job->f.nbig, a);
    for (size_t v = a; v < b; v++) {
        const v4f n = sm_load4(&S[4 * v]);
        uint32_t k = 1;
        if (deg[v] <= 8) {
            /* past the fan the sentinel's -0 sums to 0: not counted */
            for (uint32_t j = 0; j < 8; j++) {
                const uint32_t q = nb8[8 * v + j];
                const v4f d = sm_load4(&S[2 * (size_t)q]) * n;
                const uint32_t keep = d[0] + d[1] + d[2] > 0.0f;
                nm8[8 * v + j] = keep ? q : sent;
                k += keep;
            }
        } else {
            for (uint32_t j = 0; j < 8; j++) nm8[8 * v + j] = sent;
            for (uint32_t i = job->f.bstart[bk]; i < job->f.bstart[bk + 1]; i++) {
                const v4f d = sm_load4(&S[4 * (size_t)job->f.bnb[i]]) * n;
                nj->bflag[i] = d[0] + d[1] + d[2] > 0.0f;
                k += nj->bflag[i];
            }
            bk++;
        }
        job->f.inv[v] = 1.0f / (float)k;
    }
}
JM_KERNEL_AVX2(static, void, nmask_task, nmask_task_body, (void *arg, size_t chunk, int worker), (arg, chunk, worker))

/* One step of size job->tau toward the mean of the vertex's normal and
 * those nmask_task chose (directions only; made unit at the end). */
JM_BODY void nstep_task_body(void *arg, size_t chunk, int worker)
{
    (void)worker;
    nm_job *nj = arg;
    sm_job *job = nj->s;
    const float *S = job->src, *ninv = job->f.inv;
    float *D = job->dst;
    const uint32_t *nm8 = job->f.nc8;
    const size_t a = chunk * SM_CH, b = sm_chunk_end(job->nv, chunk);
    const float tau = job->tau;
    for (size_t v = a; v < b; v++) {
        const v4f n = sm_load4(&S[4 * v]);
        sm_store4(&D[4 * v], n + tau * (sm_add_slots8(n, S, &nm8[8 * v]) * ninv[v] - n));
    }
    for (size_t k = sm_lower_bound(job->f.big, job->f.nbig, a); k < job->f.nbig && job->f.big[k] < b; k++) {
        const size_t v = job->f.big[k];
        const v4f n = sm_load4(&S[4 * v]);
        v4f t = n;
        for (uint32_t i = job->f.bstart[k]; i < job->f.bstart[k + 1]; i++)
            if (nj->bflag[i]) t += sm_load4(&S[4 * (size_t)job->f.bnb[i]]);
        sm_store4(&D[4 * v], n + tau * (t * ninv[v] - n));
    }
}
JM_KERNEL_AVX2(static, void, nstep_task, nstep_task_body, (void *arg, size_t chunk, int worker), (arg, chunk, worker))

/* n / |n|, or the fallback where |n| is 0 (one division for the three). */
static inline v4f unit3(v4f n, v4f fallback)
{
    const float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    return l > 0.0f ? n / l : fallback;
}

/* Normalises the normals (job->normalise; job->src, 3 per vertex: the
 * unsmoothed normals, the fallback) and sets the UVs. */
static void finish_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    const size_t a = chunk * SM_CH, b = sm_chunk_end(job->nv, chunk);
    if (job->normalise)
        for (size_t v = a; v < b; v++) {
            float *n = &job->m->nrm[3 * v];
            const v4f k = sm_load3(&job->src[3 * v]), u = unit3(sm_load3(n), k);
            /* one smoothed past its face (across a crease) keeps its own */
            sm_store3(n, sm_dot3(u, k) > 0.0f ? u : k);
        }
    if (job->c->uv_mode != JM_UV_NONE)
        jm_uv_all(job->c, &job->m->pos[3 * a], &job->m->nrm[3 * a], &job->m->uv[2 * a], b - a);
}

static void widen(float *d, const float *s, size_t n)
{
    for (size_t v = 0; v < n; v++) d[4 * v] = s[3 * v], d[4 * v + 1] = s[3 * v + 1], d[4 * v + 2] = s[3 * v + 2], d[4 * v + 3] = 0.0f;
    for (int j = 0; j < 4; j++) d[4 * n + j] = -0.0f; /* the sentinel row */
}

static void narrow(float *d, const float *s, size_t n)
{
    for (size_t v = 0; v < n; v++) d[3 * v] = s[4 * v], d[3 * v + 1] = s[4 * v + 1], d[3 * v + 2] = s[4 * v + 2];
}

/*
 * After the positions: the normals of the smoothed surface (when it was
 * smoothed: the field's gradient at a moved vertex describes the bumpy
 * surface it left; pos, 4 per vertex, or NULL when not smoothed), then
 * c->smooth_normal_iters steps of normal smoothing, unit normals (the
 * unsmoothed ones where a sum vanishes) and UVs from the final positions
 * and normals.
 */
jm_status sm_normals(jm_mem *mem, jm_pool *pool, jm_post_scratch *sc, sm_job *job, const float *pos, int want_nrm)
{
    const size_t nv = job->nv;
    const int niters = job->c->smooth_normal_iters;
    if (!want_nrm) {
        if (job->c->uv_mode != JM_UV_NONE) {
            job->normalise = 0; /* planar UVs: no normals to normalise */
            sm_run_ranges(pool, job->nchunks, finish_task, job);
        }
        return JM_OK;
    }
    if (pos) {
        job->src = pos;
        sm_run_ranges(pool, job->nchunks, fan_normal_task, job);
    }
    float *keep = NULL;
    if (niters > 0) {
        keep = sm_scratch(sc, mem, SB_KEEP, nv * 3 * sizeof *keep);
        float *a = sm_scratch(sc, mem, SB_A, (nv + 1) * 4 * sizeof *a);
        float *b = sm_scratch(sc, mem, SB_B, (nv + 1) * 4 * sizeof *b);
        nm_job nj = {job, sm_scratch(sc, mem, SB_FLAG, (job->f.nfan + 1) * sizeof *nj.bflag)};
        if (!keep || !a || !b || !nj.bflag) return JM_E_OUT_OF_MEMORY;
        memcpy(keep, job->m->nrm, nv * 3 * sizeof *keep);
        widen(a, job->m->nrm, nv);
        widen(b, job->m->nrm, nv);
        float *tau = NULL;
        int cyc;
        const int nsteps = sm_plan(niters, mem, &tau, &cyc); /* in fewer passes, as the positions */
        if (nsteps < 0) return JM_E_OUT_OF_MEMORY;
        job->src = a;
        sm_run_ranges(pool, job->nchunks, nmask_task, &nj);
        for (int it = 0; it < nsteps; it++) {
            job->tau = tau[it];
            sm_run_swap(pool, job, nstep_task, &nj, &a, &b);
        }
        narrow(job->m->nrm, a, nv);
        jm_free(mem, tau, (size_t)nsteps * sizeof *tau);
    }
    job->src = keep ? keep : job->m->nrm;
    job->normalise = 1;
    sm_run_ranges(pool, job->nchunks, finish_task, job);
    return JM_OK;
}
