/* test_limits.c - the library's guards: estimates check what meshing checks, thread counts are capped, stated limits hold. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_estimate_checks),
        cmocka_unit_test(test_thread_cap),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
