/* test_aniso_cull.c - the anisotropic SPH field sampled only near the surface gives the same mesh bytes as every node sampled, and the box bounds hold node by node. */
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
#include "../lib/field/aniso/aniso_boxes.h"
#include "../lib/field/aniso/aniso_splat.h"
#include "../lib/field/sph/cull.h"
#include "../lib/grid/grid.h"
#include "../lib/field/sph/inside_boxes.h"
#include "util/cull_check.h"
#include "util/lattice.h"
#include "util/sheets.h"

/* Culled (1 and 2 threads) against every node sampled: the same bytes.
 * Variants: the reference case (cube r/2, threshold 0.6), then a coarser
 * lattice with a thinner threshold and a shorter kernel, and flatter
 * kernels (other block sizes, other axis ratios). */
#define VARIANTS 3
#define ANISOTROPIC 1
static int fill_case(size_t k, int me, int v, jm_params *p, char *what, size_t whatsz)
{
    const float cube[] = {0.5f, 0.75f, 0.6f}, thr[] = {0.6f, 0.35f, 0.8f}, sl[] = {2.0f, 1.6f, 2.0f},
                kr[] = {0.0f, 0.0f, 8.0f};
    if (k >= 2 && v == 0) return 0; /* the big case on the two bench frames only */
    if (k < 2 && v > 0 && me == JM_METHOD_MT) return 0;
    p->radius = 0.025f;
    p->field = JM_FIELD_SPH;
    p->anisotropic = 1;
    p->method = (jm_method)me;
    p->cube_size = cube[v];
    p->threshold = thr[v];
    p->smoothing_length = sl[v];
    p->aniso_max_ratio = kr[v];
    snprintf(what, whatsz, "%s %s cube %.2f thr %.2f h %.1f k_r %.0f", cull_frames[k], me == JM_METHOD_MC ? "mc" : "mt",
             cube[v], thr[v], sl[v], kr[v]);
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

/* The box pass's lines (aniso_boxes.h), as the floats it uses: each lies
 * below the kernel at every s = q^2 and touches it within 1e-5 at its
 * tangent point; the last is the zero line. */
static void test_box_lines_below_kernel(void **state)
{
    (void)state;
    float a[JM_AN_BOX_BINS], b[JM_AN_BOX_BINS];
    jm_aniso_box_lines(a, b);
    assert_true(a[JM_AN_BOX_BINS - 1] == 0.0f && b[JM_AN_BOX_BINS - 1] == 0.0f);
    for (int k = 0; k < JM_AN_BOX_BINS - 1; k++) {
        assert_true(b[k] >= 0.0f);
        for (int i = 0; i <= 600000; i++) {
            const double s = i * 1e-5, gap = ((double)a[k] - (double)b[k] * s) - jm_cull_kernel(sqrt(s));
            if (gap > 0.0) fail_msg("line %d at s = %.5f: %.9f is above the kernel %.9f", k, s, a[k] - b[k] * s,
                                    jm_cull_kernel(sqrt(s)));
        }
        const double sk = (k + 0.5) / JM_AN_BOX_BINS_PER_S, gap = jm_cull_kernel(sqrt(sk)) - (a[k] - b[k] * sk);
        if (!(gap >= 0.0 && gap < 1e-5)) fail_msg("line %d leaves the kernel at its tangent point (gap %.3g)", k, gap);
    }
}

/* The box pass's bounds, node by node, against the samples, on blocks of
 * 32 cubes: a jittered lattice (deep inside, across a face and at a corner,
 * where its kernels flatten, and offset by a node or two so that boxes and
 * rows fall differently) and a sheet of three layers (kernels at their
 * floors): no bound above its sample by more than the sample's rounding,
 * every node whose bound passes the proof level samples above the
 * threshold, and deep inside nearly every node proven; on path `path`.
 * White-box: the internal calls. */
static void box_bounds_case(float cube, int path, int sheet)
{
    const float r = 0.025f;
    float *xyz;
    size_t np;
    if (sheet) {
        np = test_sheet(3, 40, r, 0.3f * r, 5u, 0, 0.0f, &xyz, NULL);
    } else {
        const int S = 40;
        np = (size_t)S * S * S;
        xyz = test_lattice(S, 2.0f * r, 0.2f * r, 12345u, 0);
    }
    assert_non_null(xyz);
    jm_params p = {0};
    p.radius = r;
    p.field = JM_FIELD_SPH;
    p.anisotropic = 1;
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
    assert_int_equal(jm_aniso_build(&g, &gm, pool, &c), JM_OK);
    if (g.an_reach > c.influence) c.influence = g.an_reach; /* as mesh.c */
    const int n = 33, ns = JM_PAD(n);
    float *bound = malloc((size_t)n * n * ns * sizeof *bound), *pad = malloc((size_t)n * n * ns * sizeof *pad);
    void *work = malloc(jm_aniso_box_work_bytes());
    assert_true(bound && pad && work);
    /* first nodes of the blocks for cubes of r / 2 (the lattice spans nodes
     * 0 to about 156; the sheet, tilted, 0 to about 160 along x and y and
     * -10 to 20 along z) */
    const int64_t lattice[][3] = {{48, 48, 48}, {49, 50, 48}, {62, 63, 64}, {140, 64, 64}, {140, 140, 140},
                                  {-16, 60, 70}, {61, 71, -15}};
    const int64_t sheet_at[][3] = {{60, 60, -10}, {61, 62, -12}, {-10, 60, -8}};
    const int64_t(*origins)[3] = sheet ? sheet_at : lattice;
    const size_t blocks = sheet ? 3 : 7, inner_blocks = sheet ? 0 : 3;
    /* the box path of each level (inside_boxes.c) */
    jm_testing_force_cpu(path == JM_BOX_C ? JM_TESTING_CPU_PLAIN : path == JM_BOX_AVX2 ? JM_TESTING_CPU_AVX2 : JM_TESTING_CPU_AVX512);
    assert_int_equal(jm_box_path(), path);
    jm_an_cand cand = {NULL, 0, 0, NULL};
    for (size_t b = 0; b < blocks; b++) {
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
        assert_int_equal(jm_aniso_candidates(&g, &hood, lo, hi, 0.02f * c.support, &cand), 1);
        const float level = jm_aniso_boxes(&g, &c, &cand, x, y, z, n, work, bound);
        jm_aniso_sample(&g, &c, &cand, x, y, z, n, NULL, pad);
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
        printf("%s, cube %.2f r, path %d, block %zu: %zu of %zu nodes proven, largest bound - sample %.3g\n",
               sheet ? "sheet" : "lattice", cube, path, b, proven, all, worst);
        if (b < inner_blocks && proven * 100 < all * 95)
            fail_msg("block %zu inside the lattice: only %zu of %zu nodes proven", b, proven, all);
        if (sheet && b < 2 && proven == 0) fail_msg("sheet block %zu: nothing proven (the test proves nothing)", b);
        free(hood.range);
    }
    jm_testing_force_cpu(-1);
    free(cand.idx);
    free(work);
    free(pad);
    free(bound);
    jm_grid_free(&g, &gm);
    jm_pool_free(pool);
    free(xyz);
}

/* On every path this CPU runs (plain C, AVX2 with FMA, AVX-512); at cube
 * r / 2 and 0.4 r (a kernel's lanes in one window of 8 or both halves) */
static void test_box_bounds_hold(void **state)
{
    (void)state;
    const int best = jm_box_path();
    for (int path = JM_BOX_C; path <= best; path++) {
        box_bounds_case(0.5f, path, 0);
        box_bounds_case(0.4f, path, 0);
        box_bounds_case(0.5f, path, 1);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_box_lines_below_kernel),
        cmocka_unit_test(test_box_bounds_hold),
        cmocka_unit_test(test_block_with_holes),
        cmocka_unit_test(test_real_frames_same_bytes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
