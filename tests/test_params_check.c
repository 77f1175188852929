/* test_params_check.c - jm_params_check: which member is out of range, its accepted range, and agreement with jm_context_create. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "../lib/jetmesh.h"

static jm_params base(void)
{
    jm_params p;
    memset(&p, 0, sizeof p);
    p.radius = 0.025f;
    return p;
}

/* p is refused, naming field, with [min, max] as given; and
 * jm_context_create refuses it too. */
static void refused(jm_params p, const char *field, double min, double max)
{
    jm_param_problem pr;
    memset(&pr, 0x5a, sizeof pr);
    assert_int_equal(jm_params_check(&p, &pr), JM_E_INVALID_ARGUMENT);
    assert_non_null(pr.field);
    assert_string_equal(pr.field, field);
    assert_non_null(pr.accepted);
    assert_true(strlen(pr.accepted) > 0);
    assert_true(pr.min == min || (isinf(min) && isinf(pr.min) && (min < 0) == (pr.min < 0)));
    assert_true(pr.max == max || (isinf(max) && isinf(pr.max) && (max < 0) == (pr.max < 0)));
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    assert_null(ctx);
}

static void accepted(jm_params p)
{
    jm_param_problem pr;
    memset(&pr, 0x5a, sizeof pr);
    assert_int_equal(jm_params_check(&p, &pr), JM_OK);
    assert_null(pr.field); /* zeroed */
    assert_null(pr.accepted);
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_context_free(ctx);
}

static void test_each_member(void **state)
{
    (void)state;
    jm_params p = base();
    accepted(p);

    p = base(); p.radius = 0;                 refused(p, "radius", 0, HUGE_VAL);
    p = base(); p.radius = -1;                refused(p, "radius", 0, HUGE_VAL);
    p = base(); p.radius = NAN;               refused(p, "radius", 0, HUGE_VAL);
    p = base(); p.cube_size = 0.0005f;        refused(p, "cube_size", 1e-3f, 100.0f);
    p = base(); p.cube_size = 101;            refused(p, "cube_size", 1e-3f, 100.0f);
    p = base(); p.cube_size = INFINITY;       refused(p, "cube_size", 1e-3f, 100.0f);
    p = base(); p.field = (jm_field)7;        refused(p, "field", 0, 2);
    p = base(); p.method = (jm_method)-1;     refused(p, "method", 0, 2);
    p = base(); p.threshold = 1;              refused(p, "threshold", -1, 1);
    p = base(); p.threshold = -1;             refused(p, "threshold", -1, 1);
    p = base(); p.field = JM_FIELD_SPH; p.threshold = -0.5f; refused(p, "threshold", 0, HUGE_VAL);
    p = base(); p.threshold = NAN;            refused(p, "threshold", -HUGE_VAL, HUGE_VAL);
    p = base(); p.smoothing_length = 0.01f;   refused(p, "smoothing_length", 0.05f, 100.0f);
    p = base(); p.link_distance = -1;         refused(p, "link_distance", 0, HUGE_VAL);
    p = base(); p.threads = -2;               refused(p, "threads", 0, 2147483647.0);
    p = base(); p.uv_mode = (jm_uv_mode)9;    refused(p, "uv_mode", 0, 4);
    p = base(); p.uv_scale = -1;              refused(p, "uv_scale", 0, HUGE_VAL);
    /* issue 30: below 1e-6 r, texture coordinates could pass the float range */
    p = base(); p.uv_scale = 1.2e-38f;        refused(p, "uv_scale", 1e-6f * 0.025f, HUGE_VAL);
    p = base(); p.uv_scale = 1e-6f * 0.025f;  accepted(p);
    p = base(); p.uv_axis = 4;                refused(p, "uv_axis", 0, 3);
    p = base(); p.smooth_implicit = 2;        refused(p, "smooth_implicit", 0, 1);
    p = base(); p.smooth_implicit = -1;       refused(p, "smooth_implicit", 0, 1);

    /* the range's ends and the defaults are accepted */
    p = base(); p.cube_size = 1e-3f; p.smoothing_length = 100; accepted(p);
    p = base(); p.cube_size = 100; p.threshold = 0.999f; accepted(p);
    p = base(); p.threshold = -0.999f; p.link_distance = 0; p.uv_axis = 3; accepted(p);
    p = base(); p.smooth_implicit = 1; accepted(p); /* without smooth_iterations: nothing to do */
    p = base(); p.field = JM_FIELD_SPH; p.threshold = 0; accepted(p);
    p = base(); p.field = JM_FIELD_SPH; p.threshold = 5; accepted(p); /* legal, maybe empty */
}

static void test_value_and_order(void **state)
{
    (void)state;
    jm_param_problem pr;
    jm_params p = base();
    p.cube_size = 0.0005f;
    p.threshold = 3; /* also out: the first member in struct order is named */
    assert_int_equal(jm_params_check(&p, &pr), JM_E_INVALID_ARGUMENT);
    assert_string_equal(pr.field, "cube_size");
    assert_true(fabs(pr.value - 0.0005) < 1e-9);
    assert_int_equal(pr.min_excluded, 0);
    assert_int_equal(pr.max_excluded, 0);

    p = base();
    p.radius = 0;
    assert_int_equal(jm_params_check(&p, &pr), JM_E_INVALID_ARGUMENT);
    assert_int_equal(pr.min_excluded, 1);

    p = base();
    p.threshold = 2;
    assert_int_equal(jm_params_check(&p, &pr), JM_E_INVALID_ARGUMENT);
    assert_int_equal(pr.min_excluded, 1);
    assert_int_equal(pr.max_excluded, 1);
    assert_true(pr.value == 2);

    /* NULL params, NULL problem */
    assert_int_equal(jm_params_check(NULL, &pr), JM_E_INVALID_ARGUMENT);
    assert_null(pr.field);
    assert_non_null(pr.accepted);
    p = base();
    p.cube_size = -1;
    assert_int_equal(jm_params_check(&p, NULL), JM_E_INVALID_ARGUMENT);
    assert_int_equal(jm_params_check(NULL, NULL), JM_E_INVALID_ARGUMENT);
}

/* set_params and field_eval refuse what check refuses */
static void test_same_rules_everywhere(void **state)
{
    (void)state;
    jm_params p = base();
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_params bad = base();
    bad.smoothing_length = 200;
    assert_int_equal(jm_context_set_params(ctx, &bad), JM_E_INVALID_ARGUMENT);
    const float xyz[3] = {0, 0, 0}, at[3] = {0, 0, 0};
    jm_particles in = {xyz, 1, 0, NULL};
    float v = 0;
    assert_int_equal(jm_field_eval(&bad, &in, at, &v, NULL), JM_E_INVALID_ARGUMENT);
    assert_int_equal(jm_field_eval(&p, &in, at, &v, NULL), JM_OK);
    jm_context_free(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_each_member),
        cmocka_unit_test(test_value_and_order),
        cmocka_unit_test(test_same_rules_everywhere),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
