/* test_grid_index.c - the particle grid's dense cell index and its hash map give the same mesh bytes. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/jetmesh.h"

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
    float *xyz = malloc(3 * ((size_t)S * S * S + extra) * sizeof *xyz);
    assert_non_null(xyz);
    uint32_t seed = 12345u;
    size_t k = 0;
    for (int z = 0; z < S; z++)
        for (int y = 0; y < S; y++)
            for (int x = 0; x < S; x++) {
                const int c[3] = {x, y, z};
                for (int a = 0; a < 3; a++) {
                    seed = seed * 1664525u + 1013904223u;
                    float jitter = ((float)(seed >> 8) / 16777216.0f - 0.5f) * 0.01f;
                    xyz[3 * k + a] = 0.05f * (float)c[a] + jitter;
                }
                k++;
            }
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sph_mc),
        cmocka_unit_test(test_sph_mt),
        cmocka_unit_test(test_metasphere_mt),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
