/* eval.c - brute-force evaluation of the implicit function and its gradient at one point. */
#include "core/internal.h"
#include "field/aniso/anisotropy.h"
#include "core/units.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* particle i in the library's unit (units.h): times unit_in, a power of two */
static void load(const jm_particles *ps, size_t i, float unit_in, float p[3])
{
    size_t stride = ps->stride ? ps->stride : 3 * sizeof(float);
    memcpy(p, (const char *)ps->xyz + i * stride, 3 * sizeof(float));
    for (int a = 0; a < 3; a++) p[a] *= unit_in;
}

jm_status jm_field_eval(const jm_params *params, const jm_particles *ps, const float x_world[3], float *out_value,
                        float out_gradient[3])
{
    if (!params || !ps || !x_world || !out_value || (ps->count && !ps->xyz)) return JM_E_INVALID_ARGUMENT;
    jm_config c;
    if (jm_params_check(params, NULL) != JM_OK) return JM_E_INVALID_ARGUMENT;
    /* in the library's unit, as jm_mesh_particles: the anisotropic kernels'
     * matrices (1 / length^2, in float) stay in range at any radius */
    jm_params units;
    const int unit = jm_unit_exponent(params->radius);
    jm_unit_params(params, unit, &units);
    jm_status st = jm_config_resolve(&units, &c, NULL);
    if (st != JM_OK) return st;
    const float unit_in = ldexpf(1.0f, -unit);
    const float x[3] = {x_world[0] * unit_in, x_world[1] * unit_in, x_world[2] * unit_in};
    size_t n = ps->count;
    double grad[3] = {0, 0, 0};
    double value;
    if (c.field == JM_FIELD_SPH && c.aniso) {
        /* every particle's volume, centre and kernel by brute force, then
         * the sum (a particle with no neighbour in its support counts as
         * isolated only for the lattice, which meshes it from a template of
         * this same kernel) */
        float *an = malloc((n ? n : 1) * JM_AN_STRIDE * sizeof *an);
        if (!an) return JM_E_OUT_OF_MEMORY;
        const double inv = 1.0 / c.sph_h;
        float S2, invB;
        jm_an_near_radius(&c, &S2, &invB);
        for (size_t j = 0; j < n; j++) {
            float pj[3];
            load(ps, j, unit_in, pj);
            double sum = 0;
            jm_an_acc acc;
            memset(&acc, 0, sizeof acc);
            for (size_t k = 0; k < n; k++) {
                float pk[3];
                load(ps, k, unit_in, pk);
                double d = sqrt((double)(pk[0] - pj[0]) * (pk[0] - pj[0]) + (double)(pk[1] - pj[1]) * (pk[1] - pj[1]) +
                                (double)(pk[2] - pj[2]) * (pk[2] - pj[2]));
                if (d < c.support) sum += jm_cubic_w((float)(d * inv));
                jm_an_add(&acc, pj, pk, c.an_radius, S2, invB);
            }
            jm_an_finish(&c, pj, &acc, (float)(1.0 / sum), an + JM_AN_STRIDE * j);
        }
        value = 0;
        for (size_t j = 0; j < n; j++) {
            const float *a = an + JM_AN_STRIDE * j;
            double d[3] = {x[0] - a[0], x[1] - a[1], x[2] - a[2]};
            double md[3] = {a[3] * d[0] + a[4] * d[1] + a[5] * d[2], a[4] * d[0] + a[6] * d[1] + a[7] * d[2],
                            a[5] * d[0] + a[7] * d[1] + a[8] * d[2]};
            double q2 = d[0] * md[0] + d[1] * md[1] + d[2] * md[2];
            if (!(q2 < 4.0)) continue;
            double q = sqrt(q2);
            value += a[9] * jm_cubic_w((float)q);
            if (q > 0)
                for (int k = 0; k < 3; k++) grad[k] += a[9] * jm_cubic_dw((float)q) / q * md[k];
        }
        free(an);
    } else if (c.field == JM_FIELD_SPH) {
        const double inv = 1.0 / c.sph_h, R = c.support;
        value = 0;
        for (size_t j = 0; j < n; j++) {
            float pj[3];
            load(ps, j, unit_in, pj);
            double sum = 0;
            for (size_t k = 0; k < n; k++) {
                float pk[3];
                load(ps, k, unit_in, pk);
                double d = sqrt((double)(pk[0] - pj[0]) * (pk[0] - pj[0]) + (double)(pk[1] - pj[1]) * (pk[1] - pj[1]) +
                                (double)(pk[2] - pj[2]) * (pk[2] - pj[2]));
                if (d < R) sum += jm_cubic_w((float)(d * inv));
            }
            double w[3] = {x[0] - pj[0], x[1] - pj[1], x[2] - pj[2]};
            double d = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            if (d >= R) continue;
            value += jm_cubic_w((float)(d * inv)) / sum;
            if (d > 0)
                for (int a = 0; a < 3; a++) grad[a] += jm_cubic_dw((float)(d * inv)) * inv / sum * w[a] / d;
        }
    } else {
        const double r = c.r;
        value = -INFINITY;
        for (size_t i = 0; i < n; i++) {
            float ci[3];
            load(ps, i, unit_in, ci);
            double w[3] = {x[0] - ci[0], x[1] - ci[1], x[2] - ci[2]};
            double d = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            double v = 1.0 - d / r;
            if (v > value) {
                value = v;
                for (int a = 0; a < 3; a++) grad[a] = d > 0 ? -w[a] / (d * r) : 0;
            }
            for (size_t j = 0; j < n; j++) {
                if (j == i) continue;
                float cj[3];
                load(ps, j, unit_in, cj);
                double u[3] = {cj[0] - ci[0], cj[1] - ci[1], cj[2] - ci[2]};
                double D = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
                if (!(D < c.link) || D == 0) continue;
                for (int a = 0; a < 3; a++) u[a] /= D;
                double s = w[0] * u[0] + w[1] * u[1] + w[2] * u[2];
                if (s < 0 || s > 0.5 * D) continue; /* the other half belongs to j */
                double rad[3] = {w[0] - s * u[0], w[1] - s * u[1], w[2] - s * u[2]};
                double q = sqrt(rad[0] * rad[0] + rad[1] * rad[1] + rad[2] * rad[2]);
                double nv = cos(s / r) - q / r;
                if (nv > value) {
                    value = nv;
                    for (int a = 0; a < 3; a++) grad[a] = (-sin(s / r) * u[a] - (q > 0 ? rad[a] / q : 0)) / r;
                }
            }
        }
        if (n == 0) value = -1.0;
    }
    *out_value = (float)value;
    if (out_gradient)
        for (int a = 0; a < 3; a++) out_gradient[a] = (float)(grad[a] * unit_in); /* per world unit */
    return JM_OK;
}
