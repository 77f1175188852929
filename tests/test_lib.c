/* test_lib.c - the library's contract: shapes, topology, volume, determinism, API errors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/jetmesh.h"
#include "util/meshcheck.h"
#include "../lib/extract/tables.h" /* internal: the generated case tables */

static jm_context *make(jm_params p)
{
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    assert_non_null(ctx);
    return ctx;
}

static void mesh_ok(jm_context *ctx, const float *xyz, size_t n, jm_mesh *m, mc_report *r)
{
    jm_particles in = {xyz, n, 0, NULL};
    jm_stats st;
    assert_int_equal(jm_mesh_particles(ctx, &in, m, &st), JM_OK);
    int ok = mc_check(m, r);
    if (!ok) fail_msg("mesh not closed/manifold/oriented: %s (volume %g)", r->problem, r->volume);
    /* the field's normal agrees with the faces except at a few creases and
     * dimples finer than the cubes (the metasphere is a union of balls and
     * necks: dense frames are full of them); random normals would give 50 % */
    double away = m->vertex_count ? (double)r->normals_away / (double)m->vertex_count : 0;
    if (away > 0.03) fail_msg("%zu of %zu normals point away from their faces", r->normals_away, m->vertex_count);
}

/* ---- one particle: a sphere of radius r */
static void one_sphere(jm_method method, float cube, double tol, int templates)
{
    const float r = 0.5f;
    const float pos[3][3] = {{0, 0, 0}, {0.1234f, -0.0567f, 0.0891f}, {10.37f, -3.71f, 2.2f}};
    for (int k = 0; k < 3; k++) {
        jm_params p = {0};
        p.radius = r;
        p.cube_size = cube;
        p.method = method;
        p.no_templates = !templates;
        jm_context *ctx = make(p);
        jm_mesh m;
        mc_report rep;
        mesh_ok(ctx, pos[k], 1, &m, &rep);
        double V = 4.0 / 3.0 * M_PI * r * r * r;
        double err = fabs(rep.volume - V) / V;
        if (err > tol)
            fail_msg("method %d cube %g pos %d: volume %.6f vs %.6f (%.3f %% > %.3f %%)", method, cube, k, rep.volume, V,
                     100 * err, 100 * tol);
        assert_int_equal(rep.components, 1);
        /* every vertex near the sphere, every normal radial */
        for (size_t v = 0; v < m.vertex_count; v++) {
            const float *q = m.positions + 3 * v, *n = m.normals + 3 * v;
            double d[3] = {q[0] - pos[k][0], q[1] - pos[k][1], q[2] - pos[k][2]};
            double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            assert_true(fabs(len - r) < 0.02 * r);
            assert_true((d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) / len > 0.99);
        }
        jm_context_free(ctx);
    }
}

static void test_sphere_volume_mt(void **s)
{
    (void)s;
    one_sphere(JM_METHOD_MT, 0.25f, 0.01, 0);
    one_sphere(JM_METHOD_MT, 0.125f, 0.003, 0);
    one_sphere(JM_METHOD_MT, 0.25f, 0.01, 1);
}

static void test_sphere_volume_mc(void **s)
{
    (void)s;
    one_sphere(JM_METHOD_MC, 0.25f, 0.01, 0);
    one_sphere(JM_METHOD_MC, 0.125f, 0.003, 0);
    one_sphere(JM_METHOD_MC, 0.125f, 0.003, 1);
}

/* ---- the generated tables: every triangle corner sits on a crossed edge,
 * marching cubes fans never lie in a cube face, and each table is the
 * mirror of its complement (same edges, opposite orientation count) */
static void test_tables(void **s)
{
    (void)s;
    assert_true(jm_tables_consistent());
    const jm_case_table *tabs[2] = {jm_table_mc(), jm_table_mt()};
    for (int t = 0; t < 2; t++)
        for (int cfg = 0; cfg < 256; cfg++) {
            const jm_case_table *tab = tabs[t];
            if (cfg == 0 || cfg == 255) assert_int_equal(tab->ntri[cfg], 0);
            else assert_true(tab->ntri[cfg] > 0);
            for (int k = 0; k < 3 * tab->ntri[cfg]; k++) {
                int e = tab->edges[cfg][k];
                if (t == 0) assert_true(e < 12);
                int a = jm_cube_edge_corner[e];
                const int *d = jm_dir[jm_cube_edge_dir[e]];
                int b = a + d[0] + 2 * d[1] + 4 * d[2];
                assert_true(((cfg >> a) & 1) != ((cfg >> b) & 1));
            }
            /* the complement crosses the same edges */
            unsigned long used = 0, used_c = 0;
            for (int k = 0; k < 3 * tab->ntri[cfg]; k++) used |= 1ul << tab->edges[cfg][k];
            for (int k = 0; k < 3 * tab->ntri[255 - cfg]; k++) used_c |= 1ul << tab->edges[255 - cfg][k];
            assert_true(used == used_c);
        }
}

/* ---- metasphere topology */
static void pair(float dist, size_t expect_components, jm_method method)
{
    const float r = 1.0f;
    float xyz[6] = {0.01f, 0.02f, 0.03f, 0.01f + dist * r, 0.02f, 0.03f};
    jm_params p = {0};
    p.radius = r;
    p.cube_size = 0.25f;
    p.method = method;
    jm_context *ctx = make(p);
    jm_mesh m;
    mc_report rep;
    mesh_ok(ctx, xyz, 2, &m, &rep);
    assert_int_equal(rep.components, expect_components);
    /* the analytic function agrees at the midpoint */
    jm_particles in = {xyz, 2, 0, NULL};
    float mid[3] = {0.01f + 0.5f * dist * r, 0.02f, 0.03f}, v, g[3];
    assert_int_equal(jm_field_eval(&p, &in, mid, &v, g), JM_OK);
    if (expect_components == 1) {
        /* waist radius r cos(D/2r) */
        assert_true(fabsf(v - cosf(0.5f * dist)) < 1e-4f);
        /* the mesh's waist: vertices near the mid plane lie at that radius */
        double best = 1e9;
        for (size_t i = 0; i < m.vertex_count; i++) {
            const float *q = m.positions + 3 * i;
            if (fabsf(q[0] - mid[0]) < 0.05f) {
                double rad = sqrt((q[1] - mid[1]) * (q[1] - mid[1]) + (q[2] - mid[2]) * (q[2] - mid[2]));
                if (rad < best) best = rad;
            }
        }
        assert_true(fabs(best - r * cos(0.5 * dist)) < 0.05 * r);
    } else {
        assert_true(v < 0);
    }
    jm_context_free(ctx);
}

static void test_metasphere_pairs(void **s)
{
    (void)s;
    pair(1.5f, 1, JM_METHOD_MT);
    pair(1.5f, 1, JM_METHOD_MC);
    pair(4.0f, 2, JM_METHOD_MT);
    pair(4.0f, 2, JM_METHOD_MC);
    pair(3.0f, 1, JM_METHOD_MT); /* below pi r: a thin waist r cos(1.5) = 0.07 r */
}

static void test_field_eval(void **s)
{
    (void)s;
    jm_params p = {0};
    p.radius = 2.0f;
    float c[3] = {1, 2, 3};
    jm_particles in = {c, 1, 0, NULL};
    float x[3] = {1, 2, 6}, v, g[3];
    assert_int_equal(jm_field_eval(&p, &in, x, &v, g), JM_OK);
    assert_true(fabsf(v - (1.0f - 3.0f / 2.0f)) < 1e-6f); /* (r - d) / r */
    assert_true(fabsf(g[2] + 0.5f) < 1e-6f);
    /* SPH: one lonely particle, phi = W(d)/W(0) */
    p.field = JM_FIELD_SPH;
    x[2] = 3.0f;
    assert_int_equal(jm_field_eval(&p, &in, x, &v, NULL), JM_OK);
    assert_true(fabsf(v - 1.0f) < 1e-6f);
}

/* ---- random sets: closed and manifold for every field and method */
static float *random_cloud(size_t n, float spread, unsigned seed)
{
    float *xyz = malloc(3 * n * sizeof *xyz);
    for (size_t i = 0; i < 3 * n; i++) xyz[i] = (mc_randf(&seed) - 0.5f) * spread;
    return xyz;
}

static void test_random_closed(void **s)
{
    (void)s;
    const float spreads[] = {0.3f, 0.6f, 1.5f};
    for (int f = JM_FIELD_METASPHERE; f <= JM_FIELD_SPH; f++)
        for (int m = JM_METHOD_MT; m <= JM_METHOD_MC; m++)
            for (int k = 0; k < 3; k++) {
                float *xyz = random_cloud(400, spreads[k], 7u + (unsigned)k);
                jm_params p = {0};
                p.radius = 0.025f;
                p.field = (jm_field)f;
                p.method = (jm_method)m;
                p.cube_size = k == 2 ? 0.75f : 0.5f;
                jm_context *ctx = make(p);
                jm_mesh mesh;
                mc_report rep;
                mesh_ok(ctx, xyz, 400, &mesh, &rep);
                assert_true(mesh.triangle_count > 0);
                jm_context_free(ctx);
                free(xyz);
            }
}

/* ---- awkward sets: duplicates, planes, lines, lattice-aligned points,
 * clusters straddling block corners, far outliers; every field, method and
 * a few cube sizes; always closed, manifold and oriented */
static void test_awkward_sets(void **s)
{
    (void)s;
    unsigned seed = 2024;
    for (int round = 0; round < 24; round++) {
        size_t n = 20 + mc_rand(&seed) % 300;
        float *xyz = malloc(3 * n * sizeof *xyz);
        const float r = 0.025f;
        for (size_t i = 0; i < n; i++) {
            float *p = xyz + 3 * i;
            switch (round % 6) {
            case 0: /* exact duplicates mixed in */
                for (int a = 0; a < 3; a++) p[a] = (mc_randf(&seed) - 0.5f) * 0.3f;
                if (i % 3 == 1) memcpy(p, p - 3, 12);
                break;
            case 1: /* a plane z = const */
                p[0] = (mc_randf(&seed) - 0.5f) * 0.4f;
                p[1] = (mc_randf(&seed) - 0.5f) * 0.4f;
                p[2] = 0.1f;
                break;
            case 2: /* a line, spacing 1.2 r, on lattice nodes */
                p[0] = (float)i * 1.2f * r;
                p[1] = p[2] = 0.0f;
                break;
            case 3: /* points exactly on lattice nodes (cube 0.5 r) */
                for (int a = 0; a < 3; a++) p[a] = (float)(mc_rand(&seed) % 40) * 0.5f * r;
                break;
            case 4: /* a cluster around a block corner */
                for (int a = 0; a < 3; a++) p[a] = 0.2f + (mc_randf(&seed) - 0.5f) * 0.1f;
                break;
            default: /* clusters plus far outliers */
                for (int a = 0; a < 3; a++) p[a] = (mc_randf(&seed) - 0.5f) * (i % 10 == 0 ? 50.0f : 0.2f);
                break;
            }
        }
        for (int f = JM_FIELD_METASPHERE; f <= JM_FIELD_SPH; f++)
            for (int m = JM_METHOD_MT; m <= JM_METHOD_MC; m++) {
                jm_params p = {0};
                p.radius = r;
                p.field = (jm_field)f;
                p.method = (jm_method)m;
                p.cube_size = (round / 6) % 2 ? 0.8f : 0.5f;
                p.threads = 1 + round % 3;
                jm_context *ctx = make(p);
                jm_mesh mesh;
                mc_report rep;
                mesh_ok(ctx, xyz, n, &mesh, &rep);
                assert_true(mesh.triangle_count > 0);
                jm_context_free(ctx);
            }
        free(xyz);
    }
}

/* ---- byte-identical output for 1, 2 and 7 threads */
static uint64_t mesh_hash(const jm_mesh *m)
{
    uint64_t h = 1469598103934665603ull;
    const void *parts[4] = {m->positions, m->normals, m->uvs, m->indices};
    size_t sizes[4] = {m->vertex_count * 12, m->vertex_count * 12, m->vertex_count * 8, m->triangle_count * 12};
    for (int k = 0; k < 4; k++) {
        const unsigned char *b = parts[k];
        for (size_t i = 0; b && i < sizes[k]; i++) { h ^= b[i]; h *= 1099511628211ull; }
    }
    return h;
}

static void test_threads_identical(void **s)
{
    (void)s;
    float *xyz = random_cloud(3000, 0.8f, 99);
    for (int f = JM_FIELD_METASPHERE; f <= JM_FIELD_SPH; f++)
        for (int m = JM_METHOD_MT; m <= JM_METHOD_MC; m++) {
            uint64_t ref = 0;
            size_t nt = 0;
            const int threads[3] = {1, 2, 7};
            for (int t = 0; t < 3; t++) {
                jm_params p = {0};
                p.radius = 0.025f;
                p.field = (jm_field)f;
                p.method = (jm_method)m;
                p.threads = threads[t];
                jm_context *ctx = make(p);
                jm_particles in = {xyz, 3000, 0, NULL};
                jm_mesh mesh;
                jm_stats st;
                assert_int_equal(jm_mesh_particles(ctx, &in, &mesh, &st), JM_OK);
                assert_int_equal(st.threads, threads[t]);
                assert_true(st.blocks > 1);
                uint64_t h = mesh_hash(&mesh);
                if (t == 0) { ref = h; nt = mesh.triangle_count; }
                else {
                    assert_int_equal(mesh.triangle_count, nt);
                    assert_true(h == ref);
                }
                jm_context_free(ctx);
            }
        }
    free(xyz);
}

/* ---- ids make the mesh independent of input order */
static void test_ids_order(void **s)
{
    (void)s;
    size_t n = 500;
    float *a = random_cloud(n, 0.4f, 5), *b = malloc(3 * n * sizeof *b);
    uint32_t *ida = malloc(n * sizeof *ida), *idb = malloc(n * sizeof *idb);
    for (size_t i = 0; i < n; i++) {
        ida[i] = (uint32_t)i;
        size_t j = n - 1 - i; /* reversed */
        memcpy(b + 3 * j, a + 3 * i, 12);
        idb[j] = (uint32_t)i;
    }
    jm_params p = {0};
    p.radius = 0.025f;
    p.field = JM_FIELD_SPH;
    jm_context *ctx = make(p);
    jm_particles pa = {a, n, 0, ida}, pb = {b, n, 0, idb};
    jm_mesh m;
    assert_int_equal(jm_mesh_particles(ctx, &pa, &m, NULL), JM_OK);
    uint64_t h = mesh_hash(&m);
    assert_int_equal(jm_mesh_particles(ctx, &pb, &m, NULL), JM_OK);
    assert_true(mesh_hash(&m) == h);
    jm_context_free(ctx);
    free(a); free(b); free(ida); free(idb);
}

/* ---- templates: isolated particles, same mesh as the lattice path */
static void test_templates(void **s)
{
    (void)s;
    size_t n = 50;
    float *xyz = malloc(3 * n * sizeof *xyz);
    unsigned seed = 3;
    for (size_t i = 0; i < n; i++) { /* far apart on a jittered line */
        xyz[3 * i] = (float)i * 0.5f + 0.01f * mc_randf(&seed);
        xyz[3 * i + 1] = 0.01f * mc_randf(&seed);
        xyz[3 * i + 2] = 0.01f * mc_randf(&seed);
    }
    for (int f = JM_FIELD_METASPHERE; f <= JM_FIELD_SPH; f++) {
        jm_params p = {0};
        p.radius = 0.025f;
        p.field = (jm_field)f;
        jm_context *ctx = make(p);
        jm_mesh m;
        mc_report rep;
        jm_particles in = {xyz, n, 0, NULL};
        jm_stats st;
        assert_int_equal(jm_mesh_particles(ctx, &in, &m, &st), JM_OK);
        assert_int_equal(st.isolated, n);
        assert_true(mc_check(&m, &rep));
        assert_int_equal(rep.components, n);
        double v_tmpl = rep.volume;
        jm_context_free(ctx);
        p.no_templates = 1;
        ctx = make(p);
        assert_int_equal(jm_mesh_particles(ctx, &in, &m, &st), JM_OK);
        assert_int_equal(st.isolated, 0);
        assert_true(mc_check(&m, &rep));
        assert_int_equal(rep.components, n);
        assert_true(fabs(rep.volume - v_tmpl) / v_tmpl < 0.03);
        jm_context_free(ctx);
    }
    free(xyz);
}

/* ---- SPH: splashsurf's single-particle expectation (r = 0.025, cube 0.5 r) */
static void test_sph_single(void **s)
{
    (void)s;
    for (int t = 0; t < 2; t++) {
        jm_params p = {0};
        p.radius = 0.025f;
        p.field = JM_FIELD_SPH;
        p.method = JM_METHOD_MC;
        p.no_templates = t;
        jm_context *ctx = make(p);
        float c[3] = {0, 0, 0};
        jm_mesh m;
        mc_report rep;
        mesh_ok(ctx, c, 1, &m, &rep);
        assert_true(m.triangle_count >= 240 && m.triangle_count <= 260);
        jm_context_free(ctx);
    }
}

/* ---- UVs depend on world position only, not on the frame's extent */
static void test_uv_stable(void **s)
{
    (void)s;
    float xyz[9] = {0.1f, 0.2f, 0.3f, 0.13f, 0.21f, 0.3f, 0, 0, 0};
    for (int mode = JM_UV_BOX; mode <= JM_UV_SPHERICAL; mode++) {
        jm_params p = {0};
        p.radius = 0.025f;
        p.uv_mode = (jm_uv_mode)mode;
        jm_context *ctx = make(p);
        jm_particles in = {xyz, 2, 0, NULL};
        jm_mesh m;
        assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
        size_t nv = m.vertex_count;
        float *pos = malloc(nv * 12), *uv = malloc(nv * 8);
        memcpy(pos, m.positions, nv * 12);
        memcpy(uv, m.uvs, nv * 8);
        /* a far-away third particle changes the bounding box */
        xyz[6] = 5.0f; xyz[7] = -3.0f; xyz[8] = 2.0f;
        in.count = 3;
        assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
        assert_true(m.vertex_count > nv);
        size_t same = 0;
        for (size_t i = 0; i < m.vertex_count; i++)
            for (size_t j = 0; j < nv; j++)
                if (memcmp(m.positions + 3 * i, pos + 3 * j, 12) == 0) {
                    assert_memory_equal(m.uvs + 2 * i, uv + 2 * j, 8);
                    same++;
                    break;
                }
        assert_int_equal(same, nv);
        xyz[6] = xyz[7] = xyz[8] = 0;
        free(pos); free(uv);
        jm_context_free(ctx);
    }
}

/* ---- sparse: two droplets 100 m apart cost what two droplets cost */
static void test_sparse_memory(void **s)
{
    (void)s;
    float *a = random_cloud(200, 0.1f, 11);
    float *b = malloc(400 * 3 * sizeof *b);
    memcpy(b, a, 600 * sizeof *a);
    memcpy(b + 600, a, 600 * sizeof *a);
    for (int i = 0; i < 200; i++) b[600 + 3 * i] += 100.0f;
    jm_params p = {0};
    p.radius = 0.025f;
    p.field = JM_FIELD_SPH;
    p.threads = 1;
    jm_context *ctx = make(p);
    jm_particles one = {a, 200, 0, NULL}, two = {b, 400, 0, NULL};
    jm_mesh m;
    jm_stats s1, s2;
    assert_int_equal(jm_mesh_particles(ctx, &one, &m, &s1), JM_OK);
    size_t t1 = m.triangle_count;
    jm_context_free(ctx);
    ctx = make(p);
    assert_int_equal(jm_mesh_particles(ctx, &two, &m, &s2), JM_OK);
    /* +100 m rounds the floats, so the second copy sits a hair off the lattice */
    assert_true(m.triangle_count > 2 * t1 * 99 / 100 && m.triangle_count < 2 * t1 * 101 / 100);
    assert_true(s2.blocks <= 2 * s1.blocks + 8);
    assert_true(s2.peak_bytes < 3 * s1.peak_bytes);
    jm_context_free(ctx);
    free(a);
    free(b);
}

/* ---- API contract */
static void test_api_errors(void **s)
{
    (void)s;
    jm_context *ctx = (jm_context *)1;
    jm_params p = {0};
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT); /* radius required */
    assert_null(ctx);
    p.radius = -1;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    p.radius = NAN;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    p.radius = 0.1f;
    p.field = (jm_field)42;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    p.field = JM_FIELD_DEFAULT;
    assert_int_equal(jm_context_create(NULL, &ctx), JM_E_INVALID_ARGUMENT);
    assert_int_equal(jm_context_create(&p, NULL), JM_E_INVALID_ARGUMENT);
    jm_context_free(NULL);

    ctx = make(p);
    jm_params got;
    jm_context_get_params(ctx, &got);
    assert_int_equal(got.field, JM_FIELD_METASPHERE);
    assert_int_equal(got.method, JM_METHOD_MT);
    assert_true(fabsf(got.cube_size - 0.5f) < 1e-7f);
    assert_true(got.threads >= 1);

    jm_mesh m;
    jm_stats st;
    /* empty frame: a valid empty mesh */
    jm_particles none = {NULL, 0, 0, NULL};
    assert_int_equal(jm_mesh_particles(ctx, &none, &m, &st), JM_OK);
    assert_int_equal(m.vertex_count, 0);
    assert_int_equal(m.triangle_count, 0);
    /* NaN and infinity */
    float bad[6] = {0, 0, 0, 1, NAN, 0};
    jm_particles pb = {bad, 2, 0, NULL};
    assert_int_equal(jm_mesh_particles(ctx, &pb, &m, &st), JM_E_INVALID_PARTICLE);
    assert_int_equal(m.triangle_count, 0);
    bad[4] = INFINITY;
    assert_int_equal(jm_mesh_particles(ctx, &pb, &m, &st), JM_E_INVALID_PARTICLE);
    /* absurd lattice: coordinates beyond the lattice range */
    float far[6] = {0, 0, 0, 1e12f, 0, 0};
    jm_particles pf = {far, 2, 0, NULL};
    assert_int_equal(jm_mesh_particles(ctx, &pf, &m, &st), JM_E_TOO_LARGE);
    /* an absurdly fine lattice for the particles' spread: refused at once,
     * even without a memory limit */
    {
        jm_params fine = {0};
        fine.radius = 1.0f;
        fine.cube_size = 0.001f;
        fine.field = JM_FIELD_SPH;
        jm_context *fc = make(fine);
        /* (about the origin: 2^16 cubes from it is the numeric domain) */
        float two[6] = {-50, 0, 0, 50, 0, 0};
        jm_particles pt = {two, 2, 0, NULL};
        assert_int_equal(jm_mesh_particles(fc, &pt, &m, &st), JM_E_TOO_LARGE);
        assert_true(st.estimated_bytes > ((size_t)1 << 40));
        jm_context_free(fc);
    }
    /* a memory limit refuses before allocating the band */
    float *cloud = random_cloud(2000, 1.0f, 1);
    jm_particles pc = {cloud, 2000, 0, NULL};
    size_t est = 0;
    assert_int_equal(jm_estimate_bytes(ctx, &pc, &est), JM_OK);
    assert_true(est > 0);
    p.max_bytes = 100000;
    assert_int_equal(jm_context_set_params(ctx, &p), JM_OK);
    assert_int_equal(jm_mesh_particles(ctx, &pc, &m, &st), JM_E_TOO_LARGE);
    assert_true(st.estimated_bytes > p.max_bytes);
    p.max_bytes = 0;
    assert_int_equal(jm_context_set_params(ctx, &p), JM_OK);
    assert_int_equal(jm_mesh_particles(ctx, &pc, &m, &st), JM_OK);
    assert_true(st.peak_bytes > 0);
    assert_true(m.triangle_count > 0);
    /* strided input with ids */
    float strided[8] = {0, 0, 0, 99, 0.03f, 0, 0, 99};
    jm_particles ps = {strided, 2, 16, NULL};
    assert_int_equal(jm_mesh_particles(ctx, &ps, &m, &st), JM_OK);
    mc_report rep;
    assert_true(mc_check(&m, &rep));
    assert_int_equal(rep.components, 1);
    assert_int_equal(jm_mesh_particles(NULL, &ps, &m, &st), JM_E_INVALID_ARGUMENT);
    assert_int_equal(jm_mesh_particles(ctx, NULL, &m, &st), JM_E_INVALID_ARGUMENT);
    assert_string_equal(jm_status_message(JM_OK), "ok");
    assert_non_null(jm_status_message((jm_status)1234));
    assert_string_equal(jm_version(), JM_VERSION_STRING);
    free(cloud);
    jm_context_free(ctx);
}

/* ---- a real frame from ../shared/data, meshed closed and manifold */
static float *read_xyz(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    float *xyz = malloc((size_t)size);
    *n = fread(xyz, 1, (size_t)size, f) / 12;
    fclose(f);
    return xyz;
}

static void test_real_frame(void **s)
{
    (void)s;
    const char *shared = getenv("JETMESH_SHARED");
    char path[1024];
    snprintf(path, sizeof path, "%s/data/derived/dam_break_frame_23_24389_particles.xyz", shared ? shared : "../shared");
    size_t n = 0;
    float *xyz = read_xyz(path, &n);
    if (!xyz) { printf("skipping: %s not found\n", path); skip(); }
    assert_int_equal(n, 24389);
    for (int f = JM_FIELD_METASPHERE; f <= JM_FIELD_SPH; f++)
        for (int m = JM_METHOD_MT; m <= JM_METHOD_MC; m++) {
            jm_params p = {0};
            p.radius = 0.025f;
            p.field = (jm_field)f;
            p.method = (jm_method)m;
            p.cube_size = f == JM_FIELD_SPH ? 0.75f : 1.0f;
            jm_context *ctx = make(p);
            jm_mesh mesh;
            mc_report rep;
            mesh_ok(ctx, xyz, n, &mesh, &rep);
            assert_true(mesh.triangle_count > 10000);
            if (f == JM_FIELD_SPH) assert_true(rep.normals_away * 1000 < mesh.vertex_count);
            jm_context_free(ctx);
        }
    free(xyz);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_volume_mt),
        cmocka_unit_test(test_sphere_volume_mc),
        cmocka_unit_test(test_tables),
        cmocka_unit_test(test_metasphere_pairs),
        cmocka_unit_test(test_field_eval),
        cmocka_unit_test(test_random_closed),
        cmocka_unit_test(test_awkward_sets),
        cmocka_unit_test(test_threads_identical),
        cmocka_unit_test(test_ids_order),
        cmocka_unit_test(test_templates),
        cmocka_unit_test(test_sph_single),
        cmocka_unit_test(test_uv_stable),
        cmocka_unit_test(test_sparse_memory),
        cmocka_unit_test(test_api_errors),
        cmocka_unit_test(test_real_frame),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
