/* test_cull.c - the SPH field sampled only near the surface gives the same mesh bytes as every node sampled, and the interior bounds hold node by node. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/jetmesh_testing.h"
#include "../lib/jetmesh.h"
#include "../lib/field/sph/cull.h"
#include "../lib/field/sph/inside_boxes.h"
#include "../lib/field/sph/splat.h"
#include "util/cull_check.h"
#include "util/lattice.h"

/* Culled (1 and 2 threads) against every node sampled: the same bytes.
 * Variants: the reference case (cube r/2, threshold 0.6), then a coarser
 * lattice, a thinner threshold and a shorter kernel (other block sizes,
 * other sub-box splits). */
#define VARIANTS 4
#define ANISOTROPIC 0
static int fill_case(size_t k, int me, int v, jm_params *p, char *what, size_t whatsz)
{
    const float cube[] = {0.5f, 0.75f, 0.5f, 1.0f}, thr[] = {0.6f, 0.6f, 0.25f, 0.9f}, sl[] = {2.0f, 2.0f, 1.6f, 1.2f};
    if (k >= 2 && v == 0) return 0; /* the big cases on the two bench frames only */
    p->radius = 0.025f;
    p->field = JM_FIELD_SPH;
    p->method = (jm_method)me;
    p->cube_size = cube[v];
    p->threshold = thr[v];
    p->smoothing_length = sl[v];
    snprintf(what, whatsz, "%s %s cube %.2f thr %.2f h %.1f", cull_frames[k], me == JM_METHOD_MC ? "mc" : "mt", cube[v],
             thr[v], sl[v]);
    return 1;
}

static void test_real_frames_same_bytes(void **state)
{
    (void)state;
    char err[512];
    const int rc = cull_real_frames(VARIANTS, fill_case, err, sizeof err);
    if (rc < 0) fail_msg("%s", err);
    if (rc > 0) {
        printf("skipping: ../shared/data not found\n");
        skip();
    }
}

/* a lattice block with holes and a lone pair: culling next to cavities,
 * thin walls and particles on block faces */
static void test_block_with_holes(void **state)
{
    (void)state;
    char err[512];
    if (cull_holed_block_cases(ANISOTROPIC, err, sizeof err) != 0) fail_msg("%s", err);
}

/* The partial sums' lines (cull.h) lie below the kernel at every distance,
 * so each of their terms bounds the sample's from below: checked on a fine
 * grid of s = q^2 and at both tangent points, and they stay within 2e-3 of
 * the kernel there (the lines still touch it: a bound that proves nodes). */
static void test_tangent_lines_below_kernel(void **state)
{
    (void)state;
    const double a1 = JM_TAN_A1, b1 = JM_TAN_B1, a2 = JM_TAN_A2, b2 = JM_TAN_B2;
    double worst = -1.0; /* the largest line - kernel where a line is positive */
    for (int i = 0; i <= 6000000; i++) {
        const double s = i * 1e-6, l = fmax(0.0, fmax(a1 - b1 * s, a2 - b2 * s));
        const double gap = l - jm_cull_kernel(sqrt(s));
        if (l > 0.0 && gap > worst) worst = gap;
        if (gap >= 0.0 && l > 0.0) fail_msg("s = %.6f: line %.9f is not below the kernel %.9f", s, l, jm_cull_kernel(sqrt(s)));
    }
    const double t[2] = {0.64, 1.74}, a[2] = {a1, a2}, b[2] = {b1, b2};
    for (int k = 0; k < 2; k++) {
        const double gap = jm_cull_kernel(sqrt(t[k])) - (a[k] - b[k] * t[k]);
        assert_true(gap > 0.0 && gap < 2e-3);
    }
    assert_true(worst < 0.0);
}

/* The box pass's lines (inside_boxes.h), as the floats it uses: each lies
 * below the kernel at every s = q^2 (so a term on any line, at any
 * distance, bounds the sample's from below) and touches it within 2e-4 at
 * its tangent point (a bound that proves nodes); the last is the zero
 * line. */
static void test_box_lines_below_kernel(void **state)
{
    (void)state;
    float a[JM_BOX_BINS], b[JM_BOX_BINS];
    jm_box_lines(a, b, 1.0);
    assert_true(a[JM_BOX_BINS - 1] == 0.0f && b[JM_BOX_BINS - 1] == 0.0f);
    for (int k = 0; k < JM_BOX_BINS - 1; k++) {
        assert_true(b[k] >= 0.0f);
        for (int i = 0; i <= 600000; i++) {
            const double s = i * 1e-5, gap = ((double)a[k] - (double)b[k] * s) - jm_cull_kernel(sqrt(s));
            if (gap >= 0.0) fail_msg("line %d at s = %.5f: %.9f is not below the kernel %.9f", k, s, a[k] - b[k] * s,
                                     jm_cull_kernel(sqrt(s)));
        }
        const double sk = (k + 0.5) / JM_BOX_BINS_PER_S, gap = jm_cull_kernel(sqrt(sk)) - (a[k] - b[k] * sk);
        if (!(gap > 0.0 && gap < 2e-4)) fail_msg("line %d leaves the kernel at its tangent point (gap %.3g)", k, gap);
    }
}


/* The box pass's bounds, node by node, against the samples: on blocks of
 * a jittered lattice (deep inside, across its face, at its corner, and
 * offset by one and two nodes so that boxes and rows fall differently on
 * the particles), every node whose bound passes the proof level samples
 * above the threshold, no bound exceeds its sample by more than the
 * sample's own rounding, and deep inside nearly every node is proven (a
 * pass that proves nothing is no use); on the box pass's path `path`.
 * White-box: the internal calls. */
static void box_bounds_case(float cube, int path)
{
    const int S = 40; /* sites a side, spacing 2r, jittered by up to 0.1 r (as the block scene) */
    const float r = 0.025f;
    const size_t np = (size_t)S * S * S;
    float *xyz = test_lattice(S, 2.0f * r, 0.2f * r, 12345u, 0);
    assert_non_null(xyz);
    jm_params p = {0};
    p.radius = r;
    p.field = JM_FIELD_SPH;
    p.smoothing_length = 2.0f;
    p.threshold = 0.6f;
    p.cube_size = cube;
    jm_config c;
    assert_int_equal(jm_config_resolve(&p, &c, NULL), JM_OK);
    jm_pool *pool = NULL;
    assert_int_equal(jm_pool_create(1, &pool), JM_OK);
    jm_particles in = {xyz, np, 0, NULL};
    jm_grid g;
    jm_mem gm;
    memset(&gm, 0, sizeof gm);
    assert_int_equal(jm_grid_build(&g, &gm, pool, &c, &in), JM_OK);
    const int n = 33, ns = JM_PAD(n); /* blocks of 32 cubes */
    float *bound = malloc((size_t)n * n * ns * sizeof *bound), *pad = malloc((size_t)n * n * ns * sizeof *pad);
    void *work = malloc(jm_box_work_bytes());
    assert_true(bound && pad && work);
    /* first nodes of the blocks (the lattice spans nodes 0 to about 156) */
    const int64_t origins[][3] = {{48, 48, 48}, {49, 50, 48}, {62, 63, 64}, {140, 64, 64}, {140, 140, 140},
                                  {-16, 60, 70}, {60, -16, 70}, {60, 70, -16}, {61, 71, -15}};
    const int inner_blocks = 3;
    /* the box path of each level (inside_boxes.c) */
    jm_testing_force_cpu(path == JM_BOX_C ? JM_TESTING_CPU_PLAIN : path == JM_BOX_AVX2 ? JM_TESTING_CPU_AVX2 : JM_TESTING_CPU_AVX512);
    assert_int_equal(jm_box_path(), path);
    for (size_t b = 0; b < sizeof origins / sizeof origins[0]; b++) {
        /* the origins are for cubes of r / 2: the same places at other sizes */
        const int64_t at[3] = {(int64_t)llround(origins[b][0] * 0.5 / cube), (int64_t)llround(origins[b][1] * 0.5 / cube),
                               (int64_t)llround(origins[b][2] * 0.5 / cube)};
        float x[33], y[33], z[33];
        float *t[3] = {x, y, z};
        for (int a = 0; a < 3; a++)
            for (int i = 0; i < n; i++) t[a][i] = (float)((double)(at[a] + i) * (double)c.h);
        const float lo[3] = {x[0], y[0], z[0]}, hi[3] = {x[n - 1], y[n - 1], z[n - 1]};
        jm_hood hood;
        memset(&hood, 0, sizeof hood);
        assert_int_equal(jm_hood_build(&hood, &g, &c, lo, hi), 1);
        const float level = jm_sph_box_threshold(&c, &hood);
        jm_sph_boxes(&g, &c, &hood, x, y, z, n, work, bound);
        jm_sph_sample(&g, &c, &hood, x, y, z, n, NULL, pad);
        size_t proven = 0;
        double worst = -1e30;
        for (int k = 0; k < n; k++)
            for (int j = 0; j < n; j++)
                for (int i = 0; i < n; i++) {
                    const size_t o = ((size_t)k * n + j) * ns + i;
                    const double over = (double)bound[o] - (double)pad[o];
                    if (over > worst) worst = over;
                    if (over > 1e-5 * (1.0 + fabs((double)pad[o])))
                        fail_msg("block %zu node (%d %d %d): bound %.9g above the sample %.9g", b, i, j, k, bound[o], pad[o]);
                    if (bound[o] > level) {
                        proven++;
                        if (!(pad[o] > c.threshold))
                            fail_msg("block %zu node (%d %d %d) proven inside (bound %.9g, level %.9g) samples %.9g", b, i,
                                     j, k, bound[o], level, pad[o]);
                    }
                }
        const size_t all = (size_t)n * n * n;
        printf("cube %.2f r, path %d, block %zu: %zu of %zu nodes proven, largest bound - sample %.3g\n", cube, path, b, proven, all, worst);
        if (b < (size_t)inner_blocks && proven * 100 < all * 95)
            fail_msg("block %zu inside the lattice: only %zu of %zu nodes proven", b, proven, all);
        free(hood.range);
    }
    jm_testing_force_cpu(-1);
    free(work);
    free(pad);
    free(bound);
    jm_grid_free(&g, &gm);
    jm_pool_free(pool);
    free(xyz);
}

/* On every path this CPU runs (plain C, AVX2, AVX-512); at cube r / 2 a
 * particle's lanes in reach fit one window of 8 (the AVX2 path's
 * one-window case), at 0.4 r they need both halves. */
static void test_box_bounds_hold(void **state)
{
    (void)state;
    const int best = jm_box_path();
    for (int path = JM_BOX_C; path <= best; path++) {
        box_bounds_case(0.5f, path);
        box_bounds_case(0.4f, path);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tangent_lines_below_kernel),
        cmocka_unit_test(test_box_lines_below_kernel),
        cmocka_unit_test(test_box_bounds_hold),
        cmocka_unit_test(test_block_with_holes),
        cmocka_unit_test(test_real_frames_same_bytes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
