/* test_aniso_cull.c - the anisotropic SPH field sampled only near the surface gives the same mesh bytes as every node sampled. */
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
#include "util/shared_data.h"

/* a copy of a mesh's arrays */
typedef struct copy {
    size_t nv, nt;
    float *pos, *nrm, *uv;
    uint32_t *idx;
} copy;

static void take(const jm_mesh *m, copy *c)
{
    c->nv = m->vertex_count;
    c->nt = m->triangle_count;
    c->pos = malloc(3 * c->nv * sizeof(float) + 1);
    c->nrm = malloc(3 * c->nv * sizeof(float) + 1);
    c->uv = malloc(2 * c->nv * sizeof(float) + 1);
    c->idx = malloc(3 * c->nt * sizeof(uint32_t) + 1);
    assert_non_null(c->pos);
    assert_non_null(c->nrm);
    assert_non_null(c->uv);
    assert_non_null(c->idx);
    memcpy(c->pos, m->positions, 3 * c->nv * sizeof(float));
    if (m->normals) memcpy(c->nrm, m->normals, 3 * c->nv * sizeof(float));
    if (m->uvs) memcpy(c->uv, m->uvs, 2 * c->nv * sizeof(float));
    memcpy(c->idx, m->indices, 3 * c->nt * sizeof(uint32_t));
}

static void drop(copy *c)
{
    free(c->pos);
    free(c->nrm);
    free(c->uv);
    free(c->idx);
}

static void mesh_with(const jm_params *base, int threads, int no_culling, const float *xyz, size_t count, copy *out)
{
    jm_params p = *base;
    p.anisotropic = 1;
    p.threads = threads;
    p.no_culling = no_culling;
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {xyz, count, 0, NULL};
    jm_mesh m;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
    take(&m, out);
    jm_context_free(ctx);
}

/* culled (1 and 2 threads) against every node sampled: the same bytes */
static void same_bytes(const char *what, const jm_params *p, const float *xyz, size_t count)
{
    copy ref, got;
    mesh_with(p, 1, 1, xyz, count, &ref);
    assert_true(ref.nt > 0);
    for (int t = 1; t <= 2; t++) {
        mesh_with(p, t, 0, xyz, count, &got);
        if (got.nv != ref.nv || got.nt != ref.nt)
            fail_msg("%s (%d threads): %zu vertices %zu triangles culled, %zu %zu not", what, t, got.nv, got.nt, ref.nv,
                     ref.nt);
        assert_memory_equal(got.pos, ref.pos, 3 * ref.nv * sizeof(float));
        assert_memory_equal(got.nrm, ref.nrm, 3 * ref.nv * sizeof(float));
        assert_memory_equal(got.uv, ref.uv, 2 * ref.nv * sizeof(float));
        assert_memory_equal(got.idx, ref.idx, 3 * ref.nt * sizeof(uint32_t));
        drop(&got);
    }
    printf("%s: %zu triangles, the same bytes culled and not\n", what, ref.nt);
    drop(&ref);
}

static void test_real_frames_same_bytes(void **state)
{
    (void)state;
    const char *files[] = {
        "derived/dam_break_frame_23_24389_particles.xyz",
        "splashsurf/bunny_frame_14_7705_particles.vtk",
        "splashsurf/double_dam_break_frame_26_4732_particles.vtk",
        "splashsurf/ParticleData_Random_1000.vtk",
        "splashsurf/hilbert2_7954_particles.vtk",
    };
    int ran = 0;
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
        jmf_frame fr;
        char err[512];
        int got = test_read_shared(files[k], NULL, &fr, err, sizeof err);
        if (got < 0) fail_msg("%s", err);
        if (!got) continue;
        for (int me = JM_METHOD_MT; me <= JM_METHOD_MC; me++) {
            /* the reference case (cube r/2, threshold 0.6), then a coarser
             * lattice with a thinner threshold and a shorter kernel, and
             * flatter kernels (other block sizes, other axis ratios) */
            const float cube[] = {0.5f, 0.75f, 0.6f}, thr[] = {0.6f, 0.35f, 0.8f}, sl[] = {2.0f, 1.6f, 2.0f},
                        kr[] = {0.0f, 0.0f, 8.0f};
            for (int v = 0; v < 3; v++) {
                if (k >= 2 && v == 0) continue; /* the big case on the two bench frames only */
                if (k < 2 && v > 0 && me == JM_METHOD_MT) continue;
                jm_params p = {0};
                p.radius = 0.025f;
                p.field = JM_FIELD_SPH;
                p.method = (jm_method)me;
                p.cube_size = cube[v];
                p.threshold = thr[v];
                p.smoothing_length = sl[v];
                p.aniso_max_ratio = kr[v];
                char what[256];
                snprintf(what, sizeof what, "%s %s cube %.2f thr %.2f h %.1f k_r %.0f", files[k],
                         me == JM_METHOD_MC ? "mc" : "mt", cube[v], thr[v], sl[v], kr[v]);
                same_bytes(what, &p, fr.xyz, fr.count);
            }
        }
        jmf_frame_free(&fr);
        ran++;
    }
    if (!ran) {
        printf("skipping: ../shared/data not found\n");
        skip();
    }
}

/* a lattice block with holes and a lone pair: culling next to cavities,
 * thin walls and particles on block faces */
static void test_block_with_holes(void **state)
{
    (void)state;
    const int m = 24;
    const float r = 0.025f;
    float *xyz = malloc((size_t)m * m * m * 3 * sizeof *xyz);
    assert_non_null(xyz);
    size_t n = 0;
    for (int k = 0; k < m; k++)
        for (int j = 0; j < m; j++)
            for (int i = 0; i < m; i++) {
                float d2 = (float)((i - 8) * (i - 8) + (j - 9) * (j - 9) + (k - 10) * (k - 10));
                if (d2 < 9.0f) continue;                   /* a cavity */
                if (i == 17 && (j + k) % 5 == 0) continue; /* a perforated wall */
                if (k > 18 && i > 6 && i < 12) continue;   /* a slot */
                unsigned h = (unsigned)(i * 73856093u ^ j * 19349663u ^ k * 83492791u);
                xyz[3 * n] = 2 * r * (float)i + 0.15f * r * (float)(h % 97) / 97.0f;
                xyz[3 * n + 1] = 2 * r * (float)j + 0.15f * r * (float)(h % 89) / 89.0f;
                xyz[3 * n + 2] = 2 * r * (float)k + 0.15f * r * (float)(h % 83) / 83.0f;
                n++;
            }
    /* a pair above the block */
    for (int t = 0; t < 2; t++) {
        xyz[3 * n] = 0.6f + 1.5f * r * (float)t;
        xyz[3 * n + 1] = 0.6f;
        xyz[3 * n + 2] = 1.5f;
        n++;
    }
    for (int me = JM_METHOD_MT; me <= JM_METHOD_MC; me++) {
        jm_params p = {0};
        p.radius = r;
        p.field = JM_FIELD_SPH;
        p.method = (jm_method)me;
        same_bytes(me == JM_METHOD_MC ? "block with holes, mc" : "block with holes, mt", &p, xyz, n);
        p.threshold = 0.35f;
        p.cube_size = 0.4f;
        same_bytes(me == JM_METHOD_MC ? "block with holes, mc, thr 0.35, cube 0.4" : "block with holes, mt, thr 0.35, cube 0.4",
                   &p, xyz, n);
    }
    free(xyz);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_block_with_holes),
        cmocka_unit_test(test_real_frames_same_bytes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
