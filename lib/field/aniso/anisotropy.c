/* anisotropy.c - Yu-Turk anisotropic SPH kernels: per-particle smoothed centres and kernel matrices, and the kernels each block looks at. */
#include "field/aniso/anisotropy.h"
#include "field/aniso/aniso_moments.h"
#include "core/sym3.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])
#define AN(g, i) (&(g)->an[JM_AN_STRIDE * (size_t)(i)])

/* Yu & Turk, "Reconstructing surfaces of particle-based fluids using
 * anisotropic kernels", ACM TOG 32(1), 2013, section 3, with these changes
 * (see jetmesh.h, "Anisotropic kernels"):
 * - centres: the paper's x + lambda (mean - x) pulls every particle of a flat
 *   free surface inward by lambda times the drift of a half-ball's weighted
 *   mean, b = JM_AN_DRIFT r_n (sum w - 1) / sum w (0.32 r_n for a continuous
 *   half-ball, less with the particle's own weight): the surface would shrink
 *   by about a particle radius. Only the part of the offset beyond b moves
 *   the centre, so flat and gently curved surfaces stay put while particles
 *   standing out of them (lattice corners, ridges, tips) are pulled in.
 *   Droplets and small clusters (few particles within the support) do not
 *   move, and single particles and pairs keep the sphere: a sheet nearby
 *   would pull them in and shape them (aniso_shape.c).
 * - axes from the covariance's eigenvalues (as the paper), held back where
 *   flattening opens air pockets, thins a sheet or shapes a droplet by its
 *   neighbours (aniso_shape.c), scaled to a geometric mean of k_s instead of
 *   by the paper's absolute k_s (a constant tuned to one particle spacing):
 *   every kernel covers the volume of the isotropic one times k_s^3, bulk
 *   kernels keep the isotropic size whatever the spacing, and the longest
 *   axis is at most k_s k_r^(2/3) h.
 * - fewer than N_eps neighbours: the isotropic kernel scaled by k_n.
 * amp = V h^3 det G keeps each kernel's integral that of the isotropic one. */
#define JM_AN_DRIFT 0.27

/* the weighted mean of the neighbourhood (relative to the particle) and its
 * covariance; 1 if the covariance sets the axes (enough neighbours) */
static int an_cov(const jm_config *c, const jm_an_acc *a, double mean[3], double C[6])
{
    mean[0] = mean[1] = mean[2] = 0.0;
    if (a->w > 0.0)
        for (int k = 0; k < 3; k++) mean[k] = a->s[k] / a->w;
    if (!(a->count >= c->an_neps && a->w > 0.0)) return 0;
    C[0] = a->ss[0] / a->w - mean[0] * mean[0];
    C[1] = a->ss[1] / a->w - mean[0] * mean[1];
    C[2] = a->ss[2] / a->w - mean[0] * mean[2];
    C[3] = a->ss[3] / a->w - mean[1] * mean[1];
    C[4] = a->ss[4] / a->w - mean[1] * mean[2];
    C[5] = a->ss[5] / a->w - mean[2] * mean[2];
    return 1;
}

/* the kernel from the mean and, where an_cov returned 1, the covariance's
 * eigenvalues (descending) and eigenvectors (NULL otherwise) */
static void an_kernel(const jm_config *c, const float xi[3], const jm_an_acc *a, const double mean[3],
                      const double *val, const double *vec, float V, float out[JM_AN_STRIDE])
{
    double s[3], R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double mw = jm_an_move_weight(a->near - 1.0);
    double ml = sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]);
    double drift = a->w > 0.0 ? JM_AN_DRIFT * c->an_radius * (a->w - 1.0) / a->w : 0.0;
    double move = ml > drift ? mw * c->an_lambda * (ml - drift) / ml : 0.0;
    for (int k = 0; k < 3; k++) out[k] = (float)(xi[k] + move * mean[k]);
    s[0] = s[1] = s[2] = c->an_kn;
    if (val && val[0] > 0.0) {
        jm_an_axes(c, val, jm_an_shape_weight(a->near - 1.0), s);
        memcpy(R, vec, sizeof R);
        jm_an_rim(c, R, mean, s);
    }
    /* M = R diag(1 / (h s_k)^2) R^T; box half-side along axis a:
     * 2 sqrt((M^-1)_aa) = 2 h sqrt(sum_k s_k^2 R_ak^2) */
    const double h = c->sph_h;
    double inv2[3], M[6] = {0, 0, 0, 0, 0, 0};
    for (int k = 0; k < 3; k++) inv2[k] = 1.0 / (h * h * s[k] * s[k]);
    static const int ij[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
    for (int e = 0; e < 6; e++)
        for (int k = 0; k < 3; k++) M[e] += R[3 * ij[e][0] + k] * R[3 * ij[e][1] + k] * inv2[k];
    for (int e = 0; e < 6; e++) out[3 + e] = (float)M[e];
    out[9] = (float)((double)V / (s[0] * s[1] * s[2]));
    for (int ax = 0; ax < 3; ax++) {
        double e2 = 0.0;
        for (int k = 0; k < 3; k++) e2 += s[k] * s[k] * R[3 * ax + k] * R[3 * ax + k];
        /* a hair wider than the ellipsoid: float rounding of M */
        out[10 + ax] = (float)(2.0 * h * sqrt(e2) * (1.0 + 1e-5));
    }
    /* 1 / (h s_max), the square root of M's least eigenvalue, lowered by
     * 16 kappa u for the float rounding of M and of q (docs/culling.md, A.2) */
    const double smax = fmax(s[0], fmax(s[1], s[2])), smin = fmin(s[0], fmin(s[1], s[2]));
    const double kappa = (smax / smin) * (smax / smin);
    out[13] = (float)(1.0 / (h * smax) * (1.0 - 16.0 * kappa * 0x1p-24));
}

void jm_an_finish(const jm_config *c, const float xi[3], const jm_an_acc *a, float V, float out[JM_AN_STRIDE])
{
    double mean[3], C[6], val[3], vec[9];
    const int e = an_cov(c, a, mean, C);
    if (e) jm_sym3_eigen(C, val, vec);
    an_kernel(c, xi, a, mean, e ? val : NULL, e ? vec : NULL, V, out);
}

typedef struct an_job {
    jm_grid *g;
    const jm_config *c;
    jm_mem *mem;
    int range;       /* cells each side holding the neighbourhood */
    const float *X, *Y, *Z; /* the sorted particles' coordinates, one array each */
    float **soa;     /* per worker: the neighbourhood of a cell as x[], y[], z[] */
    size_t *soa_cap; /* per worker: floats per coordinate array */
    int failed;
} an_job;

/* The sorted particles [from, from + n) into the neighbourhood's arrays at to. */
static void copy_run(const an_job *job, float *xs, float *ys, float *zs, size_t to, uint32_t from, uint32_t n)
{
    if (!n) return;
    memcpy(xs + to, job->X + from, n * sizeof *xs);
    memcpy(ys + to, job->Y + from, n * sizeof *ys);
    memcpy(zs + to, job->Z + from, n * sizeof *zs);
}

/* The neighbourhoods of the particles of cell ci: the candidates of the
 * cells around are copied once into structure-of-arrays form (those in
 * reach, padded to 8 with far-away points), then the particles sum over
 * them (aniso_moments.h), two at a time. */
static void an_cell(void *arg, size_t ci, int worker)
{
    an_job *job = arg;
    jm_grid *g = job->g;
    const jm_config *c = job->c;
    const int32_t *cc = &g->cell_coord[3 * ci];
    const int rg = job->range;
    size_t m = 0;
    /* the cells around, found on the first pass (up to 7^3 kept) */
    uint32_t near[343];
    const int keep = 2 * rg + 1 <= 7;
    for (int pass = 0; pass < 2; pass++) {
        size_t t = 0;
        int e = 0;
        float *xs = job->soa[worker], *ys = xs + job->soa_cap[worker], *zs = ys + job->soa_cap[worker];
        /* pass 1 copies runs: cells whose particles follow each other in
         * the sorted arrays (neighbours along x, in key order) at once */
        size_t run_to = 0;
        uint32_t run_from = 0, run_n = 0;
        for (int dz = -rg; dz <= rg; dz++)
            for (int dy = -rg; dy <= rg; dy++)
                for (int dx = -rg; dx <= rg; dx++, e++) {
                    uint32_t nc = pass && keep ? near[e]
                                               : jm_grid_cell(g, (int64_t)cc[0] + dx, (int64_t)cc[1] + dy, (int64_t)cc[2] + dz);
                    if (keep) near[e] = nc;
                    if (nc == UINT32_MAX) continue;
                    const uint32_t j0 = g->cell_start[nc], k = g->cell_start[nc + 1] - j0;
                    if (pass == 1) {
                        if (run_n && j0 == run_from + run_n) {
                            run_n += k;
                        } else {
                            copy_run(job, xs, ys, zs, run_to, run_from, run_n);
                            run_to = t;
                            run_from = j0;
                            run_n = k;
                        }
                    }
                    t += k;
                }
        if (pass == 1) {
            copy_run(job, xs, ys, zs, run_to, run_from, run_n);
            float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (uint32_t i = g->cell_start[ci]; i < g->cell_start[ci + 1]; i++)
                for (int a = 0; a < 3; a++) {
                    lo[a] = fminf(lo[a], GP(g, i)[a]);
                    hi[a] = fmaxf(hi[a], GP(g, i)[a]);
                }
            t = m = jm_an_keep_in_reach(xs, ys, zs, m, lo, hi, c->an_radius * c->an_radius);
        }
        if (pass == 0) {
            m = t;
            size_t cap = (m + 7) & ~(size_t)7;
            if (cap > job->soa_cap[worker]) {
                float *b = jm_realloc(job->mem, job->soa[worker], 3 * job->soa_cap[worker] * sizeof *b,
                                      3 * cap * sizeof *b);
                if (!b) { job->failed = 1; return; }
                job->soa[worker] = b;
                job->soa_cap[worker] = cap;
            }
        } else {
            for (; t < ((m + 7) & ~(size_t)7); t++) xs[t] = ys[t] = zs[t] = 1e30f;
        }
    }
    const size_t cap = job->soa_cap[worker], groups = (m + 7) / 8;
    const float *xs = job->soa[worker], *ys = xs + cap, *zs = ys + cap;
    jm_an_radii rad = {c->an_radius * c->an_radius, 1.0f / c->an_radius, 0.0f, 0.0f};
    jm_an_near_radius(c, &rad.S2, &rad.invB);
    /* the particles not isolated, up to 8 at a time: their moments two at a
     * time, then the eigen-decompositions of their covariances together */
    uint32_t batch[8];
    int nb = 0;
    for (uint32_t i = g->cell_start[ci]; i <= g->cell_start[ci + 1]; i++) {
        const int last = i == g->cell_start[ci + 1];
        if (!last && g->isolated[i]) {
            jm_an_acc a;
            memset(&a, 0, sizeof a);
            a.w = 1.0; /* alone: the isotropic kernel where it is */
            a.near = 1.0;
            jm_an_finish(c, GP(g, i), &a, g->weight[i], AN(g, i));
            continue;
        }
        if (!last) batch[nb++] = i;
        if (nb < 8 && !last) continue;
        double sum[8][JM_AN_MOMENTS];
        for (int k = 0; k + 1 < nb; k += 2)
            jm_an_moments2(xs, ys, zs, groups, GP(g, batch[k]), GP(g, batch[k + 1]), &rad, sum[k], sum[k + 1]);
        if (nb & 1) jm_an_moments(xs, ys, zs, groups, GP(g, batch[nb - 1]), &rad, sum[nb - 1]);
        jm_an_acc acc[8];
        double mean[8][3], C[8][6], val[8][3], vec[8][9];
        int with[8], ne = 0;
        for (int k = 0; k < nb; k++) {
            acc[k].w = sum[k][0];
            for (int e = 0; e < 3; e++) acc[k].s[e] = sum[k][1 + e];
            for (int e = 0; e < 6; e++) acc[k].ss[e] = sum[k][4 + e];
            acc[k].count = (int)sum[k][10];
            acc[k].near = sum[k][11];
            with[k] = an_cov(c, &acc[k], mean[k], C[ne]) ? ne++ : -1;
        }
        jm_sym3_eigen_n(ne, (const double(*)[6])C, val, vec);
        for (int k = 0; k < nb; k++) {
            const int e = with[k];
            an_kernel(c, GP(g, batch[k]), &acc[k], mean[k], e >= 0 ? val[e] : NULL, e >= 0 ? vec[e] : NULL,
                      g->weight[batch[k]], AN(g, batch[k]));
        }
        nb = 0;
    }
}

void jm_aniso_free(jm_grid *g, jm_mem *mem)
{
    if (g->an) jm_free(mem, g->an, (g->n ? g->n : 1) * JM_AN_STRIDE * sizeof(float));
    if (g->an_cellbox) jm_free(mem, g->an_cellbox, (g->ncells ? g->ncells : 1) * 6 * sizeof(float));
    g->an = NULL;
    g->an_cellbox = NULL;
}

jm_status jm_aniso_build(jm_grid *g, jm_mem *mem, jm_pool *pool, const jm_config *c)
{
    g->an = jm_alloc(mem, (g->n ? g->n : 1) * JM_AN_STRIDE * sizeof(float));
    if (!g->an) return JM_E_OUT_OF_MEMORY;
    int nt = jm_pool_threads(pool);
    an_job job = {g, c, mem, (int)ceilf(c->an_radius * g->inv_cell), NULL, NULL, NULL, NULL, NULL, 0};
    if (job.range < 1) job.range = 1;
    const size_t np = g->n ? g->n : 1;
    float *xyz = jm_alloc(mem, 3 * np * sizeof *xyz);
    if (xyz) {
        for (size_t i = 0; i < g->n; i++) {
            xyz[i] = g->pos[3 * i];
            xyz[np + i] = g->pos[3 * i + 1];
            xyz[2 * np + i] = g->pos[3 * i + 2];
        }
        job.X = xyz;
        job.Y = xyz + np;
        job.Z = xyz + 2 * np;
    }
    job.soa = jm_calloc(mem, (size_t)nt, sizeof *job.soa);
    job.soa_cap = jm_calloc(mem, (size_t)nt, sizeof *job.soa_cap);
    if (xyz && job.soa && job.soa_cap) jm_pool_run(pool, g->ncells, 16, an_cell, &job);
    else job.failed = 1;
    if (xyz) jm_free(mem, xyz, 3 * np * sizeof *xyz);
    if (job.soa && job.soa_cap)
        for (int w = 0; w < nt; w++) jm_free(mem, job.soa[w], 3 * job.soa_cap[w] * sizeof(float));
    if (job.soa) jm_free(mem, job.soa, (size_t)nt * sizeof *job.soa);
    if (job.soa_cap) jm_free(mem, job.soa_cap, (size_t)nt * sizeof *job.soa_cap);
    if (job.failed) {
        jm_aniso_free(g, mem);
        return JM_E_OUT_OF_MEMORY;
    }
    /* the farthest any kernel's box reaches from its particle, and each
     * cell's union of its kernels' boxes, their ends formed as
     * jm_aniso_candidates forms them */
    g->an_cellbox = jm_alloc(mem, (g->ncells ? g->ncells : 1) * 6 * sizeof(float));
    if (!g->an_cellbox) {
        jm_aniso_free(g, mem);
        return JM_E_OUT_OF_MEMORY;
    }
    float reach = c->support;
    for (size_t ci = 0; ci < g->ncells; ci++) {
        float *cb = g->an_cellbox + 6 * ci;
        for (int k = 0; k < 3; k++) {
            cb[k] = INFINITY;
            cb[3 + k] = -INFINITY;
        }
        for (uint32_t i = g->cell_start[ci]; i < g->cell_start[ci + 1]; i++) {
            if (g->isolated[i]) continue;
            const float *a = AN(g, i), *x = GP(g, i);
            for (int k = 0; k < 3; k++) {
                const float r = fabsf(a[k] - x[k]) + a[10 + k];
                const float l = a[k] - a[10 + k], h = a[k] + a[10 + k];
                reach = r > reach ? r : reach;
                cb[k] = l < cb[k] ? l : cb[k];
                cb[3 + k] = h > cb[3 + k] ? h : cb[3 + k];
            }
        }
    }
    g->an_reach = reach * 1.0001f;
    return JM_OK;
}


int jm_aniso_candidates(const jm_grid *g, const jm_hood *hood, const float lo[3], const float hi[3], float margin,
                        jm_an_cand *out)
{
    const float x0 = lo[0] - margin, x1 = hi[0] + margin, y0 = lo[1] - margin, y1 = hi[1] + margin;
    const float z0 = lo[2] - margin, z1 = hi[2] + margin;
    if (hood->particles > out->cap) {
        uint32_t *b = jm_realloc_lasting(out->mem, out->idx, out->cap * sizeof *b, hood->particles * sizeof *b);
        if (!b) return 0;
        out->idx = b;
        out->cap = hood->particles;
    }
    size_t m = 0, k = 0;
    /* a cell whose kernels' box union misses the box holds no candidate
     * (each kernel's box lies within it, its ends the same floats) */
    for (int cz = 0; cz < hood->n[2]; cz++)
        for (int cy = 0; cy < hood->n[1]; cy++)
            for (int cx = 0; cx < hood->n[0]; cx++, k++) {
                if (hood->range[2 * k] == hood->range[2 * k + 1]) continue;
                const uint32_t ci = jm_grid_cell(g, hood->c0[0] + cx, hood->c0[1] + cy, hood->c0[2] + cz);
                const float *cb = g->an_cellbox + 6 * (size_t)ci;
                if (cb[3] < x0 || cb[0] > x1 || cb[4] < y0 || cb[1] > y1 || cb[5] < z0 || cb[2] > z1) continue;
                for (uint32_t p = hood->range[2 * k]; p < hood->range[2 * k + 1]; p++) {
                    const float *a = AN(g, p);
                    if (a[0] + a[10] < x0 || a[0] - a[10] > x1 || a[1] + a[11] < y0 || a[1] - a[11] > y1 ||
                        a[2] + a[12] < z0 || a[2] - a[12] > z1 || g->isolated[p])
                        continue;
                    out->idx[m++] = p;
                }
            }
    out->n = m;
    return 1;
}

void jm_aniso_gather(const jm_grid *g, const jm_an_cand *cand, const float lo[3], const float hi[3], jm_an_list *out)
{
    out->n = 0;
    for (size_t i = 0; i < cand->n; i++) {
        const uint32_t p = cand->idx[i];
        const float *a = AN(g, p);
        if (a[0] + a[10] < lo[0] || a[0] - a[10] > hi[0] || a[1] + a[11] < lo[1] || a[1] - a[11] > hi[1] ||
            a[2] + a[12] < lo[2] || a[2] - a[12] > hi[2])
            continue;
        if (out->n + 8 > out->cap) {
            size_t nc = out->cap ? out->cap * 2 : 1024;
            float *b = jm_realloc_lasting(out->mem, out->buf, 10 * out->cap * sizeof *b, 10 * nc * sizeof *b);
            if (!b) { out->n = SIZE_MAX; return; }
            out->buf = b;
            out->cap = nc;
        }
        float *b = out->buf + 10 * (out->n & ~(size_t)7) + (out->n & 7);
        for (int f = 0; f < 10; f++) b[8 * f] = a[f];
        out->n++;
    }
    /* pad the last group of 8 with weightless kernels far away */
    for (size_t m = out->n; m & 7; m++) {
        float *b = out->buf + 10 * (m & ~(size_t)7) + (m & 7);
        for (int f = 0; f < 10; f++) b[8 * f] = 0.0f;
        b[0] = b[8] = b[16] = 1e30f;
        b[24] = 1.0f; /* m00 */
    }
}
