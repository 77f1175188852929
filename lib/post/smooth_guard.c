/* smooth_guard.c - triangles the smoothing turned over: their corners taken back halfway toward where they were, a few times. */
#include "post/smooth.h"

/*
 * A crease deeper than the band (where a metasphere's beads meet) keeps its
 * bottom within the band while the vertices of its walls slide along the
 * surface toward it: some slide past the bottom and turn their triangles
 * over, a slit that renders as a dark line. After the smoothing, every
 * vertex of a triangle whose normal now points against its raw normal goes
 * halfway back to its raw position, up to six times (halfway back stays
 * within the band). The first check tests every triangle once, at its
 * smallest vertex, in parallel, then flags the other corners of the few
 * turned; the later checks, one at a time, run only over the vertices
 * moved back and their neighbours (only their triangles changed).
 */
#define GUARD_PASSES 6

typedef struct guard_job {
    const sm_job *job;
    float *pos;          /* the smoothed positions, 4 per vertex */
    const float *raw;    /* the raw ones, m->pos (3 per vertex) */
    uint8_t *flag;       /* per vertex: a triangle of its fan turned over */
    uint32_t *count;     /* per chunk: how many flagged */
} guard_job;

static inline v4f cross4(v4f a, v4f b)
{
    return __builtin_shufflevector(a, a, 1, 2, 0, 3) * __builtin_shufflevector(b, b, 2, 0, 1, 3) -
           __builtin_shufflevector(a, a, 2, 0, 1, 3) * __builtin_shufflevector(b, b, 1, 2, 0, 3);
}

/* Whether a triangle (v, q, r) of v's fan is turned over: the first whose
 * normal points against its raw normal. */
static inline int turned(const guard_job *g, size_t v, size_t *kb)
{
    const sm_fan *f = &g->job->f;
    const uint32_t d = f->deg[v];
    const uint32_t *nq = d <= 8 ? &f->nb8[8 * v] : &f->bnb[f->bstart[*kb]];
    const uint32_t *nr = d <= 8 ? &f->nc8[8 * v] : &f->bnc[f->bstart[*kb]];
    const uint32_t sh = d <= 8; /* nb8 and nc8 hold doubled indices */
    if (d > 8) ++*kb;
    const v4f p = sm_load4(&g->pos[4 * v]), p0 = sm_load3(&g->raw[3 * v]);
    for (uint32_t i = 0; i < d; i++) {
        const size_t q = nq[i] >> sh, r = nr[i] >> sh;
        const v4f n = cross4(sm_load4(&g->pos[4 * q]) - p, sm_load4(&g->pos[4 * r]) - p);
        const v4f n0 = cross4(sm_load3(&g->raw[3 * q]) - p0, sm_load3(&g->raw[3 * r]) - p0);
        if (sm_dot3(n, n0) < 0.0f) return 1;
    }
    return 0;
}

/* How many triangles of v's fan whose smallest vertex is v (it owns them)
 * are turned over: every triangle is tested once. */
static inline uint32_t turned_owned(const guard_job *g, size_t v, size_t *kb)
{
    const sm_fan *f = &g->job->f;
    const uint32_t d = f->deg[v];
    const uint32_t *nq = d <= 8 ? &f->nb8[8 * v] : &f->bnb[f->bstart[*kb]];
    const uint32_t *nr = d <= 8 ? &f->nc8[8 * v] : &f->bnc[f->bstart[*kb]];
    const uint32_t sh = d <= 8;
    if (d > 8) ++*kb;
    const v4f p = sm_load4(&g->pos[4 * v]), p0 = sm_load3(&g->raw[3 * v]);
    uint32_t n = 0;
    for (uint32_t i = 0; i < d; i++) {
        const size_t q = nq[i] >> sh, r = nr[i] >> sh;
        if (q < v || r < v) continue;
        const v4f e = cross4(sm_load4(&g->pos[4 * q]) - p, sm_load4(&g->pos[4 * r]) - p);
        const v4f e0 = cross4(sm_load3(&g->raw[3 * q]) - p0, sm_load3(&g->raw[3 * r]) - p0);
        n += sm_dot3(e, e0) < 0.0f;
    }
    return n;
}

/* Per vertex: 1 when a triangle it owns (turned_owned) is turned over. */
JM_BODY void flag_task_body(void *arg, size_t chunk, int worker)
{
    (void)worker;
    guard_job *g = arg;
    const sm_fan *f = &g->job->f;
    const size_t a = chunk * SM_CH, b = sm_chunk_end(g->job->nv, chunk);
    size_t k = sm_lower_bound(f->big, f->nbig, a);
    uint32_t n = 0;
    for (size_t v = a; v < b; v++) {
        g->flag[v] = turned_owned(g, v, &k) > 0;
        n += g->flag[v];
    }
    g->count[chunk] = n;
}
JM_KERNEL_AVX2(static, void, flag_task, flag_task_body, (void *arg, size_t chunk, int worker), (arg, chunk, worker))

/* The other corners of the turned triangles of owner v flagged too (2:
 * not an owner's mark; they are larger than v). */
static void flag_corners(guard_job *g, size_t v)
{
    const sm_fan *f = &g->job->f;
    const uint32_t d = f->deg[v];
    size_t kb = d > 8 ? sm_lower_bound(f->big, f->nbig, v) : 0;
    const uint32_t *nq = d <= 8 ? &f->nb8[8 * v] : &f->bnb[f->bstart[kb]];
    const uint32_t *nr = d <= 8 ? &f->nc8[8 * v] : &f->bnc[f->bstart[kb]];
    const uint32_t sh = d <= 8;
    const v4f p = sm_load4(&g->pos[4 * v]), p0 = sm_load3(&g->raw[3 * v]);
    for (uint32_t i = 0; i < d; i++) {
        const size_t q = nq[i] >> sh, r = nr[i] >> sh;
        if (q < v || r < v) continue;
        const v4f e = cross4(sm_load4(&g->pos[4 * q]) - p, sm_load4(&g->pos[4 * r]) - p);
        const v4f e0 = cross4(sm_load3(&g->raw[3 * q]) - p0, sm_load3(&g->raw[3 * r]) - p0);
        if (sm_dot3(e, e0) < 0.0f) g->flag[q] |= 2, g->flag[r] |= 2;
    }
}

static void back(guard_job *g, size_t v)
{
    v4f p = 0.5f * (sm_load4(&g->pos[4 * v]) + sm_load3(&g->raw[3 * v]));
    p[3] = 1.0f;
    sm_store4(&g->pos[4 * v], p);
}

/* The vertices flagged (list, n of them) moved back; returns how many of
 * them and their neighbours are then turned over, listed in list again
 * (room for nv) and flagged. mark: nv bytes of 0, left 0. */
static size_t recheck(guard_job *g, uint32_t *list, size_t n, uint32_t *cand, uint8_t *mark)
{
    const sm_fan *f = &g->job->f;
    size_t nc = 0;
    for (size_t i = 0; i < n; i++) back(g, list[i]);
    for (size_t i = 0; i < n; i++) { /* the candidates: the moved and their neighbours */
        const size_t v = list[i];
        g->flag[v] = 0;
        if (!mark[v]) mark[v] = 1, cand[nc++] = (uint32_t)v;
        const uint32_t d = f->deg[v];
        size_t kb = d > 8 ? sm_lower_bound(f->big, f->nbig, v) : 0;
        for (uint32_t j = 0; j < d; j++) {
            const uint32_t q = d <= 8 ? f->nb8[8 * v + j] / 2 : f->bnb[f->bstart[kb] + j];
            if (!mark[q]) mark[q] = 1, cand[nc++] = q;
        }
    }
    size_t m = 0;
    for (size_t i = 0; i < nc; i++) {
        const size_t v = cand[i];
        size_t kb = f->deg[v] > 8 ? sm_lower_bound(f->big, f->nbig, v) : 0;
        mark[v] = 0;
        if (turned(g, v, &kb)) g->flag[v] = 1, list[m++] = (uint32_t)v;
    }
    return m;
}

jm_status sm_guard_folds(jm_pool *pool, sm_job *job, float *pos)
{
    const size_t nv = job->nv;
    guard_job g = {job, pos, job->m->pos, jm_alloc(job->mem, nv + 1),
                   jm_alloc(job->mem, job->nchunks * sizeof(uint32_t) + 1)};
    uint8_t *mark = NULL;
    uint32_t *list = NULL, *cand = NULL;
    jm_status st = JM_OK;
    if (!g.flag || !g.count) { st = JM_E_OUT_OF_MEMORY; goto out; }
    sm_run_ranges(pool, job->nchunks, flag_task, &g);
    size_t n = 0;
    for (size_t c = 0; c < job->nchunks; c++) n += g.count[c];
    if (n == 0) goto out;
    for (size_t v = 0; v < nv; v++)
        if (g.flag[v] & 1) flag_corners(&g, v);
    mark = jm_calloc(job->mem, nv + 1, 1);
    list = jm_alloc(job->mem, (nv + 1) * sizeof *list);
    cand = jm_alloc(job->mem, (nv + 1) * sizeof *cand);
    if (!mark || !list || !cand) { st = JM_E_OUT_OF_MEMORY; goto out; }
    n = 0;
    for (size_t v = 0; v < nv; v++)
        if (g.flag[v]) g.flag[v] = 1, list[n++] = (uint32_t)v;
    for (int pass = 0; pass < GUARD_PASSES && n > 0; pass++) n = recheck(&g, list, n, cand, mark);
out:
    jm_free(job->mem, g.flag, nv + 1);
    jm_free(job->mem, g.count, job->nchunks * sizeof(uint32_t) + 1);
    jm_free(job->mem, mark, nv + 1);
    jm_free(job->mem, list, (nv + 1) * sizeof *list);
    jm_free(job->mem, cand, (nv + 1) * sizeof *cand);
    return st;
}
