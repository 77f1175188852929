/* blockset.c - the frame's active blocks: every block a particle's influence reaches, sorted by key, and the memory estimate. */
#include "extract/blockset.h"
#include "context.h"
#include "core/units.h"
#include "core/sort.h"
#include <math.h>
#include <string.h>

static inline int u64_less(const uint64_t *a, const uint64_t *b) { return *a < *b; }
JM_SORT_DEFINE(sort_u64, uint64_t, u64_less)

/* Working memory estimate for a frame of n particles, links metasphere
 * neck links (24 bytes each: jm_grid's nb, nb_owner, nb_dir) and nblocks
 * blocks. */
size_t jm_frame_estimate(const jm_config *c, size_t n, double links, size_t nblocks, int threads)
{
    size_t B = (size_t)c->block;
    double per_particle = 12 + 4 + 4 + 1 + 16 + 4 + (c->aniso ? JM_AN_STRIDE * sizeof(float) : 0);
    /* a block crossed by the surface: about 2 B^2 vertices (32 bytes with
     * normal and uv) and 4 B^2 triangle indices... counted for a quarter of
     * the blocks, the rest being inside or outside the fluid */
    double per_block = 48 + 0.25 * (2.0 * B * B * (32 + 8) + 4.0 * B * B * 12);
    double bytes = (double)n * per_particle + (c->field == JM_FIELD_METASPHERE ? 24.0 * links : 0.0) +
                   (double)nblocks * per_block +
                   (double)threads * (double)jm_scratch_bytes((int)B);
    return bytes > (double)SIZE_MAX ? SIZE_MAX : (size_t)bytes;
}

/* Lattices far finer than the particles (a tiny cube size for the radius)
 * would sample absurd numbers of nodes: at most this many (a dense
 * 100M-particle frame at r/2 samples about 8e9). */
#define JM_MAX_SAMPLES 3.4e10

jm_status jm_blocks_build(const jm_config *c, const jm_grid *g, jm_mem *mem, jm_block_set *bs, int threads,
                              size_t *out_estimate)
{
    memset(bs, 0, sizeof *bs);
    const double BW = (double)c->block * c->h;
    const float infl = c->influence;
    double box = 1.0;
    int64_t span[3];
    for (int a = 0; a < 3; a++) {
        bs->origin[a] = (int64_t)floor((g->lo[a] - infl) / BW) - 2;
        int64_t top = (int64_t)floor((g->hi[a] + infl) / BW) + 2;
        if (top - bs->origin[a] >= JM_KEY_MAX) return JM_E_TOO_LARGE;
        span[a] = top - bs->origin[a];
        box *= (double)(span[a] + 1);
    }
    /* before inserting anything: an upper bound of the blocks, refused when
     * absurd or when its memory estimate is over the limit */
    double cand = 0.0;
    for (size_t ci = 0; ci < g->ncells; ci++) {
        double v = 1.0;
        for (int a = 0; a < 3; a++) {
            double cl = (double)g->cell_coord[3 * ci + a] * g->cell;
            v *= floor((cl + g->cell + infl) / BW) - floor((cl - infl) / BW) + 1.0;
        }
        cand += v;
    }
    double bound = cand < box ? cand : box;
    *out_estimate = jm_frame_estimate(c, g->n, (double)g->nb_count, bound > 1e15 ? (size_t)1e15 : (size_t)bound, threads);
    const double per_block = (double)(c->block + 1) * (c->block + 1) * (c->block + 1);
    if (bound * per_block > JM_MAX_SAMPLES || (c->max_bytes && *out_estimate > c->max_bytes)) return JM_E_TOO_LARGE;
    jm_hashmap set;
    /* sized for at most the bound (bulk fluid: far fewer blocks than cells;
     * the keys are sorted below, so the size changes nothing else) */
    double expect = (double)g->ncells * 2 + 16;
    if (bound + 16 < expect) expect = bound + 16;
    jm_status st = jm_hashmap_init(&set, mem, (size_t)expect);
    if (st != JM_OK) return st;
    for (size_t ci = 0; ci < g->ncells; ci++) {
        int any = 0;
        for (uint32_t p = g->cell_start[ci]; p < g->cell_start[ci + 1] && !any; p++) any = !g->isolated[p];
        if (!any) continue;
        int64_t lo[3], hi[3];
        for (int a = 0; a < 3; a++) {
            double cl = (double)g->cell_coord[3 * ci + a] * g->cell;
            lo[a] = (int64_t)floor((cl - infl) / BW) - bs->origin[a];
            hi[a] = (int64_t)floor((cl + g->cell + infl) / BW) - bs->origin[a];
            if (lo[a] < 0) lo[a] = 0;
            if (hi[a] > span[a]) hi[a] = span[a]; /* keys stay within their bits */
        }
        for (int64_t z = lo[2]; z <= hi[2]; z++)
            for (int64_t y = lo[1]; y <= hi[1]; y++)
                for (int64_t x = lo[0]; x <= hi[0]; x++) {
                    if (set.count * 2 + 2 > set.cap) {
                        jm_hashmap big;
                        st = jm_hashmap_init(&big, mem, set.cap);
                        if (st != JM_OK) { jm_hashmap_free(&set, mem); return st; }
                        for (size_t s = 0; s < set.cap; s++)
                            if (set.keys[s] != JM_HASH_EMPTY) *jm_hashmap_upsert(&big, set.keys[s]) = 0;
                        jm_hashmap_free(&set, mem);
                        set = big;
                    }
                    *jm_hashmap_upsert(&set, jm_key3(x, y, z)) = 0;
                }
    }
    bs->count = set.count;
    bs->key = jm_alloc(mem, (set.count ? set.count : 1) * sizeof *bs->key);
    if (!bs->key) { jm_hashmap_free(&set, mem); return JM_E_OUT_OF_MEMORY; }
    size_t k = 0;
    for (size_t s = 0; s < set.cap; s++)
        if (set.keys[s] != JM_HASH_EMPTY) bs->key[k++] = set.keys[s];
    jm_hashmap_free(&set, mem);
    sort_u64(bs->key, bs->count); /* distinct */
    st = jm_hashmap_init(&bs->map, mem, bs->count + 1);
    if (st != JM_OK) return st;
    for (size_t i = 0; i < bs->count; i++) *jm_hashmap_upsert(&bs->map, bs->key[i]) = (uint32_t)i;
    return JM_OK;
}

void jm_blocks_free(jm_block_set *bs, jm_mem *mem)
{
    if (bs->cell_start) {
        jm_free(mem, bs->cells, (bs->ncells ? bs->ncells : 1) * sizeof *bs->cells);
        jm_free(mem, bs->cell_start, (bs->count + 1) * sizeof *bs->cell_start);
    }
    jm_free(mem, bs->key, (bs->count ? bs->count : 1) * sizeof *bs->key);
    if (bs->map.keys) jm_hashmap_free(&bs->map, mem);
    memset(bs, 0, sizeof *bs);
}

jm_status jm_estimate_bytes(jm_context *ctx, const jm_particles *particles, size_t *out_bytes)
{
    if (!ctx || !particles || !out_bytes || (particles->count && !particles->xyz)) return JM_E_INVALID_ARGUMENT;
    jm_config cb = ctx->cfg;
    const jm_config *c = &cb;
    /* anisotropic kernels: at most k_s k_r^(2/3) (or k_n) supports from a
     * centre moved at most lambda r_n */
    if (cb.aniso) {
        float k = cb.an_ks * cbrtf(cb.an_kr * cb.an_kr);
        cb.influence = cb.support * (k > cb.an_kn ? k : cb.an_kn) + cb.an_lambda * cb.an_radius;
    }
    size_t n = particles->count;
    /* at most the blocks a particle's reach can touch, and at most the
     * bounding box's blocks */
    double BW = (double)c->block * c->h;
    double per = ceil(2.0 * c->influence / BW) + 1;
    double blocks = (double)n * per * per * per, links = 0.0;
    size_t stride = particles->stride ? particles->stride : 12;
    if (stride < 12) return JM_E_INVALID_ARGUMENT; /* as jm_mesh_particles */
    if (n) {
        float lo[3], hi[3];
        memcpy(lo, particles->xyz, sizeof lo);
        for (int a = 0; a < 3; a++)
            if (!isfinite(lo[a])) return JM_E_INVALID_PARTICLE;
        memcpy(hi, lo, sizeof hi);
        for (size_t i = 1; i < n; i++) {
            float p[3];
            memcpy(p, (const char *)particles->xyz + i * stride, sizeof p);
            for (int a = 0; a < 3; a++) {
                if (!isfinite(p[a])) return JM_E_INVALID_PARTICLE;
                lo[a] = fminf(lo[a], p[a]);
                hi[a] = fmaxf(hi[a], p[a]);
            }
        }
        for (int a = 0; a < 3; a++) { /* in the library's unit (units.h) */
            lo[a] *= c->unit_in;
            hi[a] *= c->unit_in;
        }
        jm_status dom = jm_unit_check(c, lo, hi, jm_unit_reach(c)); /* as jm_grid_build */
        if (dom != JM_OK) return dom;
        double box = 1, vol = 1;
        for (int a = 0; a < 3; a++) {
            box *= floor((hi[a] - lo[a] + 2 * c->influence) / BW) + 2;
            vol *= (double)hi[a] - lo[a] + c->link;
        }
        if (box < blocks) blocks = box;
        /* metasphere links: the particles within the link distance L of
         * each, at the mean density over their bounds (each side widened by
         * L, so a line or a sheet is not taken for a dense block): about
         * right for bulk (50,000 particles 0.05 apart at r = 0.1: 700 each,
         * against about 1000 inside), within 2x for jets and sheets */
        if (c->field == JM_FIELD_METASPHERE && n > 1) {
            double each = (double)n / vol * (4.0 / 3.0) * M_PI * (double)c->link * c->link * c->link;
            links = (double)n * (each < (double)(n - 1) ? each : (double)(n - 1));
        }
    }
    size_t nb = blocks > 1e15 ? (size_t)1e15 : (size_t)blocks;
    *out_bytes = jm_frame_estimate(c, n, links, nb, ctx->threads);
    return JM_OK;
}
