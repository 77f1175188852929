/* units.c - the library's unit of length: a power of two near the radius, so no result depends on the user's unit. */
#include "core/units.h"
#include <float.h>
#include <math.h>

int jm_unit_exponent(float radius)
{
    int k = 0;
    (void)frexpf(radius, &k);
    return k;
}

/* A box's bound in units: past the float range (a bound far beyond the
 * numeric domain, where no particle lies), the largest float */
static float box_units(float v, int k)
{
    const float s = ldexpf(v, -k);
    return isinf(s) && isfinite(v) ? copysignf(FLT_MAX, s) : s;
}

void jm_unit_params(const jm_params *world, int k, jm_params *units)
{
    *units = *world;
    units->radius = ldexpf(world->radius, -k);
    units->uv_scale = ldexpf(world->uv_scale, -k); /* 0 (the default, 16 r) stays 0 */
    for (int a = 0; a < 3; a++) { /* the boxes (0, no box, stays 0) */
        units->particle_aabb_min[a] = box_units(world->particle_aabb_min[a], k);
        units->particle_aabb_max[a] = box_units(world->particle_aabb_max[a], k);
        units->mesh_aabb_min[a] = box_units(world->mesh_aabb_min[a], k);
        units->mesh_aabb_max[a] = box_units(world->mesh_aabb_max[a], k);
    }
}

void jm_unit_world_params(jm_params *filled, int k, const jm_params *world)
{
    filled->radius = world->radius;
    filled->uv_scale = ldexpf(filled->uv_scale, k);
    for (int a = 0; a < 3; a++) { /* as given */
        filled->particle_aabb_min[a] = world->particle_aabb_min[a];
        filled->particle_aabb_max[a] = world->particle_aabb_max[a];
        filled->mesh_aabb_min[a] = world->mesh_aabb_min[a];
        filled->mesh_aabb_max[a] = world->mesh_aabb_max[a];
    }
}

jm_status jm_unit_check(const jm_config *c, const float lo[3], const float hi[3], double reach)
{
    double far = 0.0;
    for (int a = 0; a < 3; a++) {
        double m = fmax(fabs((double)lo[a]), fabs((double)hi[a]));
        if (m > far) far = m;
    }
    /* float precision: the lattice nodes and the vertices between them are
     * floats, spaced |x| 2^-23 apart near |x|: beyond 2^16 cube edges from
     * the origin that exceeds 1/128 of a cube (see jetmesh.h) */
    if (far > JM_MAX_CUBES_FROM_ORIGIN * (double)c->h) return JM_E_NUMERIC_DOMAIN;
    /* the mesh (particles plus what reaches past them) stays within the
     * float range in world units, with a factor 2 to spare */
    if (ldexp(far + reach, c->unit) >= ldexp(1.0, 126)) return JM_E_NUMERIC_DOMAIN;
    return JM_OK;
}

double jm_unit_reach(const jm_config *c)
{
    double reach = c->influence;
    if (c->aniso) {
        /* as jm_estimate_bytes: k_s k_r^(2/3) (or k_n) supports from a
         * centre moved at most lambda r_n */
        double k = (double)c->an_ks * cbrt((double)c->an_kr * c->an_kr);
        double a = (double)c->support * (k > c->an_kn ? k : c->an_kn) + (double)c->an_lambda * c->an_radius;
        if (a > reach) reach = a;
    }
    return reach + 4.0 * c->block * (double)c->h;
}

void jm_unit_restore(float *pos, size_t nv, int k)
{
    if (k == 0) return;
    const float s = ldexpf(1.0f, k); /* k <= 126 within the domain: a normal float */
    for (size_t i = 0; i < 3 * nv; i++) pos[i] *= s;
}
