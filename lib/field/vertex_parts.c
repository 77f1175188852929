/* vertex_parts.c - a block's vertices sorted into parts about a support wide, so that normals gather only the particles near each part. */
#include "field/vertex_parts.h"
#include <math.h>
#include <string.h>

/* the part (of S^3, x fastest) of the block holding p */
static inline int part_of(const float p[3], const float lo[3], const float inv[3], int S)
{
    int q = 0;
    for (int a = 2; a >= 0; a--) {
        int k = (int)((p[a] - lo[a]) * inv[a]);
        q = q * S + (k < 0 ? 0 : (k >= S ? S - 1 : k));
    }
    return q;
}

/* Each part gathers only the particles within the support of its box, so
 * a vertex sums over a few times the particles that reach it instead of
 * over all that reach the block (30 times more for blocks three supports
 * wide). */
int jm_vertex_parts(const jm_config *c, jm_scratch *s, const float lo[3], const float hi[3], const jm_bout *out,
                    uint32_t start[65])
{
    int S = (int)lrintf((hi[0] - lo[0]) / c->support);
    S = S < 1 ? 1 : (S > 4 ? 4 : S);
    const size_t nv = out->nv;
    if (nv > s->cap_order) {
        uint32_t *o = jm_realloc_lasting(s->hood.mem, s->order, s->cap_order * sizeof *o, nv * sizeof *o);
        if (!o) return 0;
        s->order = o;
        s->cap_order = nv;
    }
    /* counting sort of the vertices by part */
    memset(start, 0, 65 * sizeof *start);
    float inv[3];
    for (int a = 0; a < 3; a++) inv[a] = (float)S / (hi[a] - lo[a]);
    for (size_t v = 0; v < nv; v++) start[part_of(&out->pos[3 * v], lo, inv, S) + 1]++;
    for (int q = 0; q < S * S * S; q++) start[q + 1] += start[q];
    uint32_t fill[64];
    memcpy(fill, start, sizeof fill);
    for (size_t v = 0; v < nv; v++) s->order[fill[part_of(&out->pos[3 * v], lo, inv, S)]++] = (uint32_t)v;
    return S;
}

void jm_vertex_part_box(const jm_config *c, int S, int q, const float lo[3], const float hi[3], float plo[3],
                        float phi[3])
{
    int qi[3] = {q % S, (q / S) % S, q / (S * S)};
    for (int a = 0; a < 3; a++) {
        float w = (hi[a] - lo[a]) / (float)S;
        plo[a] = qi[a] == 0 ? lo[a] : lo[a] + w * (float)qi[a];
        phi[a] = qi[a] == S - 1 ? hi[a] : lo[a] + w * (float)(qi[a] + 1);
    }
    for (int a = 0; a < 3; a++) {
        plo[a] -= 0.01f * c->support;
        phi[a] += 0.01f * c->support;
    }
}

int jm_vertex_parts_normals(const jm_block_env *env, jm_scratch *s, const float lo[3], const float hi[3], jm_bout *out,
                            jm_part_normals_fn part)
{
    uint32_t start[65];
    const int S = jm_vertex_parts(env->c, s, lo, hi, out, start);
    if (!S) return 0;
    for (int q = 0; q < S * S * S; q++) {
        if (start[q] == start[q + 1]) continue;
        float plo[3], phi[3];
        jm_vertex_part_box(env->c, S, q, lo, hi, plo, phi);
        if (!part(env, s, plo, phi, s->order + start[q], start[q + 1] - start[q], out)) return 0;
    }
    return 1;
}
