/* smooth_tangential.c - tangential relaxation: every vertex toward its neighbours' mean within its raw tangent plane, evening the triangles without moving the surface. */
#include "post/smooth.h"

/*
 * The steady smoothing (smooth.c) evens the marching cubes' slivers before
 * and after its implicit step: a vertex moves to its neighbours' mean less
 * the part along its raw normal. The surface stays where it is (to second
 * order), but the triangles no longer follow how the lattice cut it, so
 * neither does the cotangent step (issue 31: without these passes the
 * flicker is 2 to 7 times the raw mesh's; the raw normal instead of the
 * fan's, computed again each pass, changes it by 0.0003 R at half the
 * cost). Jacobi, like the steps.
 */
JM_BODY void tangential_body(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    const float *S = job->src;
    const size_t a = chunk * SM_CH, e = sm_chunk_end(job->nv, chunk);
    size_t kb = sm_lower_bound(job->f.big, job->f.nbig, a);
    for (size_t v = a; v < e; v++) {
        const v4f p = sm_load4(&S[4 * v]), sum = sm_neighbour_sum(job, S, v, &kb);
        const v4f n = sm_xyz(sm_load4(&job->dir[4 * v]));
        v4f q = p;
        if (job->f.deg[v] > 0 && sm_dot3(n, n) > 0.0f) {
            v4f move = sm_xyz(sum * job->f.inv[v] - p);
            move -= sm_dot3(move, n) * n;
            q = p + move;
        }
        sm_store4(&job->dst[4 * v], q);
    }
}
JM_KERNEL_AVX2(static, void, tangential_task, tangential_body, (void *arg, size_t chunk, int worker),
               (arg, chunk, worker))

void sm_tangential(jm_pool *pool, sm_job *job, float **a, float **b, int passes)
{
    for (int i = 0; i < passes; i++) sm_run_swap(pool, job, tangential_task, job, a, b);
}
