/* cull_check.c - culling tests' shared parts: the same mesh bytes with culling on and off, on the real frames and on a lattice block with holes. */
#include "cull_check.h"
#include "../../lib/jetmesh_testing.h"
#include "shared_data.h"
#include "test_meshes.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* p's mesh of xyz at `threads` threads, culled or not, into out; 0 or -1 */
static int mesh_with(const jm_params *base, int threads, int no_culling, const float *xyz, size_t count,
                     test_mesh *out)
{
    jm_params p = *base;
    p.threads = threads;
    jm_testing_no_culling(&p, no_culling);
    jm_context *ctx = NULL;
    if (jm_context_create(&p, &ctx) != JM_OK) return -1;
    jm_particles in = {xyz, count, 0, NULL};
    jm_mesh m;
    int rc = jm_mesh_particles(ctx, &in, &m, NULL) == JM_OK ? test_mesh_copy(&m, out) : -1;
    jm_context_free(ctx);
    return rc;
}

/* the same bytes, or both absent */
static int same(const void *a, const void *b, size_t n)
{
    if (!a || !b) return a == b;
    return memcmp(a, b, n) == 0;
}

int cull_same_bytes(const char *what, const jm_params *p, const float *xyz, size_t count, size_t *out_triangles,
                    char *err, size_t errsz)
{
    test_mesh ref, got;
    if (mesh_with(p, 1, 1, xyz, count, &ref) != 0) {
        snprintf(err, errsz, "%s: meshing without culling failed", what);
        return -1;
    }
    const size_t nv = ref.mesh.vertex_count, nt = ref.mesh.triangle_count;
    *out_triangles = nt;
    int rc = 0;
    if (nt == 0) {
        snprintf(err, errsz, "%s: no triangles", what);
        rc = -1;
    }
    for (int t = 1; t <= 2 && rc == 0; t++) {
        if (mesh_with(p, t, 0, xyz, count, &got) != 0) {
            snprintf(err, errsz, "%s (%d threads): meshing with culling failed", what, t);
            rc = -1;
            break;
        }
        if (got.mesh.vertex_count != nv || got.mesh.triangle_count != nt) {
            snprintf(err, errsz, "%s (%d threads): %zu vertices %zu triangles culled, %zu %zu not", what, t,
                     got.mesh.vertex_count, got.mesh.triangle_count, nv, nt);
            rc = -1;
        } else if (!same(got.positions, ref.positions, 3 * nv * sizeof(float)) ||
                   !same(got.normals, ref.normals, 3 * nv * sizeof(float)) ||
                   !same(got.uvs, ref.uvs, 2 * nv * sizeof(float)) ||
                   !same(got.indices, ref.indices, 3 * nt * sizeof(uint32_t))) {
            snprintf(err, errsz, "%s (%d threads): the culled mesh's bytes differ", what, t);
            rc = -1;
        }
        test_mesh_free(&got);
    }
    test_mesh_free(&ref);
    return rc;
}

float *cull_holed_block(float r, size_t *n)
{
    const int m = 24;
    float *xyz = malloc(((size_t)m * m * m + 2) * 3 * sizeof *xyz);
    if (!xyz) return NULL;
    size_t k3 = 0;
    for (int k = 0; k < m; k++)
        for (int j = 0; j < m; j++)
            for (int i = 0; i < m; i++) {
                float d2 = (float)((i - 8) * (i - 8) + (j - 9) * (j - 9) + (k - 10) * (k - 10));
                if (d2 < 9.0f) continue;                   /* a cavity */
                if (i == 17 && (j + k) % 5 == 0) continue; /* a perforated wall */
                if (k > 18 && i > 6 && i < 12) continue;   /* a slot */
                unsigned h = (unsigned)(i * 73856093u ^ j * 19349663u ^ k * 83492791u);
                xyz[3 * k3] = 2 * r * (float)i + 0.15f * r * (float)(h % 97) / 97.0f;
                xyz[3 * k3 + 1] = 2 * r * (float)j + 0.15f * r * (float)(h % 89) / 89.0f;
                xyz[3 * k3 + 2] = 2 * r * (float)k + 0.15f * r * (float)(h % 83) / 83.0f;
                k3++;
            }
    /* a pair above the block */
    for (int t = 0; t < 2; t++) {
        xyz[3 * k3] = 0.6f + 1.5f * r * (float)t;
        xyz[3 * k3 + 1] = 0.6f;
        xyz[3 * k3 + 2] = 1.5f;
        k3++;
    }
    *n = k3;
    return xyz;
}

const char *const cull_frames[CULL_FRAMES] = {
    "derived/dam_break_frame_23_24389_particles.xyz",
    "splashsurf/bunny_frame_14_7705_particles.vtk",
    "splashsurf/double_dam_break_frame_26_4732_particles.vtk",
    "splashsurf/ParticleData_Random_1000.vtk",
    "splashsurf/hilbert2_7954_particles.vtk",
};

/* one case: the same bytes, its triangle count printed */
static int one_case(const char *what, const jm_params *p, const float *xyz, size_t count, char *err, size_t errsz)
{
    size_t nt = 0;
    if (cull_same_bytes(what, p, xyz, count, &nt, err, errsz) != 0) return -1;
    printf("%s: %zu triangles, the same bytes culled and not\n", what, nt);
    return 0;
}

int cull_real_frames(int nvariants, cull_case fill, char *err, size_t errsz)
{
    int ran = 0;
    /* JETMESH_TEST_SMALL (t_sanitizers.sh: the instrumented run, where the
     * same code paths matter, not the sizes): the bench frames left out */
    const int small = getenv("JETMESH_TEST_SMALL") != NULL;
    if (small) printf("JETMESH_TEST_SMALL: the two bench frames left out\n");
    for (size_t k = small ? 2 : 0; k < CULL_FRAMES; k++) {
        jmf_frame fr;
        int got = test_read_shared(cull_frames[k], NULL, &fr, err, errsz);
        if (got < 0) return -1;
        if (!got) continue;
        int rc = 0;
        for (int me = JM_METHOD_MT; me <= JM_METHOD_MC && rc == 0; me++)
            for (int v = 0; v < nvariants && rc == 0; v++) {
                jm_params p = {0};
                char what[256];
                if (fill(k, me, v, &p, what, sizeof what)) rc = one_case(what, &p, fr.xyz, fr.count, err, errsz);
            }
        jmf_frame_free(&fr);
        if (rc) return -1;
        ran++;
    }
    return ran ? 0 : 1;
}

int cull_holed_block_cases(int anisotropic, char *err, size_t errsz)
{
    const float r = 0.025f;
    size_t n = 0;
    float *xyz = cull_holed_block(r, &n);
    if (!xyz) {
        snprintf(err, errsz, "block with holes: no memory");
        return -1;
    }
    int rc = 0;
    for (int me = JM_METHOD_MT; me <= JM_METHOD_MC && rc == 0; me++) {
        const char *m = me == JM_METHOD_MC ? "mc" : "mt";
        char what[128];
        jm_params p = {0};
        p.radius = r;
        p.field = JM_FIELD_SPH;
        p.method = (jm_method)me;
        p.anisotropic = anisotropic;
        snprintf(what, sizeof what, "block with holes, %s", m);
        rc = one_case(what, &p, xyz, n, err, errsz);
        p.threshold = 0.35f;
        p.cube_size = 0.4f;
        snprintf(what, sizeof what, "block with holes, %s, thr 0.35, cube 0.4", m);
        if (rc == 0) rc = one_case(what, &p, xyz, n, err, errsz);
    }
    free(xyz);
    return rc;
}
