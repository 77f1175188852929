/* smooth_steps.c - one step of the bounded smoothing: each vertex to its neighbours' mean, its move along its raw normal kept within the band. */
#include "post/smooth.h"

/*
 * A step moves every vertex to the mean of its neighbours (Laplacian
 * smoothing with the full step, as splashsurf's weighted smoothing takes
 * in bulk fluid; Löschner et al. 2023), all at once from the previous
 * positions (Jacobi: no dependence on the order or the threads). Then,
 * after a whole super time stepping cycle and after each plain step
 * (within a cycle some modes are amplified: a clamp there would hang on
 * how the marching cubes cut the bumps, and the mesh of a translated input
 * would not be a translated copy, issue 31), t, the vertex's displacement
 * from its raw position along its raw unit normal, is clamped to the band
 * [-b, b] (b = 0.46 r, smooth.c): bumps of
 * the particles' size go, the surface stays within 0.46 r of where
 * the particles put it (a droplet, a crest, a ripple higher than that
 * keeps its shape). The move along the surface is free: it evens the
 * marching cubes' slivers.
 */

/* p moved back into the band [-bin, b] along its raw normal (bin = b but
 * for the steady smoothing, smooth.c): p + (clamp(t) - t) n, t = p . dir;
 * the fourth lane (1) stays. */
static inline v4f into_band(v4f p, v4f dir, float b, float bin)
{
    const float t = sm_move(p, dir)[0], c = t < -bin ? -bin : (t > b ? b : t);
    return p + (c - t) * sm_xyz(dir);
}

/* Vertex v the careful way: no neighbour or no raw normal (stays), a fan
 * of more than 8 (summed whole; its fourth lane set to 1). */
static void step_one(const sm_job *job, size_t v)
{
    const float *S = job->src;
    const uint32_t d = job->f.deg[v];
    const v4f n = sm_load4(&job->dir[4 * v]);
    v4f p = sm_load4(&S[4 * v]);
    if (d != 0 && sm_dot3(n, n) > 0.0f) {
        size_t b = d > 8 ? sm_lower_bound(job->f.big, job->f.nbig, v) : 0;
        p += job->tau * (sm_neighbour_sum(job, S, v, &b) * job->f.inv[v] - p);
        p[3] = 1.0f;
        if (job->clamp) p = into_band(p, n, job->band[job->comp[v]], job->band_in * job->band[job->comp[v]]);
    }
    sm_store4(&job->dst[4 * v], p);
}

/* The step over one chunk, run by run (a piece's band each): the usual
 * vertex (1 to 8 neighbours, a raw normal) in straight-line code, its
 * row's 8 slots summed (the -0 sentinel adds nothing), then the odd ones
 * again one by one. */
JM_BODY void sm_step_task_body(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    const float *S = job->src, *N = job->dir, *inv = job->f.inv;
    const uint32_t *nb8 = job->f.nb8;
    const sm_runs *r = &job->runs;
    float *D = job->dst;
    if (!job->clamp) /* within a super time stepping cycle: no band (smooth_plan.c) */
        for (size_t v = chunk * SM_CH, e = sm_chunk_end(job->nv, chunk); v < e; v++) {
            v4f p = sm_load4(&S[4 * v]);
            sm_store4(&D[4 * v], p + job->tau * (sm_add_slots8(SM_NEG0, S, &nb8[8 * v]) * inv[v] - p));
        }
    for (uint32_t k = r->chunk_run[chunk]; job->clamp && k < r->chunk_run[chunk + 1]; k++) {
        const float b = job->band[r->piece[k]], bin = job->band_in * b;
        for (size_t v = r->first[k]; v < r->first[k + 1]; v++) {
            v4f p = sm_load4(&S[4 * v]);
            p += job->tau * (sm_add_slots8(SM_NEG0, S, &nb8[8 * v]) * inv[v] - p);
            sm_store4(&D[4 * v], into_band(p, sm_load4(&N[4 * v]), b, bin));
        }
    }
    const size_t a = chunk * SM_CH, e = sm_chunk_end(job->nv, chunk);
    for (size_t i = sm_lower_bound(job->odd, job->nodd, a); i < job->nodd && job->odd[i] < e; i++)
        step_one(job, job->odd[i]);
}
JM_KERNEL_AVX2(, void, sm_step_task, sm_step_task_body, (void *arg, size_t chunk, int worker), (arg, chunk, worker))
