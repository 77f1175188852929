/* simplify.c - simplification to a geometric error with meshoptimizer (the only file that includes it), checked closed and manifold. */
#include "post/simplify.h"
#include <meshoptimizer.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#ifndef JM_SIMPLIFY_AIM
#define JM_SIMPLIFY_AIM 0.5f
#endif

/*
 * meshopt_simplify collapses edges onto existing vertices, so the surviving
 * vertices keep their positions, and with them their normals and UVs. Its
 * error is relative to the mesh's extent (meshopt_simplifyScale). It keeps
 * triangles oriented, but an edge collapse can still, rarely, pinch the
 * surface (an edge shared by four triangles, or a vertex whose triangles form
 * two fans). The result is checked; where it fails, the original triangles
 * around the defects are kept and the rest simplified again with its border
 * locked (three rounds, the kept region growing); failing that, every
 * connected piece is simplified on its own, retried at half the error twice,
 * and kept as it was after that.
 * meshoptimizer's own scratch memory is counted too (below).
 */

/*
 * meshoptimizer's scratch, counted in the context's jm_mem. Its allocator
 * (meshopt_setAllocator) is global to the process, so it is set once
 * (pthread_once) to two functions that count on the jm_mem of the
 * simplification running on the calling thread: a thread-local pointer, set
 * for the length of jm_simplify_mesh and NULL elsewhere (uncounted), so
 * contexts simplifying on several threads at once each count their own.
 * meshoptimizer frees what it allocates before its functions return; each
 * block still carries its jm_mem (or NULL) and size in a header, since the
 * deallocation callback gets only the pointer. Over the limit a block is
 * still given, uncounted (meshoptimizer cannot take a failure), and the
 * refusal recorded (jm_mem.over): the simplification then ends with
 * JM_E_TOO_LARGE when meshoptimizer returns. An application's own
 * meshoptimizer allocator, if it set one, is replaced by plain malloc at
 * jetmesh's first simplification.
 */
static _Thread_local jm_mem *meshopt_mem;

typedef union meshopt_header {
    max_align_t align;
    struct {
        jm_mem *mem; /* counted in, or NULL */
        size_t bytes;
    } h;
} meshopt_header;

static void *meshopt_counted_alloc(size_t bytes)
{
    meshopt_header *b = malloc(sizeof *b + bytes);
    if (!b) return NULL;
    jm_mem *m = meshopt_mem;
    b->h.mem = m && jm_mem_take(m, bytes) ? m : NULL;
    b->h.bytes = bytes;
    return b + 1;
}

static void meshopt_counted_free(void *p)
{
    if (!p) return;
    meshopt_header *b = (meshopt_header *)p - 1;
    if (b->h.mem) jm_mem_sub(b->h.mem, b->h.bytes);
    free(b);
}

static pthread_once_t meshopt_once = PTHREAD_ONCE_INIT;
static void meshopt_install(void) { meshopt_setAllocator(meshopt_counted_alloc, meshopt_counted_free); }

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
 * form a single fan; 0 if not; -1 out of memory. bad (nv flags, may be NULL)
 * gets the vertices of every defect. */
static int manifold(jm_mem *mem, const uint32_t *idx, size_t ni, size_t nv, uint8_t *bad)
{
    int ok = 1;
    uint64_t *k = jm_alloc(mem, (ni ? ni : 1) * sizeof *k);
    uint32_t *start = jm_calloc(mem, nv + 1, sizeof *start);
    uint32_t *fan = jm_alloc(mem, (ni ? ni : 1) * 2 * sizeof *fan);
    if (!k || !start || !fan) { ok = -1; goto out; }
    if (bad) memset(bad, 0, nv);
    for (size_t t = 0; t + 2 < ni; t += 3)
        for (int e = 0; e < 3; e++) {
            uint32_t a = idx[t + e], b = idx[t + (e + 1) % 3];
            if (a == b) {
                ok = 0;
                if (!bad) goto out;
                bad[a] = 1;
            }
            k[t + e] = (uint64_t)a << 32 | b;
        }
    qsort(k, ni, sizeof *k, cmp_u64);
    for (size_t i = 0; i < ni && (ok || bad); i++) {
        if ((i + 1 < ni && k[i + 1] == k[i]) || !has_key(k, ni, k[i] << 32 | k[i] >> 32)) {
            ok = 0;
            if (bad) bad[k[i] >> 32] = bad[(uint32_t)k[i]] = 1;
        }
    }
    if (!ok && !bad) goto out;
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
    for (size_t v = 0; v < nv && (ok || bad); v++) {
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
        if (cur != first || steps != e - s) {
            ok = 0;
            if (bad) bad[v] = 1;
        }
    }
out:
    jm_free(mem, k, (ni ? ni : 1) * sizeof *k);
    jm_free(mem, start, (nv + 1) * sizeof *start);
    jm_free(mem, fan, (ni ? ni : 1) * 2 * sizeof *fan);
    return ok;
}

/* Simplifies the triangles idx[0..ni) over vertices pos[0..nv) to the
 * absolute error err into dst; retries at half the error twice while the
 * result is not closed and manifold, then copies the input. Returns the
 * index count, or SIZE_MAX when out of memory. */
static size_t simplify_checked(jm_mem *mem, const uint32_t *idx, size_t ni, const float *pos, size_t nv, float err,
                               int tries, uint32_t *dst)
{
    float scale = meshopt_simplifyScale(pos, nv, 3 * sizeof(float));
    float target = scale > 0.0f ? err / scale : 0.0f;
    for (int attempt = 0; attempt < tries; attempt++, target *= 0.5f) {
        size_t n = meshopt_simplify(dst, idx, ni, pos, nv, 3 * sizeof(float), 0, target, meshopt_SimplifyLockBorder,
                                    NULL);
        int ok = manifold(mem, dst, n, nv, NULL);
        if (ok < 0) return SIZE_MAX;
        if (ok) return n;
    }
    memcpy(dst, idx, ni * sizeof *idx);
    return ni;
}

static uint32_t find_root(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

/* The whole mesh failed the check: each connected piece on its own, so a
 * pinch only costs its own piece. Writes the new triangles to dst. */
static jm_status by_pieces(jm_mem *mem, const jm_post_mesh *m, float err, uint32_t *dst, size_t *out_n)
{
    size_t nv = m->nv, ni = m->ni, nt = ni / 3, done = 0;
    jm_status st = JM_OK;
    uint32_t *lab = jm_alloc(mem, nv * sizeof *lab), *loc = jm_alloc(mem, nv * sizeof *loc);
    uint32_t *tstart = NULL, *tris = NULL, *vstart = NULL, *verts = NULL, *lidx = NULL, *ldst = NULL;
    float *lpos = NULL;
    size_t ncomp = 0, maxt = 0, maxv = 0;
    if (!lab || !loc) { st = JM_E_OUT_OF_MEMORY; goto out; }
    for (size_t v = 0; v < nv; v++) lab[v] = (uint32_t)v;
    for (size_t t = 0; t < nt; t++)
        for (int k = 1; k < 3; k++) {
            uint32_t a = find_root(lab, m->idx[3 * t]), b = find_root(lab, m->idx[3 * t + k]);
            if (a != b) lab[a > b ? a : b] = a < b ? a : b;
        }
    for (size_t v = 0; v < nv; v++) { /* roots are their pieces' smallest vertices */
        uint32_t r = find_root(lab, (uint32_t)v);
        loc[v] = r == v ? (uint32_t)ncomp++ : loc[r];
    }
    memcpy(lab, loc, nv * sizeof *lab);
    tstart = jm_calloc(mem, ncomp + 1, sizeof *tstart);
    vstart = jm_calloc(mem, ncomp + 1, sizeof *vstart);
    tris = jm_alloc(mem, (nt ? nt : 1) * sizeof *tris);
    verts = jm_alloc(mem, nv * sizeof *verts);
    if (!tstart || !vstart || !tris || !verts) { st = JM_E_OUT_OF_MEMORY; goto out; }
    /* triangles and vertices grouped by piece, in their order */
    for (size_t t = 0; t < nt; t++) tstart[lab[m->idx[3 * t]] + 1]++;
    for (size_t v = 0; v < nv; v++) vstart[lab[v] + 1]++;
    for (size_t k = 0; k < ncomp; k++) {
        if (tstart[k + 1] > maxt) maxt = tstart[k + 1];
        if (vstart[k + 1] > maxv) maxv = vstart[k + 1];
        tstart[k + 1] += tstart[k];
        vstart[k + 1] += vstart[k];
    }
    for (size_t t = 0; t < nt; t++) tris[tstart[lab[m->idx[3 * t]]]++] = (uint32_t)t;
    for (size_t v = 0; v < nv; v++) {
        loc[v] = vstart[lab[v]]; /* its place in verts, for now */
        verts[vstart[lab[v]]++] = (uint32_t)v;
    }
    memmove(tstart + 1, tstart, ncomp * sizeof *tstart);
    memmove(vstart + 1, vstart, ncomp * sizeof *vstart);
    tstart[0] = vstart[0] = 0;
    for (size_t v = 0; v < nv; v++) loc[v] -= vstart[lab[v]]; /* index within its piece */
    lpos = jm_alloc(mem, (maxv ? maxv : 1) * 3 * sizeof *lpos);
    lidx = jm_alloc(mem, (maxt ? maxt : 1) * 3 * sizeof *lidx);
    ldst = jm_alloc(mem, (maxt ? maxt : 1) * 3 * sizeof *ldst);
    if (!lpos || !lidx || !ldst) { st = JM_E_OUT_OF_MEMORY; goto out; }
    for (size_t k = 0; k < ncomp; k++) {
        size_t kv = vstart[k + 1] - vstart[k], kt = tstart[k + 1] - tstart[k];
        for (size_t i = 0; i < kv; i++) memcpy(&lpos[3 * i], &m->pos[3 * (size_t)verts[vstart[k] + i]], 3 * sizeof(float));
        for (size_t i = 0; i < kt; i++)
            for (int c = 0; c < 3; c++) lidx[3 * i + c] = loc[m->idx[3 * (size_t)tris[tstart[k] + i] + c]];
        size_t n = simplify_checked(mem, lidx, 3 * kt, lpos, kv, err, 3, ldst);
        if (n == SIZE_MAX) { st = JM_E_OUT_OF_MEMORY; goto out; }
        for (size_t i = 0; i < n; i++) dst[done + i] = verts[vstart[k] + ldst[i]];
        done += n;
    }
out:
    *out_n = done;
    jm_free(mem, lab, nv * sizeof *lab);
    jm_free(mem, loc, nv * sizeof *loc);
    jm_free(mem, tstart, (ncomp + 1) * sizeof *tstart);
    jm_free(mem, vstart, (ncomp + 1) * sizeof *vstart);
    jm_free(mem, tris, (nt ? nt : 1) * sizeof *tris);
    jm_free(mem, verts, nv * sizeof *verts);
    if (lpos) jm_free(mem, lpos, (maxv ? maxv : 1) * 3 * sizeof *lpos);
    if (lidx) jm_free(mem, lidx, (maxt ? maxt : 1) * 3 * sizeof *lidx);
    if (ldst) jm_free(mem, ldst, (maxt ? maxt : 1) * 3 * sizeof *ldst);
    return st;
}

/* The simplification left defects at the vertices flagged in bad: keeps the
 * original triangles around them (within a few rings, growing each round)
 * and simplifies the rest with its border locked, so the two stitch exactly.
 * Returns 1 with the triangles in dst (count *n), 0 if still defective after
 * three rounds, -1 out of memory. */
static int repair(jm_mem *mem, const jm_post_mesh *m, float err, uint8_t *bad, uint32_t *dst, size_t *n)
{
    size_t nv = m->nv, ni = m->ni;
    uint8_t *region = jm_calloc(mem, nv, 1);
    uint32_t *rest = jm_alloc(mem, ni * sizeof *rest);
    int ok = 0;
    if (!region || !rest) { ok = -1; goto out; }
    for (int round = 0; round < 3 && !ok; round++) {
        for (size_t v = 0; v < nv; v++) region[v] |= bad[v];
        for (int ring = 0; ring < 2 + 2 * round; ring++) {
            memcpy(bad, region, nv); /* grow from the region as it was */
            for (size_t t = 0; t < ni; t += 3)
                if (bad[m->idx[t]] || bad[m->idx[t + 1]] || bad[m->idx[t + 2]])
                    region[m->idx[t]] = region[m->idx[t + 1]] = region[m->idx[t + 2]] = 1;
        }
        size_t nr = 0, nk = 0;
        for (size_t t = 0; t < ni; t += 3) {
            const uint32_t *T = &m->idx[t];
            if (region[T[0]] || region[T[1]] || region[T[2]]) continue;
            memcpy(&rest[nr], T, 3 * sizeof *T);
            nr += 3;
        }
        float scale = meshopt_simplifyScale(m->pos, nv, 3 * sizeof(float));
        size_t got = nr ? meshopt_simplify(dst, rest, nr, m->pos, nv, 3 * sizeof(float), 0,
                                           scale > 0.0f ? err / scale : 0.0f, meshopt_SimplifyLockBorder, NULL)
                        : 0;
        for (size_t t = 0; t < ni; t += 3) {
            const uint32_t *T = &m->idx[t];
            if (!(region[T[0]] || region[T[1]] || region[T[2]])) continue;
            memcpy(&dst[got + nk], T, 3 * sizeof *T);
            nk += 3;
        }
        *n = got + nk;
        ok = manifold(mem, dst, *n, nv, bad);
    }
out:
    jm_free(mem, region, nv);
    jm_free(mem, rest, ni * sizeof *rest);
    return ok;
}

jm_status jm_simplify_mesh(jm_mem *mem, const jm_config *c, jm_post_mesh *m)
{
    if (c->simplify_error <= 0.0f || m->ni == 0 || m->nv == 0) return JM_OK;
    size_t nv = m->nv, ni = m->ni;
    /* meshoptimizer's error is measured against quadrics (planes), which
     * underestimate the distance on curved fluid surfaces: aim at a part */
    float err = c->simplify_error * JM_SIMPLIFY_AIM;
    pthread_once(&meshopt_once, meshopt_install);
    meshopt_mem = mem; /* meshoptimizer's scratch counted here (see above) */
    uint32_t *dst = jm_alloc(mem, ni * sizeof *dst);
    uint32_t *remap = jm_alloc(mem, nv * sizeof *remap);
    uint8_t *bad = NULL;
    jm_status st = JM_OK;
    if (!dst || !remap) { st = JM_E_OUT_OF_MEMORY; goto out; }
    float scale = meshopt_simplifyScale(m->pos, nv, 3 * sizeof(float));
    size_t n = meshopt_simplify(dst, m->idx, ni, m->pos, nv, 3 * sizeof(float), 0, scale > 0.0f ? err / scale : 0.0f,
                                meshopt_SimplifyLockBorder, NULL);
    bad = jm_alloc(mem, nv);
    if (!bad) { st = JM_E_OUT_OF_MEMORY; goto out; }
    int ok = manifold(mem, dst, n, nv, bad);
    if (ok == 0) ok = repair(mem, m, err, bad, dst, &n);
    if (ok == 0) st = by_pieces(mem, m, err, dst, &n); /* each piece, at halved errors, or as it was */
    if (ok < 0) st = JM_E_OUT_OF_MEMORY;
    if (st != JM_OK) goto out;
    if (n < ni) {
        /* keep the used vertices, in their order */
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
out:
    meshopt_mem = NULL;
    jm_free(mem, dst, ni * sizeof *dst);
    jm_free(mem, remap, nv * sizeof *remap);
    jm_free(mem, bad, nv);
    /* a block meshoptimizer took past the limit (given uncounted) */
    if (mem && mem->limit && atomic_load(&mem->over)) return JM_E_TOO_LARGE;
    return st;
}
