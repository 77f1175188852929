/* mesh.c - the context and the frame pipeline: grid, active blocks, batches, stitching, templates. */
#include "extract/block.h"
#include "post/cavities.h"
#include "post/post.h"
#include "field/meta/metavertex.h"
#include "core/units.h"
#include "core/grow.h"
#include "core/keep.h"
#include "core/sort.h"
#include "post/interpolate.h"
#include "grid/select.h"
#include "post/small_pieces.h"
#include "post/clip.h"
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

struct jm_context {
    jm_params params; /* with defaults filled in */
    jm_config cfg;
    jm_pool *pool;
    int threads;
    jm_mem mem;
    jm_scratch *scratch;
    int nscratch;
    size_t scratch_cap; /* jm_scratch structs allocated */
    jm_bout *bouts;
    size_t nbouts;
    /* the last mesh */
    float *pos, *nrm, *uv;
    size_t capv;
    uint32_t *idx;
    size_t capi;
    size_t nv, ni;
    /* the sphere template (isolated particles) */
    int have_tmpl;
    float *t_pos, *t_nrm;
    uint32_t *t_idx;
    size_t t_nv, t_ni;
    float t_origin[3];
    jm_post_scratch post; /* post-processing arrays (post.h) */
};

static int cpu_count(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : (n > JM_MAX_THREADS ? JM_MAX_THREADS : (int)n);
}

static void drop_template(jm_context *ctx)
{
    jm_free(&ctx->mem, ctx->t_pos, ctx->t_nv * 3 * sizeof(float));
    jm_free(&ctx->mem, ctx->t_nrm, ctx->t_nv * 3 * sizeof(float));
    jm_free(&ctx->mem, ctx->t_idx, ctx->t_ni * sizeof(uint32_t));
    ctx->t_pos = ctx->t_nrm = NULL;
    ctx->t_idx = NULL;
    ctx->t_nv = ctx->t_ni = 0;
    ctx->have_tmpl = 0;
}

/* The growing buffers of a worker's scratch, counted as they grew (their
 * mem pointers, set in ensure_scratch) and freed by jm_scratch_free. */
static size_t scratch_grown(const jm_scratch *s)
{
    return s->hood.cap * 2 * sizeof(uint32_t) + s->soa.cap * 4 * sizeof(float) + s->cap_order * sizeof(uint32_t) +
           s->an_list.cap * 10 * sizeof(float) + s->an_cand.cap * sizeof(uint32_t);
}

static void drop_scratch(jm_context *ctx)
{
    for (int i = 0; i < ctx->nscratch; i++) {
        jm_mem_sub(&ctx->mem, jm_scratch_bytes(ctx->scratch[i].B) + scratch_grown(&ctx->scratch[i]));
        jm_scratch_free(&ctx->scratch[i]);
    }
    jm_free(&ctx->mem, ctx->scratch, ctx->scratch_cap * sizeof *ctx->scratch);
    ctx->scratch = NULL;
    ctx->scratch_cap = 0;
    ctx->nscratch = 0;
}

jm_status jm_context_set_params(jm_context *ctx, const jm_params *params)
{
    if (!ctx || !params) return JM_E_INVALID_ARGUMENT;
    jm_config c;
    jm_params filled, units;
    if (jm_params_check(params, NULL) != JM_OK) return JM_E_INVALID_ARGUMENT;
    /* lengths in units of a power of two near r (units.h) */
    const int unit = jm_unit_exponent(params->radius);
    jm_unit_params(params, unit, &units);
    jm_status st = jm_config_resolve(&units, &c, &filled);
    if (st != JM_OK) return st;
    c.unit = unit;
    c.unit_in = ldexpf(1.0f, -unit);
    jm_unit_world_params(&filled, unit, params);
    int threads = filled.threads ? filled.threads : cpu_count();
    if (threads > JM_MAX_THREADS) threads = JM_MAX_THREADS;
    filled.threads = threads;
    if (!ctx->pool || threads != ctx->threads) {
        jm_pool *pool = NULL;
        st = jm_pool_create(threads, &pool);
        if (st != JM_OK) return st;
        jm_pool_free(ctx->pool);
        ctx->pool = pool;
        ctx->threads = threads;
    }
    if (memcmp(&c, &ctx->cfg, sizeof c) != 0) drop_template(ctx);
    if (ctx->nscratch && (ctx->scratch[0].B != c.block || ctx->nscratch != threads)) drop_scratch(ctx);
    ctx->cfg = c;
    ctx->params = filled;
    return JM_OK;
}

jm_status jm_context_create(const jm_params *params, jm_context **out_ctx)
{
    if (!out_ctx) return JM_E_INVALID_ARGUMENT;
    *out_ctx = NULL;
    if (!params) return JM_E_INVALID_ARGUMENT;
    jm_context *ctx = calloc(1, sizeof *ctx);
    if (!ctx) return JM_E_OUT_OF_MEMORY;
    /* freed working memory kept for the next frames (keep.h) */
    ctx->mem.keep = jm_keep_create();
    if (!ctx->mem.keep) {
        free(ctx);
        return JM_E_OUT_OF_MEMORY;
    }
    jm_status st = jm_context_set_params(ctx, params);
    if (st != JM_OK) {
        jm_context_free(ctx);
        return st;
    }
    *out_ctx = ctx;
    return JM_OK;
}

void jm_context_get_params(const jm_context *ctx, jm_params *out_params)
{
    if (ctx && out_params) *out_params = ctx->params;
}

/* The mesh's vertex arrays (positions, normals, UVs: one capacity) and its
 * index array, given back */
static void free_vertices(jm_context *ctx)
{
    jm_grow_free(&ctx->mem, ctx->pos, ctx->capv * 3 * sizeof(float));
    jm_grow_free(&ctx->mem, ctx->nrm, ctx->capv * 3 * sizeof(float));
    jm_grow_free(&ctx->mem, ctx->uv, ctx->capv * 2 * sizeof(float));
    ctx->pos = ctx->nrm = ctx->uv = NULL;
    ctx->capv = 0;
}

static void free_indices(jm_context *ctx)
{
    jm_grow_free(&ctx->mem, ctx->idx, ctx->capi * sizeof(uint32_t));
    ctx->idx = NULL;
    ctx->capi = 0;
}

void jm_context_free(jm_context *ctx)
{
    if (!ctx) return;
    drop_template(ctx);
    drop_scratch(ctx);
    for (size_t i = 0; i < ctx->nbouts; i++) jm_bout_free(&ctx->bouts[i], &ctx->mem);
    jm_free(&ctx->mem, ctx->bouts, ctx->nbouts * sizeof *ctx->bouts);
    free_vertices(ctx);
    free_indices(ctx);
    jm_post_scratch_free(&ctx->post, &ctx->mem);
    jm_pool_free(ctx->pool);
    jm_keep_destroy(ctx->mem.keep);
    free(ctx);
}

/* ---- output arrays */
/* The next capacity of a mesh array of cap elements of elem bytes that
 * must hold need: by half where growing copies the array; exactly need
 * where it moves pages (grow.h: whole 2 MiB spans, so most steps make no
 * call), so that the arrays at the end of the blocks (the frame's peak)
 * hold no more than the mesh. */
static size_t next_cap(size_t cap, size_t need, size_t elem, size_t least)
{
    size_t nc = jm_grow_moves(cap * elem) ? need : cap + cap / 2;
    if (nc < need) nc = need;
    if (nc < least) nc = least;
    return nc;
}

static int reserve_mesh(jm_context *ctx, size_t nv, size_t ni)
{
    if (nv > ctx->capv) {
        size_t nc = next_cap(ctx->capv, nv, 3 * sizeof(float), 1024);
        float *p = jm_grow(&ctx->mem, ctx->pos, ctx->capv * 3 * sizeof(float), nc * 3 * sizeof(float));
        if (!p) return 0;
        ctx->pos = p;
        float *n = jm_grow(&ctx->mem, ctx->nrm, ctx->capv * 3 * sizeof(float), nc * 3 * sizeof(float));
        if (!n) { ctx->pos = jm_grow(&ctx->mem, ctx->pos, nc * 3 * sizeof(float), ctx->capv * 3 * sizeof(float)); return 0; }
        ctx->nrm = n;
        float *u = jm_grow(&ctx->mem, ctx->uv, ctx->capv * 2 * sizeof(float), nc * 2 * sizeof(float));
        if (!u) {
            ctx->pos = jm_grow(&ctx->mem, ctx->pos, nc * 3 * sizeof(float), ctx->capv * 3 * sizeof(float));
            ctx->nrm = jm_grow(&ctx->mem, ctx->nrm, nc * 3 * sizeof(float), ctx->capv * 3 * sizeof(float));
            return 0;
        }
        ctx->uv = u;
        ctx->capv = nc;
    }
    if (ni > ctx->capi) {
        size_t nc = next_cap(ctx->capi, ni, sizeof(uint32_t), 3072);
        uint32_t *p = jm_grow(&ctx->mem, ctx->idx, ctx->capi * sizeof(uint32_t), nc * sizeof(uint32_t));
        if (!p) return 0;
        ctx->idx = p;
        ctx->capi = nc;
    }
    return 1;
}

/* After a frame: where shrinking moves pages (grow.h), the mesh arrays
 * keep only what the mesh holds, so that the context carries no spare
 * capacity into the next frame's peak (a frame as large grows them again
 * without copying). A failed shrink keeps the arrays as they were. */
static void trim_mesh(jm_context *ctx)
{
    size_t v = ctx->nv > 1024 ? ctx->nv : 1024, i = ctx->ni > 3072 ? ctx->ni : 3072;
    if (ctx->capv > v && jm_grow_moves(v * 2 * sizeof(float))) {
        float *p = jm_grow(&ctx->mem, ctx->pos, ctx->capv * 3 * sizeof(float), v * 3 * sizeof(float));
        if (p) ctx->pos = p;
        float *n = p ? jm_grow(&ctx->mem, ctx->nrm, ctx->capv * 3 * sizeof(float), v * 3 * sizeof(float)) : NULL;
        if (n) ctx->nrm = n;
        float *u = n ? jm_grow(&ctx->mem, ctx->uv, ctx->capv * 2 * sizeof(float), v * 2 * sizeof(float)) : NULL;
        if (u) {
            ctx->uv = u;
            ctx->capv = v;
        } else { /* back to one capacity for the three */
            if (n) ctx->nrm = jm_grow(&ctx->mem, ctx->nrm, v * 3 * sizeof(float), ctx->capv * 3 * sizeof(float));
            if (p) ctx->pos = jm_grow(&ctx->mem, ctx->pos, v * 3 * sizeof(float), ctx->capv * 3 * sizeof(float));
        }
    }
    if (ctx->capi > i && jm_grow_moves(i * sizeof(uint32_t))) {
        uint32_t *p = jm_grow(&ctx->mem, ctx->idx, ctx->capi * sizeof(uint32_t), i * sizeof(uint32_t));
        if (p) {
            ctx->idx = p;
            ctx->capi = i;
        }
    }
}

/* Whether the mesh is post-processed (post.h), which reads the particles */
static int post_processed(const jm_config *c)
{
    return c->smooth_iters || c->smooth_normal_iters || c->simplify_error > 0.0f;
}

/* Whether a frame gives its particles back behind the block sweep: isotropic
 * SPH with no post-processing (nothing after the sweep reads the particles;
 * the anisotropic kernels and the post-processing do) */
static int releases_grid(const jm_config *c)
{
    return c->field == JM_FIELD_SPH && !c->aniso && !post_processed(c);
}

/* Before a frame of n particles that releases its grid: gives back the last
 * frame's mesh arrays that live in their own mappings (grow.h: 1 MiB and
 * more), when the grid (about 17 bytes a particle) is at least half that
 * mesh. Held, the last mesh would sit beside the whole grid, over the
 * frame's own peak (its mesh and a band of the grid) by up to the grid's
 * size; given back, it is faulted in again as it regrows, and the time
 * that takes follows the mesh (measured: the 8M-particle block, grid 0.54
 * of its mesh, 92 MiB off its peak of 395 for about 2 % more time; the 1M
 * block, 0.27, would save 5 MiB of 83 for 3 to 6 % more). Smaller arrays
 * stay: in the heap, they would fault back per 4 KiB page (the
 * 125-particle jet took twice as long). */
static void drop_mesh(jm_context *ctx, size_t n)
{
    const size_t mesh = ctx->capv * 8 * sizeof(float) + ctx->capi * sizeof(uint32_t);
    if (!releases_grid(&ctx->cfg) || 17 * n < mesh / 2) return;
    if (jm_grow_moves(ctx->capv * 2 * sizeof(float))) free_vertices(ctx);
    if (jm_grow_moves(ctx->capi * sizeof(uint32_t))) free_indices(ctx);
    ctx->nv = ctx->ni = 0;
}

/* ---- the frame pipeline */
typedef struct frame_job {
    jm_context *ctx;
    const jm_config *c;
    jm_grid *g;
    jm_block_set *bs;
    jm_block_env env;
    size_t first;          /* first block of the batch */
    size_t *vbase;         /* per block: first global vertex */
    uint32_t **bmap;       /* per block: sorted (slot, local) pairs */
    uint32_t *nbmap;
    size_t *slot_vbase, *slot_ibase, *slot_pbase;
    uint32_t *pend;        /* global pending pairs */
    size_t npend, cappend;
    atomic_int failed;     /* 1 memory, 2 internal; set by any worker */
    uint32_t *iso;         /* sorted indices of isolated particles, input order */
    float *iso_pos;        /* and their positions (the sweep may release the grid's) */
    uint32_t *roots;       /* the cavity pass's pieces, for smoothing (roots_n entries) */
    size_t roots_n;
    size_t tmpl_v0, tmpl_i0;
} frame_job;

static void block_task(void *arg, size_t i, int worker)
{
    frame_job *job = arg;
    jm_block_mesh(&job->env, job->first + i, &job->ctx->scratch[worker], &job->ctx->bouts[i]);
}

static void copy_task(void *arg, size_t i, int worker)
{
    (void)worker;
    frame_job *job = arg;
    jm_context *ctx = job->ctx;
    jm_bout *o = &ctx->bouts[i];
    size_t vb = job->slot_vbase[i], ib = job->slot_ibase[i], pb = job->slot_pbase[i];
    if (o->nv) { /* (a block without vertices may never have allocated) */
        memcpy(ctx->pos + 3 * vb, o->pos, o->nv * 3 * sizeof(float));
        memcpy(ctx->nrm + 3 * vb, o->nrm, o->nv * 3 * sizeof(float));
        memcpy(ctx->uv + 2 * vb, o->uv, o->nv * 2 * sizeof(float));
    }
    uint32_t *dst = ctx->idx + ib;
    for (size_t t = 0; t < o->ni; t++) {
        uint32_t r = o->tri[t];
        dst[t] = (r & JM_PENDING) ? (JM_PENDING | (uint32_t)(pb + (r & ~JM_PENDING))) : (uint32_t)(vb + r);
    }
    if (o->np) memcpy(job->pend + 2 * pb, o->pend, o->np * 2 * sizeof(uint32_t));
    size_t b = job->first + i;
    if (o->nb) {
        uint32_t *m = jm_alloc(&ctx->mem, o->nb * 2 * sizeof(uint32_t));
        if (!m) { job->failed = 1; return; }
        memcpy(m, o->bmap, o->nb * 2 * sizeof(uint32_t));
        job->bmap[b] = m;
        job->nbmap[b] = (uint32_t)o->nb;
    }
}

static void resolve_task(void *arg, size_t p, int worker)
{
    (void)worker;
    frame_job *job = arg;
    uint32_t owner = job->pend[2 * p], slot = job->pend[2 * p + 1];
    const uint32_t *m = job->bmap[owner];
    /* the first entry not below slot, without a branch per halving (the
     * slots are distinct: the same entry as any binary search) */
    size_t lo = 0, len = job->nbmap[owner];
    while (len > 1) {
        const size_t half = len / 2;
        lo = m[2 * (lo + half - 1)] < slot ? lo + half : lo;
        len -= half;
    }
    if (len == 1 && m[2 * lo] < slot) lo++;
    if (lo < job->nbmap[owner] && m[2 * lo] == slot) {
        job->pend[2 * p] = (uint32_t)(job->vbase[owner] + m[2 * lo + 1]);
    } else {
        job->pend[2 * p] = 0;
        job->failed = 2;
    }
}

#define CHUNK 65536
static void patch_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    frame_job *job = arg;
    jm_context *ctx = job->ctx;
    size_t a = chunk * CHUNK, b = a + CHUNK < ctx->ni ? a + CHUNK : ctx->ni;
    for (size_t t = a; t < b; t++) {
        uint32_t r = ctx->idx[t];
        if (r & JM_PENDING) ctx->idx[t] = job->pend[2 * (size_t)(r & ~JM_PENDING)];
    }
}

static void template_task(void *arg, size_t k, int worker)
{
    (void)worker;
    frame_job *job = arg;
    jm_context *ctx = job->ctx;
    const float *c = &job->iso_pos[3 * k];
    float d[3] = {c[0] - ctx->t_origin[0], c[1] - ctx->t_origin[1], c[2] - ctx->t_origin[2]};
    size_t v0 = job->tmpl_v0 + k * ctx->t_nv;
    for (size_t v = 0; v < ctx->t_nv; v++) {
        float *p = ctx->pos + 3 * (v0 + v), *n = ctx->nrm + 3 * (v0 + v);
        for (int a = 0; a < 3; a++) {
            p[a] = ctx->t_pos[3 * v + a] + d[a];
            n[a] = ctx->t_nrm[3 * v + a];
        }
        if (job->c->uv_mode != JM_UV_NONE) jm_uv(job->c, p, n, ctx->uv + 2 * (v0 + v));
    }
    uint32_t *dst = ctx->idx + job->tmpl_i0 + k * ctx->t_ni;
    for (size_t t = 0; t < ctx->t_ni; t++) dst[t] = (uint32_t)(v0 + ctx->t_idx[t]);
}

static inline int u64_less(const uint64_t *a, const uint64_t *b) { return *a < *b; }
JM_SORT_DEFINE(sort_u64, uint64_t, u64_less)

/* Working memory estimate for a frame of n particles, links metasphere
 * neck links (24 bytes each: jm_grid's nb, nb_owner, nb_dir) and nblocks
 * blocks. */
static size_t estimate(const jm_config *c, size_t n, double links, size_t nblocks, int threads)
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

static jm_status build_blocks(const jm_config *c, const jm_grid *g, jm_mem *mem, jm_block_set *bs, int threads,
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
    *out_estimate = estimate(c, g->n, (double)g->nb_count, bound > 1e15 ? (size_t)1e15 : (size_t)bound, threads);
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

static void free_blocks(jm_block_set *bs, jm_mem *mem)
{
    if (bs->cell_start) {
        jm_free(mem, bs->cells, (bs->ncells ? bs->ncells : 1) * sizeof *bs->cells);
        jm_free(mem, bs->cell_start, (bs->count + 1) * sizeof *bs->cell_start);
    }
    jm_free(mem, bs->key, (bs->count ? bs->count : 1) * sizeof *bs->key);
    if (bs->map.keys) jm_hashmap_free(&bs->map, mem);
    memset(bs, 0, sizeof *bs);
}

static jm_status ensure_scratch(jm_context *ctx)
{
    if (ctx->nscratch == ctx->threads && ctx->scratch && ctx->scratch[0].B == ctx->cfg.block) return JM_OK;
    drop_scratch(ctx);
    ctx->scratch = jm_alloc_lasting(&ctx->mem, (size_t)ctx->threads * sizeof *ctx->scratch);
    if (!ctx->scratch) return JM_E_OUT_OF_MEMORY;
    memset(ctx->scratch, 0, (size_t)ctx->threads * sizeof *ctx->scratch);
    ctx->scratch_cap = (size_t)ctx->threads;
    for (int i = 0; i < ctx->threads; i++) {
        /* counted against the limit before it is taken */
        if (!jm_mem_take(&ctx->mem, jm_scratch_bytes(ctx->cfg.block))) {
            ctx->nscratch = i;
            drop_scratch(ctx);
            return JM_E_OUT_OF_MEMORY;
        }
        if (!jm_scratch_init(&ctx->scratch[i], ctx->cfg.block)) {
            jm_mem_sub(&ctx->mem, jm_scratch_bytes(ctx->cfg.block));
            ctx->nscratch = i;
            drop_scratch(ctx);
            return JM_E_OUT_OF_MEMORY;
        }
        /* the buffers that grow with the blocks, counted as they grow */
        jm_scratch *sc = &ctx->scratch[i];
        sc->hood.mem = sc->soa.mem = sc->an_list.mem = sc->probe.mem = sc->mnorm.mem = sc->roots.mem = &ctx->mem;
        sc->an_cand.mem = &ctx->mem;
    }
    ctx->nscratch = ctx->threads;
    return JM_OK;
}

static jm_status make_template(jm_context *ctx);

/* The last steps (jetmesh.h, "Selection and clipping", 3 and 4): small
 * pieces, then the clip box, on the context's mesh (in units). */
static jm_status trim_pieces_and_clip(jm_context *ctx, const jm_config *c)
{
    size_t removed = 0;
    if (c->piece_min_volume > 0.0 &&
        !jm_drop_small_pieces(&ctx->mem, ctx->pool, ctx->pos, ctx->nrm, ctx->uv, ctx->idx, &ctx->nv, &ctx->ni,
                              c->piece_min_volume, &removed))
        return JM_E_OUT_OF_MEMORY;
    if (c->clip && !jm_clip_mesh(&ctx->mem, ctx->pool, c, ctx->pos, ctx->nrm, ctx->uv, ctx->idx, &ctx->nv, &ctx->ni))
        return JM_E_OUT_OF_MEMORY;
    return JM_OK;
}

/* Meshes particles with configuration c into the context's output arrays. */
static jm_status run(jm_context *ctx, const jm_config *c, const jm_particles *in, jm_stats *st)
{
    jm_mem *mem = &ctx->mem;
    jm_status s = JM_OK;
    double t0 = jm_now_ms();
    ctx->nv = ctx->ni = 0;
    if (in->count == 0) return JM_OK;

    jm_grid g;
    s = jm_grid_build(&g, mem, ctx->pool, c, in);
    if (s != JM_OK) {
        st->estimated_bytes = g.refused_bytes; /* the neighbour links over the limit */
        return s;
    }
    jm_config frame_cfg;
    if (c->aniso) {
        /* anisotropic kernels: the band reaches as far as this frame's kernels */
        s = jm_aniso_build(&g, mem, ctx->pool, c);
        if (s != JM_OK) { jm_grid_free(&g, mem); return s; }
        frame_cfg = *c;
        if (g.an_reach > frame_cfg.influence) frame_cfg.influence = g.an_reach;
        c = &frame_cfg;
    }
    jm_block_set bs;
    s = build_blocks(c, &g, mem, &bs, ctx->threads, &st->estimated_bytes);
    if (s != JM_OK) { jm_grid_free(&g, mem); return s; }
    /* the metasphere's blocks list the cells that reach them (their hoods
     * are filled from the lists, with the cells' coordinates) */
    if (c->field == JM_FIELD_METASPHERE) {
        if (!jm_block_cells(c, &g, mem, &bs)) {
            s = JM_E_OUT_OF_MEMORY;
            goto out_blocks;
        }
    } else {
        jm_grid_drop_coords(&g, mem); /* read no more */
    }
    st->particles = in->count;
    st->isolated = g.n_isolated;
    st->blocks = bs.count;
    st->estimated_bytes = estimate(c, in->count, (double)g.nb_count, bs.count, ctx->threads);
    if (c->max_bytes && (st->estimated_bytes > c->max_bytes || mem->current > c->max_bytes)) {
        s = JM_E_TOO_LARGE;
        goto out_blocks;
    }
    if (g.n_isolated && !ctx->have_tmpl) {
        s = make_template(ctx);
        if (s != JM_OK) goto out_blocks;
    }
    s = ensure_scratch(ctx);
    if (s != JM_OK) goto out_blocks;
    double t1 = jm_now_ms();
    st->ms_prepare += t1 - t0;

    frame_job job;
    memset(&job, 0, sizeof job);
    job.ctx = ctx;
    job.c = c;
    job.g = &g;
    job.bs = &bs;
    job.env.g = &g;
    job.env.c = c;
    job.env.blocks = &bs;
    job.env.mem = mem;
    size_t nb = bs.count ? bs.count : 1;
    job.vbase = jm_calloc(mem, nb, sizeof *job.vbase);
    job.bmap = jm_calloc(mem, nb, sizeof *job.bmap);
    job.nbmap = jm_calloc(mem, nb, sizeof *job.nbmap);
    size_t slots = (size_t)ctx->threads * 32;
    if (ctx->nbouts < slots) {
        jm_bout *b = jm_realloc_lasting(mem, ctx->bouts, ctx->nbouts * sizeof *b, slots * sizeof *b);
        if (b) {
            memset(b + ctx->nbouts, 0, (slots - ctx->nbouts) * sizeof *b);
            ctx->bouts = b;
            ctx->nbouts = slots;
        }
    }
    job.slot_vbase = jm_alloc(mem, 3 * slots * sizeof(size_t));
    if (!job.vbase || !job.bmap || !job.nbmap || !job.slot_vbase || ctx->nbouts < slots) {
        s = JM_E_OUT_OF_MEMORY;
        goto out_job;
    }
    job.slot_ibase = job.slot_vbase + slots;
    job.slot_pbase = job.slot_ibase + slots;
    /* the isolated particles, in the input's order, and where they are: the
     * templates go after the sweep, which may have released the grid */
    if (g.n_isolated) {
        job.iso = jm_alloc(mem, g.n_isolated * sizeof *job.iso);
        job.iso_pos = jm_alloc(mem, 3 * g.n_isolated * sizeof *job.iso_pos);
        if (!job.iso || !job.iso_pos || !jm_grid_isolated(&g, mem, job.iso)) {
            s = JM_E_OUT_OF_MEMORY;
            goto out_job;
        }
        for (size_t k = 0; k < g.n_isolated; k++)
            memcpy(job.iso_pos + 3 * k, &g.pos[3 * (size_t)job.iso[k]], 3 * sizeof(float));
    }
    /* the blocks run in z order (their keys): where nothing after the sweep
     * reads the particles, it gives the grid back behind it, and the peak
     * holds the mesh and a band of the grid, not both whole */
    const int post = post_processed(c), release = releases_grid(c);

    double tf = 0, te = 0, ta = 0, t_blocks = 0, t_stitch = 0;
    size_t nv = 0, ni = 0;
    for (size_t first = 0; first < bs.count; first += slots) {
        size_t m = bs.count - first < slots ? bs.count - first : slots;
        job.first = first;
        double ta0 = jm_now_ms();
        jm_pool_run(ctx->pool, m, 1, block_task, &job);
        double ta1 = jm_now_ms();
        t_blocks += ta1 - ta0;
        size_t np = job.npend;
        for (size_t i = 0; i < m; i++) {
            jm_bout *o = &ctx->bouts[i];
            if (o->failed) { s = o->failed == 1 ? JM_E_OUT_OF_MEMORY : JM_E_INTERNAL; goto out_job; }
            st->cells += o->cells;
            tf += o->t_field;
            te += o->t_extract;
            ta += o->t_attr;
            job.vbase[first + i] = nv;
            job.slot_vbase[i] = nv;
            job.slot_ibase[i] = ni;
            job.slot_pbase[i] = np;
            nv += o->nv;
            ni += o->ni;
            np += o->np;
        }
        if (nv >= JM_PENDING || np >= JM_PENDING) { s = JM_E_TOO_LARGE; goto out_job; }
        if (!reserve_mesh(ctx, nv, ni)) { s = JM_E_OUT_OF_MEMORY; goto out_job; }
        if (np > job.cappend) {
            size_t nc = job.cappend ? job.cappend * 2 : 4096;
            while (nc < np) nc *= 2;
            uint32_t *p = jm_realloc(mem, job.pend, job.cappend * 2 * sizeof(uint32_t), nc * 2 * sizeof(uint32_t));
            if (!p) { s = JM_E_OUT_OF_MEMORY; goto out_job; }
            job.pend = p;
            job.cappend = nc;
        }
        job.npend = np;
        ctx->nv = nv;
        ctx->ni = ni;
        jm_pool_run(ctx->pool, m, 1, copy_task, &job);
        if (job.failed) { s = JM_E_OUT_OF_MEMORY; goto out_job; }
        if (release && first + m < bs.count) {
            /* the blocks left lie at the next one's z or above (its low
             * nodes as block.c places them); their hoods start at a cell z
             * of at least this one's: every cell below (one more to spare)
             * is done */
            int64_t kz = (int64_t)(bs.key[first + m] >> (2 * JM_KEY_BITS)) + bs.origin[2];
            float zlo = (float)((double)(kz * c->block) * (double)c->h);
            jm_grid_release_below(&g, mem, jm_hood_cell_lo(&g, c, zlo) - 1);
        }
        t_stitch += jm_now_ms() - ta1;
    }
    /* (a failure only costs the next frame an allocation) */
    (void)jm_scratch_even(ctx->scratch, ctx->nscratch);
    double t2 = jm_now_ms();
    /* stitch: pending references to vertices owned by later blocks */
    jm_pool_run(ctx->pool, job.npend, 4096, resolve_task, &job);
    if (job.failed) { s = JM_E_INTERNAL; goto out_job; }
    for (size_t b = 0; b < bs.count; b++) { /* the owners' maps: done with */
        jm_free(mem, job.bmap[b], job.nbmap[b] * 2 * sizeof(uint32_t));
        job.bmap[b] = NULL;
    }
    jm_pool_run(ctx->pool, (ctx->ni + CHUNK - 1) / CHUNK, 1, patch_task, &job);
    if (c->field == JM_FIELD_METASPHERE && (c->compensate || c->normals) &&
        !jm_meta_finish(&ctx->mem, ctx->pool, ctx->pos, ctx->nrm, ctx->nv, ctx->idx, ctx->ni / 3, c->compensate,
                        c->normals, 0.1f * c->h)) {
        s = JM_E_OUT_OF_MEMORY;
        goto out_job;
    }
    double t3 = jm_now_ms();
    t_stitch += t3 - t2;

    /* isolated particles from the template */
    if (g.n_isolated) {
        job.tmpl_v0 = ctx->nv;
        job.tmpl_i0 = ctx->ni;
        size_t tv = ctx->nv + g.n_isolated * ctx->t_nv, ti = ctx->ni + g.n_isolated * ctx->t_ni;
        if (tv >= JM_PENDING) { s = JM_E_TOO_LARGE; goto out_job; }
        if (!reserve_mesh(ctx, tv, ti)) { s = JM_E_OUT_OF_MEMORY; goto out_job; }
        ctx->nv = tv;
        ctx->ni = ti;
        jm_pool_run(ctx->pool, g.n_isolated, 64, template_task, &job);
    }
    {
        /* nothing below reads the particles (the smoothing works on the
         * mesh alone): their grid goes before the last stages take memory */
        size_t iso = g.n_isolated;
        jm_grid_free(&g, mem);
        g.n_isolated = iso;
    }
    double tc0 = jm_now_ms();
    int roots_ok = 0;
    if (c->drop_cavities) {
        double r3 = (double)c->r * c->r * c->r;
        size_t nv = ctx->nv, ni = ctx->ni;
        if (c->smooth_iters > 0) {
            /* smoothing needs the mesh's pieces too: the cavity pass's, when
             * it removes nothing */
            job.roots_n = nv;
            job.roots = jm_alloc(mem, nv * sizeof *job.roots);
            if (!job.roots) { s = JM_E_OUT_OF_MEMORY; goto out_job; }
        }
        if (!jm_drop_small_cavities(mem, ctx->pool, ctx->pos, ctx->nrm, ctx->uv, ctx->idx, &nv, &ni,
                                    4.0 / 3.0 * M_PI * r3, job.roots, &st->cavities_removed)) {
            s = JM_E_OUT_OF_MEMORY;
            goto out_job;
        }
        roots_ok = job.roots && st->cavities_removed == 0;
        /* the sphere templates (after tmpl_v0/tmpl_i0) are outward shells,
         * never removed: what went was before them */
        if (g.n_isolated) {
            job.tmpl_v0 -= ctx->nv - nv;
            job.tmpl_i0 -= ctx->ni - ni;
        }
        ctx->nv = nv;
        ctx->ni = ni;
    }
    double t4 = jm_now_ms();
    double t_cav = t4 - tc0;
    /* wall time of the block pass, shared out by the threads' time per stage */
    double sum = tf + te + ta;
    if (sum > 0) {
        st->ms_field += t_blocks * tf / sum;
        st->ms_extract += t_blocks * te / sum;
        st->ms_attributes += t_blocks * ta / sum;
    }
    st->ms_extract += t_stitch + t_cav;
    st->ms_attributes += t4 - t3 - t_cav;

    /* post-processing (post.h) */
    if (post) {
        jm_post_mesh pm = {ctx->pos, ctx->nrm, ctx->uv, ctx->idx, ctx->nv, ctx->ni, ctx->nv, ctx->ni, NULL};
        if (g.n_isolated) {
            pm.nv_lattice = job.tmpl_v0;
            pm.ni_lattice = job.tmpl_i0;
        }
        if (roots_ok) pm.roots = job.roots;
        s = jm_smooth_mesh(mem, ctx->pool, &ctx->post, c, &pm);
        if (s == JM_OK) s = jm_simplify_mesh(mem, c, &pm);
        if (s != JM_OK) goto out_job;
        ctx->nv = pm.nv;
        ctx->ni = pm.ni;
        st->ms_post += jm_now_ms() - t4;
    }
    if (c->piece_min_volume > 0.0 || c->clip) {
        double t5 = jm_now_ms();
        s = trim_pieces_and_clip(ctx, c);
        if (s != JM_OK) goto out_job;
        st->ms_post += jm_now_ms() - t5;
    }

out_job:
    jm_free(mem, job.iso, g.n_isolated * sizeof *job.iso);
    jm_free(mem, job.iso_pos, 3 * g.n_isolated * sizeof *job.iso_pos);
    jm_free(mem, job.roots, job.roots_n * sizeof *job.roots);
    if (job.bmap)
        for (size_t b = 0; b < bs.count; b++) jm_free(mem, job.bmap[b], job.nbmap[b] * 2 * sizeof(uint32_t));
    jm_free(mem, job.pend, job.cappend * 2 * sizeof(uint32_t));
    jm_free(mem, job.vbase, nb * sizeof *job.vbase);
    jm_free(mem, job.bmap, nb * sizeof *job.bmap);
    jm_free(mem, job.nbmap, nb * sizeof *job.nbmap);
    jm_free(mem, job.slot_vbase, 3 * slots * sizeof(size_t));
out_blocks:
    free_blocks(&bs, mem);
    jm_grid_free(&g, mem);
    if (s != JM_OK) ctx->nv = ctx->ni = 0;
    return s;
}

/* One particle meshed through the lattice: the shape every isolated
 * particle gets, translated. */
static jm_status make_template(jm_context *ctx)
{
    jm_config c = ctx->cfg;
    c.templates = 0;
    c.uv_mode = JM_UV_NONE;
    c.smooth_iters = c.smooth_normal_iters = 0;
    c.simplify_error = 0.0f;
    c.normals = 1;
    /* the shape itself: nothing selected or clipped */
    c.sel_box = c.sel_min_group = c.clip = 0;
    c.piece_min_volume = 0.0;
    /* at a lattice node: the symmetric shape (and splashsurf's test case) */
    ctx->t_origin[0] = ctx->t_origin[1] = ctx->t_origin[2] = 0.0f;
    jm_particles one = {ctx->t_origin, 1, 0, NULL};
    jm_stats ignore;
    memset(&ignore, 0, sizeof ignore);
    jm_status s = run(ctx, &c, &one, &ignore);
    if (s != JM_OK) return s;
    jm_mem *mem = &ctx->mem;
    ctx->t_pos = jm_alloc_lasting(mem, ctx->nv * 3 * sizeof(float));
    ctx->t_nrm = jm_alloc_lasting(mem, ctx->nv * 3 * sizeof(float));
    ctx->t_idx = jm_alloc_lasting(mem, ctx->ni * sizeof(uint32_t));
    ctx->t_nv = ctx->nv;
    ctx->t_ni = ctx->ni;
    if (!ctx->t_pos || !ctx->t_nrm || !ctx->t_idx) { drop_template(ctx); return JM_E_OUT_OF_MEMORY; }
    if (ctx->nv) {
        memcpy(ctx->t_pos, ctx->pos, ctx->nv * 3 * sizeof(float));
        memcpy(ctx->t_nrm, ctx->nrm, ctx->nv * 3 * sizeof(float));
        memcpy(ctx->t_idx, ctx->idx, ctx->ni * sizeof(uint32_t));
    }
    ctx->have_tmpl = 1;
    ctx->nv = ctx->ni = 0;
    return JM_OK;
}

/* The bounds of nv > 0 points: four at a time as three vectors of 4
 * floats (lanes x y z x, y z x y, z x y z), whose lanes gather each axis's
 * minimum and maximum (exact: any order gives them) */
static void bounds(const float *pos, size_t nv, float lo[3], float hi[3])
{
    typedef float v4f __attribute__((vector_size(16)));
    typedef int32_t v4i __attribute__((vector_size(16)));
    v4f mn[3], mx[3];
    for (int k = 0; k < 3; k++)
        for (int l = 0; l < 4; l++) mn[k][l] = mx[k][l] = pos[(4 * k + l) % 3];
    size_t v = 0;
    for (; v + 4 <= nv; v += 4)
        for (int k = 0; k < 3; k++) {
            v4f x;
            memcpy(&x, pos + 3 * v + 4 * k, sizeof x);
            const v4i lt = x < mn[k], gt = x > mx[k];
            mn[k] = (v4f)((lt & (v4i)x) | (~lt & (v4i)mn[k]));
            mx[k] = (v4f)((gt & (v4i)x) | (~gt & (v4i)mx[k]));
        }
    for (int a = 0; a < 3; a++) lo[a] = hi[a] = pos[a];
    for (int k = 0; k < 3; k++)
        for (int l = 0; l < 4; l++) {
            const int a = (4 * k + l) % 3;
            if (mn[k][l] < lo[a]) lo[a] = mn[k][l];
            if (mx[k][l] > hi[a]) hi[a] = mx[k][l];
        }
    for (; v < nv; v++)
        for (int a = 0; a < 3; a++) {
            const float x = pos[3 * v + a];
            if (x < lo[a]) lo[a] = x;
            if (x > hi[a]) hi[a] = x;
        }
}

jm_status jm_mesh_particles(jm_context *ctx, const jm_particles *particles, jm_mesh *out_mesh, jm_stats *out_stats)
{
    if (out_mesh) memset(out_mesh, 0, sizeof *out_mesh);
    if (!ctx || !particles || !out_mesh || (particles->count && !particles->xyz)) return JM_E_INVALID_ARGUMENT;
    jm_stats st;
    memset(&st, 0, sizeof st);
    st.threads = ctx->threads;
    drop_mesh(ctx, particles->count); /* the last mesh's arrays: valid until this call */
    ctx->mem.peak = ctx->mem.current;
    /* the limit holds where memory is taken (alloc.c), not only in the
     * estimates: an allocation past it fails, and the frame is refused */
    ctx->mem.limit = ctx->cfg.max_bytes;
    ctx->mem.over = 0;
    ctx->mem.refused = 0;
    double t0 = jm_now_ms();
    /* the particles the selection keeps (select.h), copied */
    uint8_t *skip = NULL;
    size_t kept = 0;
    jm_particles sel;
    memset(&sel, 0, sizeof sel);
    jm_status s = jm_select(&ctx->mem, ctx->pool, &ctx->cfg, particles, &skip, &kept);
    if (s == JM_OK && skip) s = jm_select_copy(&ctx->mem, particles, skip, kept, &sel);
    jm_free(&ctx->mem, skip, particles->count);
    if (s == JM_OK) {
        st.ms_prepare = jm_now_ms() - t0;
        s = run(ctx, &ctx->cfg, sel.xyz ? &sel : particles, &st);
    }
    if (sel.xyz) jm_select_free_copy(&ctx->mem, &sel);
    if ((s == JM_E_OUT_OF_MEMORY || s == JM_E_TOO_LARGE) && atomic_load(&ctx->mem.over)) {
        s = JM_E_TOO_LARGE; /* with the total the refused allocation needed */
        if (ctx->mem.refused > st.estimated_bytes) st.estimated_bytes = ctx->mem.refused;
    }
    ctx->mem.limit = 0;
    if (s == JM_OK) {
        trim_mesh(ctx);
        jm_unit_restore(ctx->pos, ctx->nv, ctx->cfg.unit); /* back to world units */
        jm_mesh *m = out_mesh;
        m->positions = ctx->pos;
        m->normals = ctx->cfg.normals ? ctx->nrm : NULL;
        m->uvs = ctx->cfg.uv_mode != JM_UV_NONE ? ctx->uv : NULL;
        m->indices = ctx->idx;
        m->vertex_count = ctx->nv;
        m->triangle_count = ctx->ni / 3;
        if (ctx->nv) bounds(ctx->pos, ctx->nv, m->bounds_min, m->bounds_max);
        if (!m->positions) { m->vertex_count = 0; m->triangle_count = 0; }
        st.vertices = ctx->nv;
        st.triangles = ctx->ni / 3;
    }
    st.ms_total = jm_now_ms() - t0;
    st.peak_bytes = ctx->mem.peak;
    if (out_stats) *out_stats = st;
    return s;
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
    *out_bytes = estimate(c, n, links, nb, ctx->threads);
    return JM_OK;
}

jm_status jm_context_interpolate(jm_context *ctx, const jm_particles *particles, const float *positions,
                                 size_t vertex_count, jm_attribute *attributes, size_t attribute_count)
{
    size_t total;
    if (!ctx) return JM_E_INVALID_ARGUMENT;
    jm_status s = jm_interp_check(particles, positions, vertex_count, attributes, attribute_count, &total);
    if (s != JM_OK) return s;
    ctx->mem.limit = ctx->cfg.max_bytes;
    ctx->mem.over = 0;
    /* the particles the mesh was made of (select.h) */
    uint8_t *skip = NULL;
    size_t kept = 0;
    if (vertex_count && attribute_count) s = jm_select(&ctx->mem, ctx->pool, &ctx->cfg, particles, &skip, &kept);
    if (s == JM_OK)
        s = jm_interp_run(&ctx->mem, ctx->pool, &ctx->cfg, skip, particles, positions, vertex_count, attributes,
                          attribute_count);
    jm_free(&ctx->mem, skip, particles->count);
    if (s == JM_E_OUT_OF_MEMORY && atomic_load(&ctx->mem.over)) s = JM_E_TOO_LARGE;
    ctx->mem.limit = 0;
    return s;
}
