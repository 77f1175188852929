/* test_pieces.c - the threads' union-find gives every vertex the same piece root as the serial one, on meshes of many pieces. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/post/pieces.h"

static uint32_t next(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

/* nt triangles over n vertices: strips along runs of consecutive vertices
 * (the meshes' own locality) joined now and then by a triangle across the
 * whole index range, so that pieces merge from both ends at once; some
 * vertices in no triangle at all. */
static uint32_t *mesh(size_t n, size_t nt, uint32_t seed)
{
    uint32_t *idx = malloc(3 * nt * sizeof *idx);
    assert_non_null(idx);
    for (size_t t = 0; t < nt; t++) {
        uint32_t a = next(&seed) % (uint32_t)(n - 8);
        if (next(&seed) % 64 == 0) {
            idx[3 * t] = a;
            idx[3 * t + 1] = next(&seed) % (uint32_t)n;
            idx[3 * t + 2] = next(&seed) % (uint32_t)n;
        } else {
            idx[3 * t] = a;
            idx[3 * t + 1] = a + 1 + next(&seed) % 3;
            idx[3 * t + 2] = a + 4 + next(&seed) % 4;
        }
    }
    return idx;
}

static void same_roots(size_t n, size_t nt, uint32_t seed, int threads)
{
    uint32_t *idx = mesh(n, nt, seed);
    uint32_t *one = malloc(n * sizeof *one), *many = malloc(n * sizeof *many);
    assert_true(one && many);
    jm_mesh_pieces(NULL, one, idx, n, nt);
    size_t roots = 0;
    for (size_t v = 0; v < n; v++) {
        assert_true(one[v] <= v && one[one[v]] == one[v]);
        roots += one[v] == v;
    }
    assert_true(roots > 1 && roots < n); /* a test with several pieces, some merged */
    jm_pool *pool = NULL;
    assert_int_equal(jm_pool_create(threads, &pool), JM_OK);
    for (int rep = 0; rep < 8; rep++) {
        memset(many, 0xab, n * sizeof *many);
        jm_mesh_pieces(pool, many, idx, n, nt);
        for (size_t v = 0; v < n; v++)
            if (many[v] != one[v])
                fail_msg("%d threads, round %d: vertex %zu in piece %u, not %u", threads, rep, v, many[v], one[v]);
    }
    jm_pool_free(pool);
    free(many);
    free(one);
    free(idx);
}

/* sparse (many small pieces), dense (a few big ones), on 2 and 3 threads:
 * more than the two chunks of triangles below which the serial pass runs */
static void test_threads_same_roots(void **state)
{
    (void)state;
    same_roots(600000, 300000, 7u, 2);
    same_roots(300000, 400000, 11u, 2);
    same_roots(300000, 400000, 13u, 3);
}

/* the serial pass on a small mesh by hand: two triangles sharing a vertex,
 * one apart, one vertex alone */
static void test_small_by_hand(void **state)
{
    (void)state;
    const uint32_t idx[] = {4, 2, 6, 6, 5, 7, 1, 3, 8};
    uint32_t p[9];
    jm_mesh_pieces(NULL, p, idx, 9, 3);
    const uint32_t want[9] = {0, 1, 2, 1, 2, 2, 2, 2, 1};
    for (int v = 0; v < 9; v++) assert_int_equal(p[v], want[v]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_small_by_hand),
        cmocka_unit_test(test_threads_same_roots),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
