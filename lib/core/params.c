/* params.c - status messages, version, and parameter defaults/validation. */
#include "core/internal.h"
#include "field/sph/inside_boxes.h"
#include "field/meta/metavertex.h"
#include <math.h>
#include <string.h>

const char *jm_status_message(jm_status status)
{
    switch (status) {
    case JM_OK: return "ok";
    case JM_E_INVALID_ARGUMENT: return "invalid argument";
    case JM_E_INVALID_PARTICLE: return "a particle coordinate is NaN or infinite";
    case JM_E_OUT_OF_MEMORY: return "out of memory";
    case JM_E_TOO_LARGE: return "frame too large: over the memory limit, or a lattice far too fine for the particles' spread";
    case JM_E_THREAD: return "worker threads could not be started";
    case JM_E_INTERNAL: return "internal error (a bug in jetmesh)";
    case JM_E_TOO_DENSE: return "particles packed far closer than their radius (duplicated particles, or a radius far too large)";
    case JM_E_NUMERIC_DOMAIN: return "outside the numeric domain: a coordinate over 2^16 cube edges from the origin (float precision: move the particles nearer the origin), or a mesh beyond the float range";
    }
    return "unknown status";
}

const char *jm_version(void) { return JM_VERSION_STRING; }

jm_status jm_config_resolve(const jm_params *in, jm_config *c, jm_params *f)
{
    if (!in) return JM_E_INVALID_ARGUMENT;
    /* every range (and the member that leaves it) is in params_check.c */
    if (jm_params_check(in, NULL) != JM_OK) return JM_E_INVALID_ARGUMENT;
    memset(c, 0, sizeof *c); /* fields of unused features stay zero (contexts memcmp configs) */
    jm_params p = *in;
    if (p.field == JM_FIELD_DEFAULT) p.field = JM_FIELD_METASPHERE;
    if (p.method == JM_METHOD_DEFAULT) p.method = JM_METHOD_MT;
    if (p.uv_mode == JM_UV_DEFAULT) p.uv_mode = JM_UV_BOX;
    if (p.cube_size == 0.0f) p.cube_size = 0.5f;
    if (p.smoothing_length == 0.0f) p.smoothing_length = 2.0f;
    if (p.link_distance == 0.0f) p.link_distance = (float)M_PI;
    if (p.threshold == 0.0f && p.field == JM_FIELD_SPH) p.threshold = 0.6f;
    if (p.uv_scale == 0.0f) p.uv_scale = 16.0f * p.radius;
    if (p.uv_axis == 0) p.uv_axis = 3;

    float r = p.radius;
    c->r = r;
    c->h = p.cube_size * r;
    c->inv_h = 1.0f / c->h;
    c->field = p.field;
    c->method = p.method;
    c->threshold = p.threshold;
    c->sph_h = p.smoothing_length * r;
    c->support = 2.0f * c->sph_h;
    if (p.field == JM_FIELD_SPH && c->sph_h > 0.0f) {
        jm_box_lines(c->box_a, c->box_b, 1.0 / ((double)c->sph_h * c->sph_h));
        c->box_bin = (float)(JM_BOX_BINS_PER_S / ((double)c->sph_h * c->sph_h));
    }
    c->link = p.link_distance * r;
    /* Node values below -margin/r are clamped. Every piece is splatted
     * wherever it exceeds -margin/r, so an untouched node is truly below
     * that: inside/outside is exact for any margin. The margin only decides
     * which outside nodes near the surface keep their exact value and
     * winning piece for the vertex refinement (which then lands on the exact
     * surface from either end); one cube keeps nearly every crossed edge's
     * outer end (volumes change by under 0.05 % against 2.5 cubes) and
     * samples far fewer nodes. */
    c->margin = 1.0f * c->h + (p.threshold < 0.0f ? -p.threshold * r : 0.0f);
    if (p.field == JM_FIELD_SPH) {
        c->influence = c->support;
        c->cell = c->support;
    } else {
        /* a half-neck reaches at most (pi/2) r from its particle */
        float reach = 1.5708f * r;
        if (reach < r) reach = r;
        c->influence = reach + c->margin;
        c->cell = c->link > c->influence ? c->link : c->influence;
    }
    /* blocks three (SPH) or four (metasphere) influence radii wide (bigger
     * blocks waste nodes on thin jets and sample more per block
     * than the dense SPH splat likes; smaller ones repeat the per-block work
     * and the stitching) */
    {
        float k = p.field == JM_FIELD_SPH ? 3.0f : 4.0f;
        int b = (int)lrintf(k * c->influence / c->h);
        c->block = b < 8 ? 8 : (b > 32 ? 32 : b);
    }
    c->uv_mode = p.uv_mode;
    c->uv_scale = p.uv_scale;
    c->uv_axis = p.uv_axis - 1;
    c->normals = !p.no_normals;
    c->templates = !p.no_templates;
    c->compensate = !p.no_compensation;
    c->drop_cavities = !p.keep_cavities;
    c->max_bytes = p.max_bytes;
    /* anisotropic kernels: zeros mean defaults (see jetmesh.h); their ranges
     * are checked in params_check.c */
    if (p.anisotropic) {
        if (p.aniso_radius == 0.0f) p.aniso_radius = 4.0f * p.smoothing_length;
        if (p.aniso_smoothing == 0.0f) p.aniso_smoothing = 1.0f;
        if (p.aniso_max_ratio == 0.0f) p.aniso_max_ratio = 4.0f;
        if (p.aniso_scale == 0.0f) p.aniso_scale = 1.0f;
        if (p.aniso_iso_scale == 0.0f) p.aniso_iso_scale = 1.0f;
        if (p.aniso_min_neighbours == 0) {
            /* the paper's 25 at r_n = 8r (2r spacing: about 270 neighbours in
             * bulk), scaled with the neighbourhood's volume */
            float v = p.aniso_radius / 8.0f;
            p.aniso_min_neighbours = (int)lrintf(25.0f * v * v * v);
            if (p.aniso_min_neighbours < 3) p.aniso_min_neighbours = 3;
        }
        c->aniso = 1;
        c->an_radius = p.aniso_radius * r;
        c->an_lambda = p.aniso_smoothing < 0.0f ? 0.0f : p.aniso_smoothing;
        c->an_kr = p.aniso_max_ratio;
        c->an_ks = p.aniso_scale;
        c->an_kn = p.aniso_iso_scale;
        c->an_neps = p.aniso_min_neighbours;
    }
    c->smooth_iters = p.smooth_iterations;
    c->smooth_normal_iters = p.smooth_normal_iterations;
    c->smooth_implicit = p.smooth_implicit;
    c->simplify_error = p.simplify_error * r;
    c->unit_in = 1.0f; /* mesh.c sets the unit (units.h) */
    if (p.field == JM_FIELD_METASPHERE) jm_metavertex_config(c);
    c->cull = p.field == JM_FIELD_SPH && !p.reserved0; /* reserved0: jm_testing_no_culling */
    for (int k = 0; k < 3; k++) {
        c->sel_box |= p.particle_aabb_min[k] != 0.0f || p.particle_aabb_max[k] != 0.0f;
        c->clip |= p.mesh_aabb_min[k] != 0.0f || p.mesh_aabb_max[k] != 0.0f;
    }
    if (c->sel_box) {
        memcpy(c->sel_lo, p.particle_aabb_min, sizeof c->sel_lo);
        memcpy(c->sel_hi, p.particle_aabb_max, sizeof c->sel_hi);
    }
    if (p.min_piece_particles > 1) {
        c->sel_min_group = p.min_piece_particles;
        /* metasphere: linked, or balls (radius r (1 - t)) touching */
        const float touch = 2.0f * r * (1.0f - (p.threshold < 0.0f ? p.threshold : 0.0f));
        c->sel_link = p.field == JM_FIELD_SPH ? c->support : (c->link > touch ? c->link : touch);
    }
    c->piece_min_volume = (double)p.min_piece_volume * r * r * r;
    if (c->clip) {
        c->clip = p.mesh_aabb_clamp ? 2 : 1;
        memcpy(c->clip_lo, p.mesh_aabb_min, sizeof c->clip_lo);
        memcpy(c->clip_hi, p.mesh_aabb_max, sizeof c->clip_hi);
    }
    if (f) *f = p;
    return JM_OK;
}
