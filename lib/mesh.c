/* mesh.c - jm_mesh_particles: a frame's pipeline, read as the list of its stages (run), each a call to its file. */
#include "context.h"
#include "extract/blockset.h"
#include "extract/sweep.h"
#include "extract/stitch.h"
#include "extract/templates.h"
#include "post/cavities.h"
#include "post/simplify.h"
#include "post/smooth.h"
#include "extract/scratch_even.h"
#include "field/field_ops.h"
#include "core/units.h"
#include "grid/select.h"
#include "post/small_pieces.h"
#include "post/clip.h"
#include <math.h>
#include <stdatomic.h>
#include <string.h>

static jm_status run(jm_context *ctx, const jm_config *c, const jm_particles *in, jm_stats *st);
static jm_status make_template(jm_context *ctx);

/* The particles sorted into cells with their densities or links; the
 * field's own per-particle data (the anisotropic kernels, whose reach
 * widens the frame's band). */
static jm_status stage_grid(jm_frame *f, const jm_particles *in)
{
    jm_status s = jm_grid_build(&f->g, &f->ctx->mem, f->ctx->pool, f->c, in);
    if (s != JM_OK) {
        f->st->estimated_bytes = f->g.refused_bytes; /* the neighbour links over the limit */
        return s;
    }
    return f->field->frame_grid ? f->field->frame_grid(&f->g, &f->ctx->mem, f->ctx->pool, &f->c, &f->cfg) : JM_OK;
}

/* The blocks the particles reach, and what they read of the grid's cells
 * (the metasphere's blocks list the cells that reach them); the frame
 * refused when its estimate is over the limit. */
static jm_status stage_blocks(jm_frame *f, size_t count)
{
    jm_context *ctx = f->ctx;
    const jm_config *c = f->c;
    jm_stats *st = f->st;
    jm_status s = jm_blocks_build(c, &f->g, &ctx->mem, &f->bs, ctx->threads, &st->estimated_bytes);
    if (s != JM_OK) return s;
    if (!f->field->frame_blocks(c, &f->g, &ctx->mem, &f->bs)) return JM_E_OUT_OF_MEMORY;
    st->particles = count;
    st->isolated = f->g.n_isolated;
    st->blocks = f->bs.count;
    st->estimated_bytes = jm_frame_estimate(c, count, (double)f->g.nb_count, f->bs.count, ctx->threads);
    if (c->max_bytes && (st->estimated_bytes > c->max_bytes || ctx->mem.current > c->max_bytes)) return JM_E_TOO_LARGE;
    return JM_OK;
}

/* The sphere template, the workers' scratch, the sweep's per-block and
 * per-slot arrays, and the isolated particles in the input's order with
 * their positions (the templates go after the sweep, which may release
 * the grid). */
static jm_status stage_prepare(jm_frame *f)
{
    jm_context *ctx = f->ctx;
    jm_mem *mem = &ctx->mem;
    jm_status s;
    if (f->g.n_isolated && !ctx->have_tmpl && (s = make_template(ctx)) != JM_OK) return s;
    if ((s = jm_context_scratch(ctx)) != JM_OK) return s;
    f->env = (jm_block_env){&f->g, f->c, &f->bs, mem, f->field};
    f->nb = f->bs.count ? f->bs.count : 1;
    f->vbase = jm_calloc(mem, f->nb, sizeof *f->vbase);
    f->bmap = jm_calloc(mem, f->nb, sizeof *f->bmap);
    f->nbmap = jm_calloc(mem, f->nb, sizeof *f->nbmap);
    const size_t slots = (size_t)ctx->threads * 32;
    if (ctx->nbouts < slots) {
        jm_bout *b = jm_realloc_lasting(mem, ctx->bouts, ctx->nbouts * sizeof *b, slots * sizeof *b);
        if (b) {
            memset(b + ctx->nbouts, 0, (slots - ctx->nbouts) * sizeof *b);
            ctx->bouts = b;
            ctx->nbouts = slots;
        }
    }
    f->slot_vbase = jm_alloc(mem, 3 * slots * sizeof(size_t));
    if (f->slot_vbase) f->slots = slots;
    if (!f->vbase || !f->bmap || !f->nbmap || !f->slot_vbase || ctx->nbouts < slots) return JM_E_OUT_OF_MEMORY;
    f->slot_ibase = f->slot_vbase + slots;
    f->slot_pbase = f->slot_ibase + slots;
    f->n_isolated = f->g.n_isolated;
    if (f->n_isolated) {
        f->iso = jm_alloc(mem, f->n_isolated * sizeof *f->iso);
        f->iso_pos = jm_alloc(mem, 3 * f->n_isolated * sizeof *f->iso_pos);
        if (!f->iso || !f->iso_pos || !jm_grid_isolated(&f->g, mem, f->iso)) return JM_E_OUT_OF_MEMORY;
        for (size_t k = 0; k < f->n_isolated; k++)
            memcpy(f->iso_pos + 3 * k, &f->g.pos[3 * (size_t)f->iso[k]], 3 * sizeof(float));
    }
    return JM_OK;
}

/* The field's last pass over the stitched mesh (the metasphere's sag
 * offset and normals facing their triangles). */
static jm_status stage_field_finish(jm_frame *f)
{
    jm_context *ctx = f->ctx;
    if (!f->field->frame_finish) return JM_OK;
    return f->field->frame_finish(f->c, &ctx->mem, ctx->pool, ctx->pos, ctx->nrm, ctx->nv, ctx->idx, ctx->ni)
               ? JM_OK
               : JM_E_OUT_OF_MEMORY;
}

/* Closed inward shells smaller than a particle removed (cavities.c); their
 * pieces kept for the smoothing where none went. */
static jm_status stage_cavities(jm_frame *f)
{
    jm_context *ctx = f->ctx;
    const jm_config *c = f->c;
    if (!c->drop_cavities) return JM_OK;
    double r3 = (double)c->r * c->r * c->r;
    size_t nv = ctx->nv, ni = ctx->ni;
    if (c->smooth_iters > 0) {
        /* smoothing needs the mesh's pieces too: the cavity pass's, when
         * it removes nothing */
        f->roots_n = nv;
        f->roots = jm_alloc(&ctx->mem, nv * sizeof *f->roots);
        if (!f->roots) return JM_E_OUT_OF_MEMORY;
    }
    if (!jm_drop_small_cavities(&ctx->mem, ctx->pool, ctx->pos, ctx->nrm, ctx->uv, ctx->idx, &nv, &ni,
                                4.0 / 3.0 * M_PI * r3, f->roots, &f->st->cavities_removed))
        return JM_E_OUT_OF_MEMORY;
    f->roots_ok = f->roots && f->st->cavities_removed == 0;
    /* the sphere templates (after tmpl_v0/tmpl_i0) are outward shells,
     * never removed: what went was before them */
    if (f->n_isolated) {
        f->tmpl_v0 -= ctx->nv - nv;
        f->tmpl_i0 -= ctx->ni - ni;
    }
    ctx->nv = nv;
    ctx->ni = ni;
    return JM_OK;
}

/* Bounded smoothing, normal smoothing (smooth.h) and simplification (simplify.h). */
static jm_status stage_post(jm_frame *f)
{
    jm_context *ctx = f->ctx;
    jm_post_mesh pm = {ctx->pos, ctx->nrm, ctx->uv, ctx->idx, ctx->nv, ctx->ni, ctx->nv, ctx->ni, NULL};
    if (f->n_isolated) {
        pm.nv_lattice = f->tmpl_v0;
        pm.ni_lattice = f->tmpl_i0;
    }
    if (f->roots_ok) pm.roots = f->roots;
    jm_status s = jm_smooth_mesh(&ctx->mem, ctx->pool, &ctx->post, f->c, &pm);
    if (s == JM_OK) s = jm_simplify_mesh(&ctx->mem, f->c, &pm);
    if (s != JM_OK) return s;
    ctx->nv = pm.nv;
    ctx->ni = pm.ni;
    return JM_OK;
}

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

/* The wall time of the block pass shared out by the threads' time per
 * stage; the stitching and cavities count as extraction, the rest of the
 * stitch-to-cavities span (templates, the metasphere finish) as attributes. */
static void account_times(const jm_frame *f, double t_cav, double t_after_stitch)
{
    jm_stats *st = f->st;
    double sum = f->tf + f->te + f->ta;
    if (sum > 0) {
        st->ms_field += f->t_blocks * f->tf / sum;
        st->ms_extract += f->t_blocks * f->te / sum;
        st->ms_attributes += f->t_blocks * f->ta / sum;
    }
    st->ms_extract += f->t_stitch + t_cav;
    st->ms_attributes += t_after_stitch - t_cav;
}

/* Everything a frame holds, given back. */
static void frame_free(jm_frame *f)
{
    jm_mem *mem = &f->ctx->mem;
    jm_free(mem, f->iso, f->n_isolated * sizeof *f->iso);
    jm_free(mem, f->iso_pos, 3 * f->n_isolated * sizeof *f->iso_pos);
    jm_free(mem, f->roots, f->roots_n * sizeof *f->roots);
    if (f->bmap)
        for (size_t b = 0; b < f->bs.count; b++) jm_free(mem, f->bmap[b], f->nbmap[b] * 2 * sizeof(uint32_t));
    jm_free(mem, f->pend, f->cappend * 2 * sizeof(uint32_t));
    jm_free(mem, f->vbase, f->nb * sizeof *f->vbase);
    jm_free(mem, f->bmap, f->nb * sizeof *f->bmap);
    jm_free(mem, f->nbmap, f->nb * sizeof *f->nbmap);
    jm_free(mem, f->slot_vbase, 3 * f->slots * sizeof(size_t));
    jm_blocks_free(&f->bs, mem);
    jm_grid_free(&f->g, mem);
}

/* Meshes particles with configuration c into the context's output arrays:
 * the stages in order, each timed into st. */
static jm_status run(jm_context *ctx, const jm_config *c, const jm_particles *in, jm_stats *st)
{
    double t0 = jm_now_ms();
    ctx->nv = ctx->ni = 0;
    if (in->count == 0) return JM_OK;
    jm_frame f;
    memset(&f, 0, sizeof f);
    f.ctx = ctx;
    f.c = c;
    f.st = st;
    f.field = jm_field_ops_of(c); /* chosen once: every stage asks it */
    jm_status s = stage_grid(&f, in);
    if (s == JM_OK) s = stage_blocks(&f, in->count);
    if (s == JM_OK) s = stage_prepare(&f);
    if (s != JM_OK) goto out;
    st->ms_prepare += jm_now_ms() - t0;

    s = jm_frame_sweep(&f);
    if (s != JM_OK) goto out;
    /* (a failure only costs the next frame an allocation) */
    (void)jm_scratch_even(ctx->scratch, ctx->nscratch);
    double t2 = jm_now_ms();
    s = jm_frame_stitch(&f);
    if (s == JM_OK) s = stage_field_finish(&f);
    if (s != JM_OK) goto out;
    double t3 = jm_now_ms();
    f.t_stitch += t3 - t2;
    s = jm_frame_templates(&f);
    if (s != JM_OK) goto out;
    /* nothing below reads the particles (the smoothing works on the mesh
     * alone): their grid goes before the last stages take memory */
    jm_grid_free(&f.g, &ctx->mem);

    double tc0 = jm_now_ms();
    s = stage_cavities(&f);
    if (s != JM_OK) goto out;
    double t4 = jm_now_ms();
    account_times(&f, t4 - tc0, t4 - t3);
    if (jm_frame_post(f.c)) {
        s = stage_post(&f);
        if (s != JM_OK) goto out;
        st->ms_post += jm_now_ms() - t4;
    }
    if (f.c->piece_min_volume > 0.0 || f.c->clip) {
        double t5 = jm_now_ms();
        s = trim_pieces_and_clip(ctx, f.c);
        if (s != JM_OK) goto out;
        st->ms_post += jm_now_ms() - t5;
    }
out:
    frame_free(&f);
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
    if (!ctx->t_pos || !ctx->t_nrm || !ctx->t_idx) { jm_context_drop_template(ctx); return JM_E_OUT_OF_MEMORY; }
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
    jm_context_drop_mesh(ctx, particles->count); /* the last mesh's arrays: valid until this call */
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
        jm_context_trim(ctx);
        jm_unit_restore(ctx->pos, ctx->nv, ctx->cfg.unit); /* back to world units */
        jm_mesh *m = out_mesh;
        m->positions = ctx->pos;
        /* NULL exactly when not asked for, so an empty frame's file has the
         * same layout whatever the context meshed before */
        static const float none[2];
        m->normals = ctx->cfg.normals ? (ctx->nrm ? ctx->nrm : none) : NULL;
        m->uvs = ctx->cfg.uv_mode != JM_UV_NONE ? (ctx->uv ? ctx->uv : none) : NULL;
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
