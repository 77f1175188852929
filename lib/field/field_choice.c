/* field_choice.c - jm_choose_field: metasphere + MT for sparse, chain-like frames, SPH + MC for bulk fluid. */
#include "core/internal.h"
#include <math.h>
#include <string.h>

/*
 * The measure: the mean number of other particles within the link distance
 * L of a particle (L = params->link_distance * r, default pi r: where the
 * metasphere joins two particles by a neck). A jet's column of particles
 * 1.5 r apart has at most 4 (two each side); droplets and spray fewer.
 * Bulk fluid at the usual rest spacing 2r has 18 inside (6 at 2r, 12 at
 * 2.83r) and about 9 to 13 on its surface. The mean is taken over up to
 * JM_CHOICE_SAMPLES particles spread evenly through the input order
 * (every k-th), counting neighbours among all particles, so the cost is
 * one pass over the particles plus a bounded number of neighbour scans.
 *
 * The scans are bounded in all (issue 30: a million copies of one point
 * must be refused at once, not scanned for seconds): the candidates of every
 * sample, the particles of its 27 cells, are counted first; within
 * JM_CHOICE_MAX_CHECKS in all (real frames need well under a million:
 * bulk fluid at 2r has about 100 a sample) every candidate is checked, as
 * before. Beyond, each sample checks an evenly strided share of its
 * candidates and counts found * candidates / checked: piles of particles
 * come out far denser than bulk fluid, as they are, in milliseconds.
 */
#define JM_CHOICE_SAMPLES 4096

#define PT(xyz, stride, i) ((const float *)((const char *)(xyz) + (size_t)(i) * (stride)))

/* The particles by cell of edge L (a counting sort), for the scans. */
typedef struct cells {
    jm_hashmap map;      /* cell key -> cell number */
    uint32_t *start;     /* ncells + 1: each cell's first member */
    uint32_t *members;   /* particle numbers, input order within a cell */
    size_t ncells;
    const float *xyz;
    size_t stride;
    float lo[3];
    double L;
} cells;

/* the 27 cell numbers around particle i (UINT32_MAX: none); returns its candidates */
static size_t around(const cells *c, size_t i, uint32_t cj[27])
{
    const float *q = PT(c->xyz, c->stride, i);
    int64_t k[3];
    size_t cand = 0;
    int m = 0;
    for (int a = 0; a < 3; a++) k[a] = (int64_t)(((double)q[a] - c->lo[a]) / c->L) + 1;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++, m++) {
                cj[m] = jm_hashmap_get(&c->map, jm_key3(k[0] + dx, k[1] + dy, k[2] + dz));
                if (cj[m] != UINT32_MAX) cand += c->start[cj[m] + 1] - c->start[cj[m]];
            }
    return cand;
}

/* Other particles within L of particle i among every step-th of its
 * candidates (step 1: all of them, exactly); *checked: how many it checked. */
static size_t scan(const cells *c, size_t i, const uint32_t cj[27], size_t step, size_t *checked)
{
    const float *q = PT(c->xyz, c->stride, i);
    const double L2 = c->L * c->L;
    size_t found = 0, skip = 0;
    *checked = 0;
    for (int m = 0; m < 27; m++) {
        if (cj[m] == UINT32_MAX) continue;
        for (size_t t = c->start[cj[m]] + skip; t < c->start[cj[m] + 1]; t += step) {
            uint32_t j = c->members[t];
            ++*checked;
            if (j == i) continue;
            const float *o = PT(c->xyz, c->stride, j);
            double d0 = (double)o[0] - q[0], d1 = (double)o[1] - q[1], d2 = (double)o[2] - q[2];
            if (d0 * d0 + d1 * d1 + d2 * d2 < L2) found++;
        }
        /* the stride carries on into the next cell */
        size_t len = c->start[cj[m] + 1] - c->start[cj[m]];
        skip = len > skip ? (step - (len - skip) % step) % step : skip - len;
    }
    return found;
}

/* The mean over the samples (every step-th particle, at most
 * JM_CHOICE_SAMPLES); the checks within JM_CHOICE_MAX_CHECKS (above). */
static double mean_neighbours(const cells *c, size_t n, size_t *out_checks)
{
    size_t step = n > JM_CHOICE_SAMPLES ? n / JM_CHOICE_SAMPLES : 1, taken = 0, all = 0;
    uint32_t cj[27];
    for (size_t i = 0; i < n && taken < JM_CHOICE_SAMPLES; i += step, taken++) all += around(c, i, cj);
    if (!taken) return 0.0;
    size_t total = 0, checks = 0;
    double est = 0.0;
    const size_t share = JM_CHOICE_MAX_CHECKS / taken;
    taken = 0;
    for (size_t i = 0; i < n && taken < JM_CHOICE_SAMPLES; i += step, taken++) {
        size_t cand = around(c, i, cj), checked;
        if (all <= JM_CHOICE_MAX_CHECKS) {
            total += scan(c, i, cj, 1, &checked);
        } else {
            size_t found = scan(c, i, cj, cand > share ? (cand + share - 1) / share : 1, &checked);
            est += checked ? (double)found * (double)cand / (double)checked : 0.0;
        }
        checks += checked;
    }
    if (out_checks) *out_checks = checks;
    return all <= JM_CHOICE_MAX_CHECKS ? (double)total / (double)taken : est / (double)taken;
}

jm_status jm_choose_field_work(const jm_params *params, const jm_particles *in, jm_field *out_field,
                               jm_method *out_method, float *out_neighbours, size_t *out_checks)
{
    if (out_checks) *out_checks = 0;
    if (!params || !in || (in->count && !in->xyz)) return JM_E_INVALID_ARGUMENT;
    jm_config c;
    jm_params p = *params;
    p.field = JM_FIELD_METASPHERE; /* the link distance is the metasphere's */
    p.method = JM_METHOD_DEFAULT;
    p.threshold = 0.0f;
    if (jm_config_resolve(&p, &c, NULL) != JM_OK) return JM_E_INVALID_ARGUMENT;
    size_t n = in->count, stride = in->stride ? in->stride : 12;
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (size_t i = 0; i < n; i++) {
        const float *q = PT(in->xyz, stride, i);
        for (int a = 0; a < 3; a++) {
            if (!isfinite(q[a])) return JM_E_INVALID_PARTICLE;
            if (i == 0 || q[a] < lo[a]) lo[a] = q[a];
            if (i == 0 || q[a] > hi[a]) hi[a] = q[a];
        }
    }
    double mean = 0.0;
    double L = c.link;
    int sparse_box = 0; /* over 2^21 cells of L along an axis: spread far too thin to be bulk */
    for (int a = 0; a < 3; a++)
        if ((double)hi[a] - lo[a] >= L * (double)(JM_KEY_MAX - 4)) sparse_box = 1;
    if (n > 1 && !sparse_box && n < UINT32_MAX) {
        jm_mem mem;
        memset(&mem, 0, sizeof mem);
        cells cl;
        memset(&cl, 0, sizeof cl);
        cl.xyz = in->xyz;
        cl.stride = stride;
        cl.L = L;
        memcpy(cl.lo, lo, sizeof lo);
        uint32_t *cell_of = jm_alloc(&mem, n * sizeof *cell_of);
        if (!cell_of) return JM_E_OUT_OF_MEMORY;
        jm_status s = jm_hashmap_init(&cl.map, &mem, n < 1024 ? 1024 : n);
        if (s != JM_OK) {
            jm_free(&mem, cell_of, n * sizeof *cell_of);
            return s;
        }
        /* cells of edge L: count, then place each particle (counting sort) */
        for (size_t i = 0; i < n; i++) {
            const float *q = PT(in->xyz, stride, i);
            int64_t k[3];
            for (int a = 0; a < 3; a++) k[a] = (int64_t)(((double)q[a] - lo[a]) / L) + 1;
            uint32_t *v = jm_hashmap_upsert(&cl.map, jm_key3(k[0], k[1], k[2]));
            if (*v == UINT32_MAX) *v = (uint32_t)cl.ncells++;
            cell_of[i] = *v;
        }
        cl.start = jm_calloc(&mem, cl.ncells + 1, sizeof *cl.start);
        cl.members = jm_alloc(&mem, n * sizeof *cl.members);
        if (!cl.start || !cl.members) {
            s = JM_E_OUT_OF_MEMORY;
        } else {
            for (size_t i = 0; i < n; i++) cl.start[cell_of[i] + 1]++;
            for (size_t k = 0; k < cl.ncells; k++) cl.start[k + 1] += cl.start[k];
            /* place each particle, input order kept within a cell */
            uint32_t *next = jm_alloc(&mem, (cl.ncells + 1) * sizeof *next);
            if (!next) {
                s = JM_E_OUT_OF_MEMORY;
            } else {
                memcpy(next, cl.start, (cl.ncells + 1) * sizeof *next);
                for (size_t i = 0; i < n; i++) cl.members[next[cell_of[i]]++] = (uint32_t)i;
                jm_free(&mem, next, (cl.ncells + 1) * sizeof *next);
                mean = mean_neighbours(&cl, n, out_checks);
            }
        }
        jm_free(&mem, cl.start, (cl.ncells + 1) * sizeof *cl.start);
        jm_free(&mem, cl.members, n * sizeof *cl.members);
        jm_free(&mem, cell_of, n * sizeof *cell_of);
        jm_hashmap_free(&cl.map, &mem);
        if (s != JM_OK) return s;
    }
    int bulk = mean >= JM_AUTO_BULK_NEIGHBOURS;
    if (out_field) *out_field = bulk ? JM_FIELD_SPH : JM_FIELD_METASPHERE;
    if (out_method) *out_method = bulk ? JM_METHOD_MC : JM_METHOD_MT;
    if (out_neighbours) *out_neighbours = (float)mean;
    return JM_OK;
}

jm_status jm_choose_field(const jm_params *params, const jm_particles *in, jm_field *out_field,
                          jm_method *out_method, float *out_neighbours)
{
    return jm_choose_field_work(params, in, out_field, out_method, out_neighbours, NULL);
}
