/* uv.c - texture coordinates that depend only on world position, normal and parameters. */
#include "extract/uv.h"
#include <math.h>

void jm_uv(const jm_config *c, const float p[3], const float n[3], float uv[2])
{
    const float s = 1.0f / c->uv_scale;
    int axis;
    switch (c->uv_mode) {
    case JM_UV_SPHERICAL:
        uv[0] = atan2f(n[1], n[0]) * (float)(0.5 / M_PI) + 0.5f;
        uv[1] = acosf(fmaxf(-1.0f, fminf(1.0f, n[2]))) * (float)(1.0 / M_PI);
        return;
    case JM_UV_PLANAR:
        axis = c->uv_axis;
        break;
    default: { /* box: drop the normal's dominant axis */
        float ax = fabsf(n[0]), ay = fabsf(n[1]), az = fabsf(n[2]);
        axis = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
        break;
    }
    }
    int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
    uv[0] = p[u] * s;
    uv[1] = p[v] * s;
}

void jm_uv_all(const jm_config *c, const float *pos, const float *nrm, float *uv, size_t nv)
{
    if (c->uv_mode != JM_UV_BOX) {
        for (size_t v = 0; v < nv; v++) jm_uv(c, &pos[3 * v], &nrm[3 * v], &uv[2 * v]);
        return;
    }
    /* the box mode with the scale's reciprocal taken once, and the axis
     * chosen without branches (the same comparisons) */
    const float s = 1.0f / c->uv_scale;
    for (size_t v = 0; v < nv; v++) {
        const float *p = &pos[3 * v], *n = &nrm[3 * v];
        float ax = fabsf(n[0]), ay = fabsf(n[1]), az = fabsf(n[2]);
        /* axis 0 where gx, else 1 where gy, else 2 */
        const int gx = (ax >= ay) & (ax >= az), gy = (ay >= az) & !gx;
        const int u = gx, w = 2 - (!gx & !gy);
        uv[2 * v] = p[u] * s;
        uv[2 * v + 1] = p[w] * s;
    }
}
