/* test_real_frames.c - real SPH frames from ../shared/data: splashsurf's published triangle counts, closed manifold meshes. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../formats/reader.h"
#include "../lib/jetmesh.h"
#include "util/meshcheck.h"
#include "util/shared_data.h"

/* splashsurf's own tests (SPH colour field, cubic spline, support 4r,
 * threshold 0.6, marching cubes), as listed in ../shared/data/README.md */
typedef struct expectation {
    const char *file;
    float cube;          /* relative to r */
    size_t min_tris, max_tris;
} expectation;

static const expectation cases[] = {
    {"splashsurf/bunny_frame_14_7705_particles.vtk", 0.75f, 60000, 80000},
    {"splashsurf/bunny_frame_14_7705_particles.vtk", 1.0f, 35000, 40000},
    {"splashsurf/hilbert_46843_particles.bgeo", 0.75f, 360000, 400000},
    {"splashsurf/octocat_32614_particles.bgeo", 0.75f, 140000, 180000},
    {"splashsurf/pentagonal_hexecontahedron_32286_particles.bgeo", 0.75f, 550000, 650000},
    {"splashsurf/hilbert2_7954_particles.vtk", 1.1f, 90000, 100000},
    {"splashsurf/sailors_knot_19539_particles.vtk", 1.1f, 40000, 70000},
};

static int read_frame(const char *rel, jmf_frame *fr)
{
    char err[512];
    int got = test_read_shared(rel, NULL, fr, err, sizeof err);
    if (got < 0) fail_msg("%s", err);
    return got;
}

static void test_published_counts(void **state)
{
    (void)state;
    int ran = 0;
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const expectation *e = &cases[k];
        jmf_frame fr;
        if (!read_frame(e->file, &fr)) continue;
        jm_params p = {0};
        p.radius = 0.025f;
        p.field = JM_FIELD_SPH;
        p.method = JM_METHOD_MC;
        p.cube_size = e->cube;
        p.smoothing_length = 2.0f;
        p.threshold = 0.6f;
        jm_context *ctx = NULL;
        assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
        jm_particles in = {fr.xyz, fr.count, 0, NULL};
        jm_mesh m;
        assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
        printf("%s at %.2f r: %zu triangles (splashsurf: %zu-%zu)\n", e->file, e->cube, m.triangle_count, e->min_tris,
               e->max_tris);
        if (m.triangle_count < e->min_tris || m.triangle_count > e->max_tris)
            fail_msg("%s at cube %.2f r: %zu triangles, outside splashsurf's %zu-%zu", e->file, e->cube,
                     m.triangle_count, e->min_tris, e->max_tris);
        mc_report rep;
        if (!mc_check(&m, &rep)) fail_msg("%s: %s", e->file, rep.problem);
        /* analytic SPH normals agree with the faces almost everywhere */
        assert_true(rep.normals_away * 1000 < m.vertex_count);
        jm_context_free(ctx);
        jmf_frame_free(&fr);
        ran++;
    }
    if (!ran) {
        printf("skipping: ../shared/data not found\n");
        skip();
    }
}

/* every real particle frame meshes closed and manifold with both fields and
 * both methods (the metasphere at a coarser lattice: dense frames are full of
 * small voids between its balls) */
static void test_every_frame_closed(void **state)
{
    (void)state;
    const char *files[] = {
        "splashsurf/dam_break_frame_9_6859_particles.bgeo",
        "splashsurf/double_dam_break_frame_26_4732_particles.vtk",
        "splashsurf/cube_2366_particles.vtk",
        "splashsurf/ParticleData_Random_1000.vtk",
        "splishsplash_models/bunny.bgeo",
    };
    int ran = 0;
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
        jmf_frame fr;
        if (!read_frame(files[k], &fr)) continue;
        for (int f = JM_FIELD_METASPHERE; f <= JM_FIELD_SPH; f++)
            for (int me = JM_METHOD_MT; me <= JM_METHOD_MC; me++) {
                jm_params p = {0};
                p.radius = 0.025f;
                p.field = (jm_field)f;
                p.method = (jm_method)me;
                p.cube_size = f == JM_FIELD_SPH ? 0.75f : 1.0f;
                jm_context *ctx = NULL;
                assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
                jm_particles in = {fr.xyz, fr.count, 0, fr.ids};
                jm_mesh m;
                assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
                mc_report rep;
                if (!mc_check(&m, &rep)) fail_msg("%s field %d method %d: %s", files[k], f, me, rep.problem);
                assert_true(m.triangle_count > 0);
                jm_context_free(ctx);
            }
        jmf_frame_free(&fr);
        ran++;
    }
    if (!ran) skip();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_published_counts),
        cmocka_unit_test(test_every_frame_closed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
