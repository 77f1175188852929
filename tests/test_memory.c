/* test_memory.c - the memory limit holds where memory is taken, peak_bytes counts every scratch buffer (meshoptimizer's too), estimates count the metasphere's links. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdatomic.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/jetmesh.h"
#include "../lib/field/sph/sph_normals.h" /* internal: the scratch buffers (white-box test) */

/* a block of nx * ny * nz particles `gap` apart, slightly sheared */
static float *block(int nx, int ny, int nz, float gap, size_t *n)
{
    float *xyz = malloc(3 * sizeof(float) * (size_t)nx * ny * nz);
    assert_non_null(xyz);
    size_t k = 0;
    for (int z = 0; z < nz; z++)
        for (int y = 0; y < ny; y++)
            for (int x = 0; x < nx; x++, k++) {
                xyz[3 * k] = gap * (float)x + 0.06f * gap * (float)((k * 7) % 5);
                xyz[3 * k + 1] = gap * (float)y;
                xyz[3 * k + 2] = gap * (float)z;
            }
    *n = k;
    return xyz;
}

static jm_status mesh_once(jm_params p, const float *xyz, size_t n, jm_stats *st, size_t *nv)
{
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {xyz, n, 0, NULL};
    jm_mesh m;
    jm_status s = jm_mesh_particles(ctx, &in, &m, st);
    if (nv) *nv = m.vertex_count;
    jm_context_free(ctx);
    return s;
}

/* With one thread a frame takes its memory in the same order every time:
 * a limit of its peak meshes it, one byte less refuses it (JM_E_TOO_LARGE,
 * with the total it needed), whatever the estimate said. */
static void test_limit_where_taken(void **state)
{
    (void)state;
    size_t n;
    float *xyz = block(20, 10, 10, 0.05f, &n);
    for (int v = 0; v < 4; v++) {
        jm_params p = {0};
        p.radius = 0.025f;
        p.threads = 1;
        p.field = v % 2 ? JM_FIELD_SPH : JM_FIELD_METASPHERE;
        p.simplify_error = v >= 2 ? 0.1f : 0.0f;
        jm_stats st;
        assert_int_equal(mesh_once(p, xyz, n, &st, NULL), JM_OK);
        const size_t peak = st.peak_bytes;
        assert_true(st.estimated_bytes < peak); /* the estimate alone would let it through */
        p.max_bytes = peak;
        assert_int_equal(mesh_once(p, xyz, n, &st, NULL), JM_OK);
        assert_true(st.peak_bytes <= peak);
        p.max_bytes = peak - 1;
        assert_int_equal(mesh_once(p, xyz, n, &st, NULL), JM_E_TOO_LARGE);
        assert_true(st.peak_bytes < peak);
        if (!(st.estimated_bytes > peak - 1)) fail_msg("variant %d: peak %zu, refused with an estimate of %zu", v, peak, st.estimated_bytes);
    }
    free(xyz);
}

/* meshoptimizer's scratch is counted: simplifying adds to the peak about
 * what meshopt_simplify takes (over 100 bytes a vertex), not just the few
 * bytes a vertex of jetmesh's own arrays around it */
static void test_meshopt_counted(void **state)
{
    (void)state;
    size_t n, nv = 0;
    float *xyz = block(20, 10, 10, 0.05f, &n);
    jm_params p = {0};
    p.radius = 0.025f;
    p.threads = 1;
    p.field = JM_FIELD_SPH;
    jm_stats plain, simplified;
    assert_int_equal(mesh_once(p, xyz, n, &plain, &nv), JM_OK);
    p.simplify_error = 0.1f;
    assert_int_equal(mesh_once(p, xyz, n, &simplified, NULL), JM_OK);
    if (!(simplified.peak_bytes > plain.peak_bytes + 100 * nv))
        fail_msg("peak %zu simplified, %zu not, %zu vertices", simplified.peak_bytes, plain.peak_bytes, nv);
    free(xyz);
}

/* The workers' growing scratch is counted where it grows, in the jm_mem
 * its buffers name (the context's: peak_bytes), and refused past that
 * jm_mem's limit: the block's cells (jm_hood.range) and the particles
 * gathered for SPH normals (jm_soa.buf). White-box: the internal calls. */
static void test_scratch_counted(void **state)
{
    (void)state;
    size_t n;
    float *xyz = block(24, 24, 24, 0.2f, &n); /* dense: 13,824 particles 0.2 r apart */
    jm_params p = {0};
    p.radius = 1.0f;
    p.field = JM_FIELD_SPH;
    jm_config c;
    assert_int_equal(jm_config_resolve(&p, &c, NULL), JM_OK);
    jm_pool *pool = NULL;
    assert_int_equal(jm_pool_create(1, &pool), JM_OK);
    jm_mem gm, sm;
    memset(&gm, 0, sizeof gm);
    memset(&sm, 0, sizeof sm);
    jm_particles in = {xyz, n, 0, NULL};
    jm_grid g;
    assert_int_equal(jm_grid_build(&g, &gm, pool, &c, &in), JM_OK);
    jm_hood hood;
    jm_soa soa;
    memset(&hood, 0, sizeof hood);
    memset(&soa, 0, sizeof soa);
    hood.mem = soa.mem = &sm;
    const float lo[3] = {0, 0, 0}, hi[3] = {2, 2, 2};
    assert_int_equal(jm_hood_build(&hood, &g, &c, lo, hi), 1);
    jm_sph_gather(&g, &c, &hood, lo, hi, &soa);
    assert_true(soa.n > 1000 && soa.n != SIZE_MAX);
    assert_true(hood.cap > 0);
    assert_int_equal(atomic_load(&sm.current), hood.cap * 2 * sizeof(uint32_t) + soa.cap * 4 * sizeof(float));
    assert_int_equal(atomic_load(&sm.peak), atomic_load(&sm.current));
    /* over a limit: refused, nothing more counted */
    jm_soa more;
    memset(&more, 0, sizeof more);
    more.mem = &sm;
    sm.limit = atomic_load(&sm.current) + 1000;
    jm_sph_gather(&g, &c, &hood, lo, hi, &more);
    assert_true(more.n == SIZE_MAX);
    assert_true(atomic_load(&sm.over));
    assert_int_equal(atomic_load(&sm.current), hood.cap * 2 * sizeof(uint32_t) + soa.cap * 4 * sizeof(float) +
                                                   more.cap * 4 * sizeof(float));
    jm_free(&sm, more.buf, more.cap * 4 * sizeof(float));
    jm_free(&sm, soa.buf, soa.cap * 4 * sizeof(float));
    jm_free(&sm, hood.range, hood.cap * 2 * sizeof(uint32_t));
    assert_int_equal(atomic_load(&sm.current), 0);
    jm_grid_free(&g, &gm);
    assert_int_equal(atomic_load(&gm.current), 0);
    jm_pool_free(pool);
    free(xyz);
}

/* jm_estimate_bytes counts the metasphere's links (24 bytes each): on
 * uniform particles with a radius far too large it is within a factor 2 of
 * what jm_mesh_particles refuses on once it has counted them; the issue's
 * frame (50,000 particles 0.05 apart, r = 0.25) is refused at once, as
 * too dense, and estimated over 1 GiB. */
static void test_estimate_links(void **state)
{
    (void)state;
    size_t n;
    float *xyz = block(30, 30, 30, 0.05f, &n);
    jm_params p = {0};
    p.radius = 0.1f;
    p.max_bytes = (size_t)100 << 20;
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {xyz, n, 0, NULL};
    size_t est = 0;
    assert_int_equal(jm_estimate_bytes(ctx, &in, &est), JM_OK);
    jm_mesh m;
    jm_stats st;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, &st), JM_E_TOO_LARGE);
    if (!(est > st.estimated_bytes / 2 && est < 2 * st.estimated_bytes))
        fail_msg("estimated %zu bytes, refused on %zu", est, st.estimated_bytes);
    jm_context_free(ctx);
    free(xyz);

    xyz = block(37, 37, 37, 0.05f, &n);
    in.xyz = xyz;
    in.count = n;
    p.radius = 0.25f;
    p.max_bytes = (size_t)1 << 30;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    assert_int_equal(jm_estimate_bytes(ctx, &in, &est), JM_OK);
    assert_true(est > ((size_t)1 << 30));
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, &st), JM_E_TOO_DENSE);
    jm_context_free(ctx);
    free(xyz);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_limit_where_taken),
        cmocka_unit_test(test_meshopt_counted),
        cmocka_unit_test(test_scratch_counted),
        cmocka_unit_test(test_estimate_links),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
