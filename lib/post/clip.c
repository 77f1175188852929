/* clip.c - the mesh clip box: triangles with a corner outside removed, or the vertices outside clamped onto the box. */
#include "post/clip.h"
#include "extract/uv.h"
#include "extract/compact.h"
#include "post/pieces.h"
#include <string.h>

static int inside(const jm_config *c, const float *p)
{
    return p[0] >= c->clip_lo[0] && p[0] <= c->clip_hi[0] && p[1] >= c->clip_lo[1] && p[1] <= c->clip_hi[1] &&
           p[2] >= c->clip_lo[2] && p[2] <= c->clip_hi[2];
}

/* Moves vertex v onto the box if it lies outside: its normal the sum of
 * the outward normals of the faces it was clamped to, normalised, and its
 * texture coordinates from the new position and normal. */
static void clamp_vertex(const jm_config *c, float *p, float *n, float *uv)
{
    float o[3] = {0, 0, 0};
    int moved = 0;
    for (int k = 0; k < 3; k++) {
        if (p[k] < c->clip_lo[k]) {
            p[k] = c->clip_lo[k];
            o[k] = -1.0f;
            moved = 1;
        } else if (p[k] > c->clip_hi[k]) {
            p[k] = c->clip_hi[k];
            o[k] = 1.0f;
            moved = 1;
        }
    }
    if (!moved) return;
    const float len = sqrtf(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
    for (int k = 0; k < 3; k++) n[k] = o[k] / len;
    if (c->uv_mode != JM_UV_NONE) jm_uv(c, p, n, uv);
}

int jm_clip_mesh(jm_mem *mem, jm_pool *pool, const jm_config *c, float *pos, float *nrm, float *uv, uint32_t *idx,
                 size_t *nv, size_t *ni)
{
    const size_t n = *nv, nt = *ni / 3;
    if (n == 0) return 1;
    uint8_t *keep = jm_alloc(mem, nt ? nt : 1);
    if (!keep) return 0;
    int ok = 1;
    if (c->clip == 1) {
        /* a triangle stays when its three corners are in the box */
        for (size_t t = 0; t < nt; t++)
            keep[t] = (uint8_t)(inside(c, pos + 3 * (size_t)idx[3 * t]) && inside(c, pos + 3 * (size_t)idx[3 * t + 1]) &&
                                inside(c, pos + 3 * (size_t)idx[3 * t + 2]));
    } else {
        /* whole pieces with no vertex in the box go (clamped, they would
         * collapse onto it); the rest are clamped */
        uint32_t *parent = jm_alloc(mem, n * sizeof *parent);
        uint8_t *live = jm_calloc(mem, n, 1);
        ok = parent && live;
        if (ok) {
            jm_mesh_pieces(pool, parent, idx, n, nt);
            for (size_t v = 0; v < n; v++)
                if (inside(c, pos + 3 * v)) live[parent[v]] = 1;
            for (size_t t = 0; t < nt; t++) keep[t] = live[parent[idx[3 * t]]];
            for (size_t v = 0; v < n; v++)
                if (live[parent[v]]) clamp_vertex(c, pos + 3 * v, nrm + 3 * v, uv + 2 * v);
        }
        jm_free(mem, parent, n * sizeof *parent);
        jm_free(mem, live, n);
    }
    if (ok) ok = jm_mesh_compact(mem, pos, nrm, uv, idx, nv, ni, keep);
    jm_free(mem, keep, nt ? nt : 1);
    return ok;
}
