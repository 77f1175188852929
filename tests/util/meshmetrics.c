/* meshmetrics.c - figures of a mesh against a reference: smoothness, distance, pieces' volume and roundness, normals. */
#include "meshmetrics.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../cli/bench/mesh_distance.h"
#include "../../lib/core/sym3.h"

#define DEG (180.0 / M_PI)

/* ---- reading */

typedef struct fbuf {
    float *p;
    size_t n, cap;
} fbuf;

static int fpush(fbuf *b, float x)
{
    if (b->n == b->cap) {
        size_t nc = b->cap ? 2 * b->cap : 4096;
        float *q = realloc(b->p, nc * sizeof *q);
        if (!q) return -1;
        b->p = q;
        b->cap = nc;
    }
    b->p[b->n++] = x;
    return 0;
}

/* One corner of an f line: the vertex index (0-based) and the normal's, or -1. */
static int corner(char **s, long nv, long nn, long *v, long *n)
{
    char *e;
    *v = strtol(*s, &e, 10);
    if (e == *s) return 0;
    *n = -1;
    if (*e == '/') {
        e++;
        if (*e != '/') strtol(e, &e, 10); /* the texture coordinate */
        if (*e == '/') {
            e++;
            *n = strtol(e, &e, 10);
            *n = *n < 0 ? nn + *n : *n - 1;
        }
    }
    *v = *v < 0 ? nv + *v : *v - 1;
    *s = e;
    return 1;
}

int mm_read_obj(const char *path, mm_mesh *m, char *err, size_t errlen)
{
    memset(m, 0, sizeof *m);
    FILE *f = fopen(path, "r");
    if (!f) {
        snprintf(err, errlen, "%s: cannot open", path);
        return -1;
    }
    fbuf v = {0}, vn = {0};
    uint32_t *idx = NULL;
    long *nidx = NULL; /* per corner its normal */
    size_t ni = 0, icap = 0, line = 0;
    char buf[4096];
    int bad = 0;
    while (!bad && fgets(buf, sizeof buf, f)) {
        line++;
        char *s = buf;
        if (s[0] == 'v' && (s[1] == ' ' || s[1] == 'n')) {
            fbuf *b = s[1] == 'n' ? &vn : &v;
            s += 2;
            for (int k = 0; k < 3 && !bad; k++) {
                char *e;
                float x = strtof(s, &e);
                if (e == s) bad = 1;
                else bad = fpush(b, x) != 0, s = e;
            }
        } else if (s[0] == 'f' && s[1] == ' ') {
            s += 2;
            long c[3], cn[3], k = 0;
            while (!bad && corner(&s, (long)(v.n / 3), (long)(vn.n / 3), &c[k < 2 ? k : 2], &cn[k < 2 ? k : 2])) {
                if (c[k < 2 ? k : 2] < 0 || c[k < 2 ? k : 2] >= (long)(v.n / 3)) bad = 1;
                if (++k < 3) continue;
                if (ni + 3 > icap) {
                    icap = icap ? 2 * icap : 3 * 4096;
                    uint32_t *q = realloc(idx, icap * sizeof *q);
                    long *qn = realloc(nidx, icap * sizeof *qn);
                    if (q) idx = q;
                    if (qn) nidx = qn;
                    if (!q || !qn) bad = 1;
                }
                if (bad) break;
                for (int j = 0; j < 3; j++) idx[ni + j] = (uint32_t)c[j], nidx[ni + j] = cn[j];
                ni += 3;
                c[1] = c[2], cn[1] = cn[2]; /* a polygon: a fan about its first corner */
            }
            if (k < 3) bad = 1;
        }
    }
    fclose(f);
    if (bad) {
        snprintf(err, errlen, "%s:%zu: cannot read this line", path, line);
        free(v.p), free(vn.p), free(idx), free(nidx);
        return -1;
    }
    m->pos = v.p;
    m->nv = v.n / 3;
    m->idx = idx;
    m->nt = ni / 3;
    m->owned = 1;
    if (vn.n > 0 && m->nv > 0) {
        m->nrm = calloc(3 * m->nv, sizeof *m->nrm);
        for (size_t i = 0; m->nrm && i < ni; i++)
            if (nidx[i] >= 0 && nidx[i] < (long)(vn.n / 3))
                memcpy(&m->nrm[3 * (size_t)idx[i]], &vn.p[3 * nidx[i]], 3 * sizeof(float));
    }
    free(vn.p);
    free(nidx);
    return 0;
}

void mm_mesh_free(mm_mesh *m)
{
    if (m->owned) free(m->pos), free(m->nrm), free(m->idx);
    memset(m, 0, sizeof *m);
}

/* ---- basic sums */

static void tri(const mm_mesh *m, size_t t, double a[3], double b[3], double c[3])
{
    for (int i = 0; i < 3; i++) {
        a[i] = m->pos[3 * (size_t)m->idx[3 * t] + i];
        b[i] = m->pos[3 * (size_t)m->idx[3 * t + 1] + i];
        c[i] = m->pos[3 * (size_t)m->idx[3 * t + 2] + i];
    }
}

static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* Twice the triangle's area vector. */
static void tri_normal(const mm_mesh *m, size_t t, double n[3])
{
    double a[3], b[3], c[3], e1[3], e2[3];
    tri(m, t, a, b, c);
    for (int i = 0; i < 3; i++) e1[i] = b[i] - a[i], e2[i] = c[i] - a[i];
    cross(e1, e2, n);
}

static double tri_volume(const mm_mesh *m, size_t t)
{
    double a[3], b[3], c[3], bc[3];
    tri(m, t, a, b, c);
    cross(b, c, bc);
    return (a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2]) / 6.0;
}

double mm_volume(const mm_mesh *m)
{
    double v = 0;
    for (size_t t = 0; t < m->nt; t++) v += tri_volume(m, t);
    return v;
}

double mm_area(const mm_mesh *m)
{
    double s = 0;
    for (size_t t = 0; t < m->nt; t++) {
        double n[3];
        tri_normal(m, t, n);
        s += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    return s;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The q-quantile of the n values (sorted in place). */
static double quantile(double *v, size_t n, double q)
{
    if (n == 0) return 0;
    qsort(v, n, sizeof *v, cmp_d);
    size_t i = (size_t)(q * (double)(n - 1) + 0.5);
    return v[i < n ? i : n - 1];
}

/* ---- pieces */

static uint32_t find(uint32_t *par, uint32_t v)
{
    while (par[v] != v) v = par[v] = par[par[v]];
    return v;
}

size_t mm_pieces(const mm_mesh *m, mm_piece **out, uint32_t **labp)
{
    uint32_t *par = malloc((m->nv + 1) * sizeof *par), *lab = malloc((m->nv + 1) * sizeof *lab);
    size_t np = 0;
    *out = NULL;
    if (!par || !lab) goto done;
    for (size_t v = 0; v < m->nv; v++) par[v] = (uint32_t)v;
    for (size_t t = 0; t < m->nt; t++)
        for (int k = 1; k < 3; k++) {
            uint32_t a = find(par, m->idx[3 * t]), b = find(par, m->idx[3 * t + k]);
            if (a != b) par[a > b ? a : b] = a < b ? a : b;
        }
    for (size_t v = 0; v < m->nv; v++) {
        uint32_t r = find(par, (uint32_t)v);
        lab[v] = r == v ? (uint32_t)np++ : lab[r];
    }
    mm_piece *p = calloc(np + 1, sizeof *p);
    double(*mom)[6] = calloc(np + 1, sizeof *mom);
    if (!p || !mom) {
        free(p), free(mom);
        np = 0;
        goto done;
    }
    for (size_t v = 0; v < m->nv; v++) p[lab[v]].nv++;
    /* area, volume and the area-weighted centroid, then the second moments
     * of the triangles' centroids about it: enough for the proportions */
    for (size_t t = 0; t < m->nt; t++) {
        mm_piece *q = &p[lab[m->idx[3 * t]]];
        double n[3], a[3], b[3], c[3];
        tri_normal(m, t, n);
        tri(m, t, a, b, c);
        double ar = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        q->area += ar;
        q->volume += tri_volume(m, t);
        for (int i = 0; i < 3; i++) q->c[i] += ar * (a[i] + b[i] + c[i]) / 3.0;
    }
    for (size_t k = 0; k < np; k++)
        for (int i = 0; i < 3; i++) p[k].c[i] = p[k].area > 0 ? p[k].c[i] / p[k].area : 0;
    for (size_t t = 0; t < m->nt; t++) {
        mm_piece *q = &p[lab[m->idx[3 * t]]];
        double n[3], a[3], b[3], c[3], d[3];
        tri_normal(m, t, n);
        tri(m, t, a, b, c);
        double ar = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), *M = mom[q - p];
        for (int i = 0; i < 3; i++) d[i] = (a[i] + b[i] + c[i]) / 3.0 - q->c[i];
        M[0] += ar * d[0] * d[0], M[1] += ar * d[0] * d[1], M[2] += ar * d[0] * d[2];
        M[3] += ar * d[1] * d[1], M[4] += ar * d[1] * d[2], M[5] += ar * d[2] * d[2];
    }
    for (size_t k = 0; k < np; k++) {
        double val[3], vec[9], a = p[k].area > 0 ? p[k].area : 1;
        for (int i = 0; i < 6; i++) mom[k][i] /= a;
        jm_sym3_eigen(mom[k], val, vec);
        for (int i = 0; i < 3; i++) p[k].ext[i] = sqrt(val[i] > 0 ? val[i] : 0);
        p[k].roundness = p[k].ext[0] > 0 ? p[k].ext[2] / p[k].ext[0] : 0;
    }
    free(mom);
    *out = p;
done:
    free(par);
    if (labp && *out) *labp = lab;
    else free(lab);
    return np;
}

/* ---- smoothness */

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

void mm_dihedral(const mm_mesh *m, double *mean, double *p95)
{
    *mean = *p95 = 0;
    /* every edge's key (low vertex, high vertex) with its triangle, sorted:
     * the two triangles of an edge end up side by side */
    uint64_t(*e)[2] = malloc(3 * m->nt * sizeof *e);
    double *nrm = malloc(3 * m->nt * sizeof *nrm), *ang = malloc(3 * m->nt * sizeof *ang);
    if (!e || !nrm || !ang) goto out;
    for (size_t t = 0; t < m->nt; t++) {
        double *n = &nrm[3 * t];
        tri_normal(m, t, n);
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int i = 0; i < 3; i++) n[i] = l > 0 ? n[i] / l : 0;
        for (int k = 0; k < 3; k++) {
            uint64_t a = m->idx[3 * t + k], b = m->idx[3 * t + (k + 1) % 3];
            e[3 * t + k][0] = a < b ? a << 32 | b : b << 32 | a;
            e[3 * t + k][1] = t;
        }
    }
    qsort(e, 3 * m->nt, sizeof *e, cmp_u64);
    size_t na = 0;
    double sum = 0;
    for (size_t i = 0; i < 3 * m->nt;) {
        size_t j = i + 1;
        while (j < 3 * m->nt && e[j][0] == e[i][0]) j++;
        if (j == i + 2) {
            const double *a = &nrm[3 * e[i][1]], *b = &nrm[3 * e[i + 1][1]];
            double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            if ((a[0] != 0 || a[1] != 0 || a[2] != 0) && (b[0] != 0 || b[1] != 0 || b[2] != 0)) {
                ang[na] = acos(d > 1 ? 1 : (d < -1 ? -1 : d)) * DEG;
                sum += ang[na++];
            }
        }
        i = j;
    }
    *mean = na ? sum / (double)na : 0;
    *p95 = quantile(ang, na, 0.95);
out:
    free(e), free(nrm), free(ang);
}

/* ---- distance */

void mm_distances(const mm_mesh *m, const mm_mesh *ref, double *p50, double *p99, double *max)
{
    *p50 = *p99 = *max = 0;
    md_grid *g = md_build(ref->pos, ref->idx, ref->nt, 0);
    double *d = malloc((m->nv + 1) * sizeof *d);
    if (g && d) {
        for (size_t v = 0; v < m->nv; v++) {
            double p[3] = {m->pos[3 * v], m->pos[3 * v + 1], m->pos[3 * v + 2]};
            d[v] = md_distance(g, p, INFINITY);
            if (d[v] > *max) *max = d[v];
        }
        *p99 = quantile(d, m->nv, 0.99);
        *p50 = quantile(d, m->nv, 0.50);
    }
    free(d);
    md_free(g);
}

double mm_bbox_pull(const mm_mesh *ref, const mm_mesh *m)
{
    double lo[2][3], hi[2][3], pull = 0;
    const mm_mesh *ms[2] = {ref, m};
    for (int k = 0; k < 2; k++) {
        for (int a = 0; a < 3; a++) lo[k][a] = INFINITY, hi[k][a] = -INFINITY;
        for (size_t t = 0; t < ms[k]->nt; t++) /* referenced vertices only */
            for (int j = 0; j < 3; j++)
                for (int a = 0; a < 3; a++) {
                    double x = ms[k]->pos[3 * (size_t)ms[k]->idx[3 * t + j] + a];
                    lo[k][a] = x < lo[k][a] ? x : lo[k][a];
                    hi[k][a] = x > hi[k][a] ? x : hi[k][a];
                }
    }
    for (int a = 0; a < 3; a++) {
        if (lo[1][a] - lo[0][a] > pull) pull = lo[1][a] - lo[0][a];
        if (hi[0][a] - hi[1][a] > pull) pull = hi[0][a] - hi[1][a];
    }
    return pull;
}

/* ---- normals */

/* Each vertex's fan normal: the sum of its triangles' area vectors. */
static double *fan_normals(const mm_mesh *m)
{
    double *f = calloc(3 * m->nv + 1, sizeof *f);
    if (!f) return NULL;
    for (size_t t = 0; t < m->nt; t++) {
        double n[3];
        tri_normal(m, t, n);
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++) f[3 * (size_t)m->idx[3 * t + k] + i] += n[i];
    }
    return f;
}

static double angle(const double a[3], const double b[3])
{
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    if (!(la > 0 && lb > 0)) return 0;
    double d = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
    return acos(d > 1 ? 1 : (d < -1 ? -1 : d)) * DEG;
}

void mm_normals(const mm_mesh *m, double *p95, double *away)
{
    *p95 = *away = 0;
    if (!m->nrm) return;
    double *f = fan_normals(m), *a = malloc((m->nv + 1) * sizeof *a);
    size_t n = 0, bad = 0;
    if (f && a)
        for (size_t v = 0; v < m->nv; v++) {
            double nv[3] = {m->nrm[3 * v], m->nrm[3 * v + 1], m->nrm[3 * v + 2]};
            if (f[3 * v] == 0 && f[3 * v + 1] == 0 && f[3 * v + 2] == 0) continue; /* unreferenced */
            a[n] = angle(nv, &f[3 * v]);
            bad += a[n++] > 90;
        }
    *away = n ? (double)bad / (double)n : 0;
    *p95 = quantile(a, n, 0.95);
    free(f), free(a);
}

void mm_sphere(const mm_mesh *m, const uint32_t *lab, uint32_t which, double *sd, double *p95)
{
    double c[3] = {0, 0, 0}, s = 0, s2 = 0;
    size_t n = 0;
    *sd = *p95 = 0;
    for (size_t v = 0; v < m->nv; v++) {
        if (lab && lab[v] != which) continue;
        for (int i = 0; i < 3; i++) c[i] += m->pos[3 * v + i];
        n++;
    }
    if (n == 0) return;
    for (int i = 0; i < 3; i++) c[i] /= (double)n;
    double *f = m->nrm ? NULL : fan_normals(m), *a = malloc(n * sizeof *a);
    if (!a || (!m->nrm && !f)) goto out;
    n = 0;
    for (size_t v = 0; v < m->nv; v++) {
        if (lab && lab[v] != which) continue;
        double d[3], nv[3];
        for (int i = 0; i < 3; i++) d[i] = m->pos[3 * v + i] - c[i], nv[i] = m->nrm ? m->nrm[3 * v + i] : f[3 * v + i];
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        s += l, s2 += l * l;
        a[n++] = angle(d, nv);
    }
    double mean = s / (double)n;
    *sd = sqrt(fmax(0, s2 / (double)n - mean * mean));
    *p95 = quantile(a, n, 0.95);
out:
    free(a), free(f);
}

/* ---- matching pieces */

void mm_match_pieces(const mm_piece *ref, size_t nref, const mm_piece *p, size_t np, double min_dist, mm_match *o)
{
    memset(o, 0, sizeof *o);
    o->min_volume = o->min_round = INFINITY;
    unsigned char *used = calloc(np + 1, 1);
    if (!used) return;
    for (size_t k = 0; k < np; k++) o->pieces += p[k].volume > 0;
    for (size_t i = 0; i < nref; i++) {
        if (!(ref[i].volume > 0)) continue;
        o->ref_pieces++;
        double lim = 2.0 * ref[i].ext[0] > min_dist ? 2.0 * ref[i].ext[0] : min_dist, best = lim;
        size_t bk = np;
        for (size_t k = 0; k < np; k++) {
            if (!(p[k].volume > 0)) continue;
            double d = sqrt((p[k].c[0] - ref[i].c[0]) * (p[k].c[0] - ref[i].c[0]) +
                            (p[k].c[1] - ref[i].c[1]) * (p[k].c[1] - ref[i].c[1]) +
                            (p[k].c[2] - ref[i].c[2]) * (p[k].c[2] - ref[i].c[2]));
            if (d < best) best = d, bk = k;
        }
        if (bk == np) {
            o->lost++;
            continue;
        }
        used[bk] = 1;
        double q = p[bk].volume / ref[i].volume, rr = ref[i].roundness > 0 ? p[bk].roundness / ref[i].roundness : 1;
        o->under85 += q < 0.85;
        if (q < o->min_volume) {
            o->min_volume = q;
            memcpy(o->worst_c, ref[i].c, sizeof o->worst_c);
        }
        if (rr < o->min_round) {
            o->min_round = rr;
            memcpy(o->round_c, ref[i].c, sizeof o->round_c);
            o->round_ref = ref[i].roundness;
            o->round_m = p[bk].roundness;
        }
    }
    for (size_t k = 0; k < np; k++) o->extra += p[k].volume > 0 && !used[k];
    if (o->min_volume == INFINITY) o->min_volume = o->min_round = 1;
    free(used);
}
