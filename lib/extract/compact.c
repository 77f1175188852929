/* compact.c - a mesh's arrays compacted in place: the triangles not kept removed, then the vertices no triangle uses. */
#include "extract/compact.h"
#include <string.h>

int jm_mesh_compact(jm_mem *mem, float *pos, float *nrm, float *uv, uint32_t *idx, size_t *nv, size_t *ni,
                    const uint8_t *keep_tri)
{
    const size_t n = *nv, nt = *ni / 3;
    if (n == 0) return 1;
    uint32_t *map = jm_alloc(mem, n * sizeof *map);
    if (!map) return 0;
    memset(map, 0xff, n * sizeof *map);
    for (size_t t = 0; t < nt; t++)
        if (keep_tri[t])
            for (int k = 0; k < 3; k++) map[idx[3 * t + k]] = 0;
    size_t k = 0;
    for (size_t v = 0; v < n; v++) {
        if (map[v] == UINT32_MAX) continue;
        map[v] = (uint32_t)k;
        if (k != v) {
            memmove(pos + 3 * k, pos + 3 * v, 3 * sizeof *pos);
            if (nrm) memmove(nrm + 3 * k, nrm + 3 * v, 3 * sizeof *nrm);
            if (uv) memmove(uv + 2 * k, uv + 2 * v, 2 * sizeof *uv);
        }
        k++;
    }
    size_t kt = 0;
    for (size_t t = 0; t < nt; t++) {
        if (!keep_tri[t]) continue;
        for (int c = 0; c < 3; c++) idx[3 * kt + c] = map[idx[3 * t + c]];
        kt++;
    }
    jm_free(mem, map, n * sizeof *map);
    *nv = k;
    *ni = 3 * kt;
    return 1;
}
