/* test_aniso_rim.c - jm_an_rim on random kernels: a rim's kernel reaches no further outward than the sphere, by the least change (issue 31). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* internal (white-box test): the rule under test */
#include "../lib/field/aniso/aniso_shape.h"
#include "../lib/core/sym3.h"
#include "util/meshcheck.h"

static double drand(unsigned *s) { return (double)mc_randf(s); }

/* the kernel's reach (relative to h) along unit direction u: 1 / |diag(1/s) R^T u| */
static double reach(const double R[9], const double s[3], const double u[3])
{
    double f = 0.0;
    for (int k = 0; k < 3; k++) {
        const double d = R[k] * u[0] + R[3 + k] * u[1] + R[6 + k] * u[2];
        f += d * d / (s[k] * s[k]);
    }
    return 1.0 / sqrt(f);
}

/* Random neighbourhood shapes (axes from jm_an_axes, random directions) and
 * means off the particle by 0 to 2.5 r: axes never grow and keep their
 * order, the sphere's and the shorter axes stay; from 1.5 r off, the reach
 * away from the mean is at most the sphere's, and equal to it where it had
 * been more (the least change); under 0.5 r nothing changes. */
static void test_rim_reach(void **state)
{
    (void)state;
    jm_config c;
    memset(&c, 0, sizeof c);
    c.r = 0.025f;
    c.sph_h = 2.0f * c.r;
    c.an_kr = 4.0f;
    unsigned seed = 7u;
    int cut = 0, full = 0;
    for (int trial = 0; trial < 4000; trial++) {
        c.an_ks = trial % 2 ? 1.0f : (float)(0.7 + 0.6 * drand(&seed));
        const double ks = c.an_ks;
        double val[3] = {1.0, drand(&seed), 0.0};
        val[2] = val[1] * drand(&seed);
        double s[3], s0[3], C[6], v[3], R[9];
        jm_an_axes(&c, val, drand(&seed), s);
        for (int k = 0; k < 6; k++) C[k] = 2.0 * drand(&seed) - 1.0;
        jm_sym3_eigen(C, v, R);
        double mean[3], ml = 0.0;
        for (int k = 0; k < 3; k++) mean[k] = 2.0 * drand(&seed) - 1.0, ml += mean[k] * mean[k];
        ml = sqrt(ml);
        const double off = 2.5 * drand(&seed) * c.r;
        double u[3];
        for (int k = 0; k < 3; k++) mean[k] *= off / ml, u[k] = -mean[k] / off;
        memcpy(s0, s, sizeof s);
        const double before = reach(R, s, u);
        jm_an_rim(&c, R, mean, s);
        const double after = reach(R, s, u);
        for (int k = 0; k < 3; k++) {
            assert_true(s[k] <= s0[k]);
            if (s0[k] <= ks) assert_true(s[k] == s0[k]);
            else assert_true(s[k] >= ks * (1.0 - 1e-12));
        }
        assert_true(s[0] >= s[1] && s[1] >= s[2]);
        if (off <= 0.5 * c.r || before <= ks) {
            assert_memory_equal(s, s0, sizeof s);
        } else if (off >= 1.5 * c.r) {
            assert_true(after <= ks * (1.0 + 1e-6));
            assert_true(after >= ks * (1.0 - 1e-6));
            full++;
        }
        cut += memcmp(s, s0, sizeof s) != 0;
    }
    printf("%d of 4000 kernels shortened, %d of them fully\n", cut, full);
    /* the test tests: both cases occur often */
    assert_true(cut >= 400);
    assert_true(full >= 200);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rim_reach),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
