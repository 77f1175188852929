/* context.c - the context: parameters, threads, workers' scratch, the mesh's output arrays, kept across frames. */
#include "context.h"
#include "core/units.h"
#include "post/smooth.h"
#include "core/grow.h"
#include "core/keep.h"
#include "post/interpolate.h"
#include "grid/select.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int cpu_count(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : (n > JM_MAX_THREADS ? JM_MAX_THREADS : (int)n);
}

void jm_context_drop_template(jm_context *ctx)
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
 * mem pointers, set in jm_context_scratch) and freed by jm_scratch_free. */
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
    if (memcmp(&c, &ctx->cfg, sizeof c) != 0) jm_context_drop_template(ctx);
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
    jm_context_drop_template(ctx);
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

int jm_context_reserve(jm_context *ctx, size_t nv, size_t ni)
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
void jm_context_trim(jm_context *ctx)
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

/* Before a frame of n particles that releases its grid: the last frame's
 * mesh arrays that live in their own mappings (grow.h) given back when the
 * grid (about 17 bytes a particle) is at least half that mesh, so that the
 * last mesh does not sit beside the whole grid over the frame's own peak
 * (its mesh and a band of the grid). Smaller arrays stay: in the heap,
 * they would fault back in page by page. */
void jm_context_drop_mesh(jm_context *ctx, size_t n)
{
    const size_t mesh = ctx->capv * 8 * sizeof(float) + ctx->capi * sizeof(uint32_t);
    if (!jm_frame_releases_grid(&ctx->cfg) || 17 * n < mesh / 2) return;
    if (jm_grow_moves(ctx->capv * 2 * sizeof(float))) free_vertices(ctx);
    if (jm_grow_moves(ctx->capi * sizeof(uint32_t))) free_indices(ctx);
    ctx->nv = ctx->ni = 0;
}

jm_status jm_context_scratch(jm_context *ctx)
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
