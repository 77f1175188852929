/* test_grid_index.c - the particle grid's dense cell index and its hash map give the same mesh bytes, and the grid is the same built on 1 or more threads. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <stdatomic.h>

#include "../lib/jetmesh.h"
#include "../lib/grid/grid.h"
#include "util/lattice.h"

/* A jittered lattice of S^3 particles at spacing 2r (r = 0.025): its box
 * of grid cells (edge 4r for SPH, wider for the metasphere) holds fewer cells
 * than particles, so jm_grid_build indexes the cells densely. One more
 * particle far away (100 units off, no neighbour) makes that box about 10^9
 * cells: the hash map instead. That particle is isolated: meshed from the
 * sphere template after every block's triangles, it changes neither the
 * blocks nor their order, nor the cells or the sorted order of the others
 * (cells numbered by first appearance, or in key order for SPH: either way
 * it comes last). So the block part of both meshes must be the same bytes. */
#define S 14

static float *lattice(size_t extra)
{
    float *xyz = test_lattice(S, 0.05f, 0.01f, 12345u, extra);
    assert_non_null(xyz);
    return xyz;
}

static void same_blocks(jm_field field, jm_method method, int threads)
{
    const size_t n = (size_t)S * S * S;
    float *xyz = lattice(1);
    xyz[3 * n] = xyz[3 * n + 1] = xyz[3 * n + 2] = 100.0f;
    jm_params p = {0}; /* zero means default */
    p.radius = 0.025f;
    p.field = field;
    p.method = method;
    p.threads = threads;
    if (field == JM_FIELD_SPH) p.threshold = 0.6f;
    jm_context *a = NULL, *b = NULL;
    assert_int_equal(jm_context_create(&p, &a), JM_OK);
    assert_int_equal(jm_context_create(&p, &b), JM_OK);
    jm_particles dense = {xyz, n, 0, NULL}, hashed = {xyz, n + 1, 0, NULL};
    jm_mesh ma, mb;
    jm_stats sa, sb;
    assert_int_equal(jm_mesh_particles(a, &dense, &ma, &sa), JM_OK);
    assert_int_equal(jm_mesh_particles(b, &hashed, &mb, &sb), JM_OK);
    assert_int_equal(sa.isolated, 0);
    assert_int_equal(sb.isolated, 1);
    assert_true(ma.triangle_count > 1000);
    assert_true(mb.vertex_count > ma.vertex_count);
    assert_true(mb.triangle_count > ma.triangle_count);
    assert_memory_equal(ma.positions, mb.positions, 3 * ma.vertex_count * sizeof(float));
    if (ma.normals) assert_memory_equal(ma.normals, mb.normals, 3 * ma.vertex_count * sizeof(float));
    assert_memory_equal(ma.indices, mb.indices, 3 * ma.triangle_count * sizeof(uint32_t));
    jm_context_free(a);
    jm_context_free(b);
    free(xyz);
}

static void test_sph_mc(void **state)
{
    (void)state;
    same_blocks(JM_FIELD_SPH, JM_METHOD_MC, 1);
    same_blocks(JM_FIELD_SPH, JM_METHOD_MC, 2);
}

static void test_sph_mt(void **state)
{
    (void)state;
    same_blocks(JM_FIELD_SPH, JM_METHOD_MT, 2);
}

static void test_metasphere_mt(void **state)
{
    (void)state;
    same_blocks(JM_FIELD_METASPHERE, JM_METHOD_MT, 2);
}

/* The grid built on 1, 2 and 3 threads (its passes over the particles and
 * cells run in chunks, the placement in two halves from both ends of each
 * cell): the same cells, the same particles in the same order, the same
 * weights and isolation flags, on a shuffled lattice (dense index), with a
 * far particle (hash map), and with ids (sorted order); a NaN late in the
 * input is found on every thread count. */
static jm_status build(const float *xyz, size_t n, const uint32_t *ids, int threads, jm_grid *g, jm_mem *mem)
{
    jm_params p = {0};
    p.radius = 0.025f;
    p.field = JM_FIELD_SPH;
    p.threshold = 0.6f;
    jm_config c;
    assert_int_equal(jm_config_resolve(&p, &c, NULL), JM_OK);
    jm_pool *pool = NULL;
    assert_int_equal(jm_pool_create(threads, &pool), JM_OK);
    memset(mem, 0, sizeof *mem);
    jm_particles in = {xyz, n, 0, ids};
    const jm_status st = jm_grid_build(g, mem, pool, &c, &in);
    jm_pool_free(pool);
    return st;
}

static void test_threads_same_grid(void **state)
{
    (void)state;
    const int L = 60; /* 216,000 particles: several chunks of the passes */
    const size_t n = (size_t)L * L * L;
    float *xyz = test_lattice(L, 0.05f, 0.01f, 777u, 1);
    uint32_t *ids = malloc((n + 1) * sizeof *ids);
    assert_true(xyz && ids);
    uint32_t seed = 777u;
    for (size_t k = 0; k < n; k++) ids[k] = (uint32_t)(n - k);
    for (size_t k = n - 1; k > 0; k--) { /* shuffled: cells filled from all over the input */
        seed = seed * 1664525u + 1013904223u;
        const size_t j = (seed >> 4) % (k + 1);
        float t[3];
        memcpy(t, &xyz[3 * k], sizeof t);
        memcpy(&xyz[3 * k], &xyz[3 * j], sizeof t);
        memcpy(&xyz[3 * j], t, sizeof t);
    }
    xyz[3 * n] = xyz[3 * n + 1] = xyz[3 * n + 2] = 100.0f;
    ids[n] = 0;
    for (int v = 0; v < 3; v++) {
        const size_t m = v == 1 ? n + 1 : n;       /* 1: the far particle, a hash map */
        const uint32_t *id = v == 2 ? ids : NULL; /* 2: ids */
        jm_grid g1, gt;
        jm_mem m1, mt;
        assert_int_equal(build(xyz, m, id, 1, &g1, &m1), JM_OK);
        assert_true(v == 1 ? g1.dense == NULL : g1.dense != NULL);
        for (int t = 2; t <= 3; t++) {
            assert_int_equal(build(xyz, m, id, t, &gt, &mt), JM_OK);
            assert_int_equal(gt.ncells, g1.ncells);
            assert_memory_equal(gt.cell_start, g1.cell_start, (g1.ncells + 1) * sizeof *g1.cell_start);
            assert_memory_equal(gt.pos, g1.pos, 3 * m * sizeof(float));
            assert_memory_equal(gt.weight, g1.weight, m * sizeof(float));
            assert_memory_equal(gt.isolated, g1.isolated, m);
            for (int a = 0; a < 3; a++) assert_true(gt.lo[a] == g1.lo[a] && gt.hi[a] == g1.hi[a]);
            jm_grid_free(&gt, &mt);
        }
        jm_grid_free(&g1, &m1);
    }
    /* a NaN in the last chunk, after good particles in the others */
    xyz[3 * (n - 5) + 1] = NAN;
    for (int t = 1; t <= 2; t++) {
        jm_grid g;
        jm_mem mem;
        assert_int_equal(build(xyz, n, NULL, t, &g, &mem), JM_E_INVALID_PARTICLE);
        assert_int_equal(atomic_load(&mem.current), 0);
    }
    free(ids);
    free(xyz);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sph_mc),
        cmocka_unit_test(test_sph_mt),
        cmocka_unit_test(test_metasphere_mt),
        cmocka_unit_test(test_threads_same_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
