/* smooth.h - the bounded smoothing's shared state and helpers (smooth.c and its stages smooth_*.c). */
#ifndef JETMESH_SMOOTH_H
#define JETMESH_SMOOTH_H
#include "post/post_mesh.h"
#include <string.h>

#define SM_CH 2048 /* vertices per task: fixed, so every sum is the same whatever the threads */

/* Positions, directions and normals while they are worked on: 4 floats per
 * vertex (positions (x, y, z, 1): the mean of a vertex's up to 8 neighbours
 * keeps the 1, d * (1 / d) being 1 for d <= 8), so a neighbour is one
 * 16-byte load and one vector add; the lanes do what scalar code would, in
 * the same order. */
typedef float v4f __attribute__((vector_size(16)));

static inline v4f sm_load4(const float *p)
{
    v4f r;
    memcpy(&r, p, sizeof r);
    return r;
}
static inline void sm_store4(float *p, v4f v) { memcpy(p, &v, sizeof v); }
static inline v4f sm_load3(const float *p)
{
    v4f r = {p[0], p[1], p[2], 0.0f};
    return r;
}
static inline void sm_store3(float *p, v4f r) { p[0] = r[0], p[1] = r[1], p[2] = r[2]; }
static inline float sm_dot3(v4f a, v4f b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
/* The move t = p . dir of a position (x, y, z, 1) along a raw frame dir =
 * (n, -x0 . n), in every lane: the products added pairwise, (0 + 1) + (2
 * + 3) (float addition commutes exactly: each lane the same bits). */
static inline v4f sm_move(v4f p, v4f dir)
{
    const v4f q = p * dir, s = q + __builtin_shufflevector(q, q, 1, 0, 3, 2);
    return s + __builtin_shufflevector(s, s, 2, 3, 0, 1);
}
/* a with its fourth lane 0 */
static inline v4f sm_xyz(v4f a)
{
    const v4f z = {0.0f, 0.0f, 0.0f, 0.0f};
    return __builtin_shufflevector(a, z, 0, 1, 2, 4);
}

static const v4f SM_NEG0 = {-0.0f, -0.0f, -0.0f, -0.0f};

/* acc plus the 4-float rows S of the 8 slots q[0..7] of a fan row (doubled
 * indices, so &S[2 q] is a row; the -0 sentinel row adds nothing), in slot
 * order, straight-line code. */
static inline v4f sm_add_slots8(v4f acc, const float *S, const uint32_t *q)
{
    acc += sm_load4(&S[2 * (size_t)q[0]]);
    acc += sm_load4(&S[2 * (size_t)q[1]]);
    acc += sm_load4(&S[2 * (size_t)q[2]]);
    acc += sm_load4(&S[2 * (size_t)q[3]]);
    acc += sm_load4(&S[2 * (size_t)q[4]]);
    acc += sm_load4(&S[2 * (size_t)q[5]]);
    acc += sm_load4(&S[2 * (size_t)q[6]]);
    acc += sm_load4(&S[2 * (size_t)q[7]]);
    return acc;
}

/* The end of task `chunk`'s vertices [chunk * SM_CH, end). */
static inline size_t sm_chunk_end(size_t nv, size_t chunk)
{
    const size_t e = (chunk + 1) * SM_CH;
    return e < nv ? e : nv;
}

/* The first of the n increasing entries of list that is at least a. */
static inline size_t sm_lower_bound(const uint32_t *list, size_t n, size_t a)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (list[mid] < a) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* Every vertex's fan (smooth_fans.c): for its first 8 triangles in triangle
 * order the next corner (nb8) and the one after (nc8), doubled, padded
 * with nv (the sentinel row of -0); the vertices of more than 8 (big, in
 * increasing order) with their whole fans in bnb and bnc from bstart. */
typedef struct sm_fan {
    size_t nv;
    uint32_t *deg;   /* triangles around each vertex (= its neighbours on a closed mesh) */
    float *inv;      /* 1 / deg, 0 for none */
    uint32_t *nb8, *nc8;
    uint32_t *big, *bstart, *bnb, *bnc;
    size_t nbig, nfan;
} sm_fan;

/* A piece's run: consecutive vertices [first, next run's first) of one
 * piece within one task's chunk (smooth_runs.c). Sums over a piece are the
 * runs' sums added in run order: the same for any thread count. */
typedef struct sm_runs {
    uint32_t *first, *piece; /* per run */
    uint32_t *chunk_run;     /* per chunk its first run; nchunks + 1 entries */
    size_t nruns, nchunks;
    double *sum;             /* SM_RUN_SUMS per run: what the last pass summed */
} sm_runs;
#define SM_RUN_SUMS 3

/* The working set of one smoothing (smooth.c fills it). */
typedef struct sm_job {
    const jm_config *c;
    jm_post_mesh *m;
    jm_mem *mem;
    size_t nv, nchunks;
    sm_fan f;
    sm_runs runs;
    const uint32_t *comp; /* per vertex its piece (labels in vertex order) */
    size_t npieces;
    const uint32_t *odd;  /* increasing: vertices done one at a time (no or over 8 neighbours, no direction) */
    size_t nodd;
    float *dir;           /* per vertex its unit raw fan normal n and -x0 . n (x0 its raw
                           * position): its move along n is sm_move(x, dir); 0 for no normal */
    const float *src;     /* positions (4 per vertex, a -0 sentinel row at nv) */
    float *dst;
    const double *origin; /* per piece a point of it: 3 doubles (its volume sums about it) */
    const double *shift;  /* restoration: per piece its offset along dir */
    const float *band;    /* per piece: the largest |t| (smooth.c) */
    float band_in;        /* the band inward, as a fraction of band: [-band_in band, band] */
    int normalise;        /* smooth_normals.c's last pass: make the normals unit */
    float tau;            /* this step's size (smooth_plan.c) */
    int clamp;            /* this step ends in the band (sm_plan_settled) */
    int failed;
} sm_job;

/* The area vector of vertex v's fan: the sum of its triangles' cross
 * products / 2, from the positions P (4 floats per vertex; the fourth
 * lanes cancel); *k walks the big vertices (the first at least v). */
static inline v4f sm_fan_area(const sm_job *job, const float *P, size_t v, size_t *k)
{
    const uint32_t *nb8 = job->f.nb8, *nc8 = job->f.nc8;
    const v4f p = sm_load4(&P[4 * v]);
    v4f n = {0.0f, 0.0f, 0.0f, 0.0f};
#define FAN_AREA(qb, qc)                                                                                    \
    do {                                                                                                   \
        v4f e1 = sm_load4(&P[qb]) - p, e2 = sm_load4(&P[qc]) - p;                                          \
        n += __builtin_shufflevector(e1, e1, 1, 2, 0, 3) * __builtin_shufflevector(e2, e2, 2, 0, 1, 3) -   \
             __builtin_shufflevector(e1, e1, 2, 0, 1, 3) * __builtin_shufflevector(e2, e2, 1, 2, 0, 3);    \
    } while (0)
    const uint32_t d = job->f.deg[v];
    if (d <= 8) {
        for (uint32_t i = 0; i < d; i++) FAN_AREA(2 * (size_t)nb8[8 * v + i], 2 * (size_t)nc8[8 * v + i]);
    } else {
        for (uint32_t i = job->f.bstart[*k]; i < job->f.bstart[*k + 1]; i++)
            FAN_AREA(4 * (size_t)job->f.bnb[i], 4 * (size_t)job->f.bnc[i]);
        ++*k;
    }
#undef FAN_AREA
    n *= 0.5f;
    n[3] = 0.0f;
    return n;
}

/* The sum of vertex v's neighbours' rows of S (4 floats each, a -0
 * sentinel row at nv), its slots of 8 or its whole big fan in fan order;
 * *k walks the big vertices (the first at least v), as sm_fan_area. */
static inline v4f sm_neighbour_sum(const sm_job *job, const float *S, size_t v, size_t *k)
{
    if (job->f.deg[v] <= 8) return sm_add_slots8(SM_NEG0, S, &job->f.nb8[8 * v]);
    v4f sum = SM_NEG0;
    for (uint32_t i = job->f.bstart[*k]; i < job->f.bstart[*k + 1]; i++) sum += sm_load4(&S[4 * (size_t)job->f.bnb[i]]);
    ++*k;
    return sum;
}

/* smooth_scratch.c: a pass over the chunks, each thread the same contiguous
 * range every pass (the lines it wrote stay in its cache). */
void sm_run_ranges(jm_pool *pool, size_t nchunks, jm_task_fn fn, void *arg);
/* ... a pass of fn(arg) from *src into *dst (job->src, job->dst), then
 * the two swapped: the result in *src. */
void sm_run_swap(jm_pool *pool, sm_job *job, jm_task_fn fn, void *arg, float **src, float **dst);

/* smooth_fans.c */
jm_status sm_fans_build(jm_mem *mem, jm_pool *pool, jm_post_scratch *sc, const jm_post_mesh *m, sm_fan *f);

/* smooth_runs.c: the runs of comp (labels in vertex order) per chunk;
 * sm_runs_total adds each run's first nsums sums into its piece's (nsums
 * doubles per piece), in run order. */
jm_status sm_runs_build(jm_mem *mem, const uint32_t *comp, size_t nv, size_t nchunks, sm_runs *r);
void sm_runs_total(const sm_runs *r, int nsums, double *piece_sums, size_t npieces);
void sm_runs_free(jm_mem *mem, sm_runs *r);

/* smooth_plan.c: the step sizes of n iterations (*out, jm_alloc'ed, freed
 * by the caller; *cycle_steps: the steps of each super time stepping
 * cycle, 0 for none); returns their number, -1 when out of memory.
 * sm_plan_settled: whether the state after step it (of total) is a
 * smoothing: 1 after a plain step, 2 at the end of a cycle, 0 within one. */
int sm_plan(int n, jm_mem *mem, float **out, int *cycle_steps);
int sm_plan_settled(int it, int total, int cycle_steps, int n);

/* smooth_steps.c: one bounded step of size job->tau, job->src to job->dst. */
void sm_step_task(void *arg, size_t chunk, int worker);

/* smooth_implicit.c: out (4 per vertex) from x0 by one backward Euler step
 * (M + dt K) out = M x0 of the cotangent Laplacian K, lumped mass M. */
jm_status sm_implicit_step(jm_mem *mem, jm_pool *pool, jm_post_scratch *sc, sm_job *job, const float *x0, float *out,
                           float dt);
/* smooth_tangential.c: `passes` passes of tangential relaxation from *a,
 * through *b; the result in *a (the two swapped after each pass). */
void sm_tangential(jm_pool *pool, sm_job *job, float **a, float **b, int passes);

/* smooth_volume.c */
void sm_restore_volumes(jm_pool *pool, sm_job *job, const double *vol0, const double *thick, double *work);
void sm_piece_volumes(jm_pool *pool, sm_job *job, const float *P, double *out);
void sm_recentre(jm_pool *pool, sm_job *job, float *P, const double *vol0, double *work);

/* smooth_guard.c: triangles of pos (the smoothed positions, 4 per vertex;
 * job->m->pos the raw ones) turned over by the smoothing: their corners
 * taken back toward the raw positions. */
jm_status sm_guard_folds(jm_pool *pool, sm_job *job, float *pos);

/* smooth_normals.c */
jm_status sm_normals(jm_mem *mem, jm_pool *pool, jm_post_scratch *sc, sm_job *job, const float *pos, int want_nrm);

/* smooth_scratch.c: buffer k of the scratch with room for at least `bytes`. */
void *sm_scratch(jm_post_scratch *s, jm_mem *mem, int k, size_t bytes);
enum { SB_DEG, SB_INV, SB_NB8, SB_NC8, SB_BIG, SB_BNB, SB_A, SB_B, SB_DIR, SB_COMP, SB_ODD, SB_PIECE, SB_KEEP,
       SB_FLAG, SB_IMPL_W, SB_IMPL_V, SB_COUNT };
_Static_assert(SB_COUNT == JM_POST_BUFS, "the scratch has a buffer per SB_ name");
/* The post-processing's working arrays given back (smooth_scratch.c). */
void jm_post_scratch_free(jm_post_scratch *s, jm_mem *mem);

/* Smooths the lattice part of m (smooth.c): c->smooth_iters steps of
 * Laplacian smoothing, every vertex's move along its raw normal bounded,
 * with the enclosed volume of every connected piece restored, normals from
 * the new surface, then c->smooth_normal_iters iterations of normal
 * smoothing and fresh UVs. Deterministic for any thread count. */
jm_status jm_smooth_mesh(jm_mem *mem, jm_pool *pool, jm_post_scratch *scratch, const jm_config *c, jm_post_mesh *m);
#endif
