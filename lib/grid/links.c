/* links.c - the metasphere grid's links: every pair of particles closer than the link distance, counted then written. */
#include "grid/links.h"

/* Metasphere links of the particles of cell ci: pass 0 counts them (and
 * flags isolated particles), pass 1 writes them at nb_start. */
static void meta_links(jm_nb_job *job, size_t ci, int fill)
{
    jm_grid *g = job->g;
    float link2 = job->c->link * job->c->link;
    uint32_t r[27][2];
    int nr = jm_near_ranges(g, ci, r);
    for (uint32_t i = g->cell_start[ci]; i < g->cell_start[ci + 1]; i++) {
        const float *p = GP(g, i);
        uint32_t e = fill ? g->nb_start[i] : 0;
        for (int k = 0; k < nr; k++)
            for (uint32_t j = r[k][0]; j < r[k][1]; j++) {
                const float *q = GP(g, j);
                float dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
                float d2 = dx * dx + dy * dy + dz * dz;
                if (j == i || !(d2 < link2 && d2 > 0.0f)) continue;
                if (fill) {
                    float D = sqrtf(d2);
                    float *dir = &g->nb_dir[4 * (size_t)e];
                    dir[0] = dx / D;
                    dir[1] = dy / D;
                    dir[2] = dz / D;
                    dir[3] = D;
                    g->nb_owner[e] = i;
                    g->nb[e] = j;
                }
                e++;
            }
        if (!fill) {
            job->counts[i] = e;
            g->isolated[i] = job->c->templates && e == 0 && jm_lonely(g, (uint32_t)ci, i, job->range, job->iso2);
        }
    }
}

static void meta_count(void *arg, size_t ci, int worker)
{
    (void)worker;
    meta_links(arg, ci, 0);
}

static void meta_fill(void *arg, size_t ci, int worker)
{
    (void)worker;
    meta_links(arg, ci, 1);
}

jm_status jm_grid_links(jm_nb_job *job, jm_pool *pool, size_t *refused)
{
    jm_grid *g = job->g;
    jm_mem *mem = job->mem;
    const jm_config *c = job->c;
    const size_t n = g->n, ncells = g->ncells;
    g->nb_start = jm_alloc(mem, (n + 1) * sizeof(uint32_t));
    if (!g->nb_start) return JM_E_OUT_OF_MEMORY;
    job->counts = g->nb_start;
    jm_pool_run(pool, ncells, 16, meta_count, job);
    size_t total = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t k = g->nb_start[i];
        g->nb_start[i] = (uint32_t)total;
        total += k;
        /* links are numbered after the n balls, below the sentinel */
        if ((uint64_t)n + total >= UINT32_MAX) return JM_E_TOO_LARGE;
    }
    g->nb_start[n] = (uint32_t)total;
    g->nb_count = total;
    if (!total) g->nb_count = 1; /* what is allocated */
    /* over 1000 links a particle on average (bulk fluid at rest
     * spacing 2r has 18): the radius is far too large for the spacing */
    if (total > 1000 * (size_t)n) return JM_E_TOO_DENSE;
    /* 24 bytes a link: checked against the limit before it is taken */
    if (c->max_bytes && atomic_load(&mem->current) + g->nb_count * 24 > c->max_bytes) {
        *refused = atomic_load(&mem->current) + g->nb_count * 24;
        return JM_E_TOO_LARGE;
    }
    g->nb = jm_alloc(mem, g->nb_count * sizeof(uint32_t));
    g->nb_owner = jm_alloc(mem, g->nb_count * sizeof(uint32_t));
    g->nb_dir = jm_alloc(mem, g->nb_count * 4 * sizeof(float));
    if (!g->nb || !g->nb_owner || !g->nb_dir) return JM_E_OUT_OF_MEMORY;
    jm_pool_run(pool, ncells, 16, meta_fill, job);
    return JM_OK;
}
