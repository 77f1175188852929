/* params.c - status messages, version, and parameter defaults/validation. */
#include "internal.h"
#include "metavertex.h"
#include <math.h>

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
    }
    return "unknown status";
}

const char *jm_version(void) { return JM_VERSION_STRING; }

static int bad(float v) { return !isfinite(v) || v < 0.0f; }

jm_status jm_config_resolve(const jm_params *in, jm_config *c, jm_params *f)
{
    if (!in) return JM_E_INVALID_ARGUMENT;
    jm_params p = *in;
    if (!isfinite(p.radius) || p.radius <= 0.0f) return JM_E_INVALID_ARGUMENT;
    if (bad(p.cube_size) || bad(p.smoothing_length) || bad(p.link_distance) || bad(p.uv_scale) ||
        !isfinite(p.threshold) || p.threads < 0 || p.uv_axis < 0 || p.uv_axis > 3)
        return JM_E_INVALID_ARGUMENT;
    if (p.field == JM_FIELD_DEFAULT) p.field = JM_FIELD_METASPHERE;
    if (p.method == JM_METHOD_DEFAULT) p.method = JM_METHOD_MT;
    if (p.uv_mode == JM_UV_DEFAULT) p.uv_mode = JM_UV_BOX;
    if (p.field != JM_FIELD_METASPHERE && p.field != JM_FIELD_SPH) return JM_E_INVALID_ARGUMENT;
    if (p.method != JM_METHOD_MT && p.method != JM_METHOD_MC) return JM_E_INVALID_ARGUMENT;
    if (p.uv_mode < JM_UV_BOX || p.uv_mode > JM_UV_NONE) return JM_E_INVALID_ARGUMENT;
    if (p.cube_size == 0.0f) p.cube_size = 0.5f;
    if (p.smoothing_length == 0.0f) p.smoothing_length = 2.0f;
    if (p.link_distance == 0.0f) p.link_distance = (float)M_PI;
    if (p.threshold == 0.0f && p.field == JM_FIELD_SPH) p.threshold = 0.6f;
    if (p.uv_scale == 0.0f) p.uv_scale = 16.0f * p.radius;
    if (p.uv_axis == 0) p.uv_axis = 3;
    if (p.cube_size < 1e-3f || p.cube_size > 100.0f) return JM_E_INVALID_ARGUMENT;
    if (p.smoothing_length < 0.05f || p.smoothing_length > 100.0f) return JM_E_INVALID_ARGUMENT;
    if (p.field == JM_FIELD_SPH && (p.threshold <= 0.0f)) return JM_E_INVALID_ARGUMENT;
    if (p.field == JM_FIELD_METASPHERE && (p.threshold <= -1.0f || p.threshold >= 1.0f))
        return JM_E_INVALID_ARGUMENT;

    float r = p.radius;
    c->r = r;
    c->h = p.cube_size * r;
    c->inv_h = 1.0f / c->h;
    c->field = p.field;
    c->method = p.method;
    c->threshold = p.threshold;
    c->sph_h = p.smoothing_length * r;
    c->support = 2.0f * c->sph_h;
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
    /* blocks three (SPH) or four (metasphere) influence radii wide: measured
     * best (bigger blocks waste nodes on thin jets and sample more per block
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
    c->max_bytes = p.max_bytes;
    c->exact = p.exact_surface != 0;
    if (p.field == JM_FIELD_METASPHERE) jm_metavertex_config(c);
    if (f) *f = p;
    return JM_OK;
}
