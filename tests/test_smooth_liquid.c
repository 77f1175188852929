/* test_smooth_liquid.c - smoothing keeps droplets, pairs, dense clusters, lines and hanging drops round and whole, and smooths balls without moving the surface more than the band (issue 31). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../cli/scenes.h"
#include "../lib/jetmesh.h"
#include "util/meshcheck.h"
#include "util/meshmetrics.h"
#include "util/test_meshes.h"

#define R 0.025f

static void mesh_with(const scene_points *pts, jm_params p, test_mesh *out)
{
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {pts->xyz, pts->count, 0, NULL};
    jm_mesh m;
    jm_stats st;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, &st), JM_OK);
    assert_int_equal(test_mesh_copy(&m, out), 0);
    jm_context_free(ctx);
}

static mm_mesh view(const test_mesh *t)
{
    mm_mesh m = {(float *)t->mesh.positions, (float *)t->mesh.normals, (uint32_t *)t->mesh.indices,
                 t->mesh.vertex_count, t->mesh.triangle_count, 0};
    return m;
}

/* The smoothed mesh of p against the raw one: closed and oriented, normals
 * facing their faces, no vertex farther than `band` from the raw surface;
 * *d99 gets the 99th percentile of that distance. */
static void check_common(const char *what, const test_mesh *raw, const test_mesh *sm, double band, double *d99)
{
    mc_report r0, r1;
    assert_true(mc_check(&raw->mesh, &r0));
    if (!mc_check(&sm->mesh, &r1)) fail_msg("%s smoothed: %s", what, r1.problem);
    if (r1.normals_away) fail_msg("%s: %zu normals face away from their faces", what, r1.normals_away);
    mm_mesh a = view(sm), b = view(raw);
    double p50, mx;
    mm_distances(&a, &b, &p50, d99, &mx);
    if (mx > band) fail_msg("%s: a vertex %.3f r from the raw surface (band %.2f r)", what, mx / R, band / R);
}

/* Droplets of every kind keep their number, >= 85 % of their volume and
 * their roundness (>= 0.8 of the raw piece's), with --smooth 25
 * --smooth-normals 10, for both fields and with and without templates;
 * also with --smooth-implicit. */
static void droplets(int implicit)
{
    for (uint64_t seed = 1; seed <= 3; seed++) {
        scene_points pts;
        assert_int_equal(scene_droplets(40, R, seed, &pts), 0);
        for (int v = 0; v < 3; v++) {
            jm_params p = {0};
            p.radius = R;
            p.field = v < 2 ? JM_FIELD_SPH : JM_FIELD_METASPHERE;
            p.method = v < 2 ? JM_METHOD_MC : JM_METHOD_MT;
            p.no_templates = v == 1;
            test_mesh raw, sm;
            mesh_with(&pts, p, &raw);
            p.smooth_iterations = 25;
            p.smooth_normal_iterations = 10;
            p.smooth_implicit = implicit;
            mesh_with(&pts, p, &sm);
            char what[64];
            snprintf(what, sizeof what, "droplets seed %d variant %d%s", (int)seed, v, implicit ? ", implicit" : "");
            mm_mesh a = view(&sm), b = view(&raw);
            mm_piece *pa, *pb;
            size_t na = mm_pieces(&a, &pa, NULL), nb = mm_pieces(&b, &pb, NULL);
            mm_match mt;
            mm_match_pieces(pb, nb, pa, na, 2 * R, &mt);
            printf("%s: %zu pieces -> %zu, least volume kept %.1f %%, least roundness kept %.2f\n", what,
                   mt.ref_pieces, mt.pieces, 100 * mt.min_volume, mt.min_round);
            assert_true(mt.ref_pieces >= 40);
            assert_int_equal(mt.pieces, mt.ref_pieces);
            assert_int_equal(mt.lost, 0);
            assert_int_equal(mt.extra, 0);
            if (mt.min_volume < 0.85)
                fail_msg("%s: the piece at (%.3f %.3f %.3f) keeps %.1f %% of its volume", what, mt.worst_c[0],
                         mt.worst_c[1], mt.worst_c[2], 100 * mt.min_volume);
            if (mt.min_round < 0.8)
                fail_msg("%s: the piece at (%.3f %.3f %.3f) goes from roundness %.2f to %.2f", what, mt.round_c[0],
                         mt.round_c[1], mt.round_c[2], mt.round_ref, mt.round_m);
            double d99;
            check_common(what, &raw, &sm, 0.6 * R, &d99);
            free(pa);
            free(pb);
            test_mesh_free(&raw);
            test_mesh_free(&sm);
        }
        scene_points_free(&pts);
    }
}

static void test_droplets_kept(void **state)
{
    (void)state;
    droplets(0);
}

static void test_droplets_kept_implicit(void **state)
{
    (void)state;
    droplets(1);
}

/* Balls packed at random (their truth a sphere), several seeds and sizes:
 * the radial deviation at most 0.56 of the raw mesh's (0.50 to 0.55 with
 * the band of 0.46 r, 0.49 to 0.53 with 0.5 r, which moved two real frames'
 * surfaces more than splashsurf does. Issue 31 asks a third: these balls'
 * deviation lies mostly at wavelengths of 8 to 14 r, which 25 iterations
 * keep; a third takes about 100 plain steps and moves of 0.6 to 0.7 r),
 * normals within 10 degrees of the sphere's at the 95th percentile, the
 * volume within 1 %. */
static void balls(int iters, int implicit, double most)
{
    const size_t sizes[3] = {600, 2000, 4000};
    for (int s = 0; s < 3; s++)
        for (uint64_t seed = 1; seed <= 2; seed++) {
            scene_points pts;
            assert_int_equal(scene_ball(sizes[s], R, seed, &pts), 0);
            jm_params p = {0};
            p.radius = R;
            p.field = JM_FIELD_SPH;
            p.method = JM_METHOD_MC;
            test_mesh raw, sm;
            mesh_with(&pts, p, &raw);
            p.smooth_iterations = iters;
            p.smooth_normal_iterations = 10;
            p.smooth_implicit = implicit;
            mesh_with(&pts, p, &sm);
            char what[80];
            snprintf(what, sizeof what, "ball of %zu (seed %d), --smooth %d%s", pts.count, (int)seed, iters,
                     implicit ? " --smooth-implicit" : "");
            double d99;
            check_common(what, &raw, &sm, 0.6 * R, &d99);
            mm_mesh a = view(&sm), b = view(&raw);
            mm_piece *pa;
            uint32_t *lab;
            size_t na = mm_pieces(&a, &pa, &lab);
            uint32_t big = 0;
            for (size_t k = 1; k < na; k++)
                if (pa[k].volume > pa[big].volume) big = (uint32_t)k;
            double sd0, a0, sd1, a1, v0 = mm_volume(&b), v1 = mm_volume(&a);
            mm_sphere(&b, lab, big, &sd0, &a0);
            mm_sphere(&a, lab, big, &sd1, &a1);
            printf("%s: radial sd %.3f r -> %.3f r (%.2f), normals p95 %.1f -> %.1f deg, volume %+.3f %%, p99 move "
                   "%.2f r\n", what, sd0 / R, sd1 / R, sd1 / sd0, a0, a1, 100 * (v1 - v0) / v0, d99 / R);
            assert_true(sd1 <= most * sd0);
            assert_true(a1 <= 10.0);
            assert_true(fabs(v1 - v0) <= 0.01 * v0);
            free(pa);
            free(lab);
            test_mesh_free(&raw);
            test_mesh_free(&sm);
            scene_points_free(&pts);
        }
}

static void test_balls_smoothed(void **state)
{
    (void)state;
    balls(25, 0, 0.56);
}

/* More iterations smooth more: --smooth 100 takes the balls to 0.36 to 0.50
 * of the raw deviation (the smallest, of radius 10 r, held by the band).
 * The super time stepping cycles shrink a piece by its curvature; its volume
 * is restored between them (smooth_volume.c), or the shrinkage would fill
 * the band and the smaller balls come out rougher than with 25. */
static void test_balls_smoothed_more(void **state)
{
    (void)state;
    balls(100, 0, 0.51);
}

/* The steady smoothing (--smooth-implicit) smooths these balls as much
 * with 25 (0.51 to 0.54 of the raw deviation; test_post's ball checks 25)
 * and more with 100 (0.32 to 0.40): its backward Euler steps damp the long
 * wavelengths that bound the explicit steps' band. */
static void test_balls_smoothed_implicit(void **state)
{
    (void)state;
    balls(100, 1, 0.43);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_droplets_kept),
        cmocka_unit_test(test_droplets_kept_implicit),
        cmocka_unit_test(test_balls_smoothed),
        cmocka_unit_test(test_balls_smoothed_more),
        cmocka_unit_test(test_balls_smoothed_implicit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
