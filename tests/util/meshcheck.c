/* meshcheck.c - test helpers: closedness, manifoldness, orientation, volume, components of a mesh. */
#include "meshcheck.h"
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

unsigned mc_rand(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}
float mc_randf(unsigned *s) { return (float)(mc_rand(s) & 0xffffff) / 16777216.0f; }

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static size_t find_root(size_t *p, size_t x)
{
    while (p[x] != x) { p[x] = p[p[x]]; x = p[x]; }
    return x;
}

typedef struct { uint32_t v, b, c; } corner;
static int cmp_corner(const void *a, const void *b)
{
    const corner *x = a, *y = b;
    if (x->v != y->v) return x->v < y->v ? -1 : 1;
    return x->b < y->b ? -1 : x->b > y->b;
}

int mc_check(const jm_mesh *m, mc_report *r)
{
    memset(r, 0, sizeof *r);
    r->closed = r->edge_manifold = r->vertex_manifold = r->no_degenerate = r->all_referenced = r->normals_ok = 1;
    size_t nt = m->triangle_count, nv = m->vertex_count;
    const uint32_t *I = m->indices;
    const float *P = m->positions;
    uint64_t *e = malloc((3 * nt + 1) * sizeof *e);
    corner *cs = malloc((3 * nt + 1) * sizeof *cs);
    size_t *parent = malloc((nv + 1) * sizeof *parent);
    char *used = calloc(nv + 1, 1);
    double *fn = calloc(3 * nv + 1, sizeof *fn);
    for (size_t v = 0; v < nv; v++) parent[v] = v;
    for (size_t t = 0; t < nt; t++) {
        uint32_t a = I[3 * t], b = I[3 * t + 1], c = I[3 * t + 2];
        if (a >= nv || b >= nv || c >= nv) {
            snprintf(r->problem, sizeof r->problem, "triangle %zu has an index out of range", t);
            r->closed = 0;
            goto out;
        }
        if (a == b || b == c || a == c) {
            if (r->no_degenerate) snprintf(r->problem, sizeof r->problem, "triangle %zu is degenerate", t);
            r->no_degenerate = 0;
        }
        e[3 * t] = (uint64_t)a << 32 | b;
        e[3 * t + 1] = (uint64_t)b << 32 | c;
        e[3 * t + 2] = (uint64_t)c << 32 | a;
        cs[3 * t] = (corner){a, b, c};
        cs[3 * t + 1] = (corner){b, c, a};
        cs[3 * t + 2] = (corner){c, a, b};
        used[a] = used[b] = used[c] = 1;
        parent[find_root(parent, a)] = find_root(parent, b);
        parent[find_root(parent, b)] = find_root(parent, c);
        const float *pa = P + 3 * a, *pb = P + 3 * b, *pc = P + 3 * c;
        double u[3], w[3], n[3];
        for (int k = 0; k < 3; k++) { u[k] = pb[k] - pa[k]; w[k] = pc[k] - pa[k]; }
        n[0] = u[1] * w[2] - u[2] * w[1];
        n[1] = u[2] * w[0] - u[0] * w[2];
        n[2] = u[0] * w[1] - u[1] * w[0];
        r->area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        r->volume += ((double)pa[0] * ((double)pb[1] * pc[2] - (double)pb[2] * pc[1]) -
                      (double)pa[1] * ((double)pb[0] * pc[2] - (double)pb[2] * pc[0]) +
                      (double)pa[2] * ((double)pb[0] * pc[1] - (double)pb[1] * pc[0])) / 6.0;
        for (int k = 0; k < 3; k++) {
            fn[3 * a + k] += n[k];
            fn[3 * b + k] += n[k];
            fn[3 * c + k] += n[k];
        }
    }
    qsort(e, 3 * nt, sizeof *e, cmp_u64);
    for (size_t i = 0; i + 1 < 3 * nt; i++)
        if (e[i] == e[i + 1]) {
            if (r->edge_manifold)
                snprintf(r->problem, sizeof r->problem, "directed edge %u-%u used twice", (unsigned)(e[i] >> 32), (unsigned)e[i]);
            r->edge_manifold = 0;
        }
    for (size_t i = 0; i < 3 * nt; i++) {
        uint64_t rev = (e[i] << 32) | (e[i] >> 32);
        if (!bsearch(&rev, e, 3 * nt, sizeof *e, cmp_u64)) {
            if (r->closed)
                snprintf(r->problem, sizeof r->problem, "edge %u-%u has no opposite (open or misoriented)",
                         (unsigned)(e[i] >> 32), (unsigned)e[i]);
            r->closed = 0;
        }
    }
    /* one fan per vertex: the map b -> c of the corners at v is one cycle */
    qsort(cs, 3 * nt, sizeof *cs, cmp_corner);
    for (size_t i = 0; i < 3 * nt;) {
        size_t j = i;
        while (j < 3 * nt && cs[j].v == cs[i].v) j++;
        size_t len = j - i, steps = 0;
        uint32_t start = cs[i].b, cur = start;
        do {
            corner key = {cs[i].v, cur, 0};
            corner *f = bsearch(&key, cs + i, len, sizeof *cs, cmp_corner);
            if (!f) break;
            cur = f->c;
            steps++;
        } while (cur != start && steps <= len);
        if (cur != start || steps != len) {
            if (r->vertex_manifold)
                snprintf(r->problem, sizeof r->problem, "vertex %u is not manifold (%zu corners, fan of %zu)",
                         (unsigned)cs[i].v, len, steps);
            r->vertex_manifold = 0;
        }
        i = j;
    }
    for (size_t v = 0; v < nv; v++) {
        if (!used[v]) {
            if (r->all_referenced) snprintf(r->problem, sizeof r->problem, "vertex %zu unused", v);
            r->all_referenced = 0;
            continue;
        }
        if (find_root(parent, v) == v) r->components++;
        if (m->normals) {
            const float *n = m->normals + 3 * v;
            double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
            double fl = sqrt(fn[3 * v] * fn[3 * v] + fn[3 * v + 1] * fn[3 * v + 1] + fn[3 * v + 2] * fn[3 * v + 2]);
            double cosang = fl > 0 ? (n[0] * fn[3 * v] + n[1] * fn[3 * v + 1] + n[2] * fn[3 * v + 2]) / (len * fl) : 1;
            /* at creases and thin necks the field's normal may lean far from
             * the faces' (the mesh is piecewise linear); never the other way */
            if (!(cosang > 0)) r->normals_away++;
            if (fabs(len - 1.0) > 1e-3) {
                if (r->normals_ok)
                    snprintf(r->problem, sizeof r->problem, "vertex %zu normal bad (length %g, cos %g)", v, len, cosang);
                r->normals_ok = 0;
            }
        }
    }
out:
    free(e);
    free(cs);
    free(parent);
    free(used);
    free(fn);
    return r->closed && r->edge_manifold && r->vertex_manifold && r->no_degenerate && r->all_referenced &&
           r->normals_ok && r->volume > 0;
}

size_t mc_cavities(const jm_mesh *m, size_t *out_components)
{
    size_t nv = m->vertex_count, nt = m->triangle_count, cavities = 0, comps = 0;
    size_t *parent = malloc((nv ? nv : 1) * sizeof *parent);
    double *vol = calloc(nv ? nv : 1, sizeof *vol);
    if (!parent || !vol) {
        free(parent);
        free(vol);
        return (size_t)-1;
    }
    for (size_t v = 0; v < nv; v++) parent[v] = v;
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *i = m->indices + 3 * t;
        parent[find_root(parent, i[0])] = find_root(parent, i[1]);
        parent[find_root(parent, i[1])] = find_root(parent, i[2]);
    }
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *i = m->indices + 3 * t;
        const float *a = m->positions + 3 * i[0], *b = m->positions + 3 * i[1], *c = m->positions + 3 * i[2];
        double d = (double)a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) -
                   (double)a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
                   (double)a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0]);
        vol[find_root(parent, i[0])] += d / 6.0;
    }
    for (size_t t = 0; t < nt; t++) { /* each root once: mark by its first triangle */
        size_t r = find_root(parent, m->indices[3 * t]);
        if (parent[r] == r && vol[r] == vol[r]) {
            comps++;
            if (vol[r] < 0) cavities++;
            vol[r] = NAN; /* counted */
        }
    }
    free(parent);
    free(vol);
    if (out_components) *out_components = comps;
    return cavities;
}

/* Crossings of the ray from o along d (d = (1, e1, e2), tilted off every
 * axis so that it misses edges and vertices of lattice meshes) with the
 * triangle a b c (Moller-Trumbore, in double). */
static int ray_hits(const double o[3], const double d[3], const float *a, const float *b, const float *c)
{
    double e1[3], e2[3], p[3], t[3], q[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)b[k] - a[k];
        e2[k] = (double)c[k] - a[k];
        t[k] = o[k] - a[k];
    }
    p[0] = d[1] * e2[2] - d[2] * e2[1];
    p[1] = d[2] * e2[0] - d[0] * e2[2];
    p[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0) return 0;
    double u = (t[0] * p[0] + t[1] * p[1] + t[2] * p[2]) / det;
    if (u < 0 || u > 1) return 0;
    q[0] = t[1] * e1[2] - t[2] * e1[1];
    q[1] = t[2] * e1[0] - t[0] * e1[2];
    q[2] = t[0] * e1[1] - t[1] * e1[0];
    double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    if (v < 0 || u + v > 1) return 0;
    return (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det > 0;
}

int mc_shell_check(const jm_mesh *m, mc_shells *out, mc_shell **list)
{
    memset(out, 0, sizeof *out);
    if (list) *list = NULL;
    size_t nv = m->vertex_count, nt = m->triangle_count;
    size_t *parent = malloc((nv ? nv : 1) * sizeof *parent), *comp = malloc((nv ? nv : 1) * sizeof *comp);
    size_t *tc = malloc((nt ? nt : 1) * sizeof *tc);
    /* per shell: volume, area, box (6), a vertex */
    double *sh = calloc(9 * (nv ? nv : 1), sizeof *sh);
    size_t *rep = malloc((nv ? nv : 1) * sizeof *rep);
    if (!parent || !comp || !tc || !sh || !rep) {
        free(parent), free(comp), free(tc), free(sh), free(rep);
        return 0;
    }
    for (size_t v = 0; v < nv; v++) parent[v] = v, comp[v] = SIZE_MAX;
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *i = m->indices + 3 * t;
        parent[find_root(parent, i[0])] = find_root(parent, i[1]);
        parent[find_root(parent, i[1])] = find_root(parent, i[2]);
    }
    size_t ns = 0;
    for (size_t t = 0; t < nt; t++) {
        size_t r = find_root(parent, m->indices[3 * t]);
        if (comp[r] == SIZE_MAX) {
            comp[r] = ns;
            rep[ns] = m->indices[3 * t];
            double *s = sh + 9 * ns;
            for (int k = 0; k < 3; k++) s[2 + k] = INFINITY, s[5 + k] = -INFINITY;
            ns++;
        }
        tc[t] = comp[r];
    }
    out->components = ns;
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *i = m->indices + 3 * t;
        const float *a = m->positions + 3 * i[0], *b = m->positions + 3 * i[1], *c = m->positions + 3 * i[2];
        double u[3], w[3], n[3];
        for (int k = 0; k < 3; k++) u[k] = (double)b[k] - a[k], w[k] = (double)c[k] - a[k];
        n[0] = u[1] * w[2] - u[2] * w[1];
        n[1] = u[2] * w[0] - u[0] * w[2];
        n[2] = u[0] * w[1] - u[1] * w[0];
        double *s = sh + 9 * tc[t];
        s[0] += ((double)a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) -
                 (double)a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
                 (double)a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0])) / 6.0;
        s[1] += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++) {
                const float x = m->positions[3 * i[j] + k];
                if (x < s[2 + k]) s[2 + k] = x;
                if (x > s[5 + k]) s[5 + k] = x;
            }
        if (m->normals)
            for (int j = 0; j < 3; j++) {
                const float *nr = m->normals + 3 * i[j];
                out->corners++;
                if (!(nr[0] * n[0] + nr[1] * n[1] + nr[2] * n[2] > 0)) out->corners_away++;
            }
    }
    const double d[3] = {1.0, 0.3183098861837907, 0.1414213562373095};
    mc_shell *L = list ? malloc((ns ? ns : 1) * sizeof *L) : NULL;
    if (list && !L) {
        free(parent), free(comp), free(tc), free(sh), free(rep);
        return 0;
    }
    for (size_t s = 0; s < ns; s++) {
        const double *bs = sh + 9 * s;
        out->volume += bs[0];
        if (bs[0] < 0) out->negative++;
        const float *p = m->positions + 3 * rep[s];
        const double o[3] = {p[0], p[1], p[2]};
        int inner = 0;
        for (size_t e = 0; e < ns && !inner; e++) {
            const double *be = sh + 9 * e;
            if (e == s || be[2] > bs[2] || be[3] > bs[3] || be[4] > bs[4] || be[5] < bs[5] || be[6] < bs[6] ||
                be[7] < bs[7])
                continue;
            size_t hits = 0;
            for (size_t t = 0; t < nt; t++) {
                if (tc[t] != e) continue;
                const uint32_t *i = m->indices + 3 * t;
                hits += (size_t)ray_hits(o, d, m->positions + 3 * i[0], m->positions + 3 * i[1], m->positions + 3 * i[2]);
            }
            inner = (int)(hits & 1);
        }
        if (L) {
            L[s].volume = bs[0];
            L[s].area = bs[1];
            for (int k = 0; k < 3; k++) L[s].lo[k] = bs[2 + k], L[s].hi[k] = bs[5 + k];
            L[s].inner = inner;
        }
        if (inner) {
            out->inner++;
            out->inner_area += bs[1];
            out->inner_volume += bs[0];
        }
    }
    free(parent), free(comp), free(tc), free(sh), free(rep);
    if (list) *list = L;
    return 1;
}

size_t mc_points_in_shell(const jm_mesh *m, size_t shell, const float *xyz, size_t n)
{
    size_t nv = m->vertex_count, nt = m->triangle_count, in = 0;
    size_t *parent = malloc((nv ? nv : 1) * sizeof *parent), *order = malloc((nv ? nv : 1) * sizeof *order);
    if (!parent || !order) {
        free(parent), free(order);
        return (size_t)-1;
    }
    for (size_t v = 0; v < nv; v++) parent[v] = v, order[v] = SIZE_MAX;
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *i = m->indices + 3 * t;
        parent[find_root(parent, i[0])] = find_root(parent, i[1]);
        parent[find_root(parent, i[1])] = find_root(parent, i[2]);
    }
    /* the shells numbered in the order of their first triangles */
    size_t ns = 0, root = SIZE_MAX;
    for (size_t t = 0; t < nt && root == SIZE_MAX; t++) {
        size_t r = find_root(parent, m->indices[3 * t]);
        if (order[r] == SIZE_MAX) order[r] = ns++;
        if (order[r] == shell) root = r;
    }
    const double d[3] = {1.0, 0.3183098861837907, 0.1414213562373095};
    for (size_t p = 0; p < n && root != SIZE_MAX; p++) {
        const double o[3] = {xyz[3 * p], xyz[3 * p + 1], xyz[3 * p + 2]};
        size_t hits = 0;
        for (size_t t = 0; t < nt; t++) {
            const uint32_t *i = m->indices + 3 * t;
            if (find_root(parent, i[0]) != root) continue;
            hits += (size_t)ray_hits(o, d, m->positions + 3 * i[0], m->positions + 3 * i[1], m->positions + 3 * i[2]);
        }
        in += hits & 1;
    }
    free(parent), free(order);
    return in;
}
