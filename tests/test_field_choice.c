/* test_field_choice.c - jm_choose_field (metasphere for sparse frames, SPH for bulk) and the removal of sub-particle cavities. */
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
#include "../lib/core/internal.h"
#include "../lib/jetmesh.h"
#include "util/meshcheck.h"
#include "util/shared_data.h"

#define R 0.025f

/* n x n x n lattice of spacing s*R, jittered by up to j*R (deterministic) */
static float *lattice(int n, float s, float j, size_t *count)
{
    float *p = malloc((size_t)n * n * n * 3 * sizeof *p);
    unsigned st = 7;
    size_t k = 0;
    for (int z = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++) {
                p[k++] = (x * s + j * (2 * mc_randf(&st) - 1)) * R;
                p[k++] = (y * s + j * (2 * mc_randf(&st) - 1)) * R;
                p[k++] = (z * s + j * (2 * mc_randf(&st) - 1)) * R;
            }
    *count = k / 3;
    return p;
}

static void choose(const float *xyz, size_t n, size_t stride, jm_field *f, jm_method *m, float *nb)
{
    jm_params p = {0};
    p.radius = R;
    jm_particles in = {xyz, n, stride, NULL};
    assert_int_equal(jm_choose_field(&p, &in, f, m, nb), JM_OK);
}

static void test_choice(void **state)
{
    (void)state;
    jm_field f;
    jm_method m;
    float nb;
    /* a jet-like chain 1.5 r apart: 4 neighbours within pi r, the ends fewer */
    float chain[3 * 40];
    for (int i = 0; i < 40; i++) {
        chain[3 * i] = 1.5f * R * (float)i;
        chain[3 * i + 1] = 0.01f * R * (float)(i % 3);
        chain[3 * i + 2] = 0.0f;
    }
    choose(chain, 40, 0, &f, &m, &nb);
    assert_int_equal(f, JM_FIELD_METASPHERE);
    assert_int_equal(m, JM_METHOD_MT);
    assert_true(nb > 3.8f && nb < 4.0f); /* (36*4 + 2*3 + 2*2) / 40 */
    /* bulk: a jittered block at spacing 2r */
    size_t n;
    float *blk = lattice(12, 2.0f, 0.3f, &n);
    choose(blk, n, 0, &f, &m, &nb);
    assert_int_equal(f, JM_FIELD_SPH);
    assert_int_equal(m, JM_METHOD_MC);
    assert_true(nb > 12.0f && nb < 18.0f);
    /* the same particles through a stride of 16 bytes */
    float *wide = malloc(n * 16);
    for (size_t i = 0; i < n; i++) memcpy((char *)wide + 16 * i, blk + 3 * i, 12);
    float nb2;
    choose(wide, n, 16, &f, &m, &nb2);
    assert_true(nb2 == nb);
    /* the link distance is the measure's reach: 1.9 r sees no lattice neighbour */
    jm_params p = {0};
    p.radius = R;
    p.link_distance = 1.5f;
    jm_particles in = {blk, n, 0, NULL};
    assert_int_equal(jm_choose_field(&p, &in, &f, &m, &nb2), JM_OK);
    assert_int_equal(f, JM_FIELD_METASPHERE);
    free(wide);
    /* spread out: spray at spacing 4r has none */
    float *spray = lattice(8, 4.0f, 0.3f, &n); /* nearest 3.4 r apart */
    choose(spray, n, 0, &f, &m, &nb);
    assert_int_equal(f, JM_FIELD_METASPHERE);
    assert_true(nb == 0.0f);
    /* empty and single frames, NULL out pointers */
    choose(spray, 0, 0, &f, &m, &nb);
    assert_int_equal(f, JM_FIELD_METASPHERE);
    assert_true(nb == 0.0f);
    choose(spray, 1, 0, NULL, NULL, NULL);
    /* errors */
    spray[4] = NAN;
    jm_particles bad = {spray, n, 0, NULL};
    p.link_distance = 0;
    assert_int_equal(jm_choose_field(&p, &bad, &f, &m, &nb), JM_E_INVALID_PARTICLE);
    p.radius = -1;
    assert_int_equal(jm_choose_field(&p, &in, &f, &m, &nb), JM_E_INVALID_ARGUMENT);
    assert_int_equal(jm_choose_field(NULL, &in, &f, &m, &nb), JM_E_INVALID_ARGUMENT);
    free(spray);
    free(blk);
}

static int read_shared(const char *rel, jmf_frame *fr)
{
    char err[512];
    int got = test_read_shared(rel, NULL, fr, err, sizeof err);
    if (got < 0) fail_msg("%s", err);
    return got;
}

/* Meshes with p; the mesh's report, cavities and components. */
static size_t mesh_with(const jm_params *p, const float *xyz, size_t n, const uint32_t *ids, jm_stats *st,
                        size_t *comps, size_t *tris)
{
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(p, &ctx), JM_OK);
    jm_particles in = {xyz, n, 0, ids};
    jm_mesh m;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, st), JM_OK);
    mc_report rep;
    if (!mc_check(&m, &rep)) fail_msg("%s", rep.problem);
    size_t cav = mc_cavities(&m, comps);
    *tris = m.triangle_count;
    jm_context_free(ctx);
    return cav;
}

/* Real frames of bulk fluid, with no options: the SPH field and marching
 * cubes, closed, one component for one body of liquid, no cavity. The
 * dam-break frame has one sub-particle cavity (44 triangles) that is
 * removed by default and kept with keep_cavities. */
static void test_real_bulk(void **state)
{
    (void)state;
    static const struct {
        const char *file;
        size_t comps; /* bodies of liquid in the frame */
    } frames[] = {
        {"splashsurf/dam_break_frame_9_6859_particles.bgeo", 1},
        {"splashsurf/bunny_frame_14_7705_particles.vtk", 1},
        {"splashsurf/cube_2366_particles.vtk", 1},
        {"splashsurf/double_dam_break_frame_01_4732_particles.vtk", 2},
    };
    int ran = 0;
    for (size_t k = 0; k < sizeof frames / sizeof *frames; k++) {
        jmf_frame fr;
        if (!read_shared(frames[k].file, &fr)) continue;
        jm_params p = {0};
        p.radius = R;
        jm_particles in = {fr.xyz, fr.count, 0, fr.ids};
        float nb;
        assert_int_equal(jm_choose_field(&p, &in, &p.field, &p.method, &nb), JM_OK);
        if (p.field != JM_FIELD_SPH || p.method != JM_METHOD_MC)
            fail_msg("%s: %.2f neighbours: not taken for bulk fluid", frames[k].file, (double)nb);
        jm_stats st;
        size_t comps, tris, keep_comps, keep_tris;
        size_t cav = mesh_with(&p, fr.xyz, fr.count, fr.ids, &st, &comps, &tris);
        if (cav != 0 || comps != frames[k].comps)
            fail_msg("%s: %zu components, %zu cavities", frames[k].file, comps, cav);
        p.keep_cavities = 1;
        jm_stats st2;
        size_t kept = mesh_with(&p, fr.xyz, fr.count, fr.ids, &st2, &keep_comps, &keep_tris);
        assert_int_equal(st2.cavities_removed, 0);
        assert_int_equal(kept, st.cavities_removed);
        assert_int_equal(keep_comps, comps + kept);
        if (k == 0) { /* the known one */
            assert_int_equal(st.cavities_removed, 1);
            assert_int_equal(keep_tris, tris + 44);
        }
        jmf_frame_free(&fr);
        ran++;
    }
    if (!ran) skip();
}

/* The metasphere on bulk fluid leaves a shell between every few balls that
 * do not touch: those smaller than a particle go, the mesh stays closed,
 * and the result is the same bytes for 1 and 3 threads. */
static void test_metasphere_bulk_cavities(void **state)
{
    (void)state;
    size_t n;
    float *blk = lattice(7, 2.0f, 0.25f, &n);
    jm_params p = {0};
    p.radius = R;
    p.field = JM_FIELD_METASPHERE;
    jm_stats st;
    size_t comps, tris, kcomps, ktris;
    size_t cav = mesh_with(&p, blk, n, NULL, &st, &comps, &tris);
    p.keep_cavities = 1;
    jm_stats st2;
    size_t kcav = mesh_with(&p, blk, n, NULL, &st2, &kcomps, &ktris);
    assert_true(kcav > 20);
    assert_int_equal(st.cavities_removed, kcav - cav);
    assert_true(cav < kcav / 4);
    assert_int_equal(comps, kcomps - st.cavities_removed);
    /* 1 and 3 threads: the same bytes */
    p.keep_cavities = 0;
    jm_mesh a, b;
    jm_context *c1 = NULL, *c3 = NULL;
    p.threads = 1;
    assert_int_equal(jm_context_create(&p, &c1), JM_OK);
    p.threads = 3;
    assert_int_equal(jm_context_create(&p, &c3), JM_OK);
    jm_particles in = {blk, n, 0, NULL};
    assert_int_equal(jm_mesh_particles(c1, &in, &a, NULL), JM_OK);
    assert_int_equal(jm_mesh_particles(c3, &in, &b, NULL), JM_OK);
    assert_int_equal(a.vertex_count, b.vertex_count);
    assert_int_equal(a.triangle_count, b.triangle_count);
    assert_memory_equal(a.positions, b.positions, 3 * a.vertex_count * sizeof(float));
    assert_memory_equal(a.normals, b.normals, 3 * a.vertex_count * sizeof(float));
    assert_memory_equal(a.uvs, b.uvs, 2 * a.vertex_count * sizeof(float));
    assert_memory_equal(a.indices, b.indices, 3 * a.triangle_count * sizeof(uint32_t));
    jm_context_free(c1);
    jm_context_free(c3);
    free(blk);
}

/* The measure by brute force over the same samples as jm_choose_field. */
static double brute_mean(const float *xyz, size_t n, double L)
{
    size_t step = n > 4096 ? n / 4096 : 1, taken = 0, total = 0;
    for (size_t i = 0; i < n && taken < 4096; i += step, taken++)
        for (size_t j = 0; j < n; j++) {
            double d0 = (double)xyz[3 * j] - xyz[3 * i], d1 = (double)xyz[3 * j + 1] - xyz[3 * i + 1],
                   d2 = (double)xyz[3 * j + 2] - xyz[3 * i + 2];
            if (j != i && d0 * d0 + d1 * d1 + d2 * d2 < L * L) total++;
        }
    return taken ? (double)total / (double)taken : 0.0;
}

/* Issue 30: the choice's work is bounded whatever the particles (a million
 * copies of one point took 10 s before the meshing refused them); frames
 * within the bound are measured exactly, as before. */
static void test_choice_bounded(void **state)
{
    (void)state;
    jm_params p = {0};
    p.radius = R;
    jm_field f;
    jm_method m;
    float nb;
    size_t checks;
    /* exact within the bound: the brute-force mean, to the bit */
    size_t n;
    float *blk = lattice(12, 2.0f, 0.3f, &n);
    jm_particles in = {blk, n, 0, NULL};
    assert_int_equal(jm_choose_field_work(&p, &in, &f, &m, &nb, &checks), JM_OK);
    const float link = 3.14159265f * R; /* the default link distance, as the library computes it */
    assert_true(nb == (float)brute_mean(blk, n, (double)link));
    assert_true(checks > 0 && checks <= JM_CHOICE_MAX_CHECKS);
    free(blk);
    /* a million copies of one point: bounded, and far denser than bulk */
    const size_t pile = 1000000;
    float *pts = malloc(pile * 3 * sizeof *pts);
    assert_non_null(pts);
    for (size_t i = 0; i < pile; i++) {
        pts[3 * i] = 1.0f;
        pts[3 * i + 1] = 2.0f;
        pts[3 * i + 2] = 3.0f;
    }
    jm_particles pl = {pts, pile, 0, NULL};
    assert_int_equal(jm_choose_field_work(&p, &pl, &f, &m, &nb, &checks), JM_OK);
    assert_true(checks <= JM_CHOICE_MAX_CHECKS);
    assert_int_equal(f, JM_FIELD_SPH);
    assert_true(nb > 0.9f * (float)pile);
    /* two piles 1.01 L apart in neighbouring cells: each sample's candidates
     * are half neighbours, half not, and the strided share sees both */
    for (size_t i = pile / 2; i < pile; i++) pts[3 * i] = 1.0f + 1.01f * 3.14159265f * R;
    assert_int_equal(jm_choose_field_work(&p, &pl, &f, &m, &nb, &checks), JM_OK);
    assert_true(checks <= JM_CHOICE_MAX_CHECKS);
    assert_true(nb > 0.4f * (float)pile && nb < 0.6f * (float)pile);
    free(pts);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_choice),
        cmocka_unit_test(test_choice_bounded),
        cmocka_unit_test(test_real_bulk),
        cmocka_unit_test(test_metasphere_bulk_cavities),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
