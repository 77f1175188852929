/* density.c - the SPH grid's densities: each particle's kernel sum over the cells around it, 16 lanes at a time, and isolation. */
#include "grid/density.h"
#include "grid/release.h"
#include "core/cpu.h"
#include "core/cubic8.h"

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
/* the 8 lanes in one AVX2 or AVX-512 register where the CPU has them (the
 * level of core/cpu.h): the same operations per lane in the same order (no
 * FMA: ISO C mode keeps -ffp-contract=off), so the same bits on every machine */
JM_BODY void sph_cell_body(void *arg, size_t ci, int worker)
{
    jm_nb_job *job = arg;
    jm_grid *g = job->g;
    const float inv = 1.0f / job->c->sph_h, sup2 = job->c->support * job->c->support;
#ifdef JM_DENS_AVX2
    const int avx2 = jm_cpu_avx2() && !jm_cpu_avx512();
    const float skip2 = sup2 * (1.0f + 1e-5f);
#endif
    uint32_t r[27][2];
    int nr = jm_near_ranges(g, ci, r);
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
            g->isolated[pi] = job->c->templates && count <= 1 && jm_lonely(g, (uint32_t)ci, pi, job->range, job->iso2);
            if (!g->isolated[pi]) {
                ws += g->weight[pi];
                live++;
            }
        }
    }
    g->cell_wsum[ci] = ws;
    g->cell_live[ci] = live;
}
JM_KERNEL_V4(static, void, sph_cell, sph_cell_body, (void *arg, size_t ci, int worker), (arg, ci, worker))

jm_status jm_grid_densities(jm_nb_job *job, jm_pool *pool, size_t most)
{
    jm_grid *g = job->g;
    jm_mem *mem = job->mem;
    const size_t n = g->n, ncells = g->ncells;
    g->weight = jm_grid_alloc(job->c, g, mem, (n ? n : 1) * sizeof(float));
    g->cell_wsum = jm_alloc(mem, (ncells ? ncells : 1) * sizeof *g->cell_wsum);
    g->cell_live = jm_alloc(mem, (ncells ? ncells : 1) * sizeof *g->cell_live);
    if (!g->weight || !g->cell_wsum || !g->cell_live) return JM_E_OUT_OF_MEMORY;
    int nt = jm_pool_threads(pool);
    job->soa = jm_calloc(mem, (size_t)nt, sizeof *job->soa);
    job->soa_cap = jm_calloc(mem, (size_t)nt, sizeof *job->soa_cap);
    if (!job->soa || !job->soa_cap) {
        jm_free(mem, job->soa, (size_t)nt * sizeof *job->soa);
        jm_free(mem, job->soa_cap, (size_t)nt * sizeof *job->soa_cap);
        return JM_E_OUT_OF_MEMORY;
    }
    /* every worker's buffer at once as large as the largest cell needs:
     * the same blocks whichever worker takes which cells (a context's
     * next frame then finds them again, keep.h) */
    for (int w = 0; w < nt && !job->failed; w++) {
        const size_t cap = (most + 7) & ~(size_t)7;
        job->soa[w] = jm_alloc(mem, 6 * (cap ? cap : 8) * sizeof(float));
        if (job->soa[w]) job->soa_cap[w] = cap ? cap : 8;
        else job->failed = 1;
    }
    if (!job->failed) jm_pool_run(pool, ncells, 16, sph_cell, job);
    for (int w = 0; w < nt; w++) jm_free(mem, job->soa[w], 6 * job->soa_cap[w] * sizeof(float));
    jm_free(mem, job->soa, (size_t)nt * sizeof *job->soa);
    jm_free(mem, job->soa_cap, (size_t)nt * sizeof *job->soa_cap);
    return job->failed ? JM_E_OUT_OF_MEMORY : JM_OK;
}
