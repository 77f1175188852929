/* test_context_interpolate.c - jm_context_interpolate: a brute-force reference, the same bits on 1 to 3 threads, agreement with jm_interpolate_attributes on real frames, the fallback and the errors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../formats/reader.h"
#include "../lib/jetmesh.h"
#include "util/ref_interpolate.h"
#include "util/shared_data.h"

#define R 0.025f

static float frand(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (float)(*s >> 8) / 16777216.0f;
}

static jm_context *context(int threads, jm_field field)
{
    jm_params p = {0};
    p.radius = R;
    p.threads = threads;
    p.field = field;
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    return ctx;
}

/* random particles in a 10r box with a 3-vector and a scalar each; random
 * points (some out of reach); every point against the double-precision
 * sum over all particles, the fallback against the nearest particle, and
 * the same bits for 1, 2 and 3 threads */
static void test_reference(void **state)
{
    (void)state;
    enum { N = 500, NV = 2000 };
    unsigned s = 7;
    float *xyz = malloc(N * 12), *vel = malloc(N * 12), *rho = malloc(N * 4), *pos = malloc(NV * 12);
    for (size_t i = 0; i < 3 * N; i++) {
        xyz[i] = 10 * R * frand(&s);
        vel[i] = 2 * frand(&s) - 1;
    }
    for (size_t i = 0; i < N; i++) rho[i] = 1000 + 10 * frand(&s);
    for (size_t i = 0; i < 3 * NV; i++) pos[i] = -3 * R + 16 * R * frand(&s);
    float *out[4][2];
    jm_particles in = {xyz, N, 0, NULL};
    for (int t = 1; t <= 3; t++) {
        out[t][0] = malloc(NV * 12);
        out[t][1] = malloc(NV * 4);
        jm_context *ctx = context(t, JM_FIELD_SPH);
        jm_attribute at[2] = {{3, vel, out[t][0]}, {1, rho, out[t][1]}};
        assert_int_equal(jm_context_interpolate(ctx, &in, pos, NV, at, 2), JM_OK);
        jm_context_free(ctx);
        if (t > 1) {
            assert_memory_equal(out[t][0], out[1][0], NV * 12);
            assert_memory_equal(out[t][1], out[1][1], NV * 4);
        }
    }
    const double h = 2 * R;
    size_t fallback = 0;
    for (size_t v = 0; v < NV; v++) {
        ref_interp r;
        ref_interpolate(pos + 3 * v, xyz, vel, rho, N, h, &r);
        const double sw = r.sw, *a = r.a;
        const size_t best = r.nearest;
        if (sw > 1e-6) {
            for (int k = 0; k < 3; k++) assert_true(fabs(out[1][0][3 * v + k] - a[k] / sw) < 1e-5);
            assert_true(fabs(out[1][1][v] - a[3] / sw) < 1e-3);
        } else if (sw == 0) {
            fallback++;
            for (int k = 0; k < 3; k++) assert_true(out[1][0][3 * v + k] == vel[3 * best + k]);
            assert_true(out[1][1][v] == rho[best]);
        }
    }
    assert_true(fallback > 0 && fallback < NV); /* both paths were taken */
    for (int t = 1; t <= 3; t++) {
        free(out[t][0]);
        free(out[t][1]);
    }
    free(xyz); free(vel); free(rho); free(pos);
}

/* a real frame's velocities on its own mesh, both fields: the same bits on
 * 1 and 2 threads, within float roundings of jm_interpolate_attributes */
static void real_frame(const char *rel, jm_field field)
{
    jmf_read_options o = {0};
    o.attributes = "velocity";
    jmf_frame f;
    char err[512];
    if (test_read_shared(rel, &o, &f, err, sizeof err) != 1) {
        fprintf(stderr, "skipping: %s\n", err);
        skip();
    }
    jm_particles in = {f.xyz, f.count, 0, f.ids};
    float *out[3] = {NULL, NULL, NULL}, *ref = NULL;
    size_t nv = 0;
    for (int t = 1; t <= 2; t++) {
        jm_context *ctx = context(t, field);
        jm_mesh m;
        assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
        nv = m.vertex_count;
        assert_true(nv > 1000);
        out[t] = malloc(nv * 12);
        jm_attribute a = {3, f.attributes[0].values, out[t]};
        assert_int_equal(jm_context_interpolate(ctx, &in, m.positions, nv, &a, 1), JM_OK);
        if (t == 1) {
            ref = malloc(nv * 12);
            jm_attribute b = {3, f.attributes[0].values, ref};
            jm_params p;
            jm_context_get_params(ctx, &p);
            assert_int_equal(jm_interpolate_attributes(&p, &in, m.positions, nv, &b, 1), JM_OK);
        }
        jm_context_free(ctx);
    }
    assert_memory_equal(out[1], out[2], nv * 12);
    double top = 0, worst = 0;
    for (size_t i = 0; i < 3 * f.count; i++) top = fmax(top, fabs(f.attributes[0].values[i]));
    for (size_t i = 0; i < 3 * nv; i++) worst = fmax(worst, fabs((double)out[1][i] - ref[i]));
    assert_true(top > 0.1);
    assert_true(worst <= 1e-5 * top);
    free(out[1]); free(out[2]); free(ref);
    jmf_frame_free(&f);
}

static void test_real_sph(void **state)
{
    (void)state;
    real_frame("splashsurf/dam_break_frame_9_6859_particles.bgeo", JM_FIELD_SPH);
}

static void test_real_metasphere(void **state)
{
    (void)state;
    real_frame("splashsurf/ParticleData_Fluid_5.vtk", JM_FIELD_METASPHERE);
}

static void test_errors(void **state)
{
    (void)state;
    float xyz[6] = {0, 0, 0, R, 0, 0}, val[2] = {1, 3}, pos[6] = {0.5f * R, 0, 0, 100, 100, 100}, out[2] = {-1, -1};
    jm_context *ctx = context(2, JM_FIELD_METASPHERE);
    jm_particles in = {xyz, 2, 0, NULL};
    jm_attribute a = {1, val, out};
    /* one point between the two (the mean by symmetry), one far: the nearest */
    assert_int_equal(jm_context_interpolate(ctx, &in, pos, 2, &a, 1), JM_OK);
    assert_true(fabsf(out[0] - 2.0f) < 1e-6f);
    assert_true(out[1] == 3.0f);
    /* no particles: zeros */
    jm_particles none = {xyz, 0, 0, NULL};
    assert_int_equal(jm_context_interpolate(ctx, &none, pos, 2, &a, 1), JM_OK);
    assert_true(out[0] == 0.0f && out[1] == 0.0f);
    /* refused */
    assert_int_equal(jm_context_interpolate(NULL, &in, pos, 2, &a, 1), JM_E_INVALID_ARGUMENT);
    jm_attribute bad = {0, val, out};
    assert_int_equal(jm_context_interpolate(ctx, &in, pos, 2, &bad, 1), JM_E_INVALID_ARGUMENT);
    jm_attribute many[5] = {{16, val, out}, {16, val, out}, {16, val, out}, {16, val, out}, {1, val, out}};
    assert_int_equal(jm_context_interpolate(ctx, &in, pos, 2, many, 5), JM_E_INVALID_ARGUMENT);
    pos[4] = NAN;
    assert_int_equal(jm_context_interpolate(ctx, &in, pos, 2, &a, 1), JM_E_INVALID_ARGUMENT);
    pos[4] = 0;
    xyz[1] = INFINITY;
    assert_int_equal(jm_context_interpolate(ctx, &in, pos, 2, &a, 1), JM_E_INVALID_PARTICLE);
    jm_context_free(ctx);
}

/* a support far under the surface's distance (smoothing length 0.05 r):
 * every vertex takes its nearest particle's values, the same as
 * jm_interpolate_attributes finds them (ties: the first in input order) */
static void test_nearest_everywhere(void **state)
{
    (void)state;
    enum { N = 400 };
    unsigned s = 3;
    float *xyz = malloc(N * 12), *val = malloc(N * 4);
    for (size_t i = 0; i < N; i++) {
        for (int k = 0; k < 3; k++) xyz[3 * i + k] = 0.025f * (float)(int)(16 * frand(&s)); /* ties on a lattice */
        val[i] = (float)i;
    }
    jm_params p = {0};
    p.radius = R;
    p.smoothing_length = 0.05f;
    p.threads = 2;
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {xyz, N, 0, NULL};
    jm_mesh m;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
    assert_true(m.vertex_count > 1000);
    float *a = malloc(m.vertex_count * 4), *b = malloc(m.vertex_count * 4);
    jm_attribute aa = {1, val, a}, bb = {1, val, b};
    assert_int_equal(jm_context_interpolate(ctx, &in, m.positions, m.vertex_count, &aa, 1), JM_OK);
    assert_int_equal(jm_interpolate_attributes(&p, &in, m.positions, m.vertex_count, &bb, 1), JM_OK);
    assert_memory_equal(a, b, m.vertex_count * 4);
    free(a); free(b); free(xyz); free(val);
    jm_context_free(ctx);
}

/* the particles the context's selection leaves out of the mesh are left
 * out of the sums: between a particle inside the particle box (1) and one
 * outside (3), 1 rather than the mean */
static void test_selection(void **state)
{
    (void)state;
    float xyz[6] = {0, 0, 0, R, 0, 0}, val[2] = {1, 3}, pos[3] = {0.5f * R, 0, 0}, out = -1;
    jm_params p = {0};
    p.radius = R;
    p.particle_aabb_min[0] = p.particle_aabb_min[1] = p.particle_aabb_min[2] = -R;
    p.particle_aabb_max[0] = 0.5f * R;
    p.particle_aabb_max[1] = p.particle_aabb_max[2] = R;
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {xyz, 2, 0, NULL};
    jm_attribute a = {1, val, &out};
    assert_int_equal(jm_context_interpolate(ctx, &in, pos, 1, &a, 1), JM_OK);
    assert_true(out == 1.0f);
    /* every particle outside: zeros, as with none */
    p.particle_aabb_min[0] = 2 * R;
    p.particle_aabb_max[0] = 3 * R;
    assert_int_equal(jm_context_set_params(ctx, &p), JM_OK);
    assert_int_equal(jm_context_interpolate(ctx, &in, pos, 1, &a, 1), JM_OK);
    assert_true(out == 0.0f);
    jm_context_free(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference),
        cmocka_unit_test(test_real_sph),
        cmocka_unit_test(test_real_metasphere),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_selection),
        cmocka_unit_test(test_nearest_everywhere),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
