/* attributes.c - jm_interpolate_attributes: per-particle values carried onto mesh vertices by normalised SPH weights. */
#include "core/internal.h"
#include "core/units.h"
#include <string.h>

/*
 * a_v = sum_j a_j W(|v - x_j|, h) / sum_j W(|v - x_j|, h) over the particles
 * within the kernel's support 2h of vertex v (the cubic spline of the SPH
 * field, h = smoothing_length * r), as splashsurf interpolates attributes;
 * a vertex with no particle in reach takes its nearest particle's value
 * (ties: the first in input order). Particles are binned into cells of
 * edge 2h; each vertex sums the 27 cells around it in a fixed order, the
 * particles of a cell in input order, in double precision: the result
 * depends only on the inputs. One thread.
 */

typedef struct bins {
    jm_mem mem;
    jm_hashmap map;      /* cell key -> cell index */
    uint32_t *start;     /* ncells + 1 */
    uint32_t *items;     /* particle indices, by cell, input order within */
    size_t ncells, n;
    int64_t lo[3], span[3];
    float inv;
} bins;

static const float *pos_of(const jm_particles *p, size_t i)
{
    size_t stride = p->stride ? p->stride : 3 * sizeof(float);
    return (const float *)(const void *)((const char *)p->xyz + i * stride);
}

static int64_t cell_of(float x, float inv)
{
    return (int64_t)floorf(x * inv);
}

static void bins_free(bins *b)
{
    jm_hashmap_free(&b->map, &b->mem);
    jm_free(&b->mem, b->start, (b->ncells + 1) * sizeof *b->start);
    jm_free(&b->mem, b->items, b->n * sizeof *b->items);
}

static uint64_t key_rel(const bins *b, int64_t x, int64_t y, int64_t z, int *ok)
{
    x -= b->lo[0];
    y -= b->lo[1];
    z -= b->lo[2];
    *ok = x >= 0 && y >= 0 && z >= 0 && x <= b->span[0] && y <= b->span[1] && z <= b->span[2];
    return *ok ? jm_key3(x, y, z) : 0;
}

static jm_status bins_build(bins *b, const jm_particles *p, float cell)
{
    size_t n = p->count;
    uint32_t *cellof;
    jm_status s;
    b->n = n;
    b->inv = 1.0f / cell;
    for (int k = 0; k < 3; k++) {
        b->lo[k] = INT64_MAX;
        b->span[k] = 0;
    }
    int64_t hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    for (size_t i = 0; i < n; i++) {
        const float *x = pos_of(p, i);
        for (int k = 0; k < 3; k++) {
            if (!isfinite(x[k])) return JM_E_INVALID_PARTICLE;
            int64_t c = cell_of(x[k], b->inv);
            if (c < b->lo[k]) b->lo[k] = c;
            if (c > hi[k]) hi[k] = c;
        }
    }
    for (int k = 0; k < 3; k++) {
        b->span[k] = hi[k] - b->lo[k];
        if (b->span[k] >= JM_KEY_MAX - 1) return JM_E_TOO_LARGE;
    }
    s = jm_hashmap_init(&b->map, &b->mem, n < 64 ? 64 : n);
    if (s) return s;
    cellof = jm_alloc(&b->mem, n * sizeof *cellof);
    if (!cellof) return JM_E_OUT_OF_MEMORY;
    for (size_t i = 0; i < n; i++) {
        const float *x = pos_of(p, i);
        int ok;
        uint64_t key = key_rel(b, cell_of(x[0], b->inv), cell_of(x[1], b->inv), cell_of(x[2], b->inv), &ok);
        uint32_t *v = jm_hashmap_upsert(&b->map, key);
        if (*v == UINT32_MAX) *v = (uint32_t)b->ncells++;
        cellof[i] = *v;
    }
    b->start = jm_calloc(&b->mem, b->ncells + 1, sizeof *b->start);
    b->items = jm_alloc(&b->mem, n * sizeof *b->items);
    if (!b->start || !b->items) {
        jm_free(&b->mem, cellof, n * sizeof *cellof);
        return JM_E_OUT_OF_MEMORY;
    }
    for (size_t i = 0; i < n; i++) b->start[cellof[i] + 1]++;
    for (size_t c = 0; c < b->ncells; c++) b->start[c + 1] += b->start[c];
    /* counting sort: stable, so input order within a cell */
    for (size_t i = 0; i < n; i++) b->items[b->start[cellof[i]]++] = (uint32_t)i;
    for (size_t c = b->ncells; c > 0; c--) b->start[c] = b->start[c - 1];
    b->start[0] = 0;
    jm_free(&b->mem, cellof, n * sizeof *cellof);
    return JM_OK;
}

jm_status jm_interpolate_attributes(const jm_params *params, const jm_particles *particles, const float *positions,
                                    size_t vertex_count, jm_attribute *attributes, size_t attribute_count)
{
    jm_config cfg;
    jm_status s;
    bins b;
    double acc[64];
    if (!params || !particles || (vertex_count && !positions) || (attribute_count && !attributes) ||
        (particles->count && !particles->xyz) || particles->count > UINT32_MAX - 1)
        return JM_E_INVALID_ARGUMENT;
    s = jm_config_resolve(params, &cfg, NULL);
    if (s) return s;
    size_t total = 0;
    for (size_t a = 0; a < attribute_count; a++) {
        const jm_attribute *at = &attributes[a];
        if (at->components < 1 || at->components > 16 || (particles->count && !at->particle_values) ||
            (vertex_count && !at->vertex_values))
            return JM_E_INVALID_ARGUMENT;
        total += (size_t)at->components;
    }
    if (total > sizeof acc / sizeof acc[0]) return JM_E_INVALID_ARGUMENT;
    if (vertex_count == 0 || attribute_count == 0) return JM_OK;
    if (particles->count == 0) {
        for (size_t a = 0; a < attribute_count; a++)
            memset(attributes[a].vertex_values, 0, vertex_count * (size_t)attributes[a].components * sizeof(float));
        return JM_OK;
    }
    /* distances in the library's unit (units.h): squared lengths neither
     * overflow nor underflow at any radius, and the weights are the same
     * bits as in world units wherever those do neither */
    const float unit_in = ldexpf(1.0f, -jm_unit_exponent(params->radius));
    const float h = cfg.sph_h, support = 2.0f * cfg.sph_h, inv_h = 1.0f / (cfg.sph_h * unit_in);
    memset(&b, 0, sizeof b);
    s = bins_build(&b, particles, support);
    if (s) {
        bins_free(&b);
        return s;
    }
    (void)h;
    for (size_t v = 0; v < vertex_count; v++) {
        const float *x = positions + 3 * v;
        double sumw = 0.0;
        memset(acc, 0, total * sizeof acc[0]);
        int64_t cx = cell_of(x[0], b.inv), cy = cell_of(x[1], b.inv), cz = cell_of(x[2], b.inv);
        for (int dz = -1; dz <= 1; dz++)
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int ok;
                    uint64_t key = key_rel(&b, cx + dx, cy + dy, cz + dz, &ok);
                    if (!ok) continue;
                    uint32_t c = jm_hashmap_get(&b.map, key);
                    if (c == UINT32_MAX) continue;
                    for (uint32_t k = b.start[c]; k < b.start[c + 1]; k++) {
                        const uint32_t j = b.items[k];
                        const float *p = pos_of(particles, j);
                        const float ex = (x[0] - p[0]) * unit_in, ey = (x[1] - p[1]) * unit_in,
                                    ez = (x[2] - p[2]) * unit_in;
                        const float q = sqrtf(ex * ex + ey * ey + ez * ez) * inv_h;
                        if (q >= 2.0f) continue;
                        const double w = jm_cubic_w(q);
                        if (w <= 0.0) continue;
                        sumw += w;
                        size_t o = 0;
                        for (size_t a = 0; a < attribute_count; a++) {
                            const int nc = attributes[a].components;
                            const float *pv = attributes[a].particle_values + (size_t)j * (size_t)nc;
                            for (int cc = 0; cc < nc; cc++) acc[o + (size_t)cc] += w * (double)pv[cc];
                            o += (size_t)nc;
                        }
                    }
                }
        if (sumw > 0.0) {
            size_t o = 0;
            for (size_t a = 0; a < attribute_count; a++) {
                const int nc = attributes[a].components;
                float *out = attributes[a].vertex_values + v * (size_t)nc;
                for (int cc = 0; cc < nc; cc++) out[cc] = (float)(acc[o + (size_t)cc] / sumw);
                o += (size_t)nc;
            }
            continue;
        }
        /* nothing in reach: the nearest particle (first in input order on a tie) */
        size_t best = 0;
        double bd = INFINITY;
        for (size_t j = 0; j < particles->count; j++) {
            const float *p = pos_of(particles, j);
            const double ex = (double)x[0] - p[0], ey = (double)x[1] - p[1], ez = (double)x[2] - p[2];
            const double d = ex * ex + ey * ey + ez * ez;
            if (d < bd) {
                bd = d;
                best = j;
            }
        }
        for (size_t a = 0; a < attribute_count; a++) {
            const size_t nc = (size_t)attributes[a].components;
            memcpy(attributes[a].vertex_values + v * nc, attributes[a].particle_values + best * nc,
                   nc * sizeof(float));
        }
    }
    bins_free(&b);
    return JM_OK;
}
