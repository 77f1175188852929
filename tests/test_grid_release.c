/* test_grid_release.c - the SPH grid numbered in key order and given back behind the block sweep: the same mesh bytes, no released byte read, a lower peak. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../lib/jetmesh.h"
#include "../lib/core/internal.h"
#include "../lib/grid/grid.h"
#include "../lib/jetmesh_testing.h"

/* A column of fluid, W x W x H particles on a jittered lattice of spacing
 * 2r (r = 0.025), long in z so that the block sweep, which runs in z,
 * passes many cell slabs; droplets scattered around it (isolated: meshed
 * from the sphere template, in the input's order) and, with far = 1, one
 * more 100 units off, so that the grid indexes its cells in a hash map
 * instead of densely. The input order is shuffled: cells first appear in
 * no spatial order. */
#define W 9
#define H 120
#define DROPS 24

static uint32_t rnd(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

static float *column(size_t *out_n, int far)
{
    const size_t lat = (size_t)W * W * H, n = lat + DROPS + (size_t)far;
    float *xyz = malloc(3 * n * sizeof *xyz);
    assert_non_null(xyz);
    uint32_t seed = 777u;
    size_t k = 0;
    for (int z = 0; z < H; z++)
        for (int y = 0; y < W; y++)
            for (int x = 0; x < W; x++, k++) {
                const int c[3] = {x, y, z};
                for (int a = 0; a < 3; a++)
                    xyz[3 * k + a] = 0.05f * (float)c[a] + ((float)rnd(&seed) / 16777216.0f - 0.5f) * 0.012f;
            }
    for (int d = 0; d < DROPS; d++, k++) { /* 1 unit beside the column, along its length */
        xyz[3 * k] = 1.5f + 0.4f * (float)(d % 3);
        xyz[3 * k + 1] = 0.2f * (float)(d % 5);
        xyz[3 * k + 2] = 0.25f * (float)d;
    }
    if (far) {
        xyz[3 * k] = xyz[3 * k + 1] = xyz[3 * k + 2] = 100.0f;
        k++;
    }
    for (size_t i = n - 1; i > 0; i--) { /* shuffle */
        size_t j = rnd(&seed) % (i + 1);
        for (int a = 0; a < 3; a++) {
            float t = xyz[3 * i + a];
            xyz[3 * i + a] = xyz[3 * j + a];
            xyz[3 * j + a] = t;
        }
    }
    *out_n = n;
    return xyz;
}

typedef struct {
    float *pos, *nrm, *uv;
    uint32_t *idx;
    size_t nv, nt, isolated, peak;
} copy;

static copy mesh_with(const jm_params *p, const float *xyz, size_t n)
{
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(p, &ctx), JM_OK);
    jm_particles in = {xyz, n, 0, NULL};
    jm_mesh m;
    jm_stats st;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, &st), JM_OK);
    copy c = {NULL, NULL, NULL, NULL, m.vertex_count, m.triangle_count, st.isolated, st.peak_bytes};
    c.pos = malloc(3 * c.nv * sizeof(float) + 1);
    c.nrm = malloc(3 * c.nv * sizeof(float) + 1);
    c.uv = malloc(2 * c.nv * sizeof(float) + 1);
    c.idx = malloc(3 * c.nt * sizeof(uint32_t) + 1);
    assert_true(c.pos && c.nrm && c.uv && c.idx);
    memcpy(c.pos, m.positions, 3 * c.nv * sizeof(float));
    assert_non_null(m.normals);
    assert_non_null(m.uvs);
    memcpy(c.nrm, m.normals, 3 * c.nv * sizeof(float));
    memcpy(c.uv, m.uvs, 2 * c.nv * sizeof(float));
    memcpy(c.idx, m.indices, 3 * c.nt * sizeof(uint32_t));
    jm_context_free(ctx);
    return c;
}

static void same(const copy *a, const copy *b)
{
    assert_int_equal(a->nv, b->nv);
    assert_int_equal(a->nt, b->nt);
    assert_int_equal(a->isolated, b->isolated);
    assert_memory_equal(a->pos, b->pos, 3 * a->nv * sizeof(float));
    assert_memory_equal(a->nrm, b->nrm, 3 * a->nv * sizeof(float));
    assert_memory_equal(a->uv, b->uv, 2 * a->nv * sizeof(float));
    assert_memory_equal(a->idx, b->idx, 3 * a->nt * sizeof(uint32_t));
}

static void drop(copy *c)
{
    free(c->pos);
    free(c->nrm);
    free(c->uv);
    free(c->idx);
}

/* A solid block of S^3 particles on a jittered lattice of spacing 2r */
static float *solid(int S, size_t *out_n, uint32_t seed)
{
    const size_t n = (size_t)S * S * S;
    float *xyz = malloc(3 * n * sizeof *xyz);
    assert_non_null(xyz);
    for (size_t k = 0; k < n; k++)
        for (int a = 0; a < 3; a++) {
            const size_t c = a == 0 ? k % (size_t)S : (a == 1 ? k / (size_t)S % (size_t)S : k / (size_t)S / (size_t)S);
            xyz[3 * k + a] = 0.05f * (float)c + ((float)rnd(&seed) / 16777216.0f - 0.5f) * 0.012f;
        }
    *out_n = n;
    return xyz;
}

static jm_params sph(jm_method method, int threads)
{
    jm_params p = {0}; /* zero means default */
    p.radius = 0.025f;
    p.field = JM_FIELD_SPH;
    p.method = method;
    p.threads = threads;
    p.threshold = 0.6f;
    return p;
}

/* first appearance, nothing released (the numbering before the change)
 * against key order released in pages the size of the system's, made
 * unreadable once released: any read of them after faults (the test
 * crashes), and every byte of the mesh must be the same */
static void check_same(const jm_params *p, int far)
{
    size_t n;
    float *xyz = column(&n, far);
    const size_t page = (size_t)sysconf(_SC_PAGESIZE);
    jm_testing_grid_mode(0, 0, 0);
    copy ref = mesh_with(p, xyz, n);
    jm_testing_grid_mode(1, 2, page);
    copy got = mesh_with(p, xyz, n);
    jm_testing_grid_mode(1, 1, 0);
    copy dflt = mesh_with(p, xyz, n);
    assert_true(ref.nt > 20000);
    assert_int_equal(ref.isolated, DROPS + (size_t)far);
    same(&ref, &got);
    same(&ref, &dflt);
    drop(&ref);
    drop(&got);
    drop(&dflt);
    free(xyz);
}

static void test_same_bytes_dense(void **state)
{
    (void)state;
    for (int t = 1; t <= 2; t++) {
        jm_params p = sph(JM_METHOD_MC, t);
        check_same(&p, 0);
    }
    jm_params p = sph(JM_METHOD_MT, 2);
    check_same(&p, 0);
}

static void test_same_bytes_hashed(void **state)
{
    (void)state;
    jm_params p = sph(JM_METHOD_MC, 2);
    check_same(&p, 1);
}

/* the grid is read after the sweep here (smoothing; anisotropic kernels):
 * nothing is released, and the key order changes no byte */
static void test_same_bytes_post(void **state)
{
    (void)state;
    jm_params p = sph(JM_METHOD_MC, 2);
    p.smooth_iterations = 3;
    check_same(&p, 0);
    jm_params q = sph(JM_METHOD_MC, 2);
    q.anisotropic = 1;
    check_same(&q, 1);
}

/* The peak with the grid given back is below the peak without by most of
 * the particles' grid (pos, weight, isolated: 17 bytes a particle): the
 * peak is at the end of the sweep, where only its last slabs are left (a
 * solid block, whose grid is large beside its mesh; no cavity pass, which
 * comes after the grid is gone in both cases and may peak higher). */
static void test_lower_peak(void **state)
{
    (void)state;
    size_t n;
    float *xyz = solid(30, &n, 99u);
    const size_t page = (size_t)sysconf(_SC_PAGESIZE);
    jm_params p = sph(JM_METHOD_MC, 1);
    p.keep_cavities = 1;
    jm_testing_grid_mode(1, 0, page);
    copy kept = mesh_with(&p, xyz, n);
    jm_testing_grid_mode(1, 1, page);
    copy given = mesh_with(&p, xyz, n);
    jm_testing_grid_mode(1, 1, 0);
    same(&kept, &given);
    assert_true(given.peak + 17 * n / 2 < kept.peak);
    drop(&kept);
    drop(&given);
    free(xyz);
}

/* A context gives the last mesh back when the next frame starts, where the
 * frame's particles are many beside that mesh (bulk fluid; here a coarse
 * lattice, cube r, so that the mesh is small beside the particles): the
 * same frame again peaks where it peaked the first time. Held, the last
 * mesh would sit beside the whole grid. */
static void test_last_mesh_dropped(void **state)
{
    (void)state;
    size_t n;
    float *xyz = solid(70, &n, 4242u);
    jm_params p = sph(JM_METHOD_MC, 1);
    p.cube_size = 1.0f;
    p.keep_cavities = 1;
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {xyz, n, 0, NULL};
    jm_mesh m;
    jm_stats s1, s2;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, &s1), JM_OK);
    const size_t mesh_bytes = m.vertex_count * 8 * sizeof(float) + m.triangle_count * 3 * sizeof(uint32_t);
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, &s2), JM_OK);
    assert_true(m.vertex_count > 140000); /* its arrays in their own mappings */
    assert_true(17 * n >= mesh_bytes / 2);
    assert_true(s2.peak_bytes <= s1.peak_bytes + 17 * n / 4);
    jm_context_free(ctx);
    free(xyz);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_bytes_dense),  cmocka_unit_test(test_same_bytes_hashed),
        cmocka_unit_test(test_same_bytes_post),   cmocka_unit_test(test_lower_peak),
        cmocka_unit_test(test_last_mesh_dropped),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
