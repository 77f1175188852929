/* meshoutline.c - outline pull-in: how far a mesh's silhouettes along the three axes shrink inside a reference mesh's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "meshmetrics.h"

typedef struct raster {
    double lo[2], px;
    int w, h;
} raster;

/* Marks the pixels whose centres the projection (axes u, v) of a triangle
 * covers (either orientation, edges included). */
static void fill_tri(const raster *r, unsigned char *img, const float *P[3], int u, int v)
{
    double x[3], y[3];
    for (int k = 0; k < 3; k++) x[k] = (P[k][u] - r->lo[0]) / r->px - 0.5, y[k] = (P[k][v] - r->lo[1]) / r->px - 0.5;
    double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (area == 0) return; /* seen edge-on: its neighbours cover it */
    int x0 = (int)ceil(fmin(x[0], fmin(x[1], x[2]))), x1 = (int)floor(fmax(x[0], fmax(x[1], x[2])));
    int y0 = (int)ceil(fmin(y[0], fmin(y[1], y[2]))), y1 = (int)floor(fmax(y[0], fmax(y[1], y[2])));
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= r->w ? r->w - 1 : x1, y1 = y1 >= r->h ? r->h - 1 : y1;
    double s = area > 0 ? 1 : -1;
    for (int j = y0; j <= y1; j++)
        for (int i = x0; i <= x1; i++) {
            int in = 1;
            for (int k = 0; k < 3 && in; k++) {
                int a = k, b = (k + 1) % 3;
                double e = (x[b] - x[a]) * (j - y[a]) - (y[b] - y[a]) * (i - x[a]);
                in = s * e >= 0;
            }
            if (in) img[(size_t)j * r->w + i] = 1;
        }
}

static void silhouette(const raster *r, const mm_mesh *m, int u, int v, unsigned char *img)
{
    memset(img, 0, (size_t)r->w * r->h);
    for (size_t t = 0; t < m->nt; t++) {
        const float *P[3] = {&m->pos[3 * (size_t)m->idx[3 * t]], &m->pos[3 * (size_t)m->idx[3 * t + 1]],
                             &m->pos[3 * (size_t)m->idx[3 * t + 2]]};
        fill_tri(r, img, P, u, v);
    }
}

/* Squared distance transform of one row or column (Felzenszwalb and
 * Huttenlocher 2012, the lower envelope of parabolas): f[i] = min_j (f[j] +
 * (i - j)^2) over n values a stride apart; unset pixels hold FAR. */
#define FAR 1e20
static void edt1(double *f, size_t stride, int n, double *d, int *z, double *zz)
{
    int k = 0;
    z[0] = 0;
    zz[0] = -INFINITY, zz[1] = INFINITY;
    for (int q = 1; q < n; q++) {
        double fq = f[(size_t)q * stride] + (double)q * q, s;
        for (;;) {
            int p = z[k];
            s = (fq - (f[(size_t)p * stride] + (double)p * p)) / (2.0 * (q - p));
            if (s > zz[k] || k == 0) break;
            k--;
        }
        if (s <= zz[k]) { /* k == 0: q's parabola lies below the first everywhere */
            z[0] = q;
            continue;
        }
        k++;
        z[k] = q;
        zz[k] = s;
        zz[k + 1] = INFINITY;
    }
    k = 0;
    for (int q = 0; q < n; q++) {
        while (zz[k + 1] < q) k++;
        double dq = (double)(q - z[k]);
        d[q] = dq * dq + f[(size_t)z[k] * stride];
    }
    for (int q = 0; q < n; q++) f[(size_t)q * stride] = d[q];
}

/* dist[i] = squared distance in pixels from pixel i to the nearest set pixel of img. */
static int distance_to(const raster *r, const unsigned char *img, double *dist)
{
    int n = r->w > r->h ? r->w : r->h;
    double *d = malloc((size_t)n * sizeof *d), *zz = malloc((size_t)(n + 1) * sizeof *zz);
    int *z = malloc((size_t)n * sizeof *z);
    if (!d || !zz || !z) {
        free(d), free(zz), free(z);
        return -1;
    }
    for (size_t i = 0; i < (size_t)r->w * r->h; i++) dist[i] = img[i] ? 0 : FAR;
    for (int j = 0; j < r->h; j++) edt1(&dist[(size_t)j * r->w], 1, r->w, d, z, zz);
    for (int i = 0; i < r->w; i++) edt1(&dist[i], (size_t)r->w, r->h, d, z, zz);
    free(d), free(zz), free(z);
    return 0;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

void mm_outline(const mm_mesh *ref, const mm_mesh *m, double px, double *pull, double *pull99, double *push)
{
    *pull = *pull99 = *push = 0;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const mm_mesh *ms[2] = {ref, m};
    for (int k = 0; k < 2; k++)
        for (size_t v = 0; v < ms[k]->nv; v++)
            for (int a = 0; a < 3; a++) {
                lo[a] = fmin(lo[a], ms[k]->pos[3 * v + a]);
                hi[a] = fmax(hi[a], ms[k]->pos[3 * v + a]);
            }
    double *all = NULL;
    size_t nall = 0;
    for (int axis = 0; axis < 3; axis++) {
        int u = (axis + 1) % 3, v = (axis + 2) % 3;
        raster r = {{lo[u] - 2 * px, lo[v] - 2 * px}, px, (int)((hi[u] - lo[u]) / px) + 5,
                    (int)((hi[v] - lo[v]) / px) + 5};
        size_t np = (size_t)r.w * r.h;
        unsigned char *s0 = malloc(np), *s1 = malloc(np);
        double *d1 = malloc(np * sizeof *d1), *d0 = malloc(np * sizeof *d0);
        double *grown = realloc(all, (nall + np) * sizeof *all);
        if (grown) all = grown;
        if (!s0 || !s1 || !d1 || !d0 || !grown || px <= 0) {
            free(s0), free(s1), free(d1), free(d0);
            break;
        }
        silhouette(&r, ref, u, v, s0);
        silhouette(&r, m, u, v, s1);
        if (distance_to(&r, s1, d1) == 0 && distance_to(&r, s0, d0) == 0)
            for (int j = 0; j < r.h; j++)
                for (int i = 0; i < r.w; i++) {
                    size_t p = (size_t)j * r.w + i;
                    if (s0[p] && d1[p] > 0) *pull = fmax(*pull, sqrt(d1[p]) * px);
                    if (s1[p] && d0[p] > 0) *push = fmax(*push, sqrt(d0[p]) * px);
                    /* the outline of S0: a pixel of it beside one outside */
                    int edge = s0[p] && (i == 0 || j == 0 || i == r.w - 1 || j == r.h - 1 || !s0[p - 1] ||
                                         !s0[p + 1] || !s0[p - (size_t)r.w] || !s0[p + (size_t)r.w]);
                    if (edge) all[nall++] = sqrt(d1[p]) * px;
                }
        free(s0), free(s1), free(d1), free(d0);
    }
    if (nall > 0) {
        qsort(all, nall, sizeof *all, cmp_d);
        *pull99 = all[(size_t)(0.99 * (double)(nall - 1) + 0.5)];
    }
    free(all);
}
