/* smooth_volume.c - every piece's enclosed volume, and its restoration after smoothing within the same band. */
#include "post/smooth.h"

/* Per run: the volume sum (p - o) . A over its vertices (A the fan's area
 * vector; the triangles' a . N / 3 regrouped by vertex, / 9 in the total;
 * o its piece's origin, job->origin), and the derivative of the volume
 * along the raw normals over the vertices free to grow and to shrink. */
JM_BODY void volume_task_body(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    const sm_runs *r = &job->runs;
    const float *P = job->src, *N = job->dir;
    size_t kb = sm_lower_bound(job->f.big, job->f.nbig, chunk * SM_CH);
    for (uint32_t k = r->chunk_run[chunk]; k < r->chunk_run[chunk + 1]; k++) {
        const double *o = &job->origin[3 * (size_t)r->piece[k]];
        const float bound = job->band[r->piece[k]], inward = job->band_in * bound;
        double vol = 0.0, grow = 0.0, shrink = 0.0;
        for (size_t v = r->first[k]; v < r->first[k + 1]; v++) {
            const float *p = &P[4 * v];
            const v4f a = sm_fan_area(job, P, v, &kb), n = sm_load4(&N[4 * v]);
            vol += ((double)p[0] - o[0]) * a[0] + ((double)p[1] - o[1]) * a[1] + ((double)p[2] - o[2]) * a[2];
            const float t = sm_move(sm_load4(p), n)[0], d = sm_dot3(n, a);
            if (t < bound) grow += d;
            if (t > -inward) shrink += d;
        }
        r->sum[SM_RUN_SUMS * k] = vol;
        r->sum[SM_RUN_SUMS * k + 1] = grow;
        r->sum[SM_RUN_SUMS * k + 2] = shrink;
    }
}
JM_KERNEL_AVX2(static, void, volume_task, volume_task_body, (void *arg, size_t chunk, int worker), (arg, chunk, worker))

/* The pieces' volumes of the positions P: 3 doubles per piece in out, the
 * volume and its derivatives along the raw normals over the vertices free
 * to grow and to shrink. The origins in job->origin. */
void sm_piece_volumes(jm_pool *pool, sm_job *job, const float *P, double *out)
{
    job->src = P;
    sm_run_ranges(pool, job->nchunks, volume_task, job);
    sm_runs_total(&job->runs, 3, out, job->npieces);
    for (size_t k = 0; k < job->npieces; k++) {
        out[3 * k] /= 9.0;
        out[3 * k + 1] /= 3.0;
        out[3 * k + 2] /= 3.0;
    }
}

/* The restored positions job->dst from the smoothed job->src: each vertex
 * moved along its raw normal by its piece's offset job->shift, its t kept
 * within its piece's band. */
JM_BODY void offset_task_body(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    const size_t a = chunk * SM_CH, b = sm_chunk_end(job->nv, chunk);
    for (size_t v = a; v < b; v++) {
        const float bound = job->band[job->comp[v]], inward = job->band_in * bound;
        const v4f n = sm_load4(&job->dir[4 * v]);
        v4f p = sm_load4(&job->src[4 * v]);
        const float t = sm_move(p, n)[0];
        float u = t + (float)job->shift[job->comp[v]];
        u = u < -inward ? -inward : (u > bound ? bound : u);
        p += (u - t) * sm_xyz(n);
        sm_store4(&job->dst[4 * v], p);
    }
}
JM_KERNEL_AVX2(static, void, offset_task, offset_task_body, (void *arg, size_t chunk, int worker), (arg, chunk, worker))

/* A first Newton step s this small against the piece's thickness R (3 V /
 * A, a ball's radius) leaves an error of about 3 (s / R)^2 of its volume,
 * here under 0.001 %: no second step. */
#define SM_NEWTON_ONE 0.0018

/*
 * Every piece gets its raw volume back: an offset s along the raw normals
 * (Newton's method on V(s), two passes, one where every first step is
 * tiny), each vertex's t staying within
 * the band. Only the vertices free to move the asked way count in the
 * derivative, so a piece whose vertices all sit at the band's edge still
 * grows; the steps are at most 0.3 of the piece's thickness (3 V / A: a
 * ball's radius), so a small shrunken piece is not overshot, and no cap
 * keeps a droplet from coming back (issue 31). job->src: the smoothed
 * positions; the result in job->dst. work: 4 doubles per piece.
 */
void sm_restore_volumes(jm_pool *pool, sm_job *job, const double *vol0, const double *thick, double *work)
{
    const size_t np = job->npieces;
    double *s = work, *d = s + np; /* d: 3 per piece */
    const float *smoothed = job->src;
    float *out = job->dst;
    memset(s, 0, np * sizeof *s);
    for (int pass = 0, again = 1; pass < 2 && again; pass++) {
        sm_piece_volumes(pool, job, pass == 0 ? smoothed : out, d);
        again = 0;
        for (size_t k = 0; k < np; k++) {
            const double need = vol0[k] - d[3 * k], dv = need > 0.0 ? d[3 * k + 1] : d[3 * k + 2];
            const double cap = fmin((double)job->band[k], 0.3 * fabs(thick[k]));
            if (dv > 0.0 && need != 0.0) {
                const double step = need / dv;
                s[k] += fmax(-cap, fmin(cap, step));
                again |= fabs(step) > SM_NEWTON_ONE * fabs(thick[k]) || fabs(step) > cap;
            }
        }
        job->src = smoothed;
        job->dst = out;
        job->shift = s;
        sm_run_ranges(pool, job->nchunks, offset_task, job);
    }
}

/* At the end of a super time stepping cycle (smooth.c), before the band:
 * the positions P (in place) moved along the raw normals by each piece's
 * Newton offset toward its raw volume, then clamped into the band. The
 * cycle shrinks a piece by its curvature (a ball of 15 r by about 0.2 r);
 * clamped first, that shrinkage would take its share of the band. */
void sm_recentre(jm_pool *pool, sm_job *job, float *P, const double *vol0, double *work)
{
    const size_t np = job->npieces;
    double *s = work, *d = s + np;
    sm_piece_volumes(pool, job, P, d);
    for (size_t k = 0; k < np; k++) {
        const double need = vol0[k] - d[3 * k], dv = need > 0.0 ? d[3 * k + 1] : d[3 * k + 2];
        const double cap = (double)job->band[k];
        s[k] = dv > 0.0 && need != 0.0 ? fmax(-cap, fmin(cap, need / dv)) : 0.0;
    }
    job->src = P;
    job->dst = P;
    job->shift = s;
    sm_run_ranges(pool, job->nchunks, offset_task, job);
}
