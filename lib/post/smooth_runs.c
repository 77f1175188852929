/* smooth_runs.c - sums over the smoothing's pieces that do not depend on the threads: per task chunk, the runs of consecutive vertices of one piece. */
#include "post/smooth.h"

jm_status sm_runs_build(jm_mem *mem, const uint32_t *comp, size_t nv, size_t nchunks, sm_runs *r)
{
    memset(r, 0, sizeof *r);
    r->nchunks = nchunks;
    size_t n = 0;
    for (size_t v = 0; v < nv; v++) n += v % SM_CH == 0 || comp[v] != comp[v - 1];
    r->nruns = n;
    r->first = jm_alloc(mem, (n + 1) * sizeof *r->first);
    r->piece = jm_alloc(mem, (n + 1) * sizeof *r->piece);
    r->chunk_run = jm_alloc(mem, (nchunks + 1) * sizeof *r->chunk_run);
    r->sum = jm_calloc(mem, SM_RUN_SUMS * (n + 1), sizeof *r->sum);
    if (!r->first || !r->piece || !r->chunk_run || !r->sum) {
        sm_runs_free(mem, r);
        return JM_E_OUT_OF_MEMORY;
    }
    n = 0;
    for (size_t v = 0; v < nv; v++) {
        if (v % SM_CH == 0) r->chunk_run[v / SM_CH] = (uint32_t)n;
        if (v % SM_CH == 0 || comp[v] != comp[v - 1]) {
            r->first[n] = (uint32_t)v;
            r->piece[n] = comp[v];
            n++;
        }
    }
    r->chunk_run[nchunks] = (uint32_t)n;
    r->first[n] = (uint32_t)nv; /* the end of the last run */
    return JM_OK;
}

void sm_runs_total(const sm_runs *r, int nsums, double *piece_sums, size_t npieces)
{
    memset(piece_sums, 0, (size_t)nsums * npieces * sizeof *piece_sums);
    for (size_t k = 0; k < r->nruns; k++)
        for (int j = 0; j < nsums; j++) piece_sums[nsums * (size_t)r->piece[k] + j] += r->sum[SM_RUN_SUMS * k + j];
}

void sm_runs_free(jm_mem *mem, sm_runs *r)
{
    size_t n = r->nruns + 1;
    if (r->first) jm_free(mem, r->first, n * sizeof *r->first);
    if (r->piece) jm_free(mem, r->piece, n * sizeof *r->piece);
    if (r->chunk_run) jm_free(mem, r->chunk_run, (r->nchunks + 1) * sizeof *r->chunk_run);
    if (r->sum) jm_free(mem, r->sum, SM_RUN_SUMS * n * sizeof *r->sum);
    memset(r, 0, sizeof *r);
}
