/* params_check.c - validates jm_params and names the member out of range with the values it accepts. */
#include "core/internal.h"
#include <float.h>
#include <limits.h>
#include <math.h>
#include <string.h>

/* Fills the problem (when wanted) and returns JM_E_INVALID_ARGUMENT. */
static jm_status refuse(jm_param_problem *out, const char *field, double value, double min, int min_excluded,
                        double max, int max_excluded, const char *accepted)
{
    if (out) {
        out->field = field;
        out->value = value;
        out->min = min;
        out->min_excluded = min_excluded;
        out->max = max;
        out->max_excluded = max_excluded;
        out->accepted = accepted;
    }
    return JM_E_INVALID_ARGUMENT;
}

/* 0 (the default) or a finite value from lo to hi. */
static int in_range_or_zero(float v, float lo, float hi)
{
    return v == 0.0f || (isfinite(v) && v >= lo && v <= hi);
}

/* A box (which: 0 particle_aabb, 1 mesh_aabb): off (all six 0), or finite
 * with min below max on every axis. */
static jm_status check_box(const float lo[3], const float hi[3], int which, jm_param_problem *out)
{
    static const char *const lo_name[2][3] = {{"particle_aabb_min[0]", "particle_aabb_min[1]", "particle_aabb_min[2]"},
                                              {"mesh_aabb_min[0]", "mesh_aabb_min[1]", "mesh_aabb_min[2]"}};
    static const char *const hi_name[2][3] = {{"particle_aabb_max[0]", "particle_aabb_max[1]", "particle_aabb_max[2]"},
                                              {"mesh_aabb_max[0]", "mesh_aabb_max[1]", "mesh_aabb_max[2]"}};
    int on = 0;
    for (int k = 0; k < 3; k++) on |= lo[k] != 0.0f || hi[k] != 0.0f;
    if (!on) return JM_OK;
    for (int k = 0; k < 3; k++) {
        if (!isfinite(lo[k]))
            return refuse(out, lo_name[which][k], lo[k], -HUGE_VAL, 1, HUGE_VAL, 1, "a finite number");
        if (!isfinite(hi[k]))
            return refuse(out, hi_name[which][k], hi[k], -HUGE_VAL, 1, HUGE_VAL, 1, "a finite number");
        if (!(lo[k] < hi[k]))
            return refuse(out, hi_name[which][k], hi[k], lo[k], 1, HUGE_VAL, 0,
                          "above the box's minimum on this axis (min < max on every axis; all six 0 = no box)");
    }
    return JM_OK;
}

jm_status jm_params_check(const jm_params *p, jm_param_problem *out)
{
    if (out)
        memset(out, 0, sizeof *out);
    if (!p)
        return refuse(out, NULL, 0, 0, 0, 0, 0, "a jm_params (NULL given)");
    if (!isfinite(p->radius) || p->radius <= 0.0f)
        return refuse(out, "radius", p->radius, 0, 1, HUGE_VAL, 0, "a finite number above 0");
    if (p->radius < FLT_MIN) /* the numeric domain (jetmesh.h): a normal float */
        return refuse(out, "radius", p->radius, FLT_MIN, 0, HUGE_VAL, 0, "a normal float: 1.18e-38 or more");
    if (!in_range_or_zero(p->cube_size, 1e-3f, 100.0f))
        return refuse(out, "cube_size", p->cube_size, 1e-3f, 0, 100.0f, 0,
                      "0.001 to 100 (times radius; 0 = the default 0.5)");
    if (p->field != JM_FIELD_DEFAULT && p->field != JM_FIELD_METASPHERE && p->field != JM_FIELD_SPH)
        return refuse(out, "field", (double)p->field, JM_FIELD_DEFAULT, 0, JM_FIELD_SPH, 0,
                      "JM_FIELD_DEFAULT, JM_FIELD_METASPHERE or JM_FIELD_SPH");
    if (p->method != JM_METHOD_DEFAULT && p->method != JM_METHOD_MT && p->method != JM_METHOD_MC)
        return refuse(out, "method", (double)p->method, JM_METHOD_DEFAULT, 0, JM_METHOD_MC, 0,
                      "JM_METHOD_DEFAULT, JM_METHOD_MT or JM_METHOD_MC");
    if (!isfinite(p->threshold))
        return refuse(out, "threshold", p->threshold, -HUGE_VAL, 1, HUGE_VAL, 1, "a finite number");
    if (p->field == JM_FIELD_SPH && p->threshold < 0.0f)
        return refuse(out, "threshold", p->threshold, 0, 1, HUGE_VAL, 0,
                      "above 0 for the sph field (0 = the default 0.6)");
    if (p->field != JM_FIELD_SPH && (p->threshold <= -1.0f || p->threshold >= 1.0f))
        return refuse(out, "threshold", p->threshold, -1, 1, 1, 1,
                      "above -1 and below 1 for the metasphere field (default 0)");
    if (!in_range_or_zero(p->smoothing_length, 0.05f, 100.0f))
        return refuse(out, "smoothing_length", p->smoothing_length, 0.05f, 0, 100.0f, 0,
                      "0.05 to 100 (times radius; 0 = the default 2)");
    if (!isfinite(p->link_distance) || p->link_distance < 0.0f)
        return refuse(out, "link_distance", p->link_distance, 0, 0, HUGE_VAL, 0,
                      "a finite number from 0 (times radius; 0 = the default pi)");
    if (p->threads < 0)
        return refuse(out, "threads", p->threads, 0, 0, INT_MAX, 0, "0 (all cores) or more");
    if (p->uv_mode < JM_UV_DEFAULT || p->uv_mode > JM_UV_NONE)
        return refuse(out, "uv_mode", (double)p->uv_mode, JM_UV_DEFAULT, 0, JM_UV_NONE, 0,
                      "JM_UV_DEFAULT, JM_UV_BOX, JM_UV_PLANAR, JM_UV_SPHERICAL or JM_UV_NONE");
    if (!isfinite(p->uv_scale) || p->uv_scale < 0.0f)
        return refuse(out, "uv_scale", p->uv_scale, 0, 0, HUGE_VAL, 0,
                      "a finite number from 0 (world units; 0 = the default 16 radius)");
    if (p->uv_scale > 0.0f && p->uv_scale < (float)JM_UV_SCALE_MIN * p->radius) /* texture coordinates stay finite */
        return refuse(out, "uv_scale", p->uv_scale, (float)JM_UV_SCALE_MIN * p->radius, 0, HUGE_VAL, 0,
                      "0 (the default 16 radius) or 1e-06 radius and more (world units; texture coordinates "
                      "stay finite)");
    if (p->uv_axis < 0 || p->uv_axis > 3)
        return refuse(out, "uv_axis", p->uv_axis, 0, 0, 3, 0, "0 (default z), 1 x, 2 y or 3 z");
    if (p->anisotropic < 0 || p->anisotropic > 1)
        return refuse(out, "anisotropic", p->anisotropic, 0, 0, 1, 0, "0 or 1");
    if (p->anisotropic && p->field != JM_FIELD_SPH)
        return refuse(out, "anisotropic", p->anisotropic, 0, 0, 0, 0, "0 unless the field is JM_FIELD_SPH");
    if (p->anisotropic) {
        float sl = p->smoothing_length > 0.0f ? p->smoothing_length : 2.0f;
        if (!in_range_or_zero(p->aniso_radius, 0.1f, 4.0f * sl))
            return refuse(out, "aniso_radius", p->aniso_radius, 0.1f, 0, 4.0 * sl, 0,
                          "0.1 to 4 smoothing lengths (times radius; 0 = the default 4 smoothing lengths)");
        if (!isfinite(p->aniso_smoothing) || p->aniso_smoothing > 1.0f)
            return refuse(out, "aniso_smoothing", p->aniso_smoothing, -HUGE_VAL, 1, 1, 0,
                          "at most 1 (0 = the default 1; negative = no smoothing)");
        if (!in_range_or_zero(p->aniso_max_ratio, 1.0f, 100.0f))
            return refuse(out, "aniso_max_ratio", p->aniso_max_ratio, 1, 0, 100, 0, "1 to 100 (0 = the default 4)");
        if (!in_range_or_zero(p->aniso_scale, 0.05f, 4.0f))
            return refuse(out, "aniso_scale", p->aniso_scale, 0.05, 0, 4, 0, "0.05 to 4 (0 = the default 1)");
        if (!in_range_or_zero(p->aniso_iso_scale, 0.05f, 4.0f))
            return refuse(out, "aniso_iso_scale", p->aniso_iso_scale, 0.05, 0, 4, 0, "0.05 to 4 (0 = the default 1)");
        if (p->aniso_min_neighbours < 0)
            return refuse(out, "aniso_min_neighbours", p->aniso_min_neighbours, 0, 0, INT_MAX, 0,
                          "0 (the default) or more");
    }
    if (p->smooth_iterations < 0 || p->smooth_iterations > 100000)
        return refuse(out, "smooth_iterations", p->smooth_iterations, 0, 0, 100000, 0, "0 (off) to 100000");
    if (p->smooth_normal_iterations < 0 || p->smooth_normal_iterations > 100000)
        return refuse(out, "smooth_normal_iterations", p->smooth_normal_iterations, 0, 0, 100000, 0,
                      "0 (off) to 100000");
    if (!isfinite(p->simplify_error) || p->simplify_error < 0.0f || p->simplify_error > 1000.0f)
        return refuse(out, "simplify_error", p->simplify_error, 0, 0, 1000, 0, "0 (off) to 1000 (times radius)");
    jm_status b = check_box(p->particle_aabb_min, p->particle_aabb_max, 0, out);
    if (b != JM_OK) return b;
    if (p->min_piece_particles < 0)
        return refuse(out, "min_piece_particles", p->min_piece_particles, 0, 0, INT_MAX, 0, "0 (off) or more");
    if (!isfinite(p->min_piece_volume) || p->min_piece_volume < 0.0f)
        return refuse(out, "min_piece_volume", p->min_piece_volume, 0, 0, HUGE_VAL, 0,
                      "0 (off) or a finite volume above 0 (times radius cubed)");
    b = check_box(p->mesh_aabb_min, p->mesh_aabb_max, 1, out);
    if (b != JM_OK) return b;
    if (p->mesh_aabb_clamp < 0 || p->mesh_aabb_clamp > 1)
        return refuse(out, "mesh_aabb_clamp", p->mesh_aabb_clamp, 0, 0, 1, 0, "0 or 1");
    if (p->mesh_aabb_clamp) {
        int on = 0;
        for (int k = 0; k < 3; k++) on |= p->mesh_aabb_min[k] != 0.0f || p->mesh_aabb_max[k] != 0.0f;
        if (!on)
            return refuse(out, "mesh_aabb_clamp", p->mesh_aabb_clamp, 0, 0, 0, 0,
                          "0 unless the clip box (mesh_aabb_min/max) is set");
    }
    if (p->smooth_implicit < 0 || p->smooth_implicit > 1)
        return refuse(out, "smooth_implicit", p->smooth_implicit, 0, 0, 1, 0, "0 (off) or 1");
    return JM_OK;
}
