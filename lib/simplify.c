/* simplify.c - simplification to a geometric error with meshoptimizer (the only file that includes it), checked closed and manifold. */
#include "post.h"
#include <meshoptimizer.h>
#include <stdlib.h>
#include <string.h>

/*
 * meshopt_simplify collapses edges onto existing vertices, so the surviving
 * vertices keep their positions, and with them their normals and UVs. Its
 * error is relative to the mesh's extent (meshopt_simplifyScale). It keeps
 * triangles oriented, but an edge collapse can still, rarely, pinch the
 * surface (an edge shared by four triangles, or a vertex whose triangles form
 * two fans). The result is checked; when it fails, the simplification is
 * retried at half the error, twice, and the unsimplified mesh kept after that.
 * meshoptimizer's own scratch memory is not counted in jm_stats.peak_bytes.
 */

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static int has_key(const uint64_t *k, size_t n, uint64_t key)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (k[mid] < key) lo = mid + 1; else hi = mid;
    }
    return lo < n && k[lo] == key;
}

/* 1 if every directed edge appears once and its reverse once (closed,
 * edge-manifold, consistently oriented) and the triangles around every vertex
 * form a single fan; 0 if not; -1 out of memory. */
static int manifold(jm_mem *mem, const uint32_t *idx, size_t ni, size_t nv)
{
    int ok = 1;
    uint64_t *k = jm_alloc(mem, (ni ? ni : 1) * sizeof *k);
    uint32_t *start = jm_calloc(mem, nv + 1, sizeof *start);
    uint32_t *fan = jm_alloc(mem, (ni ? ni : 1) * 2 * sizeof *fan);
    if (!k || !start || !fan) { ok = -1; goto out; }
    for (size_t t = 0; t + 2 < ni; t += 3)
        for (int e = 0; e < 3; e++) {
            uint32_t a = idx[t + e], b = idx[t + (e + 1) % 3];
            if (a == b) { ok = 0; goto out; }
            k[t + e] = (uint64_t)a << 32 | b;
        }
    qsort(k, ni, sizeof *k, cmp_u64);
    for (size_t i = 0; i < ni && ok; i++) {
        if (i + 1 < ni && k[i + 1] == k[i]) ok = 0;
        else if (!has_key(k, ni, k[i] << 32 | k[i] >> 32)) ok = 0;
    }
    if (!ok) goto out;
    /* fans: from each vertex, its triangles' (next, previous) corners; the
     * walk next -> previous must visit all of them before it closes */
    for (size_t t = 0; t < ni; t++) start[idx[t] + 1]++;
    for (size_t v = 0; v < nv; v++) start[v + 1] += start[v];
    for (size_t t = 0; t + 2 < ni; t += 3)
        for (int e = 0; e < 3; e++) {
            uint32_t at = start[idx[t + e]]++;
            fan[2 * (size_t)at] = idx[t + (e + 1) % 3];
            fan[2 * (size_t)at + 1] = idx[t + (e + 2) % 3];
        }
    for (size_t v = nv; v > 0; v--) start[v] = start[v - 1];
    start[0] = 0;
    for (size_t v = 0; v < nv && ok; v++) {
        uint32_t s = start[v], e = start[v + 1];
        if (s == e) continue;
        uint32_t first = fan[2 * (size_t)s], cur = fan[2 * (size_t)s + 1], steps = 1;
        while (cur != first && steps <= e - s) {
            uint32_t i = s;
            while (i < e && fan[2 * (size_t)i] != cur) i++;
            if (i == e) break;
            cur = fan[2 * (size_t)i + 1];
            steps++;
        }
        if (cur != first || steps != e - s) ok = 0;
    }
out:
    jm_free(mem, k, (ni ? ni : 1) * sizeof *k);
    jm_free(mem, start, (nv + 1) * sizeof *start);
    jm_free(mem, fan, (ni ? ni : 1) * 2 * sizeof *fan);
    return ok;
}

jm_status jm_simplify_mesh(jm_mem *mem, const jm_config *c, jm_post_mesh *m)
{
    if (c->simplify_error <= 0.0f || m->ni == 0 || m->nv == 0) return JM_OK;
    size_t nv = m->nv, ni = m->ni;
    uint32_t *dst = jm_alloc(mem, ni * sizeof *dst);
    uint32_t *remap = jm_alloc(mem, nv * sizeof *remap);
    if (!dst || !remap) {
        jm_free(mem, dst, ni * sizeof *dst);
        jm_free(mem, remap, nv * sizeof *remap);
        return JM_E_OUT_OF_MEMORY;
    }
    float scale = meshopt_simplifyScale(m->pos, nv, 3 * sizeof(float));
    float target = scale > 0.0f ? c->simplify_error / scale : 0.0f;
    size_t n = 0;
    int ok = 0;
    for (int attempt = 0; attempt < 3 && !ok; attempt++, target *= 0.5f) {
        n = meshopt_simplify(dst, m->idx, ni, m->pos, nv, 3 * sizeof(float), 0, target,
                             meshopt_SimplifyLockBorder, NULL);
        ok = manifold(mem, dst, n, nv);
        if (ok < 0) break;
    }
    jm_status st = ok < 0 ? JM_E_OUT_OF_MEMORY : JM_OK;
    if (ok == 1 && n < ni) {
        /* keep the used vertices in their order */
        memset(remap, 0xff, nv * sizeof *remap);
        for (size_t t = 0; t < n; t++) remap[dst[t]] = 0;
        size_t k = 0;
        for (size_t v = 0; v < nv; v++) {
            if (remap[v]) continue;
            remap[v] = (uint32_t)k;
            if (k != v) {
                memcpy(&m->pos[3 * k], &m->pos[3 * v], 3 * sizeof(float));
                memcpy(&m->nrm[3 * k], &m->nrm[3 * v], 3 * sizeof(float));
                memcpy(&m->uv[2 * k], &m->uv[2 * v], 2 * sizeof(float));
            }
            k++;
        }
        for (size_t t = 0; t < n; t++) m->idx[t] = remap[dst[t]];
        m->nv = k;
        m->ni = n;
    }
    jm_free(mem, dst, ni * sizeof *dst);
    jm_free(mem, remap, nv * sizeof *remap);
    return st;
}
