/* cull_check.c - culling tests' shared parts: the same mesh bytes with culling on and off, and a lattice block with holes. */
#include "cull_check.h"
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
    p.no_culling = no_culling;
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
