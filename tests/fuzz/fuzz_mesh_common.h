/* fuzz_mesh_common.h - the shared body of the meshing fuzz target and its replay: CSV in, meshed with bounded parameters, the mesh's invariants checked. */
#ifndef JETMESH_FUZZ_MESH_COMMON_H
#define JETMESH_FUZZ_MESH_COMMON_H

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "../../formats/reader.h"
#include "../../lib/jetmesh.h"

/* what a broken invariant does: abort() in the fuzzer, a test failure in
 * the replay (which defines it before including this) */
#ifndef FUZZ_MESH_FAIL
#define FUZZ_MESH_FAIL(what) abort()
#endif

/* Bounds that keep one input well under the fuzzer's timeout and RSS limit:
 * at most this many particles (the neighbour search is at most n^2 pairs
 * and the lattice band grows with n) and this much library memory. */
#define FUZZ_MESH_MAX_PARTICLES 2000
#define FUZZ_MESH_MAX_BYTES (256u << 20)

/* One meshing: a valid status; on success finite positions within the
 * bounds, unit normals, finite uvs, indices below the vertex count; on
 * failure an empty mesh. */
static void fuzz_mesh_once(const jmf_frame *fr, float radius, jm_field field, jm_method method)
{
    jm_params p;
    memset(&p, 0, sizeof p);
    p.radius = radius;
    p.field = field;
    p.method = method;
    p.threads = 1;
    p.max_bytes = FUZZ_MESH_MAX_BYTES;
    jm_context *ctx = NULL;
    if (jm_context_create(&p, &ctx) != JM_OK) FUZZ_MESH_FAIL("context refused valid parameters");
    jm_particles in = {fr->xyz, fr->count, 0, fr->ids};
    jm_mesh m;
    jm_stats st;
    jm_status s = jm_mesh_particles(ctx, &in, &m, &st);
    size_t est = 0;
    jm_status se = jm_estimate_bytes(ctx, &in, &est);
    if ((int)s < JM_OK || s > JM_E_NUMERIC_DOMAIN) FUZZ_MESH_FAIL("status out of range");
    if (s == JM_E_INTERNAL || s == JM_E_INVALID_ARGUMENT || s == JM_E_INVALID_PARTICLE)
        FUZZ_MESH_FAIL("finite particles refused as invalid, or an internal error");
    /* the estimate refuses the numeric domain as meshing does (meshing
     * may first refuse coordinates beyond the lattice's range instead) */
    if ((s == JM_E_NUMERIC_DOMAIN && se != JM_E_NUMERIC_DOMAIN) ||
        (se == JM_E_NUMERIC_DOMAIN && s != JM_E_NUMERIC_DOMAIN && s != JM_E_TOO_LARGE))
        FUZZ_MESH_FAIL("estimate and mesh disagree on the numeric domain");
    if (s != JM_OK) {
        if (m.positions || m.vertex_count || m.triangle_count) FUZZ_MESH_FAIL("a refused frame left a mesh");
        jm_context_free(ctx);
        return;
    }
    for (size_t v = 0; v < m.vertex_count; v++) {
        const float *x = &m.positions[3 * v], *n = &m.normals[3 * v], *u = &m.uvs[2 * v];
        for (int a = 0; a < 3; a++)
            if (!isfinite(x[a]) || x[a] < m.bounds_min[a] || x[a] > m.bounds_max[a]) FUZZ_MESH_FAIL("vertex not finite or out of bounds");
        double len = (double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2];
        if (!(fabs(len - 1.0) < 1e-3)) FUZZ_MESH_FAIL("normal not unit");
        if (!isfinite(u[0]) || !isfinite(u[1])) FUZZ_MESH_FAIL("uv not finite");
    }
    for (size_t t = 0; t < 3 * m.triangle_count; t++)
        if (m.indices[t] >= m.vertex_count) FUZZ_MESH_FAIL("index out of range");
    if (st.peak_bytes > FUZZ_MESH_MAX_BYTES) FUZZ_MESH_FAIL("peak over the memory limit");
    jm_context_free(ctx);
}

/* Reads data as CSV, chooses its field as --field auto does, and meshes
 * it (up to FUZZ_MESH_MAX_PARTICLES particles) at radius 0.25 with the
 * metasphere (MT) and SPH (MC), and at
 * a radius from the data's own scale (its largest |coordinate| over 8,
 * when that is a normal float), so extreme magnitudes reach the library's
 * units and numeric domain rather than stopping at the lattice range. */
static void fuzz_mesh(const uint8_t *data, size_t size)
{
    jmf_read_options opt;
    jmf_frame fr;
    char err[512];
    memset(&opt, 0, sizeof opt);
    opt.format = JMF_IN_CSV;
    opt.drop_invalid = 1;
    opt.max_bytes = 64u << 20;
    if (jmf_read_particles_mem(data, size, "particles.csv", &opt, &fr, err, sizeof err) != JMF_OK) return;
    if (fr.count > FUZZ_MESH_MAX_PARTICLES) {
        jmf_frame_free(&fr);
        return;
    }
    float far = 0.0f;
    for (size_t i = 0; i < 3 * fr.count; i++)
        if (fabsf(fr.xyz[i]) > far) far = fabsf(fr.xyz[i]);
    /* the automatic field choice (its work is bounded: issue 30's piles) */
    {
        jm_params cp;
        memset(&cp, 0, sizeof cp);
        cp.radius = 0.25f;
        jm_particles in = {fr.xyz, fr.count, 0, NULL};
        jm_field f;
        jm_method m;
        float nb = -1.0f;
        if (jm_choose_field(&cp, &in, &f, &m, &nb) != JM_OK) FUZZ_MESH_FAIL("field choice refused finite particles");
        if (!(nb >= 0.0f) || !isfinite(nb)) FUZZ_MESH_FAIL("field choice measure not finite");
    }
    fuzz_mesh_once(&fr, 0.25f, JM_FIELD_METASPHERE, JM_METHOD_MT);
    fuzz_mesh_once(&fr, 0.25f, JM_FIELD_SPH, JM_METHOD_MC);
    float own = far / 8.0f;
    if (own >= FLT_MIN && isfinite(own)) {
        fuzz_mesh_once(&fr, own, JM_FIELD_METASPHERE, JM_METHOD_MC);
        fuzz_mesh_once(&fr, own, JM_FIELD_SPH, JM_METHOD_MT);
    }
    jmf_frame_free(&fr);
}

#endif
