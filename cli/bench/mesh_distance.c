/* mesh_distance.c - distances from points to a triangle mesh through a uniform grid of its triangles (flicker figure, mesh comparisons). */
#include "mesh_distance.h"

#include <math.h>
#include <stdlib.h>

struct md_grid {
    const float *pos;
    const uint32_t *idx;
    double lo[3], cell;
    int64_t n[3];
    uint32_t *start, *items; /* per cell its triangles: items[start[c] .. start[c + 1]) */
};

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The closest point on a triangle by its Voronoi regions (Ericson,
 * Real-Time Collision Detection, 5.1.5), as a distance. */
double md_point_triangle(const double p[3], const double a[3], const double b[3], const double c[3])
{
    double ab[3], ac[3], ap[3], q[3];
    for (int i = 0; i < 3; i++) ab[i] = b[i] - a[i], ac[i] = c[i] - a[i], ap[i] = p[i] - a[i];
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) return sqrt(dot3(ap, ap));
    double bp[3];
    for (int i = 0; i < 3; i++) bp[i] = p[i] - b[i];
    double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) return sqrt(dot3(bp, bp));
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        for (int i = 0; i < 3; i++) q[i] = ap[i] - v * ab[i];
        return sqrt(dot3(q, q));
    }
    double cp[3];
    for (int i = 0; i < 3; i++) cp[i] = p[i] - c[i];
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) return sqrt(dot3(cp, cp));
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double w = d2 / (d2 - d6);
        for (int i = 0; i < 3; i++) q[i] = ap[i] - w * ac[i];
        return sqrt(dot3(q, q));
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int i = 0; i < 3; i++) q[i] = bp[i] - w * (c[i] - b[i]);
        return sqrt(dot3(q, q));
    }
    double den = 1.0 / (va + vb + vc), v = vb * den, w = vc * den;
    for (int i = 0; i < 3; i++) q[i] = ap[i] - v * ab[i] - w * ac[i];
    return sqrt(dot3(q, q));
}

static void corner(const md_grid *g, uint32_t v, double out[3])
{
    for (int i = 0; i < 3; i++) out[i] = g->pos[3 * (size_t)v + i];
}

static int64_t clampi(int64_t x, int64_t hi) { return x < 0 ? 0 : (x > hi ? hi : x); }

/* The cells of a triangle's bounding box, lo and hi per axis. */
static void tri_cells(const md_grid *g, size_t t, int64_t lo[3], int64_t hi[3])
{
    for (int a = 0; a < 3; a++) {
        double mn = INFINITY, mx = -INFINITY;
        for (int k = 0; k < 3; k++) {
            double x = g->pos[3 * (size_t)g->idx[3 * t + k] + a];
            mn = x < mn ? x : mn;
            mx = x > mx ? x : mx;
        }
        lo[a] = clampi((int64_t)floor((mn - g->lo[a]) / g->cell), g->n[a] - 1);
        hi[a] = clampi((int64_t)floor((mx - g->lo[a]) / g->cell), g->n[a] - 1);
    }
}

md_grid *md_build(const float *pos, const uint32_t *idx, size_t nt, double cell)
{
    if (nt == 0) return NULL;
    md_grid *g = calloc(1, sizeof *g);
    if (!g) return NULL;
    g->pos = pos;
    g->idx = idx;
    double mn[3] = {INFINITY, INFINITY, INFINITY}, mx[3] = {-INFINITY, -INFINITY, -INFINITY}, len = 0;
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            const float *p = &pos[3 * (size_t)idx[3 * t + k]], *q = &pos[3 * (size_t)idx[3 * t + (k + 1) % 3]];
            len += sqrt(((double)p[0] - q[0]) * (p[0] - q[0]) + ((double)p[1] - q[1]) * (p[1] - q[1]) +
                        ((double)p[2] - q[2]) * (p[2] - q[2]));
            for (int a = 0; a < 3; a++) mn[a] = p[a] < mn[a] ? p[a] : mn[a], mx[a] = p[a] > mx[a] ? p[a] : mx[a];
        }
    if (!(cell > 0)) cell = 2.0 * len / (3.0 * (double)nt);
    double ext = 0;
    for (int a = 0; a < 3; a++) ext = mx[a] - mn[a] > ext ? mx[a] - mn[a] : ext;
    if (!(cell > ext / 512)) cell = ext / 512; /* at most 512 cells an axis */
    if (!(cell > 0)) cell = 1.0;
    g->cell = cell;
    size_t cells = 1;
    for (int a = 0; a < 3; a++) {
        g->lo[a] = mn[a];
        g->n[a] = (int64_t)floor((mx[a] - mn[a]) / cell) + 1;
        cells *= (size_t)g->n[a];
    }
    g->start = calloc(cells + 1, sizeof *g->start);
    if (!g->start) return md_free(g), NULL;
    for (int pass = 0; pass < 2; pass++) {
        for (size_t t = 0; t < nt; t++) {
            int64_t lo[3], hi[3];
            tri_cells(g, t, lo, hi);
            for (int64_t z = lo[2]; z <= hi[2]; z++)
                for (int64_t y = lo[1]; y <= hi[1]; y++)
                    for (int64_t x = lo[0]; x <= hi[0]; x++) {
                        size_t c = (size_t)((z * g->n[1] + y) * g->n[0] + x);
                        if (pass == 0) g->start[c + 1]++;
                        else g->items[g->start[c]++] = (uint32_t)t;
                    }
        }
        if (pass == 0) {
            for (size_t c = 0; c < cells; c++) g->start[c + 1] += g->start[c];
            g->items = malloc((g->start[cells] + 1) * sizeof *g->items);
            if (!g->items) return md_free(g), NULL;
        } else { /* the fill advanced each start to the next cell's: back by one */
            for (size_t c = cells; c > 0; c--) g->start[c] = g->start[c - 1];
            g->start[0] = 0;
        }
    }
    return g;
}

/* The nearest triangle of one cell, improving *best. */
static void scan_cell(const md_grid *g, size_t c, const double p[3], double *best)
{
    for (uint32_t i = g->start[c]; i < g->start[c + 1]; i++) {
        const uint32_t *T = &g->idx[3 * (size_t)g->items[i]];
        double a[3], b[3], d[3];
        corner(g, T[0], a);
        corner(g, T[1], b);
        corner(g, T[2], d);
        double e = md_point_triangle(p, a, b, d);
        if (e < *best) *best = e;
    }
}

double md_distance(const md_grid *g, const double p[3], double limit)
{
    double best = limit;
    int64_t c[3];
    for (int a = 0; a < 3; a++) c[a] = (int64_t)floor((p[a] - g->lo[a]) / g->cell);
    int64_t kmax = 0; /* beyond it every cell of the grid has been searched */
    for (int a = 0; a < 3; a++) {
        int64_t far = c[a] < 0 ? g->n[a] - 1 - c[a] : (c[a] >= g->n[a] ? c[a] : (c[a] > g->n[a] - 1 - c[a] ? c[a] : g->n[a] - 1 - c[a]));
        kmax = far > kmax ? far : kmax;
    }
    for (int64_t k = 0; k <= kmax; k++) {
        /* the cells at Chebyshev distance k from c, clipped to the grid */
        for (int64_t z = c[2] - k; z <= c[2] + k; z++) {
            if (z < 0 || z >= g->n[2]) continue;
            for (int64_t y = c[1] - k; y <= c[1] + k; y++) {
                if (y < 0 || y >= g->n[1]) continue;
                int64_t edge = z == c[2] - k || z == c[2] + k || y == c[1] - k || y == c[1] + k;
                for (int64_t x = c[0] - k; x <= c[0] + k; x += edge ? 1 : 2 * k) {
                    if (x >= 0 && x < g->n[0]) scan_cell(g, (size_t)((z * g->n[1] + y) * g->n[0] + x), p, &best);
                    if (k == 0) break;
                }
            }
        }
        /* every point outside the cells searched is at least k cells away */
        if (best <= (double)k * g->cell || (double)k * g->cell >= limit) break;
    }
    return best;
}

void md_free(md_grid *g)
{
    if (!g) return;
    free(g->start);
    free(g->items);
    free(g);
}
