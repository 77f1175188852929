/* select.c - the particles a frame meshes: inside the particle box, in groups of at least min_piece_particles. */
#include "grid/select.h"
#include "grid/particle_groups.h"
#include <string.h>

int jm_select_on(const jm_config *c)
{
    return c->sel_box || c->sel_min_group > 1;
}

static const float *pos_of(const jm_particles *p, size_t i)
{
    size_t stride = p->stride ? p->stride : 3 * sizeof(float);
    return (const float *)(const void *)((const char *)p->xyz + i * stride);
}

/* The groups of the particles kept so far (in units, compacted), and
 * those of fewer than c->sel_min_group left out too. */
static jm_status drop_small_groups(jm_mem *mem, jm_pool *pool, const jm_config *c, const jm_particles *in,
                                   uint8_t *skip, size_t *kept)
{
    const size_t m = *kept;
    if (m == 0) return JM_OK;
    float *pos = jm_alloc(mem, 3 * m * sizeof *pos);
    uint32_t *parent = jm_alloc(mem, m * sizeof *parent), *count = jm_calloc(mem, m, sizeof *count);
    jm_status s = pos && parent && count ? JM_OK : JM_E_OUT_OF_MEMORY;
    if (s == JM_OK) {
        for (size_t i = 0, k = 0; i < in->count; i++)
            if (!skip[i]) {
                const float *x = pos_of(in, i);
                for (int a = 0; a < 3; a++) pos[3 * k + a] = x[a] * c->unit_in;
                k++;
            }
        s = jm_particle_groups(mem, pool, pos, m, c->sel_link, parent);
    }
    if (s == JM_OK) {
        for (size_t k = 0; k < m; k++) count[parent[k]]++;
        for (size_t i = 0, k = 0; i < in->count; i++)
            if (!skip[i]) {
                if (count[parent[k]] < (uint32_t)c->sel_min_group) {
                    skip[i] = 1;
                    (*kept)--;
                }
                k++;
            }
    }
    jm_free(mem, pos, 3 * m * sizeof *pos);
    jm_free(mem, parent, m * sizeof *parent);
    jm_free(mem, count, m * sizeof *count);
    return s;
}

jm_status jm_select(jm_mem *mem, jm_pool *pool, const jm_config *c, const jm_particles *in, uint8_t **out_skip,
                    size_t *out_kept)
{
    const size_t n = in->count;
    *out_skip = NULL;
    *out_kept = n;
    if (!jm_select_on(c) || n == 0) return JM_OK;
    if (in->stride && in->stride < 3 * sizeof(float)) return JM_E_INVALID_ARGUMENT;
    uint8_t *skip = jm_alloc(mem, n);
    if (!skip) return JM_E_OUT_OF_MEMORY;
    size_t kept = 0;
    for (size_t i = 0; i < n; i++) {
        const float *x = pos_of(in, i);
        int inside = 1;
        for (int a = 0; a < 3; a++) {
            if (!isfinite(x[a])) {
                jm_free(mem, skip, n);
                return JM_E_INVALID_PARTICLE;
            }
            /* in units (an exact scaling), as the box is */
            const float u = x[a] * c->unit_in;
            inside &= !c->sel_box || (u >= c->sel_lo[a] && u <= c->sel_hi[a]);
        }
        skip[i] = (uint8_t)!inside;
        kept += (size_t)inside;
    }
    jm_status s = c->sel_min_group > 1 ? drop_small_groups(mem, pool, c, in, skip, &kept) : JM_OK;
    if (s != JM_OK) {
        jm_free(mem, skip, n);
        return s;
    }
    *out_skip = skip;
    *out_kept = kept;
    return JM_OK;
}

jm_status jm_select_copy(jm_mem *mem, const jm_particles *in, const uint8_t *skip, size_t kept, jm_particles *out)
{
    memset(out, 0, sizeof *out);
    float *xyz = jm_alloc(mem, 3 * (kept ? kept : 1) * sizeof *xyz);
    uint32_t *ids = in->ids ? jm_alloc(mem, (kept ? kept : 1) * sizeof *ids) : NULL;
    if (!xyz || (in->ids && !ids)) {
        jm_free(mem, xyz, 3 * (kept ? kept : 1) * sizeof *xyz);
        jm_free(mem, ids, (kept ? kept : 1) * sizeof *ids);
        return JM_E_OUT_OF_MEMORY;
    }
    for (size_t i = 0, k = 0; i < in->count; i++)
        if (!skip[i]) {
            memcpy(xyz + 3 * k, pos_of(in, i), 3 * sizeof *xyz);
            if (ids) ids[k] = in->ids[i];
            k++;
        }
    out->xyz = xyz;
    out->count = kept;
    out->ids = ids;
    return JM_OK;
}

void jm_select_free_copy(jm_mem *mem, jm_particles *p)
{
    const size_t k = p->count ? p->count : 1;
    jm_free(mem, (void *)p->xyz, 3 * k * sizeof(float));
    jm_free(mem, (void *)p->ids, k * sizeof(uint32_t));
    memset(p, 0, sizeof *p);
}
