/* field_choice.c - jm_choose_field: metasphere + MT for sparse, chain-like frames, SPH + MC for bulk fluid. */
#include "internal.h"
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
 */
#define JM_CHOICE_SAMPLES 4096

#define PT(xyz, stride, i) ((const float *)((const char *)(xyz) + (size_t)(i) * (stride)))

jm_status jm_choose_field(const jm_params *params, const jm_particles *in, jm_field *out_field,
                          jm_method *out_method, float *out_neighbours)
{
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
    double L = c.link, L2 = L * L;
    int sparse_box = 0; /* over 2^21 cells of L along an axis: spread far too thin to be bulk */
    for (int a = 0; a < 3; a++)
        if ((double)hi[a] - lo[a] >= L * (double)(JM_KEY_MAX - 4)) sparse_box = 1;
    if (n > 1 && !sparse_box && n < UINT32_MAX) {
        jm_mem mem;
        memset(&mem, 0, sizeof mem);
        jm_hashmap cells;
        uint32_t *cell_of = jm_alloc(&mem, n * sizeof *cell_of);
        if (!cell_of) return JM_E_OUT_OF_MEMORY;
        jm_status s = jm_hashmap_init(&cells, &mem, n < 1024 ? 1024 : n);
        if (s != JM_OK) {
            jm_free(&mem, cell_of, n * sizeof *cell_of);
            return s;
        }
        /* cells of edge L: count, then place each particle (counting sort) */
        size_t ncells = 0;
        for (size_t i = 0; i < n; i++) {
            const float *q = PT(in->xyz, stride, i);
            int64_t k[3];
            for (int a = 0; a < 3; a++) k[a] = (int64_t)(((double)q[a] - lo[a]) / L) + 1;
            uint32_t *v = jm_hashmap_upsert(&cells, jm_key3(k[0], k[1], k[2]));
            if (*v == UINT32_MAX) *v = (uint32_t)ncells++;
            cell_of[i] = *v;
        }
        uint32_t *start = jm_calloc(&mem, ncells + 1, sizeof *start);
        uint32_t *members = jm_alloc(&mem, n * sizeof *members);
        if (!start || !members) {
            s = JM_E_OUT_OF_MEMORY;
        } else {
            for (size_t i = 0; i < n; i++) start[cell_of[i] + 1]++;
            for (size_t k = 0; k < ncells; k++) start[k + 1] += start[k];
            /* place each particle, input order kept within a cell */
            uint32_t *next = jm_alloc(&mem, (ncells + 1) * sizeof *next);
            if (!next) {
                s = JM_E_OUT_OF_MEMORY;
            } else {
                memcpy(next, start, (ncells + 1) * sizeof *next);
                for (size_t i = 0; i < n; i++) members[next[cell_of[i]]++] = (uint32_t)i;
                jm_free(&mem, next, (ncells + 1) * sizeof *next);
                size_t step = n > JM_CHOICE_SAMPLES ? n / JM_CHOICE_SAMPLES : 1;
                size_t taken = 0, total = 0;
                for (size_t i = 0; i < n && taken < JM_CHOICE_SAMPLES; i += step, taken++) {
                    const float *q = PT(in->xyz, stride, i);
                    int64_t k[3];
                    for (int a = 0; a < 3; a++) k[a] = (int64_t)(((double)q[a] - lo[a]) / L) + 1;
                    for (int dz = -1; dz <= 1; dz++)
                        for (int dy = -1; dy <= 1; dy++)
                            for (int dx = -1; dx <= 1; dx++) {
                                uint32_t cj = jm_hashmap_get(&cells, jm_key3(k[0] + dx, k[1] + dy, k[2] + dz));
                                if (cj == UINT32_MAX) continue;
                                for (uint32_t m = start[cj]; m < start[cj + 1]; m++) {
                                    uint32_t j = members[m];
                                    if (j == i) continue;
                                    const float *o = PT(in->xyz, stride, j);
                                    double d0 = (double)o[0] - q[0], d1 = (double)o[1] - q[1],
                                           d2 = (double)o[2] - q[2];
                                    if (d0 * d0 + d1 * d1 + d2 * d2 < L2) total++;
                                }
                            }
                }
                mean = taken ? (double)total / (double)taken : 0.0;
            }
        }
        jm_free(&mem, start, (ncells + 1) * sizeof *start);
        jm_free(&mem, members, n * sizeof *members);
        jm_free(&mem, cell_of, n * sizeof *cell_of);
        jm_hashmap_free(&cells, &mem);
        if (s != JM_OK) return s;
    }
    int bulk = mean >= JM_AUTO_BULK_NEIGHBOURS;
    if (out_field) *out_field = bulk ? JM_FIELD_SPH : JM_FIELD_METASPHERE;
    if (out_method) *out_method = bulk ? JM_METHOD_MC : JM_METHOD_MT;
    if (out_neighbours) *out_neighbours = (float)mean;
    return JM_OK;
}
