/* smooth_implicit.c - the steady smoothing's step: (M + dt K) x = M x0 with the cotangent Laplacian K, by conjugate gradients. */
#include "post/smooth.h"
#include "core/lanes8.h"

/*
 * Issue 31. The bounded smoothing moves a vertex toward its neighbours'
 * mean; how far depends on how the marching cubes cut the surface there,
 * so the mesh of a translated input is no translated copy of the mesh (its
 * flicker is 2.4 times the raw mesh's). The cotangent Laplacian K with the
 * lumped mass M (a third of the fan's area) is the surface's own mean
 * curvature whatever the triangles (Meyer et al. 2003). One backward Euler
 * step of it (Desbrun et al. 1999), (M + dt K) x = M x0, damps a bump of
 * wavelength L by 1 / (1 + dt (2 pi / L)^2), free of the explicit steps'
 * limit on dt, which the marching cubes' slivers would make tiny. Jacobi-
 * preconditioned conjugate gradients, each coordinate its own, run a fixed
 * number of iterations from x0 (20; under 18 the flicker of marching
 * tetrahedra's meshes rises past the unsmoothed mesh's, issue 31):
 * the same work and the same bits every time. Every sum is per chunk (in
 * vertex order), the chunks' added in chunk order in double: the same for
 * any thread count.
 */
#define CG_ITERS 20

typedef struct cg_job {
    sm_job *job;
    float *w8;        /* per vertex 8 weights dt w aligned with its nb8 row, 0 in the padding */
    float *bw;        /* the big fans' weights, aligned with bnb */
    float *diag;      /* M + dt sum w; 0: the vertex stays */
    float *inv;       /* 1 / diag, 0 where it stays (Jacobi's preconditioner) */
    float *mass;
    const float *x0;  /* the start (4 per vertex) */
    float *x, *r, *p, *ap; /* 4 per vertex; p with a row of 0 at nv */
    double *part;     /* 4 per chunk: this pass's sums */
    v4f alpha, beta;
    float dt;
    int pass;         /* CG_START ... */
} cg_job;

/* Triangle (v, q, r) of positions P: half the cotangents of its angles at r
 * (the weight of edge v q) and at q (of edge v r); returns twice its area. */
JM_BODY float tri_cots(const float *P, size_t v, size_t q, size_t r, float *at_r, float *at_q)
{
    const v4f pv = sm_load4(&P[4 * v]), pq = sm_load4(&P[4 * q]), pr = sm_load4(&P[4 * r]);
    const v4f e1 = sm_xyz(pq - pv), e2 = sm_xyz(pr - pv), e3 = sm_xyz(pr - pq);
    const v4f c = __builtin_shufflevector(e1, e1, 1, 2, 0, 3) * __builtin_shufflevector(e2, e2, 2, 0, 1, 3) -
                  __builtin_shufflevector(e1, e1, 2, 0, 1, 3) * __builtin_shufflevector(e2, e2, 1, 2, 0, 3);
    const float a2 = sqrtf(sm_dot3(c, c)), h = a2 > 0.0f ? 0.5f / a2 : 0.0f;
    *at_r = h * sm_dot3(e2, e3);  /* (v - r) . (q - r) */
    *at_q = -h * sm_dot3(e1, e3); /* (v - q) . (r - q) */
    return a2;
}

/* Vertex v's fan of d triangles (v, q[i], r[i]; indices shifted left by
 * sh, padded to 8 with a sentinel index for d < 8): neighbour q[i]'s
 * weight, dt (cot at r[i] + cot at q[j] of the triangle j whose r[j] is
 * q[i]) / 2, into w[i]; its diagonal and mass. A fan of over FAN_MAX
 * triangles (none on a lattice mesh) stays put. */
#define FAN_MAX 64
JM_BODY void fan_weights(cg_job *g, size_t v, const uint32_t *q, const uint32_t *r, int sh, uint32_t d, float *w)
{
    float at_q[FAN_MAX], mass = 0.0f, sum = 0.0f;
    g->mass[v] = g->diag[v] = g->inv[v] = 0.0f;
    if (d == 0 || d > FAN_MAX) {
        for (uint32_t i = 0; i < d; i++) w[i] = 0.0f;
        return;
    }
    for (uint32_t i = 0; i < d; i++) mass += tri_cots(g->x0, v, q[i] >> sh, r[i] >> sh, &w[i], &at_q[i]) / 6.0f;
    if (d <= 8) { /* the row of 8 against each r[j], 8 lanes at once: the padding's weights are 0 */
        v8i qv, wq = {0, 0, 0, 0, 0, 0, 0, 0};
        memcpy(&qv, q, sizeof qv);
        for (uint32_t j = 0; j < d; j++) {
            int32_t a;
            memcpy(&a, &at_q[j], sizeof a);
            wq = (v8i)((v8f)wq + (v8f)((qv == (v8i){0} + (int32_t)r[j]) & a));
        }
        float add[8];
        memcpy(add, &wq, sizeof add);
        for (uint32_t i = 0; i < d; i++) w[i] += add[i];
    } else {
        for (uint32_t j = 0; j < d; j++)
            for (uint32_t i = 0; i < d; i++)
                if (q[i] == r[j]) {
                    w[i] += at_q[j];
                    break;
                }
    }
    for (uint32_t i = 0; i < d; i++) {
        w[i] *= g->dt;
        sum += w[i];
    }
    const float dg = mass + sum;
    g->mass[v] = mass;
    g->diag[v] = dg > 0.0f ? dg : 0.0f;
    g->inv[v] = dg > 0.0f ? 1.0f / dg : 0.0f;
}

/* The weights of one chunk's vertices (the positions x0). */
JM_BODY void weights_body(void *arg, size_t chunk, int worker)
{
    (void)worker;
    cg_job *g = arg;
    const sm_job *job = g->job;
    const size_t a = chunk * SM_CH, e = sm_chunk_end(job->nv, chunk);
    size_t kb = sm_lower_bound(job->f.big, job->f.nbig, a);
    for (size_t v = a; v < e; v++) {
        const uint32_t d = job->f.deg[v];
        float *w = &g->w8[8 * v];
        memset(w, 0, 8 * sizeof *w);
        if (d <= 8) {
            fan_weights(g, v, &job->f.nb8[8 * v], &job->f.nc8[8 * v], 1, d, w);
        } else {
            const uint32_t s = job->f.bstart[kb];
            fan_weights(g, v, &job->f.bnb[s], &job->f.bnc[s], 0, d, &g->bw[s]);
            kb++;
        }
    }
}
JM_KERNEL_AVX2(static, void, weights_task, weights_body, (void *arg, size_t chunk, int worker), (arg, chunk, worker))

/* (A y)_v = diag_v y_v - sum_i w_i y_(q_i), y 4 per vertex with a row of 0 at nv. */
JM_BODY v4f apply(const cg_job *g, const float *y, size_t v, size_t *kb)
{
    const sm_job *job = g->job;
    v4f s = {0.0f, 0.0f, 0.0f, 0.0f};
    if (job->f.deg[v] <= 8) {
        const uint32_t *q = &job->f.nb8[8 * v];
        const float *w = &g->w8[8 * v];
        for (int i = 0; i < 8; i++) s += w[i] * sm_load4(&y[2 * (size_t)q[i]]);
    } else {
        for (uint32_t i = job->f.bstart[*kb]; i < job->f.bstart[*kb + 1]; i++)
            s += g->bw[i] * sm_load4(&y[4 * (size_t)job->f.bnb[i]]);
        ++*kb;
    }
    return g->diag[v] * sm_load4(&y[4 * v]) - s;
}

static inline v4f precondition(const cg_job *g, v4f r, size_t v) { return g->inv[v] * r; }

/* The passes of the conjugate gradients, vertex by vertex; each returns
 * its share of the pass's sum. */
enum { CG_START, CG_AP, CG_UPDATE, CG_DIRECTION };

/* r = M x0 - A x0, p = r / diag, x = x0; sums r . p */
JM_BODY v4f start_vertex(cg_job *g, size_t v, size_t *kb)
{
    const v4f x = sm_load4(&g->x0[4 * v]);
    v4f r = g->mass[v] * x - apply(g, g->x0, v, kb);
    r[3] = 0.0f;
    if (g->inv[v] == 0.0f) r = (v4f){0.0f, 0.0f, 0.0f, 0.0f};
    const v4f z = precondition(g, r, v);
    sm_store4(&g->x[4 * v], x);
    sm_store4(&g->r[4 * v], r);
    sm_store4(&g->p[4 * v], z);
    return r * z;
}

/* ap = A p; sums p . ap */
JM_BODY v4f ap_vertex(cg_job *g, size_t v, size_t *kb)
{
    const v4f ap = apply(g, g->p, v, kb);
    sm_store4(&g->ap[4 * v], ap);
    return sm_load4(&g->p[4 * v]) * ap;
}

/* x += alpha p, r -= alpha ap; sums r . r / diag */
JM_BODY v4f update_vertex(cg_job *g, size_t v)
{
    const v4f p = sm_load4(&g->p[4 * v]);
    sm_store4(&g->x[4 * v], sm_load4(&g->x[4 * v]) + g->alpha * p);
    const v4f r = sm_load4(&g->r[4 * v]) - g->alpha * sm_load4(&g->ap[4 * v]);
    sm_store4(&g->r[4 * v], r);
    return r * precondition(g, r, v);
}

/* p = r / diag + beta p */
JM_BODY v4f direction_vertex(cg_job *g, size_t v)
{
    sm_store4(&g->p[4 * v], precondition(g, sm_load4(&g->r[4 * v]), v) + g->beta * sm_load4(&g->p[4 * v]));
    return (v4f){0.0f, 0.0f, 0.0f, 0.0f};
}

/* Pass g->pass over one chunk; its sum (in float, in vertex order) kept
 * in double for the chunk. */
JM_BODY void pass_body(void *arg, size_t chunk, int worker)
{
    (void)worker;
    cg_job *g = arg;
    const size_t a = chunk * SM_CH, e = sm_chunk_end(g->job->nv, chunk);
    size_t kb = sm_lower_bound(g->job->f.big, g->job->f.nbig, a);
    v4f sum = {0.0f, 0.0f, 0.0f, 0.0f};
    switch (g->pass) { /* the loop in each case: no branch per vertex */
    case CG_START: for (size_t v = a; v < e; v++) sum += start_vertex(g, v, &kb); break;
    case CG_AP: for (size_t v = a; v < e; v++) sum += ap_vertex(g, v, &kb); break;
    case CG_UPDATE: for (size_t v = a; v < e; v++) sum += update_vertex(g, v); break;
    default: for (size_t v = a; v < e; v++) sum += direction_vertex(g, v);
    }
    double *part = &g->part[4 * chunk];
    part[0] = sum[0], part[1] = sum[1], part[2] = sum[2];
}
JM_KERNEL_AVX2(static, void, pass_task, pass_body, (void *arg, size_t chunk, int worker), (arg, chunk, worker))

static void run_pass(jm_pool *pool, cg_job *g, int pass)
{
    g->pass = pass;
    sm_run_ranges(pool, g->job->nchunks, pass_task, g);
}

/* The chunks' sums, added in chunk order: 3 lanes. */
static v4f total(const cg_job *g)
{
    double s[3] = {0.0, 0.0, 0.0};
    for (size_t c = 0; c < g->job->nchunks; c++)
        for (int j = 0; j < 3; j++) s[j] += g->part[4 * c + j];
    return (v4f){(float)s[0], (float)s[1], (float)s[2], 0.0f};
}

static v4f ratio(v4f a, v4f b)
{
    v4f q = {0.0f, 0.0f, 0.0f, 0.0f};
    for (int j = 0; j < 3; j++) q[j] = b[j] > 0.0f ? a[j] / b[j] : 0.0f;
    return q;
}

jm_status sm_implicit_step(jm_mem *mem, jm_pool *pool, jm_post_scratch *sc, sm_job *job, const float *x0, float *out,
                           float dt)
{
    const size_t nv = job->nv, nfan = job->f.nfan, nc = job->nchunks;
    /* weights 8, diag, mass, 1 / diag per vertex, then the big fans' weights */
    float *w = sm_scratch(sc, mem, SB_IMPL_W, ((nv * 11) + nfan) * sizeof *w);
    /* r, p (with its row of 0), ap: 4 per vertex each; then the sums */
    float *vec = sm_scratch(sc, mem, SB_IMPL_V, (3 * nv + 1) * 4 * sizeof *vec + 4 * nc * sizeof(double) + 16);
    if (!w || !vec) return JM_E_OUT_OF_MEMORY;
    cg_job g = {.job = job, .w8 = w, .diag = w + 8 * nv, .mass = w + 9 * nv, .inv = w + 10 * nv, .bw = w + 11 * nv,
                .x0 = x0, .x = out, .r = vec, .p = vec + 4 * nv, .ap = vec + 8 * nv + 4, .dt = dt};
    g.part = (double *)(((uintptr_t)(vec + 12 * nv + 4) + 15) & ~(uintptr_t)15);
    memset(&g.p[4 * nv], 0, 4 * sizeof *g.p);
    sm_run_ranges(pool, nc, weights_task, &g);
    run_pass(pool, &g, CG_START);
    v4f rz = total(&g);
    for (int it = 0; it < CG_ITERS; it++) {
        run_pass(pool, &g, CG_AP);
        g.alpha = ratio(rz, total(&g));
        run_pass(pool, &g, CG_UPDATE);
        const v4f rz1 = total(&g);
        if (it + 1 == CG_ITERS) break;
        g.beta = ratio(rz1, rz);
        rz = rz1;
        run_pass(pool, &g, CG_DIRECTION);
    }
    return JM_OK; /* out's fourth lanes stay x0's 1: alpha's and p's are 0 */
}
