/* grid.c - sorts particles into cells (counting sort) and computes densities, links and isolation. */
#include "grid.h"
#include "sort.h"
#include "cpu.h"
#include "cubic8.h"
#include "anisotropy.h"
#include "units.h"
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])

/* A particle's coordinates in the library's unit (units.h): times s, an
 * exact power of two. */
static inline void load_units(float p[3], const char *src, float s)
{
    memcpy(p, src, 3 * sizeof(float));
    p[0] *= s;
    p[1] *= s;
    p[2] *= s;
}

static int cmp_id(const void *a, const void *b, const uint32_t *ids)
{
    uint32_t x = ids[*(const uint32_t *)a], y = ids[*(const uint32_t *)b];
    if (x != y) return x < y ? -1 : 1;
    uint32_t ia = *(const uint32_t *)a, ib = *(const uint32_t *)b;
    return ia < ib ? -1 : ia > ib;
}

/* Stable sort of input indices by id (merge sort; ids may repeat). */
static void sort_by_id(uint32_t *idx, uint32_t *tmp, size_t n, const uint32_t *ids)
{
    if (n < 2) return;
    size_t m = n / 2;
    sort_by_id(idx, tmp, m, ids);
    sort_by_id(idx + m, tmp, n - m, ids);
    size_t i = 0, j = m, k = 0;
    while (i < m && j < n) tmp[k++] = cmp_id(&idx[j], &idx[i], ids) < 0 ? idx[j++] : idx[i++];
    while (i < m) tmp[k++] = idx[i++];
    while (j < n) tmp[k++] = idx[j++];
    memcpy(idx, tmp, n * sizeof *idx);
}

typedef struct {
    jm_grid *g;
    const jm_config *c;
    int range;        /* cells to scan each side for the isolation test */
    float iso2;       /* squared isolation radius */
    uint32_t *counts; /* metasphere: links per particle */
    float **soa;      /* per worker: neighbours of a cell as x[], y[], z[] */
    size_t *soa_cap;  /* per worker: floats per coordinate array */
    atomic_int failed; /* set by any worker */
    jm_mem *mem;      /* the context's accounting */
} nb_job;

/* The particle ranges of the (up to 27) non-empty cells around cell ci. */
static int near_ranges(const jm_grid *g, size_t ci, uint32_t r[27][2])
{
    const int32_t *cc = &g->cell_coord[3 * ci];
    int k = 0;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                uint32_t nc = jm_grid_cell(g, (int64_t)cc[0] + dx, (int64_t)cc[1] + dy, (int64_t)cc[2] + dz);
                if (nc == UINT32_MAX) continue;
                r[k][0] = g->cell_start[nc];
                r[k][1] = g->cell_start[nc + 1];
                k++;
            }
    return k;
}

/* Visits the particles of the cells within `range` of cell ci. */
#define FOR_NEAR_CELLS(g, ci, range, ...)                                              \
    do {                                                                                \
        const int32_t *cc_ = &(g)->cell_coord[3 * (size_t)(ci)];                        \
        for (int dz_ = -(range); dz_ <= (range); dz_++)                                 \
            for (int dy_ = -(range); dy_ <= (range); dy_++)                             \
                for (int dx_ = -(range); dx_ <= (range); dx_++) {                       \
                    uint32_t nc_ = jm_grid_cell((g), (int64_t)cc_[0] + dx_,             \
                                                (int64_t)cc_[1] + dy_, (int64_t)cc_[2] + dz_); \
                    if (nc_ == UINT32_MAX) continue;                                    \
                    for (uint32_t j = (g)->cell_start[nc_]; j < (g)->cell_start[nc_ + 1]; j++) { \
                        __VA_ARGS__                                                            \
                    }                                                                   \
                }                                                                       \
    } while (0)

/* Is particle i (in cell ci) without any other particle closer than sqrt(iso2)? */
static int lonely(const jm_grid *g, uint32_t ci, uint32_t i, int range, float iso2)
{
    const float *p = GP(g, i);
    FOR_NEAR_CELLS(g, ci, range, {
        if (j == i) continue;
        const float *q = GP(g, j);
        float dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
        if (dx * dx + dy * dy + dz * dz < iso2) return 0;
    });
    return 1;
}

/* The dense index's entry of the cell holding p (in the library's unit;
 * within the particles' box, which the index covers: floorf is monotone
 * and the box bounds p). */
static inline uint32_t *dense_slot(const jm_grid *g, const float p[3])
{
    const size_t d0 = (size_t)((int64_t)floorf(p[0] * g->inv_cell) - g->dense_lo[0]);
    const size_t d1 = (size_t)((int64_t)floorf(p[1] * g->inv_cell) - g->dense_lo[1]);
    const size_t d2 = (size_t)((int64_t)floorf(p[2] * g->inv_cell) - g->dense_lo[2]);
    return &g->dense[(d2 * (size_t)g->dense_n[1] + d1) * (size_t)g->dense_n[0] + d0];
}

/* ---- the build's passes over all particles or cells, on the pool's
 * threads in chunks; each gives what the serial loop would */
#define PCH ((size_t)1 << 16) /* particles or cells a task */
#define PAIR_CH ((size_t)1 << 12) /* cells a task of the pair count (27 look-ups a cell) */
/* particles from which placement runs as two halves on two threads (below,
 * the halves' start-up costs more than they save) */
#define PLACE_SPLIT ((size_t)1 << 13)

/* Validation and bounds: per chunk the box of its particles (in the
 * library's unit) and the failure of its first bad particle. */
typedef struct {
    const char *base;
    size_t stride, n;
    float unit;
    float *box;    /* per chunk: lo[3], hi[3] */
    jm_status *st; /* per chunk */
} bound_job;

static void bound_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    bound_job *j = arg;
    const size_t a = chunk * PCH, b = a + PCH < j->n ? a + PCH : j->n;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    jm_status st = JM_OK;
    for (size_t i = a; i < b && st == JM_OK; i++) {
        float p[3];
        memcpy(p, j->base + i * j->stride, sizeof p);
        for (int k = 0; k < 3; k++) {
            if (!isfinite(p[k])) { st = JM_E_INVALID_PARTICLE; break; }
            p[k] *= j->unit; /* in the library's unit (units.h) */
            if (!isfinite(p[k])) { st = JM_E_NUMERIC_DOMAIN; break; } /* |x| / 2^unit past FLT_MAX */
            if (p[k] < lo[k]) lo[k] = p[k];
            if (p[k] > hi[k]) hi[k] = p[k];
        }
    }
    memcpy(&j->box[6 * chunk], lo, sizeof lo);
    memcpy(&j->box[6 * chunk + 3], hi, sizeof hi);
    j->st[chunk] = st;
}

/* The particles' box into lo, hi; the first bad particle's failure (in
 * input order), or JM_OK. */
static jm_status bound_all(jm_pool *pool, jm_mem *mem, const char *base, size_t stride, size_t n, float unit,
                           float lo[3], float hi[3])
{
    const size_t nch = (n + PCH - 1) / PCH;
    for (int a = 0; a < 3; a++) lo[a] = INFINITY, hi[a] = -INFINITY;
    if (!nch) return JM_OK;
    float *box = jm_alloc(mem, nch * 6 * sizeof *box);
    jm_status *st = jm_alloc(mem, nch * sizeof *st);
    jm_status r = JM_OK;
    if (!box || !st) r = JM_E_OUT_OF_MEMORY;
    else {
        bound_job j = {base, stride, n, unit, box, st};
        jm_pool_run(pool, nch, 1, bound_task, &j);
        for (size_t k = 0; k < nch && r == JM_OK; k++) {
            r = st[k];
            for (int a = 0; a < 3; a++) {
                if (box[6 * k + a] < lo[a]) lo[a] = box[6 * k + a];
                if (box[6 * k + 3 + a] > hi[a]) hi[a] = box[6 * k + 3 + a];
            }
        }
    }
    jm_free(mem, box, nch * 6 * sizeof *box);
    jm_free(mem, st, nch * sizeof *st);
    return r;
}

/* The neighbour search's pair checks: per chunk of cells, each cell's
 * particles times those of the cells around it (whole numbers: any order
 * of the sums gives the same total below 2^53, and one far over the
 * limit above it). */
typedef struct {
    const jm_grid *g;
    double *part; /* per chunk */
    size_t *most; /* per chunk: the most particles around a cell */
} pair_job;

static void pair_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    pair_job *j = arg;
    const jm_grid *g = j->g;
    const size_t a = chunk * PAIR_CH, b = a + PAIR_CH < g->ncells ? a + PAIR_CH : g->ncells;
    double pairs = 0.0;
    size_t most = 0;
    uint32_t rr[27][2];
    for (size_t ci = a; ci < b; ci++) {
        const int nr = near_ranges(g, ci, rr);
        size_t around = 0;
        for (int k = 0; k < nr; k++) around += rr[k][1] - rr[k][0];
        pairs += (double)(g->cell_start[ci + 1] - g->cell_start[ci]) * (double)around;
        if (around > most) most = around;
    }
    j->part[chunk] = pairs;
    j->most[chunk] = most;
}

/* Placement: particle k (input order, or order[k]) into the next free
 * place of its cell, cells filled in input order. On two threads or more,
 * the first half of the particles fills each cell from its start upwards
 * and the second half, taken backwards, from its end downwards: each cell
 * gets the same particles in the same order as from one pass. */
typedef struct {
    jm_grid *g;
    const char *base;
    size_t stride, n;
    float unit;
    const uint32_t *order, *pcell;
    uint32_t *count; /* 4 a cell: [0] the upward cursor, [1] the downward one */
} place_job;

/* particle k into its cell: at the upward cursor (up) or below the downward one */
static inline void place_one(const place_job *j, size_t k, int up)
{
    float p[3];
    load_units(p, j->base + (size_t)(j->order ? j->order[k] : k) * j->stride, j->unit);
    /* its cell, as the first pass found it */
    const uint32_t ci = j->pcell ? j->pcell[k] : *dense_slot(j->g, p);
    memcpy(GP(j->g, up ? j->count[4 * ci]++ : --j->count[4 * ci + 1]), p, sizeof p);
}

/* half 0: the first half upwards; 1: the second half downwards, backwards */
static void place_task(void *arg, size_t half, int worker)
{
    (void)worker;
    const place_job *j = arg;
    if (half == 0)
        for (size_t k = 0; k < j->n / 2; k++) place_one(j, k, 1);
    else
        for (size_t k = j->n; k-- > j->n / 2;) place_one(j, k, 0);
}

#ifdef JM_CUBIC8
#define JM_DENS_AVX2 1
/* sph_cell's lane sums by hand in AVX2 (where the CPU has it but not
 * AVX-512): each half of 8 lanes (particle p + 3 h against the candidates'
 * group) does what sph_cell's lanes do, the same IEEE operations in the same
 * order, but skips a group whose 8 candidates all lie at d2 >= skip2 =
 * sup2 (1 + 1e-5): there the float q = fl(fl(sqrt d2) inv) is at least 2
 * (sqrt gains 5e-6, inv and the product lose 1.2e-7), so each lane would
 * add W = 0 exactly and count no neighbour. The same sums and counts. */
__attribute__((target("avx2"))) static void dens_avx2(const float *xs, const float *ys, const float *zs, size_t cap,
                                                      const float *p, int halves, float inv, float sup2, float skip2,
                                                      float lane[16], int near[16])
{
    const __m256 zero = _mm256_setzero_ps(), vinv = _mm256_set1_ps(inv);
    const __m256 vsup2 = _mm256_set1_ps(sup2), vskip = _mm256_set1_ps(skip2);
    for (int h = 0; h < halves; h++) {
        const __m256 px = _mm256_set1_ps(p[3 * h]), py = _mm256_set1_ps(p[3 * h + 1]), pz = _mm256_set1_ps(p[3 * h + 2]);
        __m256 acc = zero;
        __m256i cnt = _mm256_setzero_si256();
        for (size_t b = 0; b < cap; b += 8) {
            const size_t o = 2 * b + 8 * (size_t)h;
            const __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(xs + o), px), dy = _mm256_sub_ps(_mm256_loadu_ps(ys + o), py);
            const __m256 dz = _mm256_sub_ps(_mm256_loadu_ps(zs + o), pz);
            const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
            if (!_mm256_movemask_ps(_mm256_cmp_ps(d2, vskip, _CMP_LT_OQ))) continue;
            acc = _mm256_add_ps(acc, jm_cubic_w8(_mm256_mul_ps(_mm256_sqrt_ps(d2), vinv)));
            cnt = _mm256_sub_epi32(cnt, _mm256_castps_si256(_mm256_cmp_ps(d2, vsup2, _CMP_LT_OQ)));
        }
        _mm256_storeu_ps(lane + 8 * h, acc);
        _mm256_storeu_si256((__m256i *)(near + 8 * h), cnt);
    }
}
#endif

/* Densities: the neighbours of a cell are copied once into structure-of-
 * arrays form (padded to 8 with far-away points), then each particle sums
 * its kernel over them in 8 lanes added in a fixed order. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
/* the 8 lanes in one AVX2 or AVX-512 register where the CPU has them: the
 * same operations per lane in the same order (no FMA: ISO C mode keeps
 * -ffp-contract=off), so the same bits on every machine */
JM_CLONES_512_AVX2
#endif
static void sph_cell(void *arg, size_t ci, int worker)
{
    nb_job *job = arg;
    jm_grid *g = job->g;
    const float inv = 1.0f / job->c->sph_h, sup2 = job->c->support * job->c->support;
#ifdef JM_DENS_AVX2
    const int avx2 = jm_cpu_avx2() && !jm_cpu_avx512();
    const float skip2 = sup2 * (1.0f + 1e-5f);
#endif
    uint32_t r[27][2];
    int nr = near_ranges(g, ci, r);
    size_t m = 0;
    for (int k = 0; k < nr; k++) m += r[k][1] - r[k][0];
    size_t cap = (m + 7) & ~(size_t)7;
    if (cap > job->soa_cap[worker]) {
        float *b = jm_realloc(job->mem, job->soa[worker], 6 * job->soa_cap[worker] * sizeof *b, 6 * cap * sizeof *b);
        if (!b) { job->failed = 1; return; }
        job->soa[worker] = b;
        job->soa_cap[worker] = cap;
    }
    /* each group of 8 neighbours twice in a row: 16 lanes for two particles */
    float *xs = job->soa[worker], *ys = xs + 2 * cap, *zs = ys + 2 * cap;
    size_t t = 0;
    for (int k = 0; k < nr; k++)
        for (uint32_t j = r[k][0]; j < r[k][1]; j++, t++) {
            size_t at = 16 * (t >> 3) + (t & 7);
            xs[at] = xs[at + 8] = g->pos[3 * (size_t)j];
            ys[at] = ys[at + 8] = g->pos[3 * (size_t)j + 1];
            zs[at] = zs[at + 8] = g->pos[3 * (size_t)j + 2];
        }
    for (; t < cap; t++) {
        size_t at = 16 * (t >> 3) + (t & 7);
        xs[at] = xs[at + 8] = ys[at] = ys[at + 8] = zs[at] = zs[at + 8] = 1e30f;
    }
    const uint32_t end = g->cell_start[ci + 1];
    double ws = 0.0; /* the cell's census (jm_hood_build adds the cells') */
    uint32_t live = 0;
    for (uint32_t i = g->cell_start[ci]; i < end; i += 2) {
        /* particles i and i + 1 at once, lanes 0-7 and 8-15 (one 16-lane
         * register where the CPU has them), or i alone: each lane gets the
         * same operations in the same order either way, so the same sums */
        const int two = i + 1 < end;
        float lane[16] = {0};
        int near[16] = {0};
#ifdef JM_DENS_AVX2
        if (avx2) dens_avx2(xs, ys, zs, cap, GP(g, i), 1 + two, inv, sup2, skip2, lane, near);
        else
#endif
        if (two) {
            float px[16], py[16], pz[16];
            for (int l = 0; l < 16; l++) {
                const float *q = GP(g, i + (uint32_t)(l >> 3));
                px[l] = q[0];
                py[l] = q[1];
                pz[l] = q[2];
            }
            for (size_t b = 0; b < cap; b += 8)
                for (int l = 0; l < 16; l++) {
                    float dx = xs[2 * b + l] - px[l], dy = ys[2 * b + l] - py[l], dz = zs[2 * b + l] - pz[l];
                    float d2 = dx * dx + dy * dy + dz * dz;
                    lane[l] += jm_cubic_w(sqrtf(d2) * inv); /* 0 beyond the support */
                    near[l] += d2 < sup2;
                }
        } else {
            const float px = g->pos[3 * (size_t)i], py = g->pos[3 * (size_t)i + 1], pz = g->pos[3 * (size_t)i + 2];
            for (size_t b = 0; b < cap; b += 8)
                for (int l = 0; l < 8; l++) {
                    float dx = xs[2 * b + l] - px, dy = ys[2 * b + l] - py, dz = zs[2 * b + l] - pz;
                    float d2 = dx * dx + dy * dy + dz * dz;
                    lane[l] += jm_cubic_w(sqrtf(d2) * inv);
                    near[l] += d2 < sup2;
                }
        }
        for (int k = 0; k <= two; k++) {
            const uint32_t pi = i + (uint32_t)k;
            float sum = 0.0f;
            int count = 0;
            for (int l = 0; l < 8; l++) {
                sum += lane[8 * k + l];
                count += near[8 * k + l];
            }
            g->weight[pi] = 1.0f / sum; /* sum >= w(0) = 1 */
            /* count includes the particle itself (and any exact duplicates) */
            g->isolated[pi] = job->c->templates && count <= 1 && lonely(g, (uint32_t)ci, pi, job->range, job->iso2);
            if (!g->isolated[pi]) {
                ws += g->weight[pi];
                live++;
            }
        }
    }
    g->cell_wsum[ci] = ws;
    g->cell_live[ci] = live;
}

/* Metasphere links of the particles of cell ci: pass 0 counts them (and
 * flags isolated particles), pass 1 writes them at nb_start. */
static void meta_links(nb_job *job, size_t ci, int fill)
{
    jm_grid *g = job->g;
    float link2 = job->c->link * job->c->link;
    uint32_t r[27][2];
    int nr = near_ranges(g, ci, r);
    for (uint32_t i = g->cell_start[ci]; i < g->cell_start[ci + 1]; i++) {
        const float *p = GP(g, i);
        uint32_t e = fill ? g->nb_start[i] : 0;
        for (int k = 0; k < nr; k++)
            for (uint32_t j = r[k][0]; j < r[k][1]; j++) {
                const float *q = GP(g, j);
                float dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
                float d2 = dx * dx + dy * dy + dz * dz;
                if (j == i || !(d2 < link2 && d2 > 0.0f)) continue;
                if (fill) {
                    float D = sqrtf(d2);
                    float *dir = &g->nb_dir[4 * (size_t)e];
                    dir[0] = dx / D;
                    dir[1] = dy / D;
                    dir[2] = dz / D;
                    dir[3] = D;
                    g->nb_owner[e] = i;
                    g->nb[e] = j;
                }
                e++;
            }
        if (!fill) {
            job->counts[i] = e;
            g->isolated[i] = job->c->templates && e == 0 && lonely(g, (uint32_t)ci, i, job->range, job->iso2);
        }
    }
}

static void meta_count(void *arg, size_t ci, int worker)
{
    (void)worker;
    meta_links(arg, ci, 0);
}

static void meta_fill(void *arg, size_t ci, int worker)
{
    (void)worker;
    meta_links(arg, ci, 1);
}


/* ---- the SPH grid in key order, released behind the block sweep */
static atomic_int mode_key = 1, mode_release = 1;
static _Atomic size_t mode_page; /* 0: REL_PAGE */
void jm_testing_grid_mode(int key_order, int release, size_t page)
{
    atomic_store(&mode_key, key_order != 0);
    atomic_store(&mode_release, release);
    atomic_store(&mode_page, page);
}

/* Released in whole 2 MiB pages: the arrays of a grid that may be released
 * start on such a page (so that what is released, and counted, is the same
 * on every run) and are advised huge, so that the next frame, which takes
 * the same memory again, faults it back once per 2 MiB, not per 4 KiB */
#define REL_PAGE ((size_t)2 << 20)
static size_t rel_page(void) { return atomic_load(&mode_page) ? atomic_load(&mode_page) : REL_PAGE; }

/* SPH grids are numbered in key order, and can be released */
static int keyed(const jm_config *c) { return c->field == JM_FIELD_SPH && atomic_load(&mode_key); }

/* An array of a grid: where it can be released and spans a page at least,
 * aligned to the page and advised huge */
static void *grid_alloc(const jm_config *c, jm_grid *g, jm_mem *mem, size_t bytes)
{
    const size_t ps = rel_page();
    if (!keyed(c) || bytes < ps) return jm_alloc(mem, bytes);
    g->aligned_min = ps;
    void *p = jm_alloc_aligned(mem, bytes, ps);
    jm_huge_advise(p, bytes);
    return p;
}

typedef struct {
    uint64_t key;
    uint32_t id;
} key_id;

static inline int key_less(const key_id *a, const key_id *b) { return a->key < b->key; }
JM_SORT_DEFINE(sort_key_id, key_id, key_less)

/* Renumbers the cells of the first pass (count: 4 entries a cell, the count
 * then the absolute coordinates; numbered by first appearance) in key
 * order, z slowest: the dense index or the map's values, pcell (map only)
 * and count follow; g->first_rank keeps each cell's old number and
 * g->slab_first where each z begins. */
static jm_status key_order(jm_grid *g, jm_mem *mem, uint32_t **count, size_t *count_cap, size_t ncells,
                           uint32_t *pcell, size_t n)
{
    uint32_t *rank = jm_alloc(mem, ncells * sizeof *rank); /* new number -> old */
    if (!rank) return JM_E_OUT_OF_MEMORY;
    uint32_t next = 0;
    if (g->dense) { /* z, y, x: the index is laid out in key order */
        const size_t box = (size_t)(g->dense_n[0] * g->dense_n[1] * g->dense_n[2]);
        for (size_t i = 0; i < box; i++)
            if (g->dense[i] != UINT32_MAX) {
                rank[next] = g->dense[i];
                g->dense[i] = next++;
            }
    } else {
        key_id *k = jm_alloc(mem, ncells * sizeof *k);
        if (!k) { jm_free(mem, rank, ncells * sizeof *rank); return JM_E_OUT_OF_MEMORY; }
        for (size_t i = 0; i < ncells; i++) {
            const uint32_t *e = *count + 4 * i;
            k[i].key = jm_key3((int64_t)(int32_t)e[1] - g->origin[0], (int64_t)(int32_t)e[2] - g->origin[1],
                               (int64_t)(int32_t)e[3] - g->origin[2]);
            k[i].id = (uint32_t)i;
        }
        sort_key_id(k, ncells); /* keys are distinct */
        uint32_t *to = (uint32_t *)k; /* old number -> new, in place of the pairs' first half */
        for (size_t i = 0; i < ncells; i++) rank[i] = k[i].id;
        for (size_t i = 0; i < ncells; i++) to[rank[i]] = (uint32_t)i;
        for (size_t s = 0; s < g->cells.cap; s++)
            if (g->cells.keys[s] != JM_HASH_EMPTY) g->cells.vals[s] = to[g->cells.vals[s]];
        for (size_t i = 0; i < n; i++) pcell[i] = to[pcell[i]];
        jm_free(mem, k, ncells * sizeof *k);
    }
    uint32_t *c2 = jm_alloc(mem, 4 * ncells * sizeof *c2);
    if (!c2) { jm_free(mem, rank, ncells * sizeof *rank); return JM_E_OUT_OF_MEMORY; }
    for (size_t i = 0; i < ncells; i++) memcpy(c2 + 4 * i, *count + 4 * (size_t)rank[i], 4 * sizeof *c2);
    jm_free(mem, *count, *count_cap * 4 * sizeof **count);
    *count = c2;
    *count_cap = ncells;
    g->first_rank = rank;
    /* each cell z's first cell */
    const int64_t z0 = (int32_t)c2[3], z1 = (int32_t)c2[4 * (ncells - 1) + 3];
    g->slab_z0 = z0;
    g->slab_n = (size_t)(z1 - z0 + 1);
    g->slab_first = jm_alloc(mem, (g->slab_n + 1) * sizeof *g->slab_first);
    if (!g->slab_first) return JM_E_OUT_OF_MEMORY;
    size_t ci = 0;
    for (size_t j = 0; j <= g->slab_n; j++) {
        while (ci < ncells && (int64_t)(int32_t)c2[4 * ci + 3] < z0 + (int64_t)j) ci++;
        g->slab_first[j] = (uint32_t)ci;
    }
    return JM_OK;
}

/* The whole pages of [base, base + prefix) from the first not yet released
 * (*rel bytes from the first whole page) on: returned to the system and no
 * longer counted. */
static void release_prefix(jm_mem *mem, void *base, size_t prefix, size_t *rel)
{
    const uintptr_t ps = rel_page(), a = (uintptr_t)base, e = a + (prefix & ~(ps - 1));
    if (!base || (a & (ps - 1))) return; /* smaller than a page: not aligned */
    if (e <= a + *rel) return;
#if defined(__linux__) && defined(MADV_DONTNEED)
    void *from = (void *)(a + *rel);
    const size_t len = e - a - *rel;
    if (madvise(from, len, MADV_DONTNEED) != 0) return; /* still held: still counted */
    if (atomic_load(&mode_release) == 2) mprotect(from, len, PROT_NONE);
    jm_mem_sub(mem, len);
    *rel = e - a;
#else
    (void)mem; /* elsewhere the pages are not given back: nothing changes */
#endif
}

/* Frees an array of `bytes` (as counted when taken) of which rel were
 * released; aligned_min: as in jm_grid (an array from jm_alloc goes back
 * through jm_free, to the context's kept blocks). */
static void free_released(jm_mem *mem, void *p, size_t bytes, size_t rel, size_t aligned_min)
{
    if (!p) return;
    if (!rel && (!aligned_min || (bytes ? bytes : 1) < aligned_min)) {
        jm_free(mem, p, bytes);
        return;
    }
#if defined(__linux__)
    if (rel && atomic_load(&mode_release) == 2) {
        mprotect(p, rel, PROT_READ | PROT_WRITE);
    }
#endif
    jm_free(NULL, p, bytes);
    jm_mem_sub(mem, (bytes ? bytes : 1) - rel);
}

void jm_grid_release_below(jm_grid *g, jm_mem *mem, int64_t cz)
{
    if (!g->slab_first || !g->cell_start || atomic_load(&mode_release) == 0 || cz <= g->slab_z0) return;
    const size_t j = (uint64_t)(cz - g->slab_z0) > g->slab_n ? g->slab_n : (size_t)(cz - g->slab_z0);
    const uint32_t cells = g->slab_first[j];
    if (cells <= g->rel_cells) return;
    g->rel_cells = cells;
    const size_t parts = g->cell_start[cells];
    release_prefix(mem, g->pos, 3 * parts * sizeof(float), &g->rel[0]);
    release_prefix(mem, g->weight, parts * sizeof(float), &g->rel[1]);
    release_prefix(mem, g->isolated, parts, &g->rel[2]);
    release_prefix(mem, g->cell_start, cells * sizeof(uint32_t), &g->rel[3]);
    if (g->dense && cz > g->dense_lo[2]) {
        int64_t dz = cz - g->dense_lo[2];
        if (dz > g->dense_n[2]) dz = g->dense_n[2];
        release_prefix(mem, g->dense, (size_t)(dz * g->dense_n[0] * g->dense_n[1]) * sizeof *g->dense, &g->rel[4]);
    }
}

static inline int u64_less(const uint64_t *a, const uint64_t *b) { return *a < *b; }
JM_SORT_DEFINE(sort_u64, uint64_t, u64_less)

int jm_grid_isolated(const jm_grid *g, jm_mem *mem, uint32_t *out)
{
    size_t k = 0;
    if (!g->first_rank) {
        for (size_t i = 0; i < g->n; i++)
            if (g->isolated[i]) out[k++] = (uint32_t)i;
        return 1;
    }
    /* (first appearance of the cell, sorted index), sorted: the particles of
     * one cell are in input order in both numberings */
    const size_t bytes = (g->n_isolated ? g->n_isolated : 1) * sizeof(uint64_t);
    uint64_t *pair = jm_alloc(mem, bytes);
    if (!pair) return 0;
    for (size_t ci = 0; ci < g->ncells; ci++)
        for (uint32_t i = g->cell_start[ci]; i < g->cell_start[ci + 1]; i++)
            if (g->isolated[i]) pair[k++] = (uint64_t)g->first_rank[ci] << 32 | i;
    sort_u64(pair, k); /* distinct */
    for (size_t i = 0; i < k; i++) out[i] = (uint32_t)pair[i];
    jm_free(mem, pair, bytes);
    return 1;
}

void jm_grid_free(jm_grid *g, jm_mem *mem)
{
    size_t n = g->n;
    free_released(mem, g->pos, 3 * n * sizeof(float), g->rel[0], g->aligned_min);
    free_released(mem, g->weight, n * sizeof(float), g->rel[1], g->aligned_min);
    jm_free(mem, g->nb_start, (n + 1) * sizeof(uint32_t));
    jm_free(mem, g->nb, g->nb_count * sizeof(uint32_t));
    jm_free(mem, g->nb_owner, g->nb_count * sizeof(uint32_t));
    jm_free(mem, g->nb_dir, g->nb_count * 4 * sizeof(float));
    free_released(mem, g->cell_start, (g->ncells + 1) * sizeof(uint32_t), g->rel[3], g->aligned_min);
    jm_free(mem, g->cell_coord, 3 * g->ncells * sizeof(int32_t));
    jm_free(mem, g->cell_wsum, (g->ncells ? g->ncells : 1) * sizeof *g->cell_wsum);
    jm_free(mem, g->cell_live, (g->ncells ? g->ncells : 1) * sizeof *g->cell_live);
    free_released(mem, g->isolated, n, g->rel[2], g->aligned_min);
    jm_aniso_free(g, mem);
    if (g->cells.keys) jm_hashmap_free(&g->cells, mem);
    free_released(mem, g->dense, (size_t)(g->dense_n[0] * g->dense_n[1] * g->dense_n[2]) * sizeof *g->dense, g->rel[4],
                  g->aligned_min);
    jm_free(mem, g->first_rank, g->ncells * sizeof *g->first_rank);
    jm_free(mem, g->slab_first, (g->slab_n + 1) * sizeof *g->slab_first);
    memset(g, 0, sizeof *g);
}

void jm_grid_drop_coords(jm_grid *g, jm_mem *mem)
{
    jm_free(mem, g->cell_coord, 3 * g->ncells * sizeof(int32_t));
    g->cell_coord = NULL;
}

jm_status jm_grid_build(jm_grid *g, jm_mem *mem, jm_pool *pool, const jm_config *c, const jm_particles *in)
{
    memset(g, 0, sizeof *g);
    size_t refused = 0; /* the memory a refusal over the limit would have needed */
    size_t n = in->count;
    size_t stride = in->stride ? in->stride : 3 * sizeof(float);
    if (n > UINT32_MAX / 2) return JM_E_TOO_LARGE;
    if (stride < 3 * sizeof(float)) return JM_E_INVALID_ARGUMENT;
    g->n = n;
    g->cell = c->cell;
    g->inv_cell = 1.0f / c->cell;
    const char *base = (const char *)in->xyz;

    /* validate and bound */
    float lo[3], hi[3];
    {
        const jm_status vs = bound_all(pool, mem, base, stride, n, c->unit_in, lo, hi);
        if (vs != JM_OK) return vs;
    }
    for (int a = 0; a < 3; a++) {
        /* lattice node coordinates must stay within +-2^30 cubes */
        if (fabsf(lo[a]) * c->inv_h > 1e9f || fabsf(hi[a]) * c->inv_h > 1e9f) return JM_E_TOO_LARGE;
        g->lo[a] = lo[a];
        g->hi[a] = hi[a];
        g->origin[a] = (int64_t)floorf(lo[a] * g->inv_cell) - 4;
        if ((int64_t)floorf(hi[a] * g->inv_cell) + 4 - g->origin[a] >= JM_KEY_MAX) return JM_E_TOO_LARGE;
    }
    if (n) {
        jm_status dom = jm_unit_check(c, lo, hi, jm_unit_reach(c));
        if (dom != JM_OK) return dom;
    }

    /* processing order: input order (order stays NULL), or by id */
    uint32_t *order = NULL;
    if (in->ids && n > 1) {
        order = jm_alloc(mem, n * sizeof *order);
        if (!order) return JM_E_OUT_OF_MEMORY;
        for (size_t i = 0; i < n; i++) order[i] = (uint32_t)i;
        uint32_t *tmp = jm_alloc(mem, n * sizeof *tmp);
        if (!tmp) { jm_free(mem, order, n * sizeof *order); return JM_E_OUT_OF_MEMORY; }
        sort_by_id(order, tmp, n, in->ids);
        jm_free(mem, tmp, n * sizeof *tmp);
    }

    /* cells: where the particles' box holds no more cells than there are
     * particles (bulk fluid: 8 particles a cell at rest), a dense index over
     * that box (at most 4 bytes a particle, one load a look-up); else a
     * hash map. Either numbers the cells alike, in order of first
     * appearance, and answers every look-up alike. */
    jm_status st = JM_OK;
    double box = 1.0;
    int64_t clo[3] = {0, 0, 0};
    for (int a = 0; a < 3 && n; a++) {
        clo[a] = (int64_t)floorf(lo[a] * g->inv_cell);
        box *= (double)((int64_t)floorf(hi[a] * g->inv_cell) - clo[a] + 1);
    }
    if (n && box <= (double)n + 64.0) {
        for (int a = 0; a < 3; a++) {
            g->dense_lo[a] = clo[a];
            g->dense_n[a] = (int64_t)floorf(hi[a] * g->inv_cell) - clo[a] + 1;
        }
        g->dense = grid_alloc(c, g, mem, (size_t)box * sizeof *g->dense);
        if (!g->dense) st = JM_E_OUT_OF_MEMORY;
        else memset(g->dense, 0xff, (size_t)box * sizeof *g->dense);
    } else {
        st = jm_hashmap_init(&g->cells, mem, n / 2 + 16);
    }
    /* each particle's cell, kept for the pass that places the particles
     * where the hash map answers (a dense index answers again in one load) */
    uint32_t *pcell = NULL;
    if (st == JM_OK && !g->dense) {
        pcell = jm_alloc(mem, (n ? n : 1) * sizeof *pcell);
        if (!pcell) st = JM_E_OUT_OF_MEMORY;
    }
    uint32_t *count = NULL;
    size_t count_cap = 0;
    if (st != JM_OK) goto fail;
    /* cells numbered in order of first appearance; grow the map as needed */
    size_t ncells = 0;
    for (size_t k = 0; k < n; k++) {
        float p[3];
        load_units(p, base + (size_t)(order ? order[k] : k) * stride, c->unit_in);
        int64_t cx = (int64_t)floorf(p[0] * g->inv_cell) - g->origin[0];
        int64_t cy = (int64_t)floorf(p[1] * g->inv_cell) - g->origin[1];
        int64_t cz = (int64_t)floorf(p[2] * g->inv_cell) - g->origin[2];
        uint32_t *v;
        if (g->dense) {
            v = dense_slot(g, p);
        } else {
            if (g->cells.count * 2 + 2 > g->cells.cap) {
                /* rehash into a bigger table */
                jm_hashmap big;
                st = jm_hashmap_init(&big, mem, g->cells.cap);
                if (st != JM_OK) goto fail;
                for (size_t s = 0; s < g->cells.cap; s++)
                    if (g->cells.keys[s] != JM_HASH_EMPTY) *jm_hashmap_upsert(&big, g->cells.keys[s]) = g->cells.vals[s];
                jm_hashmap_free(&g->cells, mem);
                g->cells = big;
            }
            v = jm_hashmap_upsert(&g->cells, jm_key3(cx, cy, cz));
        }
        if (*v == UINT32_MAX) {
            if (ncells == count_cap) {
                size_t nc = count_cap ? count_cap * 2 : 256;
                uint32_t *bigger = jm_realloc(mem, count, count_cap * 4 * sizeof *count, nc * 4 * sizeof *count);
                if (!bigger) { st = JM_E_OUT_OF_MEMORY; goto fail; }
                count = bigger;
                count_cap = nc;
            }
            count[4 * ncells] = 0;
            count[4 * ncells + 1] = (uint32_t)(cx + g->origin[0]);
            count[4 * ncells + 2] = (uint32_t)(cy + g->origin[1]);
            count[4 * ncells + 3] = (uint32_t)(cz + g->origin[2]);
            *v = (uint32_t)ncells++;
        }
        count[4 * *v]++;
        if (pcell) pcell[k] = *v;
    }
    g->ncells = ncells;
    /* SPH: the cells in key order (z slowest), so that the particles lie in
     * memory slab by slab, as the blocks are swept, and the sweep can give
     * them back behind it (jm_grid_release_below). Every sum over particles
     * enumerates cells by their coordinates and a cell's particles in input
     * order, so the numbering changes no value; the isolated particles keep
     * the input's order through first_rank (jm_grid_isolated). */
    if (keyed(c) && ncells) {
        st = key_order(g, mem, &count, &count_cap, ncells, pcell, n);
        if (st != JM_OK) goto fail;
    }
    const size_t start_bytes = (ncells + 1) * sizeof *g->cell_start, pos_bytes = (n ? 3 * n : 1) * sizeof(float);
    g->cell_start = grid_alloc(c, g, mem, start_bytes);
    g->cell_coord = jm_alloc(mem, (ncells ? 3 * ncells : 1) * sizeof *g->cell_coord);
    g->pos = grid_alloc(c, g, mem, pos_bytes);
    g->isolated = grid_alloc(c, g, mem, n ? n : 1);
    if (g->isolated) memset(g->isolated, 0, n ? n : 1);
    if (!g->cell_start || !g->cell_coord || !g->pos || !g->isolated) { st = JM_E_OUT_OF_MEMORY; goto fail; }
    uint32_t acc = 0;
    for (size_t ci = 0; ci < ncells; ci++) {
        g->cell_start[ci] = acc;
        acc += count[4 * ci];
        count[4 * ci] = g->cell_start[ci]; /* becomes the fill cursor */
        for (int a = 0; a < 3; a++) g->cell_coord[3 * ci + a] = (int32_t)count[4 * ci + 1 + a];
    }
    g->cell_start[ncells] = acc;
    {
        place_job pj = {g, base, stride, n, c->unit_in, order, pcell, count};
        if (jm_pool_threads(pool) >= 2 && n >= PLACE_SPLIT) {
            for (size_t ci = 0; ci < ncells; ci++) count[4 * ci + 1] = g->cell_start[ci + 1]; /* coordinates copied */
            jm_pool_run(pool, 2, 1, place_task, &pj);
        } else {
            for (size_t k = 0; k < n; k++) place_one(&pj, k, 1);
        }
    }
    jm_free(mem, count, count_cap * 4 * sizeof *count);
    count = NULL;
    jm_free(mem, pcell, (n ? n : 1) * sizeof *pcell);
    pcell = NULL;
    jm_free(mem, order, (n ? n : 1) * sizeof *order);
    order = NULL;

    /* bounded work: the neighbour search below checks every particle of a
     * cell against those of the 27 cells around it; refuse before it starts
     * when that is beyond JM_MAX_PAIR_CHECKS (a frame of duplicates, or a
     * radius far too large, would otherwise take hours) */
    size_t most = 0; /* the most particles around a cell (sph_cell's buffers) */
    {
        const size_t nch = (ncells + PAIR_CH - 1) / PAIR_CH;
        double *part = jm_alloc(mem, (nch ? nch : 1) * (sizeof *part + sizeof(size_t))), pairs = 0.0;
        if (!part) { st = JM_E_OUT_OF_MEMORY; goto fail; }
        pair_job pj = {g, part, (size_t *)(part + (nch ? nch : 1))};
        jm_pool_run(pool, nch, 1, pair_task, &pj);
        for (size_t k = 0; k < nch; k++) {
            pairs += part[k];
            if (pj.most[k] > most) most = pj.most[k];
        }
        jm_free(mem, part, (nch ? nch : 1) * (sizeof *part + sizeof(size_t)));
        if (pairs > JM_MAX_PAIR_CHECKS(n)) { st = JM_E_TOO_DENSE; goto fail; }
    }

    /* neighbour data */
    nb_job job = {g, c, 1, 0, NULL, NULL, NULL, 0, mem};
    float iso;
    if (c->field == JM_FIELD_SPH) iso = 2.0f * c->support;
    else iso = fmaxf(c->link, 2.6f * c->r);
    job.iso2 = iso * iso;
    job.range = (int)ceilf(iso / c->cell);
    if (c->field == JM_FIELD_SPH) {
        g->weight = grid_alloc(c, g, mem, (n ? n : 1) * sizeof(float));
        g->cell_wsum = jm_alloc(mem, (ncells ? ncells : 1) * sizeof *g->cell_wsum);
        g->cell_live = jm_alloc(mem, (ncells ? ncells : 1) * sizeof *g->cell_live);
        if (!g->weight || !g->cell_wsum || !g->cell_live) { st = JM_E_OUT_OF_MEMORY; goto fail; }
        int nt = jm_pool_threads(pool);
        job.soa = jm_calloc(mem, (size_t)nt, sizeof *job.soa);
        job.soa_cap = jm_calloc(mem, (size_t)nt, sizeof *job.soa_cap);
        if (!job.soa || !job.soa_cap) {
            jm_free(mem, job.soa, (size_t)nt * sizeof *job.soa);
            jm_free(mem, job.soa_cap, (size_t)nt * sizeof *job.soa_cap);
            st = JM_E_OUT_OF_MEMORY;
            goto fail;
        }
        /* every worker's buffer at once as large as the largest cell needs:
         * the same blocks whichever worker takes which cells (a context's
         * next frame then finds them again, keep.h) */
        for (int w = 0; w < nt && !job.failed; w++) {
            const size_t cap = (most + 7) & ~(size_t)7;
            job.soa[w] = jm_alloc(mem, 6 * (cap ? cap : 8) * sizeof(float));
            if (job.soa[w]) job.soa_cap[w] = cap ? cap : 8;
            else job.failed = 1;
        }
        if (!job.failed) jm_pool_run(pool, ncells, 16, sph_cell, &job);
        for (int w = 0; w < nt; w++) jm_free(mem, job.soa[w], 6 * job.soa_cap[w] * sizeof(float));
        jm_free(mem, job.soa, (size_t)nt * sizeof *job.soa);
        jm_free(mem, job.soa_cap, (size_t)nt * sizeof *job.soa_cap);
        if (job.failed) { st = JM_E_OUT_OF_MEMORY; goto fail; }
    } else {
        g->nb_start = jm_alloc(mem, (n + 1) * sizeof(uint32_t));
        if (!g->nb_start) { st = JM_E_OUT_OF_MEMORY; goto fail; }
        job.counts = g->nb_start;
        jm_pool_run(pool, ncells, 16, meta_count, &job);
        size_t total = 0;
        for (size_t i = 0; i < n; i++) {
            uint32_t k = g->nb_start[i];
            g->nb_start[i] = (uint32_t)total;
            total += k;
            /* links are numbered after the n balls, below the sentinel */
            if ((uint64_t)n + total >= UINT32_MAX) { st = JM_E_TOO_LARGE; goto fail; }
        }
        g->nb_start[n] = (uint32_t)total;
        g->nb_count = total;
        if (!total) g->nb_count = 1; /* what is allocated */
        /* over 1000 links a particle on average (bulk fluid at rest
         * spacing 2r has 18): the radius is far too large for the spacing */
        if (total > 1000 * (size_t)n) { st = JM_E_TOO_DENSE; goto fail; }
        /* 24 bytes a link: checked against the limit before it is taken */
        if (c->max_bytes && atomic_load(&mem->current) + g->nb_count * 24 > c->max_bytes) {
            refused = atomic_load(&mem->current) + g->nb_count * 24;
            st = JM_E_TOO_LARGE;
            goto fail;
        }
        g->nb = jm_alloc(mem, g->nb_count * sizeof(uint32_t));
        g->nb_owner = jm_alloc(mem, g->nb_count * sizeof(uint32_t));
        g->nb_dir = jm_alloc(mem, g->nb_count * 4 * sizeof(float));
        if (!g->nb || !g->nb_owner || !g->nb_dir) { st = JM_E_OUT_OF_MEMORY; goto fail; }
        jm_pool_run(pool, ncells, 16, meta_fill, &job);
    }
    for (size_t i = 0; i < n; i++) g->n_isolated += g->isolated[i];
    return JM_OK;

fail:
    jm_free(mem, count, count_cap * 4 * sizeof *count);
    jm_free(mem, pcell, (n ? n : 1) * sizeof *pcell);
    jm_free(mem, order, (n ? n : 1) * sizeof *order);
    jm_grid_free(g, mem);
    g->refused_bytes = refused;
    return st;
}
