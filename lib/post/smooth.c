/* smooth.c - bounded Laplacian smoothing of a mesh: bumps of the particles' size removed, the surface kept within 0.46 r, every piece's volume restored. */
#include "post/smooth.h"
#include "post/pieces.h"

/*
 * Issue 31. Laplacian smoothing (Löschner et al. 2023, as splashsurf does it)
 * removes the SPH "orange peel" but is diffusion: left alone it also wears
 * away what is larger than a bump (a crest's round beads become horns, a
 * dense droplet shrinks to nothing, the outline pulls in by 2 radii).
 * Feature weights from the particles' neighbour counts slow it where the
 * particles are few, but a dense droplet's count looks like bulk fluid.
 * Here the smoothing is bounded instead: every vertex moves freely along
 * the surface, but its move along its raw normal stays within +-0.46 r, and
 * within a quarter of its piece's thickness 3 V / A where that is less (a
 * jet's column, a pair: smooth_steps.c). A bump of the particles' size (a
 * few tenths of r high) is smoothed away; a droplet, a crest, a thin neck
 * or a ripple taller than that keeps its shape, moved by at most 0.46 r,
 * whatever the particles' count says. Then every piece gets its raw
 * volume back by an offset along the raw normals within the same band
 * (smooth_volume.c): no piece can lose more than the band lets it; and no
 * triangle stays turned over (smooth_guard.c). The iterations are those of
 * plain Laplacian smoothing, run in fewer passes (smooth_plan.c); normals:
 * smooth_normals.c. --smooth-implicit replaces the steps by implicit ones
 * whose surface does not shimmer over a sequence (steady_steps below).
 */
/* the band's half width, in r: the most a vertex moves along its raw
 * normal. 0.46 r keeps the 99th percentile of the move below splashsurf's
 * smoothed mesh's on the seven real frames of ../shared (at 0.5 r a double
 * dam break splash frame moved 0.48 r against splashsurf's 0.46 r) while
 * its mesh stays smoother than splashsurf's on each (issue 31) */
#define SM_BAND 0.46f
#define SM_THIN 0.25 /* ... and at most this times its piece's thickness 3 V / A (a jet's column, a pair) */

/* The pieces: labels in vertex order (a root is the piece's smallest
 * vertex: the cavity pass's roots when it hands them over). */
static size_t label_pieces(jm_pool *pool, const jm_post_mesh *m, size_t nv, uint32_t *comp)
{
    const uint32_t *roots = m->roots;
    if (!roots) {
        jm_mesh_pieces(pool, comp, m->idx, nv, m->ni_lattice / 3);
        roots = comp;
    }
    size_t n = 0;
    for (size_t v = 0; v < nv; v++) comp[v] = roots[v] == v ? (uint32_t)n++ : comp[roots[v]];
    return n;
}

/* Each vertex's raw frame from the raw positions job->src (4 per vertex):
 * its unit fan normal n and -x0 . n, or 0 without a normal; per run the
 * volume sum (p - o) . A (smooth_volume.c) and the sum of |A|. */
JM_BODY void frame_task_body(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    const sm_runs *r = &job->runs;
    size_t kb = sm_lower_bound(job->f.big, job->f.nbig, chunk * SM_CH);
    for (uint32_t k = r->chunk_run[chunk]; k < r->chunk_run[chunk + 1]; k++) {
        const double *o = &job->origin[3 * (size_t)r->piece[k]];
        double vol = 0.0, area = 0.0;
        for (size_t v = r->first[k]; v < r->first[k + 1]; v++) {
            const v4f A = sm_fan_area(job, job->src, v, &kb), p = sm_load4(&job->src[4 * v]);
            const float l = sqrtf(sm_dot3(A, A));
            v4f n = {0.0f, 0.0f, 0.0f, 0.0f};
            if (l > 0.0f) {
                n = A / l;
                n[3] = -sm_dot3(p, n); /* so that t = (x, 1) . dir */
            }
            sm_store4(&job->dir[4 * v], n);
            vol += ((double)p[0] - o[0]) * A[0] + ((double)p[1] - o[1]) * A[1] + ((double)p[2] - o[2]) * A[2];
            area += l;
        }
        r->sum[SM_RUN_SUMS * k] = vol;
        r->sum[SM_RUN_SUMS * k + 1] = area;
    }
}
JM_KERNEL_AVX2(static, void, frame_task, frame_task_body, (void *arg, size_t chunk, int worker), (arg, chunk, worker))

/* The bounded smoothing's steps: c->smooth_iters iterations in super time
 * stepping cycles and plain steps (smooth_plan.c); the result in *a. */
static jm_status plain_steps(jm_mem *mem, jm_pool *pool, sm_job *job, float **pa, float **pb, const double *vol0,
                             double *work)
{
    float *tau = NULL;
    int cyc;
    const int nsteps = sm_plan(job->c->smooth_iters, mem, &tau, &cyc);
    if (nsteps < 0) return JM_E_OUT_OF_MEMORY;
    for (int it = 0; it < nsteps; it++) {
        job->tau = tau[it];
        /* the band after each plain step and each cycle; between cycles each
         * piece's volume first (its shrinkage adds up over several) */
        const int settled = sm_plan_settled(it, nsteps, cyc, job->c->smooth_iters);
        const int recentre = settled == 2 && sm_plan_settled(it + cyc, nsteps, cyc, job->c->smooth_iters) == 2;
        job->clamp = settled && !recentre;
        sm_run_swap(pool, job, sm_step_task, job, pa, pb);
        if (recentre) sm_recentre(pool, job, *pa, vol0, work);
    }
    jm_free(mem, tau, (size_t)(nsteps > 0 ? nsteps : 0) * sizeof *tau);
    return JM_OK;
}

/*
 * The steady smoothing (--smooth-implicit, issue 31): the same band and
 * volumes, but the surface moved by the cotangent Laplacian, whose result
 * does not hang on how the marching cubes cut it. Two passes of tangential
 * relaxation even the triangles; one backward Euler step of dt = N 0.275
 * h^2 (h the cube's edge) per 25 iterations (smooth_implicit.c); each
 * piece's volume restored before the band (a piece's uniform shrinkage
 * would otherwise take the band up), with one more tangential pass before
 * the last; then two plain bounded steps take off what the lattice left at
 * the scale of a cube. The band is a quarter narrower inward: the
 * outline of settled fluid (a tank's edges) then pulls in no more than
 * splashsurf's. Chosen on ../shared's seven real frames, the jittered
 * balls and the flicker (issue 31's notes): kappa 0.25 roughens the balls,
 * 0.30 raises the flicker of marching tetrahedra to the raw mesh's.
 */
#define STEADY_KAPPA 0.275
#define STEADY_PER 25 /* iterations per implicit step */
#define STEADY_BEFORE 2 /* tangential passes before the implicit steps */
#define STEADY_AFTER 1  /* ... and after the last (2 measured the same, 1 slightly steadier) */
#define STEADY_TAIL 2
#define STEADY_INWARD 0.75f
static jm_status steady_steps(jm_mem *mem, jm_pool *pool, jm_post_scratch *sc, sm_job *job, float **pa, float **pb,
                              const double *vol0, double *work)
{
    const int n = job->c->smooth_iters, outer = n < STEADY_PER ? 1 : (n + STEADY_PER / 2) / STEADY_PER;
    const float h = job->c->h, dt = (float)(n * STEADY_KAPPA * h * h / outer);
    job->band_in = STEADY_INWARD;
    sm_tangential(pool, job, pa, pb, STEADY_BEFORE);
    for (int o = 0; o < outer; o++) {
        jm_status st = sm_implicit_step(mem, pool, sc, job, *pa, *pb, dt);
        if (st != JM_OK) return st;
        float *t = *pa;
        *pa = *pb;
        *pb = t;
        if (o == outer - 1) sm_tangential(pool, job, pa, pb, STEADY_AFTER);
        sm_recentre(pool, job, *pa, vol0, work);
    }
    job->tau = 1.0f;
    job->clamp = 1;
    for (int i = 0; i < STEADY_TAIL; i++) sm_run_swap(pool, job, sm_step_task, job, pa, pb);
    return JM_OK;
}

/* The positions: c->smooth_iters iterations of bounded steps, then the
 * volume restoration, into m->pos; the result also in *out (4 per vertex). */
static jm_status smooth_positions(jm_mem *mem, jm_pool *pool, jm_post_scratch *sc, sm_job *job, const float **out)
{
    const size_t nv = job->nv;
    uint32_t *comp = sm_scratch(sc, mem, SB_COMP, nv * sizeof *comp);
    float *a = sm_scratch(sc, mem, SB_A, (nv + 1) * 4 * sizeof *a), *b = sm_scratch(sc, mem, SB_B, (nv + 1) * 4 * sizeof *b);
    job->dir = sm_scratch(sc, mem, SB_DIR, nv * 4 * sizeof *job->dir);
    uint32_t *odd = sm_scratch(sc, mem, SB_ODD, nv * sizeof *odd);
    if (!comp || !a || !b || !job->dir || !odd) return JM_E_OUT_OF_MEMORY;
    job->comp = comp;
    const size_t np = job->npieces = label_pieces(pool, job->m, nv, comp);
    /* per piece: origin 3, volume, thickness, work 4, then its band */
    double *origin = sm_scratch(sc, mem, SB_PIECE, np * (9 * sizeof *origin + sizeof(float)));
    if (!origin) return JM_E_OUT_OF_MEMORY;
    double *vol0 = origin + 3 * np, *thick = vol0 + np, *work = thick + np;
    float *band = (float *)(work + 4 * np);
    for (size_t v = 0, k = 0; v < nv && k < np; v++)
        if (comp[v] == k) { /* a piece's first vertex (the labels come in vertex order): its origin */
            for (int j = 0; j < 3; j++) origin[3 * k + j] = job->m->pos[3 * v + j];
            k++;
        }
    jm_status st = sm_runs_build(mem, comp, nv, job->nchunks, &job->runs);
    if (st != JM_OK) return st;

    /* the raw frame: positions (x, y, z, 1) with a -0 sentinel row (the
     * padding of the fans of 8), normals, the odd vertices (no or over 8
     * neighbours, or no normal), volumes and thicknesses */
    for (size_t v = 0; v < nv; v++)
        for (int j = 0; j < 4; j++) a[4 * v + j] = j < 3 ? job->m->pos[3 * v + j] : 1.0f;
    for (int j = 0; j < 4; j++) a[4 * nv + j] = b[4 * nv + j] = -0.0f;
    job->src = a;
    job->origin = origin;
    sm_run_ranges(pool, job->nchunks, frame_task, job);
    job->nodd = 0;
    for (size_t v = 0; v < nv; v++) {
        const float *d = &job->dir[4 * v];
        if (job->f.deg[v] - 1 >= 8 || (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f)) odd[job->nodd++] = (uint32_t)v;
    }
    job->odd = odd;
    sm_runs_total(&job->runs, 2, work, np);
    for (size_t k = 0; k < np; k++) {
        vol0[k] = work[2 * k] / 9.0;
        thick[k] = work[2 * k + 1] > 0.0 ? 9.0 * vol0[k] / work[2 * k + 1] : 0.0; /* 3 V / area: |A| sums 3 areas */
        band[k] = (float)fmin(SM_BAND * job->c->r, SM_THIN * fabs(thick[k]));
    }
    job->band = band;
    if (job->c->smooth_implicit) st = steady_steps(mem, pool, sc, job, &a, &b, vol0, work);
    else st = plain_steps(mem, pool, job, &a, &b, vol0, work);
    job->src = a;
    job->dst = b;
    if (st == JM_OK) sm_restore_volumes(pool, job, vol0, thick, work);
    if (st == JM_OK) st = sm_guard_folds(pool, job, b);
    if (st == JM_OK)
        for (size_t v = 0; v < nv; v++)
            for (int j = 0; j < 3; j++) job->m->pos[3 * v + j] = b[4 * v + j];
    *out = b;
    sm_runs_free(mem, &job->runs);
    return st;
}

jm_status jm_smooth_mesh(jm_mem *mem, jm_pool *pool, jm_post_scratch *sc, const jm_config *c, jm_post_mesh *m)
{
    const size_t nv = m->nv_lattice;
    if (nv == 0 || (c->smooth_iters == 0 && c->smooth_normal_iters == 0)) return JM_OK;
    /* as block.c: normals exist when output or needed for the UVs */
    const int want_nrm = c->normals || c->compensate || c->uv_mode == JM_UV_BOX || c->uv_mode == JM_UV_SPHERICAL;
    sm_job job = {.c = c, .m = m, .mem = mem, .nv = nv, .nchunks = (nv + SM_CH - 1) / SM_CH, .band_in = 1.0f};
    jm_status st = sm_fans_build(mem, pool, sc, m, &job.f);
    const float *pos = NULL; /* the smoothed positions, 4 per vertex */
    if (st == JM_OK && c->smooth_iters > 0) st = smooth_positions(mem, pool, sc, &job, &pos);
    if (st == JM_OK) st = sm_normals(mem, pool, sc, &job, pos, want_nrm);
    return st;
}
