/* test_cavities.c - jm_drop_small_cavities removes exactly the small inward shells, the same on 1 and N threads, however the pieces' triangles interleave. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/post/cavities.h"

static uint32_t next(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

/* A mesh of nk closed tetrahedra (4 vertices, 4 triangles each), edge 1 or
 * 3, each with its outward or inward orientation: kind[k] bit 0 inward, bit
 * 1 big. Their triangles are laid out in runs of `run` (1: every triangle
 * of a shell apart from its others, 4: each shell's together), the runs of
 * different shells shuffled, so that pieces cross the chunks of the volume
 * sum and a chunk holds thousands of runs. */
typedef struct {
    float *pos;
    uint32_t *idx;
    size_t nv, ni;
} tmesh;

static tmesh shells(size_t nk, const uint8_t *kind, int run, uint32_t seed)
{
    tmesh m;
    m.nv = 4 * nk;
    m.ni = 12 * nk;
    m.pos = malloc(3 * m.nv * sizeof *m.pos);
    m.idx = malloc(m.ni * sizeof *m.idx);
    assert_true(m.pos && m.idx);
    /* outward faces of (0,0,0) (e,0,0) (0,e,0) (0,0,e) */
    static const uint32_t face[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    size_t nr = 4 * nk / (size_t)run;
    uint32_t *order = malloc(nr * sizeof *order);
    assert_non_null(order);
    for (size_t r = 0; r < nr; r++) order[r] = (uint32_t)r;
    for (size_t r = nr; r > 1; r--) {
        size_t o = next(&seed) % r;
        uint32_t t = order[r - 1];
        order[r - 1] = order[o];
        order[o] = t;
    }
    for (size_t k = 0; k < nk; k++) {
        const float e = (kind[k] & 2) ? 3.0f : 1.0f;
        const float o[3] = {(float)(k % 100) * 5.0f, (float)(k / 100 % 100) * 5.0f, (float)(k / 10000) * 5.0f};
        for (int v = 0; v < 4; v++)
            for (int a = 0; a < 3; a++) m.pos[3 * (4 * k + v) + a] = o[a] + ((v == a + 1) ? e : 0.0f);
    }
    /* run r holds triangles r * run .. of the shell list, in place order[r] */
    for (size_t r = 0; r < nr; r++)
        for (int q = 0; q < run; q++) {
            const size_t t = r * (size_t)run + (size_t)q, k = t / 4, f = t % 4;
            uint32_t *out = m.idx + 3 * ((size_t)order[r] * (size_t)run + (size_t)q);
            const int inward = kind[k] & 1;
            out[0] = (uint32_t)(4 * k + face[f][0]);
            out[1] = (uint32_t)(4 * k + face[f][inward ? 2 : 1]);
            out[2] = (uint32_t)(4 * k + face[f][inward ? 1 : 2]);
        }
    free(order);
    return m;
}

/* Drops the small cavities of a copy of m on `threads` threads (0: no
 * pool); checks what is left: every small inward shell gone, the others
 * whole; returns the copy for comparisons. */
static tmesh drop(const tmesh *m, size_t nk, const uint8_t *kind, int threads)
{
    tmesh c = {malloc(3 * m->nv * sizeof(float)), malloc(m->ni * sizeof(uint32_t)), m->nv, m->ni};
    assert_true(c.pos && c.idx);
    memcpy(c.pos, m->pos, 3 * m->nv * sizeof(float));
    memcpy(c.idx, m->idx, m->ni * sizeof(uint32_t));
    jm_mem mem;
    memset(&mem, 0, sizeof mem);
    jm_pool *pool = NULL;
    if (threads) assert_int_equal(jm_pool_create(threads, &pool), JM_OK);
    size_t removed = 0;
    /* a cavity below 1 (the small shells' 1/6), not the big ones' 4.5 */
    assert_true(jm_drop_small_cavities(&mem, pool, c.pos, NULL, NULL, c.idx, &c.nv, &c.ni, 1.0, NULL, &removed));
    jm_pool_free(pool);
    size_t want = 0, kept = 0;
    for (size_t k = 0; k < nk; k++) {
        if (kind[k] == 1) want++;
        else kept++;
    }
    assert_int_equal(removed, want);
    assert_int_equal(c.nv, 4 * kept);
    assert_int_equal(c.ni, 12 * kept);
    /* the kept vertices, in order, are those of the kept shells */
    size_t v = 0;
    for (size_t k = 0; k < nk; k++) {
        if (kind[k] == 1) continue;
        assert_memory_equal(c.pos + 3 * v, m->pos + 3 * 4 * k, 12 * sizeof(float));
        v += 4;
    }
    assert_int_equal(mem.current, 0);
    return c;
}

static void check(size_t nk, int run, uint32_t seed)
{
    uint8_t *kind = malloc(nk);
    assert_non_null(kind);
    uint32_t s = seed;
    for (size_t k = 0; k < nk; k++) kind[k] = (uint8_t)(next(&s) % 4);
    tmesh m = shells(nk, kind, run, seed);
    tmesh one = drop(&m, nk, kind, 0);
    for (int threads = 2; threads <= 3; threads++) {
        tmesh many = drop(&m, nk, kind, threads);
        assert_int_equal(many.ni, one.ni);
        assert_memory_equal(many.idx, one.idx, one.ni * sizeof(uint32_t));
        assert_memory_equal(many.pos, one.pos, 3 * one.nv * sizeof(float));
        free(many.pos);
        free(many.idx);
    }
    free(one.pos);
    free(one.idx);
    free(m.pos);
    free(m.idx);
    free(kind);
}

/* 40000 shells, 160000 triangles: five chunks of the volume sum, each of
 * thousands of runs (more than the 256 a chunk keeps in its slots), whether
 * each shell's triangles follow each other or lie apart */
static void test_many_small_pieces(void **state)
{
    (void)state;
    check(40000, 4, 3u);
    check(40000, 1, 5u);
    check(40000, 2, 9u);
}

/* a few shells: one chunk, few runs */
static void test_few_pieces(void **state)
{
    (void)state;
    check(8, 4, 17u);
    check(8, 1, 19u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_few_pieces),
        cmocka_unit_test(test_many_small_pieces),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
