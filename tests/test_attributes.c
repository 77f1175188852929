/* test_attributes.c - jm_interpolate_attributes against a brute-force reference, constants, the nearest-particle fallback, real velocities. */
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
#include "util/ref_interpolate.h"
#include "util/shared_data.h"

#define R 0.025f

static float frand(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (float)(*s >> 8) / 16777216.0f;
}

/* random particles in a 10r box, a random 3-vector and scalar each */
static void cloud(size_t n, float **xyz, float **vel, float **rho)
{
    unsigned s = 11;
    *xyz = malloc(n * 12);
    *vel = malloc(n * 12);
    *rho = malloc(n * 4);
    for (size_t i = 0; i < 3 * n; i++) {
        (*xyz)[i] = 10 * R * frand(&s);
        (*vel)[i] = 2 * frand(&s) - 1;
    }
    for (size_t i = 0; i < n; i++) (*rho)[i] = 1000 + 10 * frand(&s);
}

static void test_reference(void **state)
{
    (void)state;
    const size_t n = 400, nv = 300;
    float *xyz, *vel, *rho, pos[3 * 300];
    unsigned s = 5;
    cloud(n, &xyz, &vel, &rho);
    for (size_t i = 0; i < 3 * nv; i++) pos[i] = -2 * R + 14 * R * frand(&s); /* some out of reach */
    float *vv = malloc(nv * 12), *vr = malloc(nv * 4);
    jm_params p = {0};
    p.radius = R;
    jm_particles in = {xyz, n, 0, NULL};
    jm_attribute at[2] = {{3, vel, vv}, {1, rho, vr}};
    assert_int_equal(jm_interpolate_attributes(&p, &in, pos, nv, at, 2), JM_OK);
    const double h = 2 * R;
    size_t fallback = 0;
    for (size_t v = 0; v < nv; v++) {
        ref_interp r;
        ref_interpolate(pos + 3 * v, xyz, vel, rho, n, h, &r);
        const double sw = r.sw, *a = r.a;
        const size_t best = r.nearest;
        if (sw > 0) {
            for (int k = 0; k < 3; k++) assert_true(fabs(vv[3 * v + k] - a[k] / sw) < 1e-4);
            assert_true(fabs(vr[v] - a[3] / sw) < 1e-2);
        } else {
            fallback++;
            for (int k = 0; k < 3; k++) assert_true(vv[3 * v + k] == vel[3 * best + k]);
            assert_true(vr[v] == rho[best]);
        }
    }
    assert_true(fallback > 0 && fallback < nv); /* both paths were taken */

    /* the same bits again, and with another thread count in params */
    float *v2 = malloc(nv * 12), *r2 = malloc(nv * 4);
    jm_attribute at2[2] = {{3, vel, v2}, {1, rho, r2}};
    p.threads = 7;
    assert_int_equal(jm_interpolate_attributes(&p, &in, pos, nv, at2, 2), JM_OK);
    assert_memory_equal(vv, v2, nv * 12);
    assert_memory_equal(vr, r2, nv * 4);
    free(v2); free(r2); free(vv); free(vr); free(xyz); free(vel); free(rho);
}

static void test_constant_and_errors(void **state)
{
    (void)state;
    const size_t n = 200;
    float *xyz, *vel, *rho;
    cloud(n, &xyz, &vel, &rho);
    for (size_t i = 0; i < n; i++) rho[i] = 998.0f;
    jm_params p = {0};
    p.radius = R;
    jm_context *ctx;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {xyz, n, 0, NULL};
    jm_mesh m;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
    assert_true(m.vertex_count > 100);
    float *out = malloc(m.vertex_count * 4);
    jm_attribute a = {1, rho, out};
    assert_int_equal(jm_interpolate_attributes(&p, &in, m.positions, m.vertex_count, &a, 1), JM_OK);
    for (size_t v = 0; v < m.vertex_count; v++) assert_true(fabsf(out[v] - 998.0f) < 1e-3f);
    /* errors */
    jm_attribute bad = {0, rho, out};
    assert_int_equal(jm_interpolate_attributes(&p, &in, m.positions, m.vertex_count, &bad, 1), JM_E_INVALID_ARGUMENT);
    jm_params z = {0};
    assert_int_equal(jm_interpolate_attributes(&z, &in, m.positions, m.vertex_count, &a, 1), JM_E_INVALID_ARGUMENT);
    xyz[4] = NAN;
    assert_int_equal(jm_interpolate_attributes(&p, &in, m.positions, m.vertex_count, &a, 1), JM_E_INVALID_PARTICLE);
    /* no particles: zeros */
    jm_particles none = {xyz, 0, 0, NULL};
    assert_int_equal(jm_interpolate_attributes(&p, &none, m.positions, 1, &a, 1), JM_OK);
    assert_true(out[0] == 0.0f);
    free(out);
    jm_context_free(ctx);
    free(xyz); free(vel); free(rho);
}

/* a real frame's velocities on its SPH mesh: every vertex gets a value
 * within the particles' range, per component */
static void test_real_velocity(void **state)
{
    (void)state;
    jmf_read_options o = {0};
    o.attributes = "velocity";
    jmf_frame f;
    char err[512];
    if (test_read_shared("splashsurf/ParticleData_Fluid_5.vtk", &o, &f, err, sizeof err) != 1) {
        fprintf(stderr, "skipping: %s\n", err);
        skip();
    }
    assert_int_equal(f.attribute_count, 1);
    assert_int_equal(f.attributes[0].components, 3);
    jm_params p = {0};
    p.radius = R;
    p.field = JM_FIELD_SPH;
    p.method = JM_METHOD_MC;
    jm_context *ctx;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {f.xyz, f.count, 0, f.ids};
    jm_mesh m;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, NULL), JM_OK);
    float *out = malloc(m.vertex_count * 12);
    jm_attribute a = {3, f.attributes[0].values, out};
    assert_int_equal(jm_interpolate_attributes(&p, &in, m.positions, m.vertex_count, &a, 1), JM_OK);
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < f.count; i++)
        for (int k = 0; k < 3; k++) {
            float x = f.attributes[0].values[3 * i + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    for (size_t v = 0; v < m.vertex_count; v++)
        for (int k = 0; k < 3; k++) assert_true(out[3 * v + k] >= lo[k] - 1e-5f && out[3 * v + k] <= hi[k] + 1e-5f);
    free(out);
    jm_context_free(ctx);
    jmf_frame_free(&f);
}

/* the readers: named arrays from text and binary formats, grouping, the errors */
static const jmf_attribute *find(const jmf_frame *f, const char *name)
{
    for (size_t i = 0; i < f->attribute_count; i++)
        if (strcmp(f->attributes[i].name, name) == 0) return &f->attributes[i];
    return NULL;
}

static void read_mem(const char *text, size_t n, const char *name, const char *want, int drop, jmf_frame *f,
                     jmf_status expect, char *err)
{
    jmf_read_options o = {0};
    o.attributes = want;
    o.drop_invalid = drop;
    jmf_status st = jmf_read_particles_mem(text, n, name, &o, f, err, 512);
    if (st != expect) fprintf(stderr, "%s: %s\n", name, err);
    assert_int_equal(st, expect);
}

static void test_readers(void **state)
{
    (void)state;
    jmf_frame f;
    char err[512];
    const jmf_attribute *a;
    /* CSV: vx vy vz -> velocity, NAME_x/_y/_z -> NAME, others scalars; NaN dropped with its tuple */
    const char *csv = "x,y,z,vx,vy,vz,omega_x,omega_y,omega_z,density,id\n"
                      "0,0,0,1,2,3,4,5,6,1000,7\n"
                      "1,0,0,nan,0,0,0,0,0,1001,8\n"
                      "2,0,0,7,8,9,1,1,1,1002,9\n";
    read_mem(csv, strlen(csv), "a.csv", "all", 0, &f, JMF_E_FORMAT, err);
    assert_non_null(strstr(err, "a.csv: attribute 'velocity' of particle 1 is NaN"));
    read_mem(csv, strlen(csv), "a.csv", "all", 1, &f, JMF_OK, err);
    assert_int_equal(f.count, 2);
    assert_int_equal(f.dropped, 1);
    assert_int_equal(f.attribute_count, 3);
    a = find(&f, "velocity");
    assert_non_null(a);
    assert_int_equal(a->components, 3);
    assert_true(a->values[3] == 7 && a->values[4] == 8 && a->values[5] == 9); /* particle 2 moved to 1 */
    a = find(&f, "omega");
    assert_true(a && a->components == 3 && a->values[2] == 6);
    a = find(&f, "density");
    assert_true(a && a->components == 1 && a->values[1] == 1002);
    assert_non_null(f.ids);
    jmf_frame_free(&f);
    /* nothing asked for: no attributes, no names */
    read_mem(csv, strlen(csv), "a.csv", NULL, 1, &f, JMF_OK, err);
    assert_int_equal(f.attribute_count, 0);
    assert_null(f.array_names);
    jmf_frame_free(&f);
    /* a name the file lacks: the error lists what it has */
    read_mem(csv, strlen(csv), "a.csv", "velocity,pressure", 1, &f, JMF_E_FORMAT, err);
    assert_non_null(strstr(err, "no per-particle attribute 'pressure' in this file (it has: velocity, omega, density)"));

    /* PLY, binary little-endian, velocity_x/_y/_z + a double density */
    const char *head = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
                       "property float y\nproperty float z\nproperty float velocity_x\nproperty float velocity_y\n"
                       "property float velocity_z\nproperty double density\nend_header\n";
    unsigned char ply[512];
    size_t n = strlen(head);
    memcpy(ply, head, n);
    for (int i = 0; i < 2; i++) {
        float v[6] = {(float)i, 0, 0, 1.5f + i, -2, 3};
        double d = 990 + i;
        memcpy(ply + n, v, 24);
        memcpy(ply + n + 24, &d, 8);
        n += 32;
    }
    read_mem((const char *)ply, n, "b.ply", "velocity,density", 0, &f, JMF_OK, err);
    a = find(&f, "velocity");
    assert_true(a && a->components == 3 && a->values[3] == 2.5f && a->values[4] == -2);
    a = find(&f, "density");
    assert_true(a && a->values[1] == 991);
    jmf_frame_free(&f);

    /* legacy VTK ASCII: VECTORS and SCALARS in POINT_DATA; a short FIELD array */
    const char *vtk = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0 1 0 0\n"
                      "POINT_DATA 2\nVECTORS velocity float\n1 2 3 4 5 6\nSCALARS density float 1\n"
                      "LOOKUP_TABLE default\n7 8\nFIELD FieldData 1\npressure 1 1 float\n9\n";
    read_mem(vtk, strlen(vtk), "c.vtk", "velocity,density", 0, &f, JMF_OK, err);
    a = find(&f, "velocity");
    assert_true(a && a->values[5] == 6);
    a = find(&f, "density");
    assert_true(a && a->values[1] == 8);
    jmf_frame_free(&f);
    read_mem(vtk, strlen(vtk), "c.vtk", "pressure", 0, &f, JMF_E_FORMAT, err);
    assert_non_null(strstr(err, "c.vtk: attribute 'pressure' has 1 values for 2 particles"));
    /* with all, the short array is an error too: the file is inconsistent */
    read_mem(vtk, strlen(vtk), "c.vtk", "all", 0, &f, JMF_E_FORMAT, err);

    /* VTU with two pieces: the array concatenated */
    const char *vtu = "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">"
                      "<UnstructuredGrid><Piece NumberOfPoints=\"1\" NumberOfCells=\"0\"><PointData>"
                      "<DataArray type=\"Float32\" Name=\"speed\" format=\"ascii\">5</DataArray></PointData>"
                      "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0"
                      "</DataArray></Points></Piece><Piece NumberOfPoints=\"1\" NumberOfCells=\"0\"><PointData>"
                      "<DataArray type=\"Float64\" Name=\"speed\" format=\"ascii\">6</DataArray></PointData>"
                      "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">1 0 0"
                      "</DataArray></Points></Piece></UnstructuredGrid></VTKFile>\n";
    read_mem(vtu, strlen(vtu), "d.vtu", "speed", 0, &f, JMF_OK, err);
    a = find(&f, "speed");
    assert_true(a && f.count == 2 && a->values[0] == 5 && a->values[1] == 6);
    jmf_frame_free(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference),
        cmocka_unit_test(test_constant_and_errors),
        cmocka_unit_test(test_real_velocity),
        cmocka_unit_test(test_readers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
