/* smooth_fans.c - every vertex's fan of triangles for the smoothing: its neighbours in fixed rows of 8, the few bigger fans whole. */
#include "post/smooth.h"

/* What fan_task finds in its range of vertices: the fan entries past the
 * 8th (vertex, next corner, the corner after it, in triangle order), and
 * the count of vertices of more than 8 neighbours and of their entries. */
typedef struct fan_part {
    uint32_t *over;
    size_t n, cap;
    size_t nbig, nfan;
} fan_part;

typedef struct fan_job {
    jm_mem *mem;
    const jm_post_mesh *m;
    sm_fan *f;
    fan_part *parts;
    size_t nparts;
    int failed;
} fan_job;

/* The fans of the vertices of range `part` (each a contiguous range): a
 * pass over every triangle taking the corners at its own vertices, so that
 * each vertex gets its triangles in triangle order whatever the split. */
static void fan_task(void *arg, size_t part, int worker)
{
    (void)worker;
    fan_job *job = arg;
    sm_fan *f = job->f;
    const size_t nv = f->nv, ni = job->m->ni_lattice;
    const uint32_t va = (uint32_t)(nv * part / job->nparts), vb = (uint32_t)(nv * (part + 1) / job->nparts);
    uint32_t *deg = f->deg, *nb8 = f->nb8, *nc8 = f->nc8;
    fan_part *p = &job->parts[part];
    const uint32_t *idx = job->m->idx;
    memset(deg + va, 0, (size_t)(vb - va) * sizeof *deg);
    for (size_t t = 0; t + 2 < ni; t += 3) {
        const uint32_t *T = &idx[t];
        for (int k = 0; k < 3; k++) {
            const uint32_t v = T[k];
            if (v - va >= vb - va) continue; /* another range's */
            const uint32_t j = deg[v]++, q = T[k == 2 ? 0 : k + 1], r = T[k == 0 ? 2 : k - 1];
            if (j < 8) {
                nb8[8 * (size_t)v + j] = 2 * q;
                nc8[8 * (size_t)v + j] = 2 * r;
                continue;
            }
            if (p->n == p->cap) {
                const size_t nc = p->cap ? 2 * p->cap : 1024;
                uint32_t *o = jm_realloc(job->mem, p->over, 3 * p->cap * sizeof *o, 3 * nc * sizeof *o);
                if (!o) {
                    job->failed = 1;
                    return;
                }
                p->over = o;
                p->cap = nc;
            }
            p->over[3 * p->n] = v;
            p->over[3 * p->n + 1] = q;
            p->over[3 * p->n + 2] = r;
            p->n++;
        }
    }
    for (size_t v = va; v < vb; v++) {
        const uint32_t d = deg[v];
        f->inv[v] = d > 0 ? 1.0f / (float)d : 0.0f;
        for (uint32_t j = d; j < 8; j++) nb8[8 * v + j] = nc8[8 * v + j] = 2 * (uint32_t)nv;
        if (d > 8) p->nbig++, p->nfan += d;
    }
}

/* The big vertices' whole fans: the first 8 from their rows, then the
 * overflow lists (each vertex in one range's, in triangle order). */
static void gather_big(sm_fan *f, const fan_part *parts, size_t nparts, uint32_t *fill, uint32_t *place)
{
    size_t nbig = 0;
    f->bstart[0] = 0;
    for (size_t v = 0; v < f->nv; v++)
        if (f->deg[v] > 8) {
            f->big[nbig] = (uint32_t)v;
            place[v] = (uint32_t)nbig;
            fill[nbig] = f->bstart[nbig] + 8;
            f->bstart[nbig + 1] = f->bstart[nbig] + f->deg[v];
            for (int j = 0; j < 8; j++) {
                f->bnb[f->bstart[nbig] + j] = f->nb8[8 * v + j] / 2;
                f->bnc[f->bstart[nbig] + j] = f->nc8[8 * v + j] / 2;
            }
            nbig++;
        }
    for (size_t k = 0; k < nparts; k++)
        for (size_t e = 0; e < parts[k].n; e++) {
            const uint32_t *o = &parts[k].over[3 * e], i = fill[place[o[0]]]++;
            f->bnb[i] = o[1];
            f->bnc[i] = o[2];
        }
}

jm_status sm_fans_build(jm_mem *mem, jm_pool *pool, jm_post_scratch *sc, const jm_post_mesh *m, sm_fan *f)
{
    const size_t nv = m->nv_lattice, nparts = (size_t)jm_pool_threads(pool);
    memset(f, 0, sizeof *f);
    f->nv = nv;
    f->deg = sm_scratch(sc, mem, SB_DEG, nv * sizeof *f->deg);
    f->inv = sm_scratch(sc, mem, SB_INV, nv * sizeof *f->inv);
    f->nb8 = sm_scratch(sc, mem, SB_NB8, nv * 8 * sizeof *f->nb8);
    f->nc8 = sm_scratch(sc, mem, SB_NC8, nv * 8 * sizeof *f->nc8);
    fan_part *parts = jm_calloc(mem, nparts, sizeof *parts);
    jm_status st = JM_OK;
    if (!f->deg || !f->inv || !f->nb8 || !f->nc8 || !parts) { st = JM_E_OUT_OF_MEMORY; goto out; }
    fan_job job = {mem, m, f, parts, nparts, 0};
    jm_pool_run(pool, nparts, 1, fan_task, &job);
    if (job.failed) { st = JM_E_OUT_OF_MEMORY; goto out; }
    for (size_t k = 0; k < nparts; k++) f->nbig += parts[k].nbig, f->nfan += parts[k].nfan;
    /* big, bstart, a fill pointer per big vertex; the fans; a place per vertex */
    uint32_t *b = sm_scratch(sc, mem, SB_BIG, (3 * f->nbig + 1) * sizeof *b);
    uint32_t *fan = sm_scratch(sc, mem, SB_BNB, (2 * f->nfan + 1) * sizeof *fan);
    uint32_t *place = f->nbig ? jm_alloc(mem, nv * sizeof *place) : NULL;
    if (!b || !fan || (f->nbig && !place)) {
        jm_free(mem, place, nv * sizeof *place);
        st = JM_E_OUT_OF_MEMORY;
        goto out;
    }
    f->big = b;
    f->bstart = b + f->nbig;
    f->bnb = fan;
    f->bnc = fan + f->nfan;
    if (f->nbig) gather_big(f, parts, nparts, f->bstart + f->nbig + 1, place);
    else f->bstart[0] = 0;
    jm_free(mem, place, nv * sizeof *place);
out:
    for (size_t k = 0; parts && k < nparts; k++) jm_free(mem, parts[k].over, 3 * parts[k].cap * sizeof(uint32_t));
    jm_free(mem, parts, nparts * sizeof *parts);
    return st;
}
