/* small_pieces.c - removes a mesh's outward pieces enclosing less than a volume, with the cavities inside them. */
#include "post/small_pieces.h"
#include "post/cavities.h"
#include "extract/compact.h"
#include "post/pieces.h"
#include <string.h>

/*
 * min_piece_volume (issue 32): stray blobs of spray removed by the volume
 * they enclose. A piece's signed volume (cavities.c) is positive for an
 * outward shell and negative for a cavity, itself a piece of its own; a
 * cavity inside a removed blob would be left floating, so each cavity whose
 * box lies in a removed blob's box (pairs found in blobs x cavities steps)
 * is tested by its winding number about
 * that blob (the solid angles of the blob's triangles seen from one of the
 * cavity's vertices, Van Oosterom and Strackee 1983): 1 inside, 0 outside,
 * whatever the blob's shape.
 */

/* The solid angle of triangle (a, b, c) seen from p, signed by its
 * orientation (counter-clockwise seen from p: positive). */
static double solid_angle(const float *a, const float *b, const float *c, const float *p)
{
    double A[3], B[3], C[3];
    for (int k = 0; k < 3; k++) {
        A[k] = (double)a[k] - p[k];
        B[k] = (double)b[k] - p[k];
        C[k] = (double)c[k] - p[k];
    }
    const double la = sqrt(A[0] * A[0] + A[1] * A[1] + A[2] * A[2]), lb = sqrt(B[0] * B[0] + B[1] * B[1] + B[2] * B[2]),
                 lc = sqrt(C[0] * C[0] + C[1] * C[1] + C[2] * C[2]);
    const double det = A[0] * (B[1] * C[2] - B[2] * C[1]) - A[1] * (B[0] * C[2] - B[2] * C[0]) +
                       A[2] * (B[0] * C[1] - B[1] * C[0]);
    const double ab = A[0] * B[0] + A[1] * B[1] + A[2] * B[2], ac = A[0] * C[0] + A[1] * C[1] + A[2] * C[2],
                 bc = B[0] * C[0] + B[1] * C[1] + B[2] * C[2];
    return 2.0 * atan2(det, la * lb * lc + ab * lc + ac * lb + bc * la);
}

typedef struct {
    uint32_t blob, cavity;
    double angle;
} pair;

/* Marks (drop[root] = 1) the cavities inside a blob already marked. box:
 * 6 floats per root (lo, hi) of the pieces marked or of negative volume. */
static int drop_cavities_inside(jm_mem *mem, const float *pos, const uint32_t *idx, size_t n, size_t nt,
                                const uint32_t *parent, const double *vol, uint8_t *drop, size_t ncav)
{
    float *box = jm_alloc(mem, 6 * n * sizeof *box);
    uint32_t *first = jm_alloc(mem, n * sizeof *first); /* per blob root: its first pair */
    uint32_t *cav = jm_alloc(mem, ncav * sizeof *cav);   /* the cavities' roots */
    if (!box || !first || !cav) {
        jm_free(mem, box, 6 * n * sizeof *box);
        jm_free(mem, first, n * sizeof *first);
        jm_free(mem, cav, ncav * sizeof *cav);
        return 0;
    }
    for (size_t v = 0, k = 0; v < n; v++)
        if (parent[v] == v && vol[v] < 0.0) cav[k++] = (uint32_t)v;
    for (size_t v = 0; v < n; v++) {
        const uint32_t r = parent[v];
        if (!drop[r] && !(vol[r] < 0.0)) continue;
        for (int k = 0; k < 3; k++) {
            const float x = pos[3 * v + k];
            if (r == v || x < box[6 * r + k]) box[6 * r + k] = x;
            if (r == v || x > box[6 * r + 3 + k]) box[6 * r + 3 + k] = x;
        }
    }
    /* the pairs (blob, cavity) whose boxes nest, by blob in vertex order */
    pair *pairs = NULL;
    size_t np = 0, cap = 0;
    int ok = 1;
    for (size_t b = 0; ok && b < n; b++) {
        first[b] = (uint32_t)np;
        if (parent[b] != b || !drop[b]) continue;
        for (size_t k = 0; k < ncav; k++) {
            const uint32_t c = cav[k];
            int in = 1;
            for (int k = 0; k < 3; k++)
                in &= box[6 * c + k] >= box[6 * b + k] && box[6 * c + 3 + k] <= box[6 * b + 3 + k];
            if (!in) continue;
            if (np == cap) {
                const size_t nc = cap ? 2 * cap : 16;
                pair *q = jm_realloc(mem, pairs, cap * sizeof *pairs, nc * sizeof *pairs);
                if (!q) { ok = 0; break; }
                pairs = q;
                cap = nc;
            }
            pairs[np++] = (pair){(uint32_t)b, c, 0.0};
        }
    }
    if (ok && np) {
        for (size_t t = 0; t < nt; t++) {
            const uint32_t *i = idx + 3 * t, b = parent[i[0]];
            if (!drop[b]) continue;
            const uint32_t end = b + 1 < n ? first[b + 1] : (uint32_t)np;
            for (uint32_t q = first[b]; q < end; q++)
                pairs[q].angle += solid_angle(pos + 3 * (size_t)i[0], pos + 3 * (size_t)i[1], pos + 3 * (size_t)i[2],
                                              pos + 3 * (size_t)pairs[q].cavity);
        }
        /* the winding number: the angles over 4 pi; inside when near 1 */
        for (size_t q = 0; q < np; q++)
            if (fabs(pairs[q].angle) > 2.0 * M_PI) drop[pairs[q].cavity] = 1;
    }
    jm_free(mem, pairs, cap * sizeof *pairs);
    jm_free(mem, box, 6 * n * sizeof *box);
    jm_free(mem, first, n * sizeof *first);
    jm_free(mem, cav, ncav * sizeof *cav);
    return ok;
}

int jm_drop_small_pieces(jm_mem *mem, jm_pool *pool, float *pos, float *nrm, float *uv, uint32_t *idx, size_t *nv,
                         size_t *ni, double min_volume, size_t *out_removed)
{
    const size_t n = *nv, nt = *ni / 3;
    *out_removed = 0;
    if (n == 0 || nt == 0) return 1;
    uint32_t *parent = jm_alloc(mem, n * sizeof *parent);
    double *vol = jm_calloc(mem, n, sizeof *vol);
    uint8_t *drop = jm_calloc(mem, n > nt ? n : nt, 1);
    int ok = parent && vol && drop;
    if (ok) {
        jm_mesh_pieces(pool, parent, idx, n, nt);
        ok = jm_piece_volumes(mem, pool, pos, idx, nt, parent, vol);
    }
    size_t removed = 0, cavities = 0;
    for (size_t v = 0; ok && v < n; v++) {
        if (parent[v] != v) continue;
        if (vol[v] >= 0.0 && vol[v] < min_volume) {
            drop[v] = 1;
            removed++;
        }
        cavities += vol[v] < 0.0;
    }
    if (ok && removed && cavities) ok = drop_cavities_inside(mem, pos, idx, n, nt, parent, vol, drop, cavities);
    if (ok && removed) {
        /* the flags by triangle, over the roots' (a triangle's pieces is its corners') */
        uint8_t *keep = jm_alloc(mem, nt);
        ok = keep != NULL;
        if (ok) {
            for (size_t t = 0; t < nt; t++) keep[t] = !drop[parent[idx[3 * t]]];
            ok = jm_mesh_compact(mem, pos, nrm, uv, idx, nv, ni, keep);
        }
        jm_free(mem, keep, nt);
    }
    jm_free(mem, parent, n * sizeof *parent);
    jm_free(mem, vol, n * sizeof *vol);
    jm_free(mem, drop, n > nt ? n : nt);
    if (ok) *out_removed = removed;
    return ok;
}
