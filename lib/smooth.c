/* smooth.c - feature-weighted Laplacian mesh smoothing with volume restoration, then normals, normal smoothing, UVs. */
#include "post.h"
#include "block.h"
#include "pieces.h"
#include <string.h>

/*
 * Weights. After Löschner, Böttcher, Jeske and Bender (2023), "Weighted
 * Laplacian Smoothing for Surface Reconstruction of Particle-based Fluids":
 * every particle gets a distance-weighted count of its neighbours, the counts
 * are interpolated to the vertices (Shepard, cubic spline over one grid cell:
 * the SPH support; evaluated on a lattice of half a cell, about 2r, and
 * trilinearly between its nodes) and mapped through a smoothstep, so vertices over bulk
 * fluid move with weight near 1 while droplets, pairs and thin sheets barely
 * move. The count is the one the pipeline already has: the SPH kernel sum
 * 1/V_j (sph) or the links' sum of 1 - (D/L)^2 (metasphere), normalised by its
 * value in bulk fluid at the rest spacing 2r (1 means bulk, 0 a lone
 * particle), as splashsurf normalises its count by 13, the bulk value of its
 * own count.
 *
 * Steps. Each step moves vertex v to x_v + tau w_v (mean of its neighbours -
 * x_v), all vertices at once from the previous positions (Jacobi), so the
 * result does not depend on the thread count. Plain steps (tau <= 1) diffuse
 * slowly: bumps k edges wide need about k^2 steps. The steps are therefore
 * grouped in cycles of 5 with the step sizes of super time stepping
 * (Alexiades, Amiez and Gremaud 1996, damping nu = 0.02), ordered large and
 * small alternately: a cycle of 5 smooths like 15 plain steps and still damps
 * every frequency; within a cycle no mode grows more than 21-fold, harmless
 * in float.
 *
 * Volume. Laplacian smoothing shrinks: afterwards every connected piece of
 * the mesh is moved along its normals, in proportion to the weights, to
 * enclose its original volume again (one linearised step; no
 * vertex moves more than 5 % of its piece's size, so a small void that the
 * smoothing nearly closed stays small instead of asking for a huge offset).
 *
 * Normals. The area-weighted mesh normals of the new surface, blended with
 * the field's normals by the weight: the field's gradient at a moved vertex
 * describes the bumpy surface the vertex left, not the smooth one it is on,
 * and where nothing moved (weight 0) the field's normal is the exact one.
 * Normal smoothing averages each normal with its neighbours' (Jacobi), those
 * facing the same side as it before the first step (never across a thin
 * sheet or a droplet's other side), and the UVs are computed again from the
 * final positions and normals.
 */

/* The weights, steps and fan areas also cloned for AVX2 (three-operand
 * instructions, fewer register copies; the weights' 8 lanes one vector),
 * chosen at run time: the same operations, no FMA in ISO C mode, the same
 * bits. JM_SMOOTH_PLAIN builds the plain code only (tests compare them). */
#ifndef JM_SMOOTH_PLAIN
#define JM_SM_CLONES JM_CLONES_AVX2
#else
#define JM_SM_CLONES
#endif

#define CH 2048    /* vertices per task */
#define CYCLE 5    /* steps per super-time-stepping cycle */
#define STS_NU 0.02
#define NSLOT 16   /* cached particle neighbourhoods per worker */
#define NCORNER 4096 /* cached corner values per worker */

typedef struct sm_slot {
    int64_t cell[3];
    int used;
    float *buf;    /* x[cap], y[cap], z[cap], phi[cap] */
    size_t n, cap; /* padded to 8 */
} sm_slot;

typedef struct sm_corner {
    int64_t k[3];
    float v;
    int used;
} sm_corner;

typedef struct sm_job {
    const jm_config *c;
    const jm_grid *g;
    jm_post_mesh *m;
    jm_mem *mem;
    size_t nv;
    uint32_t *deg;         /* per vertex: its number of incident triangles (= of neighbours) */
    float *inv;            /* per vertex: 1 / its number of neighbours */
    uint32_t *nb8;         /* per vertex: for its first 8 incident triangles in triangle order the
                            * next corner, then nv (a -0 sentinel), each doubled: &S[2 q] is
                            * neighbour q of 4 floats per vertex in one addressing mode
                            * (q < JM_PENDING = 2^31) */
    uint32_t *nc8;         /* ... and the corner after it, doubled (past deg: undefined) */
    const uint32_t *bstart; /* per big vertex (big[k]): offsets of its whole fan in bnb, bnc */
    const uint32_t *bnb, *bnc; /* the big vertices' fans in triangle order: next and after */
    uint32_t *nm8;         /* normal smoothing: per vertex its counted neighbours (nmask_task) */
    uint8_t *bflag;        /* ... per big vertex's fan entry whether it counts */
    float *ninv;           /* ... per vertex 1 / (1 + their number) */
    const uint32_t *odd;   /* increasing: the vertices of 0 or more than 8 neighbours or a weight
                            * under 1e-30 (k = w tau might be 0), which step_task does one by one */
    size_t nodd;
    const uint32_t *big;   /* increasing: the vertices of more than 8 neighbours */
    size_t nbig;
    const float *phi;      /* per sorted particle: fullness in [0, 1] */
    float *w;              /* per vertex smoothing weight */
    sm_slot *slots;        /* NSLOT per worker */
    sm_corner *corners;    /* NCORNER per worker */
    int failed;
    struct sm_fans *fans;  /* fan_task: one per range */
    int nfans;
    const float *src;
    float *dst;
    float tau;
    float *area;           /* per vertex: area vector (3) */
    const uint32_t *comp;  /* per vertex: its piece */
    const double *shift;   /* per piece: the offset at weight 1 */
    const double *cap;     /* per piece: the largest offset */
} sm_job;

/* The per-particle count of a particle in bulk fluid at rest: over a lattice
 * of spacing 2r around it. */
static float bulk_count(const jm_config *c)
{
    double R = c->field == JM_FIELD_SPH ? c->support : c->link, s = 2.0 * c->r, sum = 0.0;
    int k = (int)ceil(R / s);
    if (k > 48) k = 48;
    for (int z = -k; z <= k; z++)
        for (int y = -k; y <= k; y++)
            for (int x = -k; x <= k; x++) {
                double d = s * sqrt((double)(x * x + y * y + z * z));
                if (d >= R) continue;
                if (c->field == JM_FIELD_SPH)
                    sum += jm_cubic_w((float)(d / c->sph_h));
                else if (d > 0.0)
                    sum += 1.0 - (d / R) * (d / R);
            }
    return (float)sum;
}

static inline float clamp01(float x) { return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x); }

/* Particle fullness (0 alone, 1 bulk) from the counts the grid already holds. */
static void fullness(const jm_config *c, const jm_grid *g, float *phi)
{
    float bulk = bulk_count(c);
    if (c->field == JM_FIELD_SPH) {
        float den = bulk > 1.5f ? bulk - 1.0f : 0.5f; /* the particle itself counts 1 */
        for (size_t i = 0; i < g->n; i++) phi[i] = clamp01((1.0f / g->weight[i] - 1.0f) / den);
    } else {
        float den = bulk > 0.5f ? bulk : 0.5f, inv_l2 = 1.0f / (c->link * c->link);
        for (size_t i = 0; i < g->n; i++) {
            float s = 0.0f;
            for (uint32_t e = g->nb_start[i]; e < g->nb_start[i + 1]; e++) {
                float D = g->nb_dir[4 * (size_t)e + 3];
                s += 1.0f - D * D * inv_l2;
            }
            phi[i] = clamp01(s / den);
        }
    }
}

/* The particles of the 27 grid cells around cell cc, as padded arrays. */
static sm_slot *neighbourhood(sm_job *job, sm_slot *slots, const int64_t cc[3])
{
    unsigned h = (unsigned)((uint64_t)(cc[0] * 73856093 ^ cc[1] * 19349663 ^ cc[2] * 83492791) % NSLOT);
    sm_slot *s = &slots[h];
    if (s->used && s->cell[0] == cc[0] && s->cell[1] == cc[1] && s->cell[2] == cc[2]) return s;
    const jm_grid *g = job->g;
    uint32_t r[27][2];
    int nr = 0;
    size_t n = 0;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                uint32_t ci = jm_grid_cell(g, cc[0] + dx, cc[1] + dy, cc[2] + dz);
                if (ci == UINT32_MAX) continue;
                r[nr][0] = g->cell_start[ci];
                r[nr][1] = g->cell_start[ci + 1];
                n += r[nr][1] - r[nr][0];
                nr++;
            }
    size_t cap = (n + 7) & ~(size_t)7;
    if (cap > s->cap) {
        float *b = jm_realloc(job->mem, s->buf, s->cap * 4 * sizeof(float), cap * 4 * sizeof(float));
        if (!b) return NULL;
        s->buf = b;
        s->cap = cap;
    }
    float *x = s->buf, *y = x + s->cap, *z = y + s->cap, *f = z + s->cap;
    size_t t = 0;
    for (int k = 0; k < nr; k++)
        for (uint32_t j = r[k][0]; j < r[k][1]; j++, t++) {
            x[t] = g->pos[3 * (size_t)j];
            y[t] = g->pos[3 * (size_t)j + 1];
            z[t] = g->pos[3 * (size_t)j + 2];
            f[t] = job->phi[j];
        }
    for (; t < cap; t++) x[t] = y[t] = z[t] = 1e30f, f[t] = 0.0f;
    s->n = cap;
    s->used = 1;
    memcpy(s->cell, cc, sizeof s->cell);
    return s;
}

/* The particles' fullness interpolated at lattice corner k (spacing half a
 * grid cell): Shepard, cubic spline of support one grid cell, sums in 8 lanes
 * in a fixed order; -1 when out of memory. A pure function of k, cached. */
static inline __attribute__((always_inline)) float corner_value(sm_job *job, int worker, const int64_t k[3])
{
    sm_corner *cs = &job->corners[(size_t)worker * NCORNER];
    unsigned h = (unsigned)((uint64_t)(k[0] * 73856093 ^ k[1] * 19349663 ^ k[2] * 83492791) % NCORNER);
    sm_corner *e = &cs[h];
    if (e->used && e->k[0] == k[0] && e->k[1] == k[1] && e->k[2] == k[2]) return e->v;
    const jm_grid *g = job->g;
    const float half = 0.5f * g->cell, inv_h = 2.0f / g->cell;
    float p[3];
    int64_t cc[3];
    for (int a = 0; a < 3; a++) {
        p[a] = (float)k[a] * half;
        cc[a] = (int64_t)floorf(p[a] * g->inv_cell);
    }
    sm_slot *s = neighbourhood(job, &job->slots[(size_t)worker * NSLOT], cc);
    if (!s) return -1.0f;
    const float *x = s->buf, *y = x + s->cap, *z = y + s->cap, *f = z + s->cap;
    float lk[8] = {0}, lf[8] = {0};
    for (size_t i = 0; i < s->n; i += 8)
        for (int l = 0; l < 8; l++) {
            float dx = x[i + l] - p[0], dy = y[i + l] - p[1], dz = z[i + l] - p[2];
            float kw = jm_cubic_w(sqrtf(dx * dx + dy * dy + dz * dz) * inv_h); /* 0 beyond the cell */
            lk[l] += kw;
            lf[l] += kw * f[i + l];
        }
    float sk = 0.0f, sf = 0.0f;
    for (int l = 0; l < 8; l++) sk += lk[l], sf += lf[l];
    e->v = sk > 0.0f ? clamp01(sf / sk) : 0.0f;
    memcpy(e->k, k, sizeof e->k);
    e->used = 1;
    return e->v;
}

/* Vertex weights: the fullness interpolated trilinearly from the corners of
 * the vertex's half-cell (the field varies on the particle scale; the
 * vertices lie four times closer), then the smoothstep. */
JM_SM_CLONES static void weight_task(void *arg, size_t chunk, int worker)
{
    sm_job *job = arg;
    const float inv_half = 2.0f * job->g->inv_cell;
    size_t a = chunk * CH, b = a + CH < job->nv ? a + CH : job->nv;
    int64_t last[3] = {0, 0, 0};
    int have = 0;
    float c[8];
    for (size_t v = a; v < b; v++) {
        const float *p = &job->m->pos[3 * v];
        int64_t k0[3];
        float t[3];
        for (int i = 0; i < 3; i++) {
            float q = p[i] * inv_half, fq = floorf(q);
            k0[i] = (int64_t)fq;
            t[i] = q - fq;
        }
        /* consecutive vertices mostly share a half-cell: its corners again */
        int same = have && k0[0] == last[0] && k0[1] == last[1] && k0[2] == last[2];
        memcpy(last, k0, sizeof last);
        have = 1;
        for (int i = 0; i < 8 && !same; i++) {
            int64_t k[3] = {k0[0] + (i & 1), k0[1] + ((i >> 1) & 1), k0[2] + (i >> 2)};
            c[i] = corner_value(job, worker, k);
            if (c[i] < 0.0f) { job->failed = 1; return; }
        }
        float x00 = c[0] + t[0] * (c[1] - c[0]), x10 = c[2] + t[0] * (c[3] - c[2]);
        float x01 = c[4] + t[0] * (c[5] - c[4]), x11 = c[6] + t[0] * (c[7] - c[6]);
        float y0 = x00 + t[1] * (x10 - x00), y1 = x01 + t[1] * (x11 - x01);
        float x = clamp01(y0 + t[2] * (y1 - y0));
        job->w[v] = x * x * x * (x * (6.0f * x - 15.0f) + 10.0f);
    }
}

/* Positions and normals while they are smoothed: 4 floats per vertex (the
 * fourth 0), so a neighbour is one 16-byte load and one vector add. The lanes
 * do the same operations in the same order as scalar code would: the same
 * bits. */
typedef float v4f __attribute__((vector_size(16)));

static inline v4f load4(const float *p)
{
    v4f r;
    memcpy(&r, p, sizeof r);
    return r;
}

static const v4f NEG0 = {-0.0f, -0.0f, -0.0f, -0.0f};

/* The sum of the positions S (4 floats per vertex) of the neighbours nb[s],
 * ..., nb[e - 1], in that order, from -0 (which adds nothing to any float):
 * the whole fan of a vertex of more than 8 (add_slots8 does the others). */
static inline v4f fan_sum(const float *S, const uint32_t *nb, uint32_t s, uint32_t e)
{
    v4f sum = NEG0;
    for (uint32_t i = s; i < e; i++) sum += load4(&S[4 * (size_t)nb[i]]);
    return sum;
}

/* acc plus the positions S (4 floats per vertex) of the 8 slots q[0..7] of
 * a row of nb8 or nm8 (doubled indices; the -0 sentinel adds nothing), in
 * slot order, in straight-line code. From acc = -0 the sum of the slots
 * alone: -0 + x is x. */
static inline v4f add_slots8(v4f acc, const float *S, const uint32_t *q)
{
    acc += load4(&S[2 * (size_t)q[0]]);
    acc += load4(&S[2 * (size_t)q[1]]);
    acc += load4(&S[2 * (size_t)q[2]]);
    acc += load4(&S[2 * (size_t)q[3]]);
    acc += load4(&S[2 * (size_t)q[4]]);
    acc += load4(&S[2 * (size_t)q[5]]);
    acc += load4(&S[2 * (size_t)q[6]]);
    acc += load4(&S[2 * (size_t)q[7]]);
    return acc;
}

/* The first of the n increasing entries of list that is at least a. */
static size_t lower_bound(const uint32_t *list, size_t n, size_t a)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (list[mid] < a) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* One step: dst = src + tau w (mean of the neighbours - src), 4 floats per
 * vertex: vertex v. */
static inline void step_one(const sm_job *job, size_t v)
{
    const float *S = job->src;
    const uint32_t *nb8 = job->nb8;
    const uint32_t d = job->deg[v];
    v4f p = load4(&S[4 * v]);
    float k = job->w[v] * job->tau;
    if (k != 0.0f && d != 0) {
        v4f sum;
        if (d <= 8) {
            sum = add_slots8(NEG0, S, &nb8[8 * v]);
        } else {
            size_t b = lower_bound(job->big, job->nbig, v);
            sum = fan_sum(S, job->bnb, job->bstart[b], job->bstart[b + 1]);
        }
        p += k * (sum * job->inv[v] - p);
    }
    memcpy(&job->dst[4 * v], &p, sizeof p);
}

/* The step over vertices [a, b): the usual vertex (1 to 8 neighbours, a
 * weight that keeps k = w tau nonzero) in straight-line code without a branch,
 * the 8 slots of its row summed (a -0 sentinel adds nothing: the same bits),
 * then the others (job->odd) again the careful way, unless they are many. */
JM_SM_CLONES static void step_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    size_t a = chunk * CH, b = a + CH < job->nv ? a + CH : job->nv;
    size_t lo = lower_bound(job->odd, job->nodd, a), hi = lower_bound(job->odd, job->nodd, b);
    if (8 * (hi - lo) > b - a) {
        for (size_t v = a; v < b; v++) step_one(job, v);
        return;
    }
    const float *S = job->src, *w = job->w, *inv = job->inv, tau = job->tau;
    float *D = job->dst;
    const uint32_t *nb8 = job->nb8;
    for (size_t v = a; v < b; v++) {
        v4f p = load4(&S[4 * v]);
        v4f sum = add_slots8(NEG0, S, &nb8[8 * v]);
        p += w[v] * tau * (sum * inv[v] - p);
        memcpy(&D[4 * v], &p, sizeof p);
    }
    for (; lo < hi; lo++) step_one(job, job->odd[lo]);
}

/* Area vector of each vertex's fan: the sum of its triangles' cross products
 * / 2, from the positions job->src (4 floats per vertex). */
JM_SM_CLONES static void area_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    const float *P = job->src;
    const uint32_t *deg = job->deg, *nb8 = job->nb8, *nc8 = job->nc8;
    float *area = job->area;
    size_t a = chunk * CH, b = a + CH < job->nv ? a + CH : job->nv;
    size_t k = lower_bound(job->big, job->nbig, a);
    for (size_t v = a; v < b; v++) {
        v4f p = load4(&P[4 * v]), n = {0.0f, 0.0f, 0.0f, 0.0f};
#define FAN_AREA(qb, qc)                                                                                    \
    do {                                                                                                   \
        v4f e1 = load4(&P[qb]) - p, e2 = load4(&P[qc]) - p;                                                \
        n += __builtin_shufflevector(e1, e1, 1, 2, 0, 3) * __builtin_shufflevector(e2, e2, 2, 0, 1, 3) -   \
             __builtin_shufflevector(e1, e1, 2, 0, 1, 3) * __builtin_shufflevector(e2, e2, 1, 2, 0, 3);    \
    } while (0)
        if (deg[v] <= 8) {
            for (uint32_t i = 0; i < deg[v]; i++) FAN_AREA(2 * (size_t)nb8[8 * v + i], 2 * (size_t)nc8[8 * v + i]);
        } else {
            for (uint32_t i = job->bstart[k]; i < job->bstart[k + 1]; i++)
                FAN_AREA(4 * (size_t)job->bnb[i], 4 * (size_t)job->bnc[i]);
            k++;
        }
#undef FAN_AREA
        for (int j = 0; j < 3; j++) area[3 * v + j] = 0.5f * n[j];
    }
}

/* 3 floats into a vector's first lanes (the fourth 0) and back */
static inline v4f load3(const float *p)
{
    v4f r = {p[0], p[1], p[2], 0.0f};
    return r;
}
static inline void store3(float *p, v4f r) { p[0] = r[0], p[1] = r[1], p[2] = r[2]; }

/* n / |n|, or the fallback where |n| is 0: each lane divided by the same
 * length, one division for the three (the same bits as three) */
static inline v4f unit3(v4f n, v4f fallback)
{
    const float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    return l > 0.0f ? n / l : fallback;
}

/* Volume restoration: moves each vertex along its normal by its weight times
 * its piece's offset, capped (positions job->dst, 4 floats per vertex). */
static void offset_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    size_t a = chunk * CH, b = a + CH < job->nv ? a + CH : job->nv;
    for (size_t v = a; v < b; v++) {
        double sd = job->shift[job->comp[v]] * job->w[v], cap = job->cap[job->comp[v]];
        const float s = (float)(sd > cap ? cap : (sd < -cap ? -cap : sd));
        if (s == 0.0f) continue;
        const v4f n = load3(&job->area[3 * v]);
        const float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(l > 0.0f)) continue;
        /* the fourth lane (0) adds 0 */
        const v4f q = load4(&job->dst[4 * v]) + s * n / l;
        memcpy(&job->dst[4 * v], &q, sizeof q);
    }
}

/* Normals of the smoothed surface: the area-weighted mesh normal blended with
 * the field normal by the vertex weight. */
static void normal_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    size_t a = chunk * CH, b = a + CH < job->nv ? a + CH : job->nv;
    for (size_t v = a; v < b; v++) {
        float *n = &job->m->nrm[3 * v];
        const v4f f = load3(n), w = {job->w[v], job->w[v], job->w[v], job->w[v]};
        store3(n, unit3(w * unit3(load3(&job->area[3 * v]), f) + (1.0f - w) * f, f));
    }
}

/* The normal smoothing's neighbours, chosen once from the normals before
 * its first step (job->src, 4 floats per vertex): a neighbour counts when
 * it faces the same side as the vertex (not across a thin sheet or
 * droplet: its other side faces away), its product with the vertex's
 * normal summed ((x + y) + z) > 0. Per vertex of up to 8 neighbours its
 * row of nb8 with the others replaced by the -0 sentinel (nm8); per big
 * vertex a flag per fan entry (bflag), its row all sentinels; 1 / (1 + the
 * number counted) in ninv. */
JM_SM_CLONES static void nmask_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    const float *S = job->src;
    const uint32_t *deg = job->deg, *nb8 = job->nb8, sent = 2 * (uint32_t)job->nv;
    uint32_t *nm8 = job->nm8;
    size_t a = chunk * CH, b = a + CH < job->nv ? a + CH : job->nv;
    size_t bk = lower_bound(job->big, job->nbig, a);
    for (size_t v = a; v < b; v++) {
        const v4f n = load4(&S[4 * v]);
        uint32_t k = 1;
        if (deg[v] <= 8) {
            /* every slot in straight-line code: past the fan the sentinel's
             * -0 gives a product summing to 0, not counted */
            for (uint32_t j = 0; j < 8; j++) {
                const uint32_t q = nb8[8 * v + j];
                const v4f d = load4(&S[2 * (size_t)q]) * n;
                const uint32_t keep = d[0] + d[1] + d[2] > 0.0f;
                nm8[8 * v + j] = keep ? q : sent;
                k += keep;
            }
        } else {
            for (uint32_t j = 0; j < 8; j++) nm8[8 * v + j] = sent;
            for (uint32_t i = job->bstart[bk]; i < job->bstart[bk + 1]; i++) {
                v4f d = load4(&S[4 * (size_t)job->bnb[i]]) * n;
                job->bflag[i] = d[0] + d[1] + d[2] > 0.0f;
                k += job->bflag[i];
            }
            bk++;
        }
        job->ninv[v] = 1.0f / (float)k;
    }
}

/* One step of normal smoothing: the mean of the vertex's normal and those of
 * the neighbours nmask_task chose (directions only; normalised after the
 * last step), 4 floats per vertex: the 8 slots of the row in order (a -0
 * sentinel adds nothing), then the big vertices again over their flagged
 * fan entries. */
JM_SM_CLONES static void nstep_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    const float *S = job->src, *ninv = job->ninv;
    float *D = job->dst;
    const uint32_t *nm8 = job->nm8;
    size_t a = chunk * CH, b = a + CH < job->nv ? a + CH : job->nv;
    for (size_t v = a; v < b; v++) {
        v4f t = add_slots8(load4(&S[4 * v]), S, &nm8[8 * v]);
        t *= ninv[v];
        memcpy(&D[4 * v], &t, sizeof t);
    }
    for (size_t k = lower_bound(job->big, job->nbig, a); k < job->nbig && job->big[k] < b; k++) {
        const size_t v = job->big[k];
        v4f t = load4(&S[4 * v]);
        for (uint32_t i = job->bstart[k]; i < job->bstart[k + 1]; i++)
            if (job->bflag[i]) t += load4(&S[4 * (size_t)job->bnb[i]]);
        t *= ninv[v];
        memcpy(&D[4 * v], &t, sizeof t);
    }
}

/* 3 floats per vertex to 4 (the fourth 0) and back. */
static void widen(float *d, const float *s, size_t n)
{
    for (size_t v = 0; v < n; v++) d[4 * v] = s[3 * v], d[4 * v + 1] = s[3 * v + 1], d[4 * v + 2] = s[3 * v + 2], d[4 * v + 3] = 0.0f;
}

static void narrow(float *d, const float *s, size_t n)
{
    for (size_t v = 0; v < n; v++) d[3 * v] = s[4 * v], d[3 * v + 1] = s[4 * v + 1], d[3 * v + 2] = s[4 * v + 2];
}

/* Normalises the normals (if tau > 0; src the fallback) and sets the UVs. */
static void finish_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    sm_job *job = arg;
    size_t a = chunk * CH, b = a + CH < job->nv ? a + CH : job->nv;
    if (job->tau > 0.0f)
        for (size_t v = a; v < b; v++) {
            float *n = &job->m->nrm[3 * v];
            store3(n, unit3(load3(n), load3(&job->src[3 * v])));
        }
    if (job->c->uv_mode != JM_UV_NONE)
        jm_uv_all(job->c, &job->m->pos[3 * a], &job->m->nrm[3 * a], &job->m->uv[2 * a], b - a);
}

enum { B_START, B_NB, B_NC, B_W, B_BUF, B_PHI, B_AREA, B_COMP, B_VOL, B_KEEP, B_WIDE_A, B_WIDE_B, B_INV, B_NB8, B_ODD, B_BIG, B_FLAG };

/* Buffer k of the scratch with room for at least `bytes` (contents
 * undefined); NULL when out of memory. */
static void *scratch_buf(jm_post_scratch *s, jm_mem *mem, int k, size_t bytes)
{
    if (bytes == 0) bytes = 1;
    if (s->bytes[k] >= bytes) return s->p[k];
    size_t want = bytes + bytes / 4;
    jm_free(mem, s->p[k], s->bytes[k]);
    s->p[k] = jm_alloc_lasting(mem, want);
    s->bytes[k] = s->p[k] ? want : 0;
    return s->p[k];
}

void jm_post_scratch_free(jm_post_scratch *s, jm_mem *mem)
{
    for (int k = 0; k < JM_POST_BUFS; k++) jm_free(mem, s->p[k], s->bytes[k]);
    memset(s, 0, sizeof *s);
}

/* Per piece (comp[], labels in vertex order) the sums of the volume
 * restoration, from the positions P (4 floats per vertex) and the fans'
 * area vectors A_v (area_task): vol, the signed volume, (1/9) sum_v
 * (p_v - o) . A_v about the piece's first vertex o (orig; the sum over a
 * closed piece of the area vectors is 0, so o changes nothing but the
 * rounding; the triangles' a . N_t / 3 = (a + b + c) . N_t / 9 regrouped by
 * vertex); when den is not NULL, den = sum_v w_v |A_v| / 3 and tot = sum_v
 * |A_v| / 3. A piece's vertices mostly follow each other: its sums stay in
 * registers while they do, the additions in vertex order. */
static void piece_sums(const float *P, const float *area, const float *w, const uint32_t *comp, size_t nv,
                       size_t ncomp, const double *orig, double *vol, double *den, double *tot)
{
    memset(vol, 0, ncomp * sizeof *vol);
    if (den) memset(den, 0, ncomp * sizeof *den), memset(tot, 0, ncomp * sizeof *tot);
    uint32_t cur = 0;
    double vacc = 0.0, dacc = 0.0, tacc = 0.0;
    for (size_t v = 0; v < nv; v++) {
        const float *A = &area[3 * v];
        if (comp[v] != cur) {
            vol[cur] = vacc;
            if (den) den[cur] = dacc, tot[cur] = tacc;
            cur = comp[v];
            vacc = vol[cur];
            if (den) dacc = den[cur], tacc = tot[cur];
        }
        const double *o = &orig[3 * (size_t)cur];
        vacc += ((double)P[4 * v] - o[0]) * A[0] + ((double)P[4 * v + 1] - o[1]) * A[1] +
                ((double)P[4 * v + 2] - o[2]) * A[2];
        if (den) {
            double ar = sqrt((double)A[0] * A[0] + (double)A[1] * A[1] + (double)A[2] * A[2]) / 3.0;
            dacc += (double)w[v] * ar;
            tacc += ar;
        }
    }
    vol[cur] = vacc;
    if (den) den[cur] = dacc, tot[cur] = tacc;
    for (size_t k = 0; k < ncomp; k++) vol[k] /= 9.0;
}

/* What fan_task finds in its range of vertices: the fan entries past the
 * 8th (vertex, next corner, the corner after it, in triangle order), and
 * the count of vertices of more than 8 neighbours and of their entries. */
typedef struct sm_fans {
    uint32_t *over;
    size_t n, cap;
    size_t nbig, nfan;
} sm_fans;

/* The fans of the vertices of range `part` (of jm_pool_threads, each a
 * contiguous range): a pass over every triangle taking the corners at its
 * own vertices, so that each vertex gets its triangles in triangle order
 * whatever the split. Per vertex, for each triangle around it, the two other
 * corners counter-clockwise: the first 8 in its rows of nb8 and nc8
 * (doubled), padded with nv (the -0 sentinel vertex of the wide positions
 * and normals), the others in the range's overflow list; its count in deg
 * and 1 / count in inv. */
static void fan_task(void *arg, size_t part, int worker)
{
    (void)worker;
    sm_job *job = arg;
    const size_t nv = job->nv, ni = job->m->ni_lattice, parts = (size_t)job->nfans;
    const uint32_t va = (uint32_t)(nv * part / parts), vb = (uint32_t)(nv * (part + 1) / parts);
    uint32_t *deg = job->deg, *nb8 = job->nb8, *nc8 = job->nc8;
    float *inv = job->inv;
    sm_fans *f = &job->fans[part];
    const uint32_t *idx = job->m->idx;
    memset(deg + va, 0, (size_t)(vb - va) * sizeof *deg);
    for (size_t t = 0; t + 2 < ni; t += 3) {
        const uint32_t *T = &idx[t];
        for (int k = 0; k < 3; k++) {
            const uint32_t v = T[k];
            if (v - va >= vb - va) continue; /* another range's */
            const uint32_t j = deg[v]++, q = T[k == 2 ? 0 : k + 1], r = T[k == 0 ? 2 : k - 1];
            if (j < 8) {
                nb8[8 * (size_t)v + j] = 2 * q;
                nc8[8 * (size_t)v + j] = 2 * r;
                continue;
            }
            if (f->n == f->cap) {
                const size_t nc = f->cap ? 2 * f->cap : 1024;
                uint32_t *o = jm_realloc(job->mem, f->over, 3 * f->cap * sizeof *o, 3 * nc * sizeof *o);
                if (!o) {
                    job->failed = 1;
                    return;
                }
                f->over = o;
                f->cap = nc;
            }
            f->over[3 * f->n] = v;
            f->over[3 * f->n + 1] = q;
            f->over[3 * f->n + 2] = r;
            f->n++;
        }
    }
    for (size_t v = va; v < vb; v++) {
        const uint32_t d = deg[v];
        inv[v] = d > 0 ? 1.0f / (float)d : 0.0f;
        for (uint32_t j = d; j < 8; j++) nb8[8 * v + j] = 2 * (uint32_t)nv;
        if (d > 8) f->nbig++, f->nfan += d;
    }
}

/* A pass over the vertices in which each thread takes one contiguous range
 * of the chunks, the same range in every pass (the caller starts first and
 * takes the first; one that finds nothing left takes nothing). The passes
 * read what the last one wrote: a thread finding the vertices it wrote in
 * its own cache runs each step about twice as fast at 2 threads as threads
 * taking chunks as they come, whose lines move between cores every step
 * (measured: a step of the 100k block 0.75 ms at 1 and at 2 threads that
 * way). Any split gives the same result. */
static void run_ranges(jm_pool *pool, size_t nchunks, jm_task_fn fn, sm_job *job)
{
    const size_t t = (size_t)jm_pool_threads(pool);
    jm_pool_run(pool, nchunks, (nchunks + t - 1) / t, fn, job);
}

/* The step sizes of one super-time-stepping cycle of k steps, largest and
 * smallest alternately. */
static void sts_steps(int k, float *tau)
{
    double t[CYCLE];
    for (int j = 0; j < k; j++)
        t[j] = 0.95 / ((STS_NU - 1.0) * cos((2.0 * j + 1.0) * M_PI / (2.0 * k)) + 1.0 + STS_NU);
    /* t[] is decreasing: take from both ends */
    int lo = 0, hi = k - 1, o = 0;
    while (lo <= hi) {
        tau[o++] = (float)t[lo++];
        if (lo <= hi) tau[o++] = (float)t[hi--];
    }
}

jm_status jm_smooth_mesh(jm_mem *mem, jm_pool *pool, jm_post_scratch *sc, const jm_config *c, const jm_grid *g,
                         jm_post_mesh *m)
{
    const size_t nv = m->nv_lattice, ni = m->ni_lattice;
    const int iters = c->smooth_iters, niters = c->smooth_normal_iters;
    if (nv == 0 || (iters == 0 && niters == 0)) return JM_OK;
    /* as block.c: normals exist when output or needed for the UVs */
    const int want_nrm = c->normals || c->compensate || c->uv_mode == JM_UV_BOX || c->uv_mode == JM_UV_SPHERICAL;
    const int threads = jm_pool_threads(pool);
    jm_status st = JM_OK;
    size_t nchunks = (nv + CH - 1) / CH;
    uint32_t *deg = scratch_buf(sc, mem, B_START, nv * sizeof *deg);
    uint32_t *nb8 = scratch_buf(sc, mem, B_NB8, nv * 8 * sizeof *nb8);
    uint32_t *nc8 = scratch_buf(sc, mem, B_NC, nv * 8 * sizeof *nc8);
    float *w = scratch_buf(sc, mem, B_W, nv * sizeof *w);
    float *buf = scratch_buf(sc, mem, B_BUF, nv * 3 * sizeof *buf);
    float *inv = scratch_buf(sc, mem, B_INV, nv * sizeof *inv);
    float *phi = NULL, *area = NULL;
    uint32_t *comp = NULL;
    double *vol0 = NULL;
    size_t ncomp = 0;
    sm_slot *slots = NULL;
    sm_corner *corners = NULL;
    sm_fans *fans = NULL;
    /* what every task reads; the rest is set as it is made */
    sm_job job = {.c = c, .g = g, .m = m, .mem = mem, .nv = nv, .deg = deg, .inv = inv, .nb8 = nb8, .nc8 = nc8,
                  .w = w, .nfans = threads};
    if (!deg || !nb8 || !nc8 || !w || !buf || !inv) { st = JM_E_OUT_OF_MEMORY; goto out; }

    /* the fans (fan_task), a range of vertices per thread; all of them for
     * the few vertices of more than 8 (big, bstart, bnb, bnc) */
    fans = jm_calloc(mem, (size_t)threads, sizeof *fans);
    if (!fans) { st = JM_E_OUT_OF_MEMORY; goto out; }
    job.fans = fans;
    jm_pool_run(pool, (size_t)threads, 1, fan_task, &job);
    if (job.failed) { st = JM_E_OUT_OF_MEMORY; goto out; }
    size_t nbig = 0, nfan = 0;
    for (int k = 0; k < threads; k++) nbig += fans[k].nbig, nfan += fans[k].nfan;
    uint32_t *big = scratch_buf(sc, mem, B_BIG, (3 * nbig + 1) * sizeof *big);
    uint32_t *bnb = scratch_buf(sc, mem, B_NB, (2 * nfan + 1) * sizeof *bnb);
    if (!big || !bnb) { st = JM_E_OUT_OF_MEMORY; goto out; }
    uint32_t *bstart = big + nbig, *bfill = bstart + nbig + 1, *bnc = bnb + nfan;
    bstart[0] = 0;
    nbig = 0;
    for (size_t v = 0; v < nv; v++)
        if (deg[v] > 8) {
            big[nbig] = (uint32_t)v;
            bfill[nbig] = bstart[nbig];
            bstart[nbig + 1] = bstart[nbig] + deg[v];
            nbig++;
        }
    if (nbig > 0) {
        /* the big vertices' whole fans: the first 8 from their rows, then
         * the overflow lists (each vertex in one, in triangle order); their
         * place in big in buf for a moment */
        uint32_t *pos = (uint32_t *)buf;
        for (size_t k = 0; k < nbig; k++) {
            const size_t v = big[k];
            pos[v] = (uint32_t)k;
            for (int j = 0; j < 8; j++) {
                bnb[bfill[k] + j] = nb8[8 * v + j] / 2;
                bnc[bfill[k] + j] = nc8[8 * v + j] / 2;
            }
            bfill[k] += 8;
        }
        for (int f = 0; f < threads; f++)
            for (size_t e = 0; e < fans[f].n; e++) {
                const uint32_t *o = &fans[f].over[3 * e], i = bfill[pos[o[0]]]++;
                bnb[i] = o[1];
                bnc[i] = o[2];
            }
    }
    job.bstart = bstart;
    job.bnb = bnb;
    job.bnc = bnc;
    job.big = big;
    job.nbig = nbig;

    if (iters > 0) {
        phi = scratch_buf(sc, mem, B_PHI, g->n * sizeof *phi);
        area = scratch_buf(sc, mem, B_AREA, nv * 3 * sizeof *area);
        comp = scratch_buf(sc, mem, B_COMP, nv * sizeof *comp);
        slots = jm_calloc(mem, (size_t)threads * NSLOT, sizeof *slots);
        corners = jm_calloc(mem, (size_t)threads * NCORNER, sizeof *corners);
        if (!phi || !area || !comp || !slots || !corners) { st = JM_E_OUT_OF_MEMORY; goto out; }
        fullness(c, g, phi);
        job.phi = phi;
        job.slots = slots;
        job.corners = corners;
        job.area = area;
        jm_pool_run(pool, nchunks, 1, weight_task, &job);
        if (job.failed) { st = JM_E_OUT_OF_MEMORY; goto out; }

        /* connected pieces (the cavity pass's where it hands them over):
         * roots the smallest vertex, labels in vertex order, in place (a
         * vertex's root comes before it) */
        const uint32_t *roots = m->roots;
        if (!roots) {
            jm_mesh_pieces(pool, comp, m->idx, nv, ni / 3);
            roots = comp;
        }
        for (size_t v = 0; v < nv; v++) comp[v] = roots[v] == v ? (uint32_t)ncomp++ : comp[roots[v]];
        vol0 = scratch_buf(sc, mem, B_VOL, ncomp * 7 * sizeof *vol0);
        if (!vol0) { st = JM_E_OUT_OF_MEMORY; goto out; }
        double *vol1 = vol0 + ncomp, *den = vol1 + ncomp, *tot = den + ncomp, *orig = tot + ncomp;
        /* each piece's first vertex (its label's first in vertex order) */
        for (size_t v = 0, k = 0; v < nv && k < ncomp; v++)
            if (comp[v] == k) {
                for (int j = 0; j < 3; j++) orig[3 * k + j] = m->pos[3 * v + j];
                k++;
            }

        /* the wide positions have a sentinel vertex nv of -0, which adds
         * nothing to any float: the padding of the fixed fans of 8 */
        float *a = scratch_buf(sc, mem, B_WIDE_A, (nv + 1) * 4 * sizeof *a);
        float *b = scratch_buf(sc, mem, B_WIDE_B, (nv + 1) * 4 * sizeof *b);
        float tau[CYCLE];
        if (!a || !b) { st = JM_E_OUT_OF_MEMORY; goto out; }
        widen(a, m->pos, nv);
        for (int j = 0; j < 4; j++) a[4 * nv + j] = b[4 * nv + j] = -0.0f;
        job.src = a;
        run_ranges(pool, nchunks, area_task, &job);
        piece_sums(a, area, w, comp, nv, ncomp, orig, vol0, NULL, NULL);
        size_t nodd = 0;
        for (size_t v = 0; v < nv; v++) nodd += deg[v] - 1 >= 8 || !(w[v] >= 1e-30f);
        uint32_t *odd = scratch_buf(sc, mem, B_ODD, nodd * sizeof *odd);
        if (!odd) { st = JM_E_OUT_OF_MEMORY; goto out; }
        nodd = 0;
        for (size_t v = 0; v < nv; v++)
            if (deg[v] - 1 >= 8 || !(w[v] >= 1e-30f)) odd[nodd++] = (uint32_t)v;
        job.odd = odd;
        job.nodd = nodd;
        for (int it = 0; it < iters; it += CYCLE) {
            int k = iters - it < CYCLE ? iters - it : CYCLE;
            sts_steps(k, tau);
            for (int s = 0; s < k; s++) {
                job.src = a;
                job.dst = b;
                job.tau = tau[s];
                run_ranges(pool, nchunks, step_task, &job);
                float *t = a; a = b; b = t;
            }
        }
        job.src = job.dst = a; /* the positions of the restoration */

        /* restore each piece's volume: vertex v moves by w_v s along its
         * normal, which changes the volume by s sum_v w_v |A_v| / 3 */
        for (int pass = 0; pass < 2; pass++) {
            run_ranges(pool, nchunks, area_task, &job);
            piece_sums(a, area, w, comp, nv, ncomp, orig, vol1, den, tot);
            /* each vertex's offset at most 5 % of its piece's size (the square
             * root of its area): small voids that smoothing nearly closes
             * would otherwise ask for huge ones */
            for (size_t k = 0; k < ncomp; k++) {
                vol1[k] = den[k] > 0.0 ? (vol0[k] - vol1[k]) / den[k] : 0.0;
                tot[k] = 0.05 * sqrt(3.0 * tot[k]);
            }
            job.comp = comp;
            job.shift = vol1;
            job.cap = tot;
            run_ranges(pool, nchunks, offset_task, &job);
        }
        if (want_nrm) {
            run_ranges(pool, nchunks, area_task, &job);
            run_ranges(pool, nchunks, normal_task, &job);
        }
        narrow(m->pos, a, nv);
    }

    if (want_nrm) {
        /* keep holds the unsmoothed normals: the fallback of a sum that vanishes */
        float *keep = NULL;
        if (niters > 0) {
            keep = area ? area : scratch_buf(sc, mem, B_KEEP, nv * 3 * sizeof *keep);
            float *a = scratch_buf(sc, mem, B_WIDE_A, (nv + 1) * 4 * sizeof *a);
            float *b = scratch_buf(sc, mem, B_WIDE_B, (nv + 1) * 4 * sizeof *b);
            if (!keep || !a || !b) { st = JM_E_OUT_OF_MEMORY; goto out; }
            memcpy(keep, m->nrm, nv * 3 * sizeof *keep);
            widen(a, m->nrm, nv);
            for (int j = 0; j < 4; j++) a[4 * nv + j] = b[4 * nv + j] = -0.0f;
            /* the neighbours that count, into the arrays of the fans' second
             * corners and of the position steps' 1 / counts (used no more) */
            job.nm8 = nc8;
            job.ninv = inv;
            job.bflag = scratch_buf(sc, mem, B_FLAG, (nfan + 1) * sizeof *job.bflag);
            if (!job.bflag) { st = JM_E_OUT_OF_MEMORY; goto out; }
            job.src = a;
            run_ranges(pool, nchunks, nmask_task, &job);
            for (int it = 0; it < niters; it++) {
                job.src = a;
                job.dst = b;
                run_ranges(pool, nchunks, nstep_task, &job);
                float *t = a; a = b; b = t;
            }
            narrow(m->nrm, a, nv);
        }
        job.src = keep ? keep : m->nrm;
        job.tau = 1.0f; /* normalise */
        run_ranges(pool, nchunks, finish_task, &job);
    } else if (c->uv_mode != JM_UV_NONE) {
        job.tau = 0.0f; /* planar UVs: no normals to normalise */
        run_ranges(pool, nchunks, finish_task, &job);
    }

out:
    if (fans)
        for (int k = 0; k < threads; k++) jm_free(mem, fans[k].over, 3 * fans[k].cap * sizeof *fans[k].over);
    jm_free(mem, fans, (size_t)threads * sizeof *fans);
    if (slots)
        for (size_t i = 0; i < (size_t)threads * NSLOT; i++) jm_free(mem, slots[i].buf, slots[i].cap * 4 * sizeof(float));
    jm_free(mem, slots, (size_t)threads * NSLOT * sizeof *slots);
    jm_free(mem, corners, (size_t)threads * NCORNER * sizeof *corners);
    return st;
}
