/* test_units.c - the mesh does not depend on the unit of length: the same frame at r = 1, 1e10, 1e-25, 1e19, or a refusal. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/jetmesh.h"
#include "util/meshcheck.h"
#include "util/test_meshes.h"

/* A small frame in units of the radius, every coordinate in [3, 10] (so no
 * vertex comes near 0, where floats turn subnormal at tiny scales): a
 * wavy chain 1.5 apart, a 3x3x3 block 1.9 apart and one isolated particle. */
#define NPART (12 + 27 + 1)
static void scene(float *xyz)
{
    size_t k = 0;
    for (int i = 0; i < 12; i++, k++) {
        xyz[3 * k] = 3.0f + 0.5f * (float)i;
        xyz[3 * k + 1] = 4.0f + 0.4f * sinf(0.9f * (float)i);
        xyz[3 * k + 2] = 4.5f + 0.3f * cosf(1.3f * (float)i);
    }
    for (int z = 0; z < 3; z++)
        for (int y = 0; y < 3; y++)
            for (int x = 0; x < 3; x++, k++) {
                xyz[3 * k] = 4.0f + 1.9f * (float)x + 0.05f * (float)y;
                xyz[3 * k + 1] = 5.5f + 1.9f * (float)y;
                xyz[3 * k + 2] = 3.5f + 1.9f * (float)z + 0.03f * (float)x;
            }
    xyz[3 * k] = 9.5f;
    xyz[3 * k + 1] = 3.2f;
    xyz[3 * k + 2] = 9.0f;
}

typedef struct variant {
    const char *name;
    jm_field field;
    jm_method method;
    int anisotropic, smooth, exact;
    float simplify;
} variant;

static const variant variants[] = {
    {"metasphere mt", JM_FIELD_METASPHERE, JM_METHOD_MT, 0, 0, 0, 0.0f},
    {"metasphere mc", JM_FIELD_METASPHERE, JM_METHOD_MC, 0, 0, 0, 0.0f},
    {"sph mt", JM_FIELD_SPH, JM_METHOD_MT, 0, 0, 0, 0.0f},
    {"sph mc", JM_FIELD_SPH, JM_METHOD_MC, 0, 0, 0, 0.0f},
    {"metasphere exact, smoothed, simplified", JM_FIELD_METASPHERE, JM_METHOD_MT, 0, 3, 1, 0.1f},
    {"sph anisotropic", JM_FIELD_SPH, JM_METHOD_MC, 1, 0, 0, 0.0f},
};

static jm_status mesh_at(const variant *v, float radius, float uv_scale, const float *xyz, size_t n, jm_mesh *m,
                         jm_context **ctx)
{
    jm_params p = {0};
    p.radius = radius;
    p.field = v->field;
    p.method = v->method;
    p.anisotropic = v->anisotropic;
    p.smooth_iterations = v->smooth;
    p.exact_surface = v->exact;
    p.simplify_error = v->simplify;
    p.uv_scale = uv_scale;
    p.threads = 2;
    assert_int_equal(jm_context_create(&p, ctx), JM_OK);
    jm_particles in = {xyz, n, 0, NULL};
    return jm_mesh_particles(*ctx, &in, m, NULL);
}

/* The same frame and parameters scaled by 2^k (radius, coordinates and a
 * uv scale in world units): the same mesh, every position times 2^k
 * exactly, normals, uvs and triangles the same bits. */
static void test_power_of_two_scales(void **state)
{
    (void)state;
    static const int ks[] = {33, -83, 63, -120, 110}; /* 8.6e9, 1.0e-25, 9.2e18, 7.5e-37, 1.3e33 */
    const float r0 = 0.8f;
    float base[3 * NPART], xyz[3 * NPART];
    scene(base);
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        for (int uvs = 0; uvs < 2; uvs++) { /* the default uv scale (16 r), and one given */
            jm_context *c0 = NULL;
            jm_mesh m;
            assert_int_equal(mesh_at(&variants[v], r0, uvs ? 2.5f : 0.0f, base, NPART, &m, &c0), JM_OK);
            assert_true(m.triangle_count > 100);
            test_mesh ref;
            assert_int_equal(test_mesh_copy(&m, &ref), 0);
            jm_context_free(c0);
            for (size_t s = 0; s < sizeof ks / sizeof ks[0]; s++) {
                const int k = ks[s];
                for (int i = 0; i < 3 * NPART; i++) xyz[i] = ldexpf(base[i], k);
                jm_context *ctx = NULL;
                jm_status st = mesh_at(&variants[v], ldexpf(r0, k), uvs ? ldexpf(2.5f, k) : 0.0f, xyz, NPART, &m, &ctx);
                if (st != JM_OK || m.vertex_count != ref.mesh.vertex_count || m.triangle_count != ref.mesh.triangle_count)
                    fail_msg("%s at 2^%d: status %d, %zu vertices, %zu triangles (at r = %g: %zu, %zu)",
                             variants[v].name, k, (int)st, m.vertex_count, m.triangle_count, (double)r0, ref.mesh.vertex_count,
                             ref.mesh.triangle_count);
                size_t bad = 0;
                for (size_t i = 0; i < 3 * ref.mesh.vertex_count; i++) {
                    bad += m.positions[i] != ldexpf(ref.positions[i], k);
                    bad += memcmp(&m.normals[i], &ref.normals[i], sizeof(float)) != 0;
                }
                for (size_t i = 0; i < 2 * ref.mesh.vertex_count; i++) bad += memcmp(&m.uvs[i], &ref.uvs[i], sizeof(float)) != 0;
                bad += memcmp(m.indices, ref.indices, 3 * ref.mesh.triangle_count * sizeof(uint32_t)) != 0;
                if (bad) fail_msg("%s at 2^%d: %zu values differ from the mesh at r = %g", variants[v].name, k, bad,
                                  (double)r0);
                jm_context_free(ctx);
            }
            test_mesh_free(&ref);
        }
    }
}

/* The radii, not powers of two: two particles 1.5 r apart give a
 * closed mesh of finite vertices whose volume, in r^3, is that at r = 1
 * (the coordinates round differently, so not the same bits). */
static void test_decimal_radii(void **state)
{
    (void)state;
    static const float radii[] = {1e10f, 1e-25f, 1e19f, 1e-30f, 1e30f};
    for (size_t v = 0; v < 4; v++) {
        double vol1 = 0.0;
        for (size_t s = 0; s <= sizeof radii / sizeof radii[0]; s++) {
            float r = s == 0 ? 1.0f : radii[s - 1];
            float xyz[6] = {0, 0, 0, 1.5f * r, 0.0f, 0.0f};
            jm_context *ctx = NULL;
            jm_mesh m;
            assert_int_equal(mesh_at(&variants[v], r, 0.0f, xyz, 2, &m, &ctx), JM_OK);
            assert_true(m.triangle_count > 100);
            for (size_t i = 0; i < 3 * m.vertex_count; i++) {
                assert_true(isfinite(m.positions[i]));
                assert_true(isfinite(m.normals[i]));
            }
            for (size_t i = 0; i < 2 * m.vertex_count; i++) assert_true(isfinite(m.uvs[i]));
            mc_report rep;
            if (!mc_check(&m, &rep)) fail_msg("%s at r = %g: %s", variants[v].name, (double)r, rep.problem);
            double vol = rep.volume / ((double)r * r * r);
            if (s == 0) vol1 = vol;
            else if (fabs(vol - vol1) > 1e-3 * vol1)
                fail_msg("%s at r = %g: volume %.6f r^3, %.6f at r = 1", variants[v].name, (double)r, vol, vol1);
            jm_context_free(ctx);
        }
    }
}

/* jm_interpolate_attributes (the kernel weights of vertices against
 * particles) does not depend on the unit either: the same values, bit for
 * bit, for the frame and its vertices scaled by 2^k. */
static void test_attributes_scale(void **state)
{
    (void)state;
    static const int ks[] = {0, 33, -83, 63, -120, 110};
    const float r0 = 0.8f;
    float base[3 * NPART], xyz[3 * NPART], vals[NPART], vbase[3 * 64], vpos[3 * 64], ref[64], got[64];
    scene(base);
    for (int i = 0; i < NPART; i++) vals[i] = (float)i * 0.37f - 2.0f;
    for (int v = 0; v < 64; v++)
        for (int a = 0; a < 3; a++) vbase[3 * v + a] = base[3 * (v % NPART) + a] + 0.3f * (float)((v * (a + 3)) % 7) - 0.9f;
    for (size_t s = 0; s < sizeof ks / sizeof ks[0]; s++) {
        const int k = ks[s];
        for (int i = 0; i < 3 * NPART; i++) xyz[i] = ldexpf(base[i], k);
        for (int i = 0; i < 3 * 64; i++) vpos[i] = ldexpf(vbase[i], k);
        jm_params p = {0};
        p.radius = ldexpf(r0, k);
        jm_particles in = {xyz, NPART, 0, NULL};
        jm_attribute at = {1, vals, s == 0 ? ref : got};
        assert_int_equal(jm_interpolate_attributes(&p, &in, vpos, 64, &at, 1), JM_OK);
        if (s > 0 && memcmp(ref, got, sizeof ref) != 0) fail_msg("attributes differ at 2^%d", k);
    }
}

/* jm_field_eval too: the same value, and the gradient (per world unit)
 * times 2^-k, for every field (the anisotropic kernels' matrices, 1 /
 * length^2 in float, overflowed at r = 1e-25) */
static void test_eval_scale(void **state)
{
    (void)state;
    static const int ks[] = {0, 33, -83, 63, -120, 110};
    float base[3 * NPART], xyz[3 * NPART];
    scene(base);
    const float probe[3] = {5.1f, 6.2f, 4.4f};
    float v0[6] = {0}, g0[6][3];
    for (size_t s = 0; s < sizeof ks / sizeof ks[0]; s++) {
        const int k = ks[s];
        for (int i = 0; i < 3 * NPART; i++) xyz[i] = ldexpf(base[i], k);
        const float x[3] = {ldexpf(probe[0], k), ldexpf(probe[1], k), ldexpf(probe[2], k)};
        jm_particles in = {xyz, NPART, 0, NULL};
        for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
            jm_params p = {0};
            p.radius = ldexpf(0.8f, k);
            p.field = variants[v].field;
            p.anisotropic = variants[v].anisotropic;
            float val, g[3];
            assert_int_equal(jm_field_eval(&p, &in, x, &val, g), JM_OK);
            if (s == 0) {
                v0[v] = val;
                memcpy(g0[v], g, sizeof g);
                assert_true(isfinite(val));
                continue;
            }
            int bad = !(fabsf(val - v0[v]) <= 1e-6f * (1.0f + fabsf(v0[v])));
            for (int a = 0; a < 3; a++) bad |= !(fabsf(ldexpf(g[a], k) - g0[v][a]) <= 1e-5f * (1.0f + fabsf(g0[v][a])));
            if (bad)
                fail_msg("%s at 2^%d: value %g, gradient %g %g %g (at 2^0: %g, %g %g %g)", variants[v].name, k,
                         (double)val, (double)ldexpf(g[0], k), (double)ldexpf(g[1], k), (double)ldexpf(g[2], k),
                         (double)v0[v], (double)g0[v][0], (double)g0[v][1], (double)g0[v][2]);
        }
    }
}

/* What remains is refused, never NaN or an empty mesh: coordinates over
 * JM_MAX_CUBES_FROM_ORIGIN cube edges from the origin, a mesh beyond the
 * float range, a subnormal radius. Just inside the bound meshes. */
static void test_domain(void **state)
{
    (void)state;
    jm_mesh m;
    jm_stats st;
    for (size_t v = 0; v < 4; v++) {
        const float r = 0.025f, h = 0.5f * r;
        const float edge = (float)JM_MAX_CUBES_FROM_ORIGIN * h;
        float xyz[6] = {edge - 4 * r, 1, 1, edge - 2.5f * r, 1, 1};
        jm_context *ctx = NULL;
        assert_int_equal(mesh_at(&variants[v], r, 0.0f, xyz, 2, &m, &ctx), JM_OK);
        assert_true(m.triangle_count > 0);
        size_t est = 0;
        jm_particles in = {xyz, 2, 0, NULL};
        assert_int_equal(jm_estimate_bytes(ctx, &in, &est), JM_OK);
        xyz[3] = edge * 1.001f;
        assert_int_equal(jm_mesh_particles(ctx, &in, &m, &st), JM_E_NUMERIC_DOMAIN);
        assert_int_equal(m.vertex_count, 0);
        assert_int_equal(jm_estimate_bytes(ctx, &in, &est), JM_E_NUMERIC_DOMAIN);
        assert_non_null(strstr(jm_status_message(JM_E_NUMERIC_DOMAIN), "numeric domain"));
        jm_context_free(ctx);
        /* a radius so large that the mesh around particles at the origin
         * would pass FLT_MAX */
        float zero[3] = {0, 0, 0};
        jm_particles one = {zero, 1, 0, NULL};
        assert_int_equal(mesh_at(&variants[v], 1e37f, 0.0f, zero, 1, &m, &ctx), JM_E_NUMERIC_DOMAIN);
        assert_int_equal(jm_estimate_bytes(ctx, &one, &est), JM_E_NUMERIC_DOMAIN);
        jm_context_free(ctx);
    }
    /* a subnormal radius is a parameter out of range */
    jm_params p = {0};
    p.radius = FLT_MIN / 4;
    jm_param_problem pr;
    jm_context *ctx = NULL;
    assert_int_equal(jm_params_check(&p, &pr), JM_E_INVALID_ARGUMENT);
    assert_string_equal(pr.field, "radius");
    assert_true(pr.min == (double)FLT_MIN);
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    assert_null(ctx);
    p.radius = FLT_MIN;
    assert_int_equal(jm_params_check(&p, NULL), JM_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_power_of_two_scales),
        cmocka_unit_test(test_decimal_radii),
        cmocka_unit_test(test_attributes_scale),
        cmocka_unit_test(test_eval_scale),
        cmocka_unit_test(test_domain),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
