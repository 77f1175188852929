/* test_aniso.c - the SPH field with Yu-Turk anisotropic kernels: smoother balls, closed real frames, determinism, API. */
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
#include "util/meshcheck.h"
#include "util/shared_data.h"

#define R 0.025f

/* A jittered ball: lattice of spacing 2r (jitter +-0.1r), every node within
 * 16r of the centre; the truth is a sphere. off: the centre's place in the
 * lattice cell (0: on a node, 0.5: in the middle of a cell). */
static size_t ball(float *xyz, float off, unsigned seed, float c[3])
{
    size_t n = 0;
    c[0] = 0.0123f;
    c[1] = -0.0071f;
    c[2] = 0.0049f;
    for (int k = -10; k <= 10; k++)
        for (int j = -10; j <= 10; j++)
            for (int i = -10; i <= 10; i++) {
                float p[3] = {2 * R * (i + off), 2 * R * (j + off), 2 * R * (k + off)};
                for (int a = 0; a < 3; a++) p[a] += 0.1f * R * (2 * mc_randf(&seed) - 1);
                if (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] > 16 * R * 16 * R) continue;
                for (int a = 0; a < 3; a++) xyz[3 * n + a] = p[a] + c[a];
                n++;
            }
    return n;
}

static jm_params sph(int aniso, jm_method method)
{
    jm_params p = {0};
    p.radius = R;
    p.field = JM_FIELD_SPH;
    p.method = method;
    p.anisotropic = aniso;
    return p;
}

/* FNV-1a of the mesh's arrays */
static uint64_t mesh_hash(const jm_mesh *m)
{
    uint64_t h = 1469598103934665603ull;
    const unsigned char *parts[4] = {(const void *)m->positions, (const void *)m->normals, (const void *)m->uvs,
                                     (const void *)m->indices};
    size_t len[4] = {m->vertex_count * 12, m->normals ? m->vertex_count * 12 : 0, m->uvs ? m->vertex_count * 8 : 0,
                     m->triangle_count * 12};
    for (int k = 0; k < 4; k++)
        for (size_t i = 0; i < len[k]; i++) h = (h ^ parts[k][i]) * 1099511628211ull;
    return h;
}

typedef struct shape {
    double sd, mean, volume, normal_deg;
    size_t tris;
} shape;

/* meshes the particles; the mesh must be closed, manifold and oriented */
static shape measure(jm_params p, const float *xyz, size_t n, const float c[3], uint64_t *hash)
{
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {xyz, n, 0, NULL};
    jm_mesh m;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
    mc_report rep;
    if (!mc_check(&m, &rep)) fail_msg("anisotropic %d: %s", p.anisotropic, rep.problem);
    assert_int_equal(rep.components, 1);
    shape s = {0, 0, rep.volume, 0, m.triangle_count};
    double sum = 0, sum2 = 0, ang = 0;
    for (size_t v = 0; v < m.vertex_count; v++) {
        const float *q = m.positions + 3 * v, *nr = m.normals + 3 * v;
        double d[3] = {q[0] - c[0], q[1] - c[1], q[2] - c[2]};
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        sum += l;
        sum2 += l * l;
        double cs = (d[0] * nr[0] + d[1] * nr[1] + d[2] * nr[2]) / l;
        ang += acos(cs > 1 ? 1 : cs);
    }
    s.mean = sum / (double)m.vertex_count;
    s.sd = sqrt(sum2 / (double)m.vertex_count - s.mean * s.mean);
    s.normal_deg = ang / (double)m.vertex_count * 180 / M_PI;
    if (hash) *hash = mesh_hash(&m);
    jm_context_free(ctx);
    return s;
}

/* The target: on a jittered ball the anisotropic surface's radial
 * deviation is at most half the isotropic one's, its volume within 5 %,
 * and its normals closer to the sphere's. A ball centred on a lattice node
 * keeps six flat polar facets up to 2r inside the sphere (one particle
 * stands on each), a third of its surface, which no local smoothing
 * removes: there the deviation drops to 0.47-0.50 of the isotropic one,
 * asserted at 0.55; centred in a cell (no such facets) to 0.35-0.37. */
static void test_ball_smoother(void **state)
{
    (void)state;
    float *xyz = malloc(3 * 21 * 21 * 21 * sizeof *xyz), c[3];
    assert_non_null(xyz);
    const float offs[2] = {0.0f, 0.5f};
    for (int o = 0; o < 2; o++)
        for (unsigned seed = 1; seed <= 2; seed++) {
            size_t n = ball(xyz, offs[o], seed, c);
            shape iso = measure(sph(0, JM_METHOD_MC), xyz, n, c, NULL);
            shape an = measure(sph(1, JM_METHOD_MC), xyz, n, c, NULL);
            printf("ball (centre offset %.1f, seed %u, %zu particles): radial sd %.3f r -> %.3f r (x%.2f), "
                   "volume %+.2f %%, normal error %.1f -> %.1f deg\n",
                   offs[o], seed, n, iso.sd / R, an.sd / R, an.sd / iso.sd, 100 * (an.volume / iso.volume - 1),
                   iso.normal_deg, an.normal_deg);
            assert_true(an.sd <= (o == 0 ? 0.55 : 0.5) * iso.sd);
            assert_true(fabs(an.volume / iso.volume - 1) <= 0.05);
            assert_true(an.normal_deg < 0.5 * iso.normal_deg);
            /* marching tetrahedra too */
            shape mt = measure(sph(1, JM_METHOD_MT), xyz, n, c, NULL);
            assert_true(fabs(mt.volume / an.volume - 1) < 0.01);
        }
    free(xyz);
}

/* the same bytes for 1 and several threads, and for a reused context */
static void test_threads_same_bytes(void **state)
{
    (void)state;
    float *xyz = malloc(3 * 21 * 21 * 21 * sizeof *xyz), c[3];
    assert_non_null(xyz);
    size_t n = ball(xyz, 0.25f, 7, c);
    uint64_t h1, h3, h4;
    jm_params p = sph(1, JM_METHOD_MC);
    p.threads = 1;
    measure(p, xyz, n, c, &h1);
    p.threads = 3;
    measure(p, xyz, n, c, &h3);
    p.threads = 4;
    p.cube_size = 0.5f;
    measure(p, xyz, n, c, &h4);
    assert_true(h1 == h3);
    assert_true(h1 == h4);
    free(xyz);
}

/* Vertices lie on the brute-force field's level set (jm_field_eval), and
 * the normals follow its gradient: the lattice samples the same function. */
static void test_matches_brute_force(void **state)
{
    (void)state;
    /* a blob stretched along x: 9 x 5 x 5 particles, jittered */
    float xyz[3 * 225];
    unsigned seed = 3;
    size_t n = 0;
    for (int k = 0; k < 5; k++)
        for (int j = 0; j < 5; j++)
            for (int i = 0; i < 9; i++) {
                float p[3] = {2 * R * i, 2 * R * j, 2 * R * k};
                for (int a = 0; a < 3; a++) xyz[3 * n + a] = p[a] + 0.3f * R * (2 * mc_randf(&seed) - 1);
                n++;
            }
    jm_params p = sph(1, JM_METHOD_MC);
    p.cube_size = 0.25f;
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {xyz, n, 0, NULL};
    jm_mesh m;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
    mc_report rep;
    if (!mc_check(&m, &rep)) fail_msg("%s", rep.problem);
    double worst = 0, worst_dot = 1;
    for (size_t v = 0; v < m.vertex_count; v += 97) {
        float val, grad[3];
        assert_int_equal(jm_field_eval(&p, &in, m.positions + 3 * v, &val, grad), JM_OK);
        /* the vertices settled along their edges onto the surface
         * (aniso_normals.c; linear interpolation between nodes a quarter r
         * apart left 0.0055) */
        double err = fabs(val - 0.6);
        if (err > worst) worst = err;
        double gl = sqrt(grad[0] * grad[0] + grad[1] * grad[1] + grad[2] * grad[2]);
        const float *nr = m.normals + 3 * v;
        double dot = -(grad[0] * nr[0] + grad[1] * nr[1] + grad[2] * nr[2]) / gl;
        if (dot < worst_dot) worst_dot = dot;
    }
    printf("brute force at the vertices: |phi - 0.6| <= %.4f, normal . -grad/|grad| >= %.6f\n", worst, worst_dot);
    assert_true(worst < 0.0025);
    /* the normal is the field's where the marching put the vertex, before
     * its settling step: within two degrees of the gradient's at the vertex */
    assert_true(worst_dot > 0.9995);
    jm_context_free(ctx);
}

/* Isolated droplets still come from the sphere template, which is the
 * isotropic kernel: the same triangles as without the option. */
static void test_isolated_template(void **state)
{
    (void)state;
    float xyz[3 * 27];
    size_t n = 0;
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++)
            for (int i = 0; i < 3; i++) {
                xyz[3 * n] = 20 * R * i + 0.01f * R * k;
                xyz[3 * n + 1] = 20 * R * j;
                xyz[3 * n + 2] = 20 * R * k;
                n++;
            }
    size_t tris[2];
    for (int aniso = 0; aniso <= 1; aniso++) {
        jm_params p = sph(aniso, JM_METHOD_MC);
        jm_context *ctx = NULL;
        assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
        jm_particles in = {xyz, n, 0, NULL};
        jm_mesh m;
        jm_stats st;
        assert_int_equal(jm_mesh_particles(ctx, &in, &m, &st), JM_OK);
        assert_int_equal(st.isolated, n);
        mc_report rep;
        if (!mc_check(&m, &rep)) fail_msg("%s", rep.problem);
        assert_int_equal(rep.components, n);
        tris[aniso] = m.triangle_count;
        jm_context_free(ctx);
    }
    assert_int_equal(tris[0], tris[1]);
}

static void test_params(void **state)
{
    (void)state;
    jm_context *ctx = NULL;
    jm_params p = sph(1, JM_METHOD_MC);
    p.field = JM_FIELD_METASPHERE;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    p.field = JM_FIELD_DEFAULT; /* the metasphere */
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    float x[3] = {0, 0, 0}, v;
    jm_particles one = {x, 1, 0, NULL};
    assert_int_equal(jm_field_eval(&p, &one, x, &v, NULL), JM_E_INVALID_ARGUMENT);
    p = sph(1, JM_METHOD_MC);
    p.aniso_max_ratio = 0.5f;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    p = sph(1, JM_METHOD_MC);
    p.aniso_smoothing = 1.5f;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    p = sph(1, JM_METHOD_MC);
    p.aniso_radius = 100.0f;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    p = sph(2, JM_METHOD_MC);
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    /* the defaults, filled in */
    p = sph(1, JM_METHOD_MC);
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_params f;
    jm_context_get_params(ctx, &f);
    assert_true(f.aniso_radius == 8.0f && f.aniso_smoothing == 1.0f && f.aniso_max_ratio == 4.0f &&
                f.aniso_scale == 1.0f && f.aniso_iso_scale == 1.0f && f.aniso_min_neighbours == 25);
    /* the estimate counts the per-particle kernels */
    float *xyz = malloc(3 * 21 * 21 * 21 * sizeof *xyz), c[3];
    assert_non_null(xyz);
    size_t n = ball(xyz, 0, 1, c);
    jm_particles in = {xyz, n, 0, NULL};
    size_t with, without;
    assert_int_equal(jm_estimate_bytes(ctx, &in, &with), JM_OK);
    jm_mesh m;
    jm_stats st;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, &st), JM_OK);
    assert_true(st.estimated_bytes >= st.peak_bytes / 2);
    jm_context_free(ctx);
    p.anisotropic = 0;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    assert_int_equal(jm_estimate_bytes(ctx, &in, &without), JM_OK);
    assert_true(with >= without + n * 13 * sizeof(float));
    jm_context_free(ctx);
    free(xyz);
}

/* real frames: closed, manifold, the same bytes for 1 and 3 threads */
static void test_real_frames(void **state)
{
    (void)state;
    const char *files[] = {
        "splashsurf/dam_break_frame_9_6859_particles.bgeo",
        "splashsurf/bunny_frame_14_7705_particles.vtk",
        "derived/dam_break_frame_23_24389_particles.xyz",
    };
    int ran = 0;
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
        char err[512];
        jmf_frame fr;
        int got = test_read_shared(files[k], NULL, &fr, err, sizeof err);
        if (got < 0) fail_msg("%s", err);
        if (!got) continue;
        for (int me = JM_METHOD_MT; me <= JM_METHOD_MC; me++) {
            uint64_t h[2];
            for (int t = 0; t < 2; t++) {
                jm_params p = sph(1, (jm_method)me);
                p.cube_size = 0.75f;
                p.threads = t ? 3 : 1;
                jm_context *ctx = NULL;
                assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
                jm_particles in = {fr.xyz, fr.count, 0, fr.ids};
                jm_mesh m;
                assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
                mc_report rep;
                if (!mc_check(&m, &rep)) fail_msg("%s method %d: %s", files[k], me, rep.problem);
                assert_true(m.triangle_count > 0);
                /* the analytic normals agree with the faces nearly everywhere */
                assert_true(rep.normals_away * 100 < m.vertex_count);
                if (t == 0)
                    printf("%s method %s: %zu triangles, %zu components, %zu of %zu normals away\n", files[k],
                           me == JM_METHOD_MC ? "mc" : "mt", m.triangle_count, rep.components, rep.normals_away,
                           m.vertex_count);
                h[t] = mesh_hash(&m);
                jm_context_free(ctx);
            }
            assert_true(h[0] == h[1]);
        }
        jmf_frame_free(&fr);
        ran++;
    }
    if (!ran) {
        printf("skipping: ../shared/data not found\n");
        skip();
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ball_smoother),      cmocka_unit_test(test_threads_same_bytes),
        cmocka_unit_test(test_matches_brute_force), cmocka_unit_test(test_isolated_template),
        cmocka_unit_test(test_params),             cmocka_unit_test(test_real_frames),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
