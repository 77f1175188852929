/* smooth_guard.c - triangles the smoothing turned over: their corners taken back halfway toward where they were, a few times. */
#include "smooth.h"

/*
 * A crease deeper than the band (where a metasphere's beads meet) keeps its
 * bottom within 0.5 r while the vertices of its walls slide along the
 * surface toward it: some slide past the bottom and turn their triangles
 * over, a slit that renders as a dark line. After the smoothing, every
 * vertex of a triangle whose normal now points against its raw normal goes
 * halfway back to its raw position, up to six times (the smoothed surface
 * stays within the band: halfway back is closer to the raw one).
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

/* Whether the triangle (v, q, r) of v's fan is turned over. */
static inline int turned(const guard_job *g, size_t v, size_t q, size_t r)
{
    const v4f p = sm_load4(&g->pos[4 * v]), p0 = sm_load3(&g->raw[3 * v]);
    const v4f n = cross4(sm_load4(&g->pos[4 * q]) - p, sm_load4(&g->pos[4 * r]) - p);
    const v4f n0 = cross4(sm_load3(&g->raw[3 * q]) - p0, sm_load3(&g->raw[3 * r]) - p0);
    return sm_dot3(n, n0) < 0.0f;
}

static void flag_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    guard_job *g = arg;
    const sm_fan *f = &g->job->f;
    const size_t a = chunk * SM_CH, b = a + SM_CH < g->job->nv ? a + SM_CH : g->job->nv;
    size_t k = sm_lower_bound(f->big, f->nbig, a);
    uint32_t n = 0;
    for (size_t v = a; v < b; v++) {
        int t = 0;
        if (f->deg[v] <= 8) {
            for (uint32_t i = 0; i < f->deg[v] && !t; i++) t = turned(g, v, f->nb8[8 * v + i] / 2, f->nc8[8 * v + i] / 2);
        } else {
            for (uint32_t i = f->bstart[k]; i < f->bstart[k + 1] && !t; i++) t = turned(g, v, f->bnb[i], f->bnc[i]);
            k++;
        }
        g->flag[v] = (uint8_t)t;
        n += (uint32_t)t;
    }
    g->count[chunk] = n;
}

static void back_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    guard_job *g = arg;
    const size_t a = chunk * SM_CH, b = a + SM_CH < g->job->nv ? a + SM_CH : g->job->nv;
    for (size_t v = a; v < b; v++)
        if (g->flag[v]) {
            v4f p = 0.5f * (sm_load4(&g->pos[4 * v]) + sm_load3(&g->raw[3 * v]));
            p[3] = 1.0f;
            sm_store4(&g->pos[4 * v], p);
        }
}

jm_status sm_guard_folds(jm_pool *pool, sm_job *job, float *pos)
{
    guard_job g = {job, pos, job->m->pos, jm_alloc(job->mem, job->nv + 1),
                   jm_alloc(job->mem, job->nchunks * sizeof(uint32_t) + 1)};
    if (!g.flag || !g.count) {
        jm_free(job->mem, g.flag, job->nv + 1);
        jm_free(job->mem, g.count, job->nchunks * sizeof(uint32_t) + 1);
        return JM_E_OUT_OF_MEMORY;
    }
    for (int pass = 0; pass < GUARD_PASSES; pass++) {
        sm_run_ranges(pool, job->nchunks, flag_task, &g);
        size_t n = 0;
        for (size_t c = 0; c < job->nchunks; c++) n += g.count[c];
        if (n == 0) break;
        sm_run_ranges(pool, job->nchunks, back_task, &g);
    }
    jm_free(job->mem, g.flag, job->nv + 1);
    jm_free(job->mem, g.count, job->nchunks * sizeof(uint32_t) + 1);
    return JM_OK;
}
