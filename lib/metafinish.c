/* metafinish.c - the stitched metasphere mesh's last pass: chord-sag compensation, normals kept facing their triangles. */
#include "metavertex.h"
#include <math.h>

/* One pass over the triangles gives, per vertex, what both steps need.
 *
 * Sag: a triangle whose corners lie on a curved surface cuts inside it by,
 * on average over its area, sum over its edges of k_e l_e^2 / 24 (k_e the
 * normal curvature along edge e; exact for a sphere), and k_e l_e^2 = dn . dp
 * with the field's unit normals n. Moving every vertex outward by the
 * area-weighted mean of that sag over its triangles makes the mesh straddle
 * the surface instead of being inscribed in it, so areas and volumes come
 * out unbiased.
 *
 * Facing: where the surface bends or creases more sharply than the cubes
 * can follow (the tunnels and saddles between densely packed particles), a
 * triangle may stand almost across the surface, and the field's normal at a
 * corner then points away from it (a renderer shades that corner from
 * behind). Such a vertex's normal is pulled toward the area-weighted mean
 * of its triangles' normals, just enough to face them all where that is
 * possible. */
int jm_meta_finish(jm_mem *mem, float *pos, float *nrm, size_t nv, const uint32_t *idx, size_t nt, int compensate,
                   int facing)
{
    /* per vertex: sag * area, area, sum of triangle normals (x2 area) */
    float *acc = jm_calloc(mem, 5 * nv, sizeof(float));
    uint8_t *bad = facing ? jm_calloc(mem, nv ? nv : 1, 1) : NULL;
    if (!acc || (facing && !bad)) {
        jm_free(mem, acc, 5 * nv * sizeof(float));
        jm_free(mem, bad, nv ? nv : 1);
        return 0;
    }
    const float cos_min = 0.02f; /* a corner faces its triangle when cos > this */
    float *restrict A = acc;
    uint8_t *restrict B = bad;
    const float *restrict P = pos, *restrict N = nrm;
    for (size_t t = 0; t < nt; t++) {
        const uint32_t i0 = idx[3 * t], i1 = idx[3 * t + 1], i2 = idx[3 * t + 2];
        float p[3][3], n[3][3];
        for (int a = 0; a < 3; a++) {
            p[0][a] = P[3 * (size_t)i0 + a], p[1][a] = P[3 * (size_t)i1 + a], p[2][a] = P[3 * (size_t)i2 + a];
            n[0][a] = N[3 * (size_t)i0 + a], n[1][a] = N[3 * (size_t)i1 + a], n[2][a] = N[3 * (size_t)i2 + a];
        }
        float e1[3], e2[3], e3[3];
        for (int a = 0; a < 3; a++) {
            e1[a] = p[1][a] - p[0][a];
            e2[a] = p[2][a] - p[1][a];
            e3[a] = p[0][a] - p[2][a];
        }
        float sag = (n[1][0] - n[0][0]) * e1[0] + (n[1][1] - n[0][1]) * e1[1] + (n[1][2] - n[0][2]) * e1[2] +
                    (n[2][0] - n[1][0]) * e2[0] + (n[2][1] - n[1][1]) * e2[1] + (n[2][2] - n[1][2]) * e2[2] +
                    (n[0][0] - n[2][0]) * e3[0] + (n[0][1] - n[2][1]) * e3[1] + (n[0][2] - n[2][2]) * e3[2];
        /* e1 x (p2 - p0) = e3 x e1 */
        const float cr[3] = {e3[1] * e1[2] - e3[2] * e1[1], e3[2] * e1[0] - e3[0] * e1[2],
                             e3[0] * e1[1] - e3[1] * e1[0]};
        const float len = sqrtf(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]), area = 0.5f * len;
        const float as = area * sag * (1.0f / 24.0f), lim = cos_min * len;
        const uint32_t vi[3] = {i0, i1, i2};
        for (int k = 0; k < 3; k++) {
            float *q = A + 5 * (size_t)vi[k];
            q[0] += as;
            q[1] += area;
            q[2] += cr[0];
            q[3] += cr[1];
            q[4] += cr[2];
            if (B && !(n[k][0] * cr[0] + n[k][1] * cr[1] + n[k][2] * cr[2] > lim)) B[vi[k]] = 1;
        }
    }
    for (size_t i = 0; i < nv; i++) {
        const float *q = acc + 5 * i;
        float *n = nrm + 3 * i;
        if (compensate && q[1] > 0.0f) {
            float d = q[0] / q[1];
            for (int a = 0; a < 3; a++) pos[3 * i + a] += d * n[a];
        }
        if (bad && bad[i]) {
            float m = sqrtf(q[2] * q[2] + q[3] * q[3] + q[4] * q[4]);
            if (m > 0.0f) {
                float o[3], l = 0.0f;
                for (int a = 0; a < 3; a++) {
                    o[a] = n[a] + 2.0f * q[2 + a] / m;
                    l += o[a] * o[a];
                }
                l = sqrtf(l);
                if (l > 0.0f)
                    for (int a = 0; a < 3; a++) n[a] = o[a] / l;
            }
        }
    }
    jm_free(mem, acc, 5 * nv * sizeof(float));
    jm_free(mem, bad, nv ? nv : 1);
    return 1;
}
