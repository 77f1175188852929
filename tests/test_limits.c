/* test_limits.c - the library's guards: estimates check what meshing checks, thread counts are capped, stated limits hold. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/jetmesh.h"

/* jm_estimate_bytes refuses what jm_mesh_particles refuses: a NaN in any
 * particle (the first one too) and a stride shorter than a particle */
static void test_estimate_checks(void **state)
{
    (void)state;
    jm_params p = {0};
    p.radius = 0.025f;
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    float xyz[9] = {NAN, 0, 0, 0.1f, 0, 0, 0.2f, 0, 0};
    jm_particles in = {xyz, 3, 0, NULL};
    size_t est = 0;
    jm_mesh m;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_E_INVALID_PARTICLE);
    assert_int_equal(jm_estimate_bytes(ctx, &in, &est), JM_E_INVALID_PARTICLE);
    xyz[0] = 0.0f;
    xyz[4] = INFINITY;
    assert_int_equal(jm_estimate_bytes(ctx, &in, &est), JM_E_INVALID_PARTICLE);
    xyz[4] = 0.0f;
    assert_int_equal(jm_estimate_bytes(ctx, &in, &est), JM_OK);
    assert_true(est > 0);
    in.stride = 8;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_E_INVALID_ARGUMENT);
    assert_int_equal(jm_estimate_bytes(ctx, &in, &est), JM_E_INVALID_ARGUMENT);
    jm_context_free(ctx);
}

/* threads beyond JM_MAX_THREADS are capped, and the cap is what the
 * parameters then say */
static void test_thread_cap(void **state)
{
    (void)state;
    jm_params p = {0};
    p.radius = 0.025f;
    p.threads = 4096;
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_params got;
    jm_context_get_params(ctx, &got);
    assert_int_equal(got.threads, JM_MAX_THREADS);
    float xyz[3] = {0, 0, 0};
    jm_particles in = {xyz, 1, 0, NULL};
    jm_mesh m;
    jm_stats st;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, &st), JM_OK);
    assert_int_equal(st.threads, JM_MAX_THREADS);
    assert_true(m.triangle_count > 0);
    jm_context_free(ctx);
}

/* Particles packed into one cell: the neighbour search is bounded and
 * refused up front (it was quadratic: 50,000 copies took seconds, ten
 * million would take days); a radius far too large for the spacing is
 * refused the same way; ordinary bulk fluid is not. */
static void test_dense_refused(void **state)
{
    (void)state;
    size_t n = 50000;
    float *xyz = malloc(n * 3 * sizeof *xyz);
    for (size_t i = 0; i < n; i++) {
        xyz[3 * i] = 0.1f;
        xyz[3 * i + 1] = 0.2f;
        xyz[3 * i + 2] = 0.3f;
    }
    jm_particles in = {xyz, n, 0, NULL};
    for (int f = JM_FIELD_METASPHERE; f <= JM_FIELD_SPH; f++) {
        jm_params p = {0};
        p.radius = 0.025f;
        p.field = (jm_field)f;
        jm_context *ctx = NULL;
        assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
        jm_mesh m;
        assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_E_TOO_DENSE);
        assert_int_equal(m.triangle_count, 0);
        jm_context_free(ctx);
    }
    /* a 40^3 lattice 0.05 apart: with r = 0.025 bulk fluid, fine; with
     * r = 0.25 (ten times too large) each particle would link to thousands */
    n = 0;
    for (int z = 0; z < 37; z++)
        for (int y = 0; y < 37; y++)
            for (int x = 0; x < 36; x++, n++) {
                xyz[3 * n] = 0.05f * (float)x;
                xyz[3 * n + 1] = 0.05f * (float)y;
                xyz[3 * n + 2] = 0.05f * (float)z;
            }
    in.count = n;
    jm_params p = {0};
    p.radius = 0.25f;
    p.field = JM_FIELD_METASPHERE;
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_mesh m;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_E_TOO_DENSE);
    jm_context_free(ctx);
    p.radius = 0.025f;
    p.field = JM_FIELD_SPH;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
    assert_true(m.triangle_count > 0);
    jm_context_free(ctx);
    assert_non_null(strstr(jm_status_message(JM_E_TOO_DENSE), "closer than their radius"));
    free(xyz);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_estimate_checks),
        cmocka_unit_test(test_thread_cap),
        cmocka_unit_test(test_dense_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
