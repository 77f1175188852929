/* test_writers.c - cmocka tests for the mesh writers (OBJ, PLY, VTK, glTF/GLB, Draco) and atomic output files. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../formats/atomic_file.h"
#include "../formats/write/write_formats.h"
#include "../formats/writer.h"
#include "util/files.h"
#include "util/test_meshes.h"

static char g_dir[256];

/* ---- helpers ------------------------------------------------------------ */

static const char *in_dir(const char *name)
{
    static char bufs[4][1024];
    static int next;
    char *p = bufs[next++ & 3];
    snprintf(p, 1024, "%s/%s", g_dir, name);
    return p;
}

static void spit(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    assert_int_equal(fclose(f), 0);
}

static int file_equals(const char *path, const char *text)
{
    size_t n;
    unsigned char *d = test_read_file(path, &n);
    int eq = d && n == strlen(text) && memcmp(d, text, n) == 0;
    free(d);
    return eq;
}

static off_t file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? st.st_size : -1;
}

/* Number of "*.jetmesh-tmp-*" files in the test directory. */
static int temp_files(void)
{
    DIR *d = opendir(g_dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)))
        if (strstr(e->d_name, ".jetmesh-tmp-")) n++;
    if (d) closedir(d);
    return n;
}

static void remove_tree(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0) return;
    if (S_ISDIR(st.st_mode)) {
        DIR *d = opendir(path);
        struct dirent *e;
        while (d && (e = readdir(d))) {
            if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
            char sub[1024];
            snprintf(sub, sizeof sub, "%s/%s", path, e->d_name);
            remove_tree(sub);
        }
        if (d) closedir(d);
        rmdir(path);
    } else {
        unlink(path);
    }
}

static int setup_dir(void **state)
{
    (void)state;
    snprintf(g_dir, sizeof g_dir, "/tmp/jetmesh-test-writers-XXXXXX");
    return mkdtemp(g_dir) ? 0 : -1;
}

static int teardown_dir(void **state)
{
    (void)state;
    remove_tree(g_dir);
    return 0;
}

static void make(const char *name, test_mesh *tm)
{
    assert_int_equal(test_mesh_make(name, tm), 0);
}

static jmf_status write_path(const char *path, const jm_mesh *m, const jmf_write_options *opt,
                             size_t *bytes, char *err)
{
    err[0] = '\0';
    return jmf_write_mesh(path, m, opt, bytes, err, 512);
}

/* ---- float printer and format names -------------------------------------------- */

static void test_format_float_matches_printf(void **state)
{
    (void)state;
    char a[JMF_FLOAT_CHARS], b[64];
    static const float fixed[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.1f, 1e-5f, 1e-4f, 123456.7f,
                                  1234567.0f, 12345678.0f, 9999999.5f, 0.99999997f,
                                  3.4028235e38f, 1.17549435e-38f, 1.4e-45f, 1234567.5f,
                                  1234566.5f, 12345675.0f, 0.5f, 2.5f, -7.25f};
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++) {
        jmf_format_float(a, fixed[i]);
        snprintf(b, sizeof b, "%.7g", fixed[i]);
        assert_string_equal(a, b);
    }
    uint64_t s = 88172645463325252ull;
    for (int i = 0; i < 2000000; i++) {
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        uint32_t bits = (uint32_t)s;
        float f;
        memcpy(&f, &bits, 4);
        if (i & 1) f = (float)((double)(s >> 11) / 9007199254740992.0 * 2000.0 - 1000.0);
        if (isnan(f)) continue;
        size_t n = jmf_format_float(a, f);
        snprintf(b, sizeof b, "%.7g", f);
        if (strcmp(a, b) != 0) fail_msg("%a: got %s, printf says %s", f, a, b);
        assert_int_equal(n, strlen(b));
    }
}

static void test_format_names(void **state)
{
    (void)state;
    int d = -1;
    jmf_write_options o;
    memset(&o, 0, sizeof o);
    assert_int_equal(jmf_output_format_for("a/b.obj", NULL, &d), JMF_OUT_OBJ);
    assert_int_equal(d, 0);
    assert_int_equal(jmf_output_format_for("x.GLB", NULL, &d), JMF_OUT_GLB);
    assert_int_equal(jmf_output_format_for("x.gltf", NULL, &d), JMF_OUT_GLTF);
    assert_int_equal(d, 0);
    assert_int_equal(jmf_output_format_for("x.draco.glb", NULL, &d), JMF_OUT_GLB);
    assert_int_equal(d, 1);
    assert_int_equal(jmf_output_format_for("x.draco.gltf", NULL, &d), JMF_OUT_GLTF);
    assert_int_equal(d, 1);
    assert_int_equal(jmf_output_format_for("x.drc", NULL, &d), JMF_OUT_DRC);
    assert_int_equal(d, 0); /* Draco by itself, not the glTF extension */
    o.draco = 1;
    assert_int_equal(jmf_output_format_for("x.obj", &o, &d), JMF_OUT_OBJ);
    assert_int_equal(d, 0);
    o.draco = 0;
    assert_int_equal(jmf_output_format_for("x.ply", NULL, &d), JMF_OUT_PLY);
    assert_int_equal(jmf_output_format_for("x.vtk", NULL, &d), JMF_OUT_VTK);
    assert_int_equal(jmf_output_format_for("x.txt", NULL, &d), -1);
    assert_int_equal(jmf_output_format_for("dir.obj/x", NULL, &d), -1);
    assert_int_equal(jmf_output_format_for("noext", NULL, &d), -1);
    o.format = JMF_OUT_PLY;
    assert_int_equal(jmf_output_format_for("x.obj", &o, &d), JMF_OUT_PLY);
    o.format = JMF_OUT_GLB;
    o.draco = 1;
    assert_int_equal(jmf_output_format_for("frame", &o, &d), JMF_OUT_GLB);
    assert_int_equal(d, 1);
    for (int f = JMF_OUT_OBJ; f <= JMF_OUT_VTK; f++)
        assert_int_equal(jmf_output_format_parse(jmf_output_format_name((jmf_output_format)f)), f);
    assert_int_equal(jmf_output_format_parse("GLTF"), JMF_OUT_GLTF);
    assert_int_equal(jmf_output_format_parse("stl"), -1);
    assert_int_equal(jmf_output_format_parse(NULL), -1);
    assert_string_equal(jmf_output_format_name(JMF_OUT_DRC), "drc");
}

/* ---- the test meshes themselves ------------------------------------------- */

/* Closed and consistently oriented: every directed edge once, and its reverse once. */
static void assert_closed_oriented(const jm_mesh *m)
{
    size_t ne = 3 * m->triangle_count;
    uint64_t *e = malloc(ne * sizeof *e);
    assert_non_null(e);
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            uint64_t a = m->indices[3 * t + (size_t)k], b = m->indices[3 * t + (size_t)(k + 1) % 3];
            e[3 * t + (size_t)k] = a << 32 | b;
        }
    for (size_t i = 0; i < ne; i++) {
        uint64_t rev = (e[i] << 32) | (e[i] >> 32);
        int fwd = 0, back = 0;
        for (size_t j = 0; j < ne && ne <= 20000; j++) {
            fwd += e[j] == e[i];
            back += e[j] == rev;
        }
        if (ne <= 20000) {
            assert_int_equal(fwd, 1);
            assert_int_equal(back, 1);
        }
    }
    free(e);
}

static void test_meshes_are_closed(void **state)
{
    (void)state;
    const char *names[] = {"octahedron", "icosphere", "icosphere:3", "torus:12x8"};
    for (size_t i = 0; i < 4; i++) {
        test_mesh tm;
        make(names[i], &tm);
        assert_closed_oriented(&tm.mesh);
        /* Outward: the face normal points away from the centre of the mesh. */
        float c[3];
        for (int k = 0; k < 3; k++) c[k] = 0.5f * (tm.mesh.bounds_min[k] + tm.mesh.bounds_max[k]);
        for (size_t t = 0; t < tm.mesh.triangle_count && i < 3; t++) {
            const float *p0 = tm.positions + 3 * tm.indices[3 * t];
            const float *p1 = tm.positions + 3 * tm.indices[3 * t + 1];
            const float *p2 = tm.positions + 3 * tm.indices[3 * t + 2];
            float u[3], v[3], n[3];
            for (int k = 0; k < 3; k++) u[k] = p1[k] - p0[k], v[k] = p2[k] - p0[k];
            n[0] = u[1] * v[2] - u[2] * v[1];
            n[1] = u[2] * v[0] - u[0] * v[2];
            n[2] = u[0] * v[1] - u[1] * v[0];
            assert_true(n[0] * (p0[0] - c[0]) + n[1] * (p0[1] - c[1]) + n[2] * (p0[2] - c[2]) > 0);
        }
        for (size_t v = 0; v < tm.mesh.vertex_count; v++) {
            const float *n = tm.normals + 3 * v;
            assert_true(fabsf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1) < 1e-5f);
        }
        test_mesh_free(&tm);
    }
    test_mesh tm;
    make("grid", &tm);
    assert_int_equal(tm.mesh.vertex_count, 70000);
    assert_int_equal(tm.mesh.triangle_count, 140000);
    test_mesh_free(&tm);
}

/* ---- read-back parsers ---------------------------------------------------------- */

typedef struct readback {
    size_t nv, nvt, nvn, nt;
    float *v, *vt, *vn;
    uint32_t *f;
} readback;

static void readback_free(readback *r)
{
    free(r->v), free(r->vt), free(r->vn), free(r->f);
    memset(r, 0, sizeof *r);
}

/* OBJ with "f a/a/a" faces (the same index three times, checked). */
static void read_obj(const char *path, readback *r, size_t cap_v, size_t cap_t)
{
    memset(r, 0, sizeof *r);
    r->v = malloc(3 * cap_v * sizeof(float) + 4);
    r->vt = malloc(2 * cap_v * sizeof(float) + 4);
    r->vn = malloc(3 * cap_v * sizeof(float) + 4);
    r->f = malloc(3 * cap_t * sizeof(uint32_t) + 4);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char line[512];
    while (fgets(line, sizeof line, f)) {
        if (!strncmp(line, "v ", 2)) {
            assert_true(r->nv < cap_v);
            float *p = r->v + 3 * r->nv++;
            assert_int_equal(sscanf(line + 2, "%f %f %f", &p[0], &p[1], &p[2]), 3);
        } else if (!strncmp(line, "vt ", 3)) {
            assert_true(r->nvt < cap_v);
            float *p = r->vt + 2 * r->nvt++;
            assert_int_equal(sscanf(line + 3, "%f %f", &p[0], &p[1]), 2);
        } else if (!strncmp(line, "vn ", 3)) {
            assert_true(r->nvn < cap_v);
            float *p = r->vn + 3 * r->nvn++;
            assert_int_equal(sscanf(line + 3, "%f %f %f", &p[0], &p[1], &p[2]), 3);
        } else if (!strncmp(line, "f ", 2)) {
            assert_true(r->nt < cap_t);
            unsigned a[9];
            assert_int_equal(sscanf(line + 2, "%u/%u/%u %u/%u/%u %u/%u/%u", &a[0], &a[1], &a[2],
                                    &a[3], &a[4], &a[5], &a[6], &a[7], &a[8]), 9);
            for (int k = 0; k < 3; k++) {
                assert_int_equal(a[3 * k], a[3 * k + 1]);
                assert_int_equal(a[3 * k], a[3 * k + 2]);
                assert_true(a[3 * k] >= 1);
                r->f[3 * r->nt + (size_t)k] = a[3 * k] - 1;
            }
            r->nt++;
        } else {
            assert_int_equal(line[0], '#');
        }
    }
    fclose(f);
}

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint32_t be32(const unsigned char *p)
{
    return (uint32_t)p[3] | (uint32_t)p[2] << 8 | (uint32_t)p[1] << 16 | (uint32_t)p[0] << 24;
}

static float as_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* Our binary PLY: x y z nx ny nz s t floats, then faces "3 a b c". */
static void read_ply(const char *path, readback *r)
{
    memset(r, 0, sizeof *r);
    size_t n;
    unsigned char *d = test_read_file(path, &n);
    assert_non_null(d);
    const char *end = strstr((const char *)d, "end_header\n");
    assert_non_null(end);
    assert_non_null(strstr((const char *)d, "format binary_little_endian 1.0\n"));
    assert_non_null(strstr((const char *)d, "property list uchar uint vertex_indices\n"));
    const char *ev = strstr((const char *)d, "element vertex ");
    const char *ef = strstr((const char *)d, "element face ");
    assert_non_null(ev);
    assert_non_null(ef);
    r->nv = r->nvt = r->nvn = strtoul(ev + 15, NULL, 10);
    r->nt = strtoul(ef + 13, NULL, 10);
    const unsigned char *p = (const unsigned char *)end + 11;
    assert_int_equal(n - (size_t)(p - d), 32 * r->nv + 13 * r->nt);
    r->v = malloc(12 * r->nv + 4);
    r->vn = malloc(12 * r->nv + 4);
    r->vt = malloc(8 * r->nv + 4);
    r->f = malloc(12 * r->nt + 4);
    for (size_t i = 0; i < r->nv; i++, p += 32) {
        for (int k = 0; k < 3; k++) r->v[3 * i + (size_t)k] = as_float(le32(p + 4 * k));
        for (int k = 0; k < 3; k++) r->vn[3 * i + (size_t)k] = as_float(le32(p + 12 + 4 * k));
        for (int k = 0; k < 2; k++) r->vt[2 * i + (size_t)k] = as_float(le32(p + 24 + 4 * k));
    }
    for (size_t t = 0; t < r->nt; t++, p += 13) {
        assert_int_equal(p[0], 3);
        for (int k = 0; k < 3; k++) r->f[3 * t + (size_t)k] = le32(p + 1 + 4 * k);
    }
    free(d);
}

/* Our legacy VTK: POINTS, POLYGONS, POINT_DATA NORMALS, TEXTURE_COORDINATES. */
static void read_vtk(const char *path, readback *r)
{
    memset(r, 0, sizeof *r);
    size_t n;
    unsigned char *d = test_read_file(path, &n);
    assert_non_null(d);
    const char *s = (const char *)d;
    assert_int_equal(strncmp(s, "# vtk DataFile Version 3.0\n", 27), 0);
    const char *pt = strstr(s, "\nBINARY\nDATASET POLYDATA\nPOINTS ");
    assert_non_null(pt);
    char *q;
    r->nv = r->nvn = r->nvt = strtoul(pt + 32, &q, 10);
    assert_int_equal(strncmp(q, " float\n", 7), 0);
    const unsigned char *p = (const unsigned char *)q + 7;
    r->v = malloc(12 * r->nv + 4);
    for (size_t i = 0; i < 3 * r->nv; i++, p += 4) r->v[i] = as_float(be32(p));
    assert_int_equal(strncmp((const char *)p, "\nPOLYGONS ", 10), 0);
    r->nt = strtoul((const char *)p + 10, &q, 10);
    assert_int_equal(strtoul(q, &q, 10), 4 * r->nt);
    assert_int_equal(*q, '\n');
    p = (const unsigned char *)q + 1;
    r->f = malloc(12 * r->nt + 4);
    for (size_t t = 0; t < r->nt; t++, p += 16) {
        assert_int_equal(be32(p), 3);
        for (int k = 0; k < 3; k++) r->f[3 * t + (size_t)k] = be32(p + 4 + 4 * k);
    }
    assert_int_equal(*p++, '\n');
    if (r->nv) {
        char head[64];
        snprintf(head, sizeof head, "POINT_DATA %zu\nNORMALS Normals float\n", r->nv);
        assert_int_equal(strncmp((const char *)p, head, strlen(head)), 0);
        p += strlen(head);
        r->vn = malloc(12 * r->nv + 4);
        for (size_t i = 0; i < 3 * r->nv; i++, p += 4) r->vn[i] = as_float(be32(p));
        const char *tc = "\nTEXTURE_COORDINATES TCoords 2 float\n";
        assert_int_equal(strncmp((const char *)p, tc, strlen(tc)), 0);
        p += strlen(tc);
        r->vt = malloc(8 * r->nv + 4);
        for (size_t i = 0; i < 2 * r->nv; i++, p += 4) r->vt[i] = as_float(be32(p));
        assert_int_equal(*p++, '\n');
    }
    assert_int_equal((size_t)(p - d), n);
    free(d);
}

/* tol 0: bit-exact; else relative to the magnitude (OBJ's 7 digits). */
static void assert_floats(const float *got, const float *want, size_t n, float tol)
{
    for (size_t i = 0; i < n; i++) {
        float e = fabsf(got[i] - want[i]);
        float lim = tol * fmaxf(1.0f, fabsf(want[i]));
        if (tol == 0 ? memcmp(&got[i], &want[i], 4) != 0 : e > lim)
            fail_msg("value %zu: got %.9g, want %.9g", i, got[i], want[i]);
    }
}

static void assert_readback(const readback *r, const jm_mesh *m, float tol)
{
    assert_int_equal(r->nv, m->vertex_count);
    assert_int_equal(r->nvt, m->vertex_count);
    assert_int_equal(r->nvn, m->vertex_count);
    assert_int_equal(r->nt, m->triangle_count);
    assert_floats(r->v, m->positions, 3 * r->nv, tol);
    if (r->nv) {
        assert_floats(r->vn, m->normals, 3 * r->nv, tol);
        assert_floats(r->vt, m->uvs, 2 * r->nv, tol);
    }
    if (r->nt) assert_memory_equal(r->f, m->indices, 12 * r->nt);
}

/* ---- OBJ, PLY, VTK round trips ------------------------------------------------------------- */

static const char *const k_meshes[] = {"octahedron", "icosphere:3", "grid", "empty"};

static void test_obj_roundtrip(void **state)
{
    (void)state;
    char err[512];
    for (size_t i = 0; i < 4; i++) {
        test_mesh tm;
        make(k_meshes[i], &tm);
        size_t bytes = 0;
        const char *path = in_dir("m.obj");
        assert_int_equal(write_path(path, &tm.mesh, NULL, &bytes, err), JMF_OK);
        assert_int_equal(bytes, (size_t)file_size(path));
        readback r;
        read_obj(path, &r, tm.mesh.vertex_count, tm.mesh.triangle_count);
        assert_readback(&r, &tm.mesh, 6e-7f); /* 7 significant digits */
        readback_free(&r);
        test_mesh_free(&tm);
    }
    assert_int_equal(temp_files(), 0);
}

static void test_obj_without_attributes(void **state)
{
    (void)state;
    char err[512];
    test_mesh tm;
    make("octahedron", &tm);
    tm.mesh.uvs = NULL;
    assert_int_equal(write_path(in_dir("n.obj"), &tm.mesh, NULL, NULL, err), JMF_OK);
    tm.mesh.normals = NULL;
    assert_int_equal(write_path(in_dir("p.obj"), &tm.mesh, NULL, NULL, err), JMF_OK);
    size_t n;
    char *a = (char *)test_read_file(in_dir("n.obj"), &n), *b = (char *)test_read_file(in_dir("p.obj"), &n);
    assert_non_null(strstr(a, "\nf 1//1 3//3 5//5\n"));
    assert_null(strstr(a, "\nvt "));
    assert_non_null(strstr(b, "\nf 1 3 5\n"));
    assert_null(strstr(b, "\nvn "));
    free(a), free(b);
    test_mesh_free(&tm);
}

static void test_ply_roundtrip(void **state)
{
    (void)state;
    char err[512];
    for (size_t i = 0; i < 4; i++) {
        test_mesh tm;
        make(k_meshes[i], &tm);
        size_t bytes = 0;
        const char *path = in_dir("m.ply");
        assert_int_equal(write_path(path, &tm.mesh, NULL, &bytes, err), JMF_OK);
        assert_int_equal(bytes, (size_t)file_size(path));
        readback r;
        read_ply(path, &r);
        assert_readback(&r, &tm.mesh, 0);
        readback_free(&r);
        test_mesh_free(&tm);
    }
}

static void test_vtk_roundtrip(void **state)
{
    (void)state;
    char err[512];
    for (size_t i = 0; i < 4; i++) {
        test_mesh tm;
        make(k_meshes[i], &tm);
        size_t bytes = 0;
        const char *path = in_dir("m.vtk");
        assert_int_equal(write_path(path, &tm.mesh, NULL, &bytes, err), JMF_OK);
        assert_int_equal(bytes, (size_t)file_size(path));
        readback r;
        read_vtk(path, &r);
        assert_int_equal(r.nv, tm.mesh.vertex_count);
        assert_int_equal(r.nt, tm.mesh.triangle_count);
        assert_floats(r.v, tm.mesh.positions, 3 * r.nv, 0);
        if (r.nt) assert_memory_equal(r.f, tm.mesh.indices, 12 * r.nt);
        if (r.nv) {
            assert_floats(r.vn, tm.mesh.normals, 3 * r.nv, 0);
            assert_floats(r.vt, tm.mesh.uvs, 2 * r.nv, 0);
        }
        readback_free(&r);
        test_mesh_free(&tm);
    }
}

/* ---- glTF, GLB, Draco -------------------------------------------------------------------- */

/* Splits a GLB into its JSON text (NUL-terminated copy) and BIN chunk. */
static char *glb_split(const unsigned char *d, size_t n, const unsigned char **bin, size_t *binlen)
{
    assert_true(n >= 20);
    assert_memory_equal(d, "glTF", 4);
    assert_int_equal(le32(d + 4), 2);
    assert_int_equal(le32(d + 8), n);
    size_t jl = le32(d + 12);
    assert_int_equal(le32(d + 16), 0x4E4F534A);
    assert_int_equal(jl % 4, 0);
    char *json = malloc(jl + 1);
    memcpy(json, d + 20, jl);
    json[jl] = 0;
    *bin = NULL;
    *binlen = 0;
    if (20 + jl < n) {
        const unsigned char *c = d + 20 + jl;
        assert_int_equal(le32(c + 4), 0x004E4942);
        *binlen = le32(c);
        *bin = c + 8;
        assert_int_equal(20 + jl + 8 + *binlen, n);
    }
    return json;
}

static void test_glb_layout(void **state)
{
    (void)state;
    char err[512];
    test_mesh tm;
    make("grid", &tm);
    jmf_write_options o;
    memset(&o, 0, sizeof o);
    size_t bytes = 0, n, binlen;
    const char *path = in_dir("g.glb");
    assert_int_equal(write_path(path, &tm.mesh, &o, &bytes, err), JMF_OK);
    unsigned char *d = test_read_file(path, &n);
    assert_int_equal(bytes, n);
    const unsigned char *bin;
    char *json = glb_split(d, n, &bin, &binlen);
    assert_non_null(strstr(json, "\"version\":\"2.0\""));
    assert_non_null(strstr(json, "\"generator\":\"jetmesh " JM_VERSION_STRING "\""));
    assert_non_null(strstr(json, "\"componentType\":5125")); /* 70000 vertices: uint32 */
    assert_null(strstr(json, "KHR_draco"));
    /* positions, normals, uvs, then indices, tightly packed */
    const size_t nv = tm.mesh.vertex_count, nt = tm.mesh.triangle_count;
    assert_int_equal(binlen, 32 * nv + 12 * nt);
    assert_memory_equal(bin, tm.positions, 12 * nv);
    assert_memory_equal(bin + 12 * nv, tm.normals, 12 * nv);
    assert_memory_equal(bin + 24 * nv, tm.uvs, 8 * nv);
    assert_memory_equal(bin + 32 * nv, tm.indices, 12 * nt);
    free(json);
    free(d);

    /* z-up: (x, y, z) -> (x, z, -y) */
    o.z_up = 1;
    assert_int_equal(write_path(path, &tm.mesh, &o, &bytes, err), JMF_OK);
    d = test_read_file(path, &n);
    json = glb_split(d, n, &bin, &binlen);
    for (size_t i = 0; i < nv; i += 997) {
        float p[3], q[3];
        memcpy(p, bin + 12 * i, 12);
        memcpy(q, bin + 12 * nv + 12 * i, 12);
        assert_true(p[0] == tm.positions[3 * i] && p[1] == tm.positions[3 * i + 2] &&
                    p[2] == -tm.positions[3 * i + 1]);
        assert_true(q[0] == tm.normals[3 * i] && q[1] == tm.normals[3 * i + 2] &&
                    q[2] == -tm.normals[3 * i + 1]);
    }
    free(json);
    free(d);
    test_mesh_free(&tm);
}

static void test_gltf_index_width(void **state)
{
    (void)state;
    char err[512];
    const char *names[] = {"torus:255x257", "torus:256x256"}; /* 65535 and 65536 vertices */
    const char *want[] = {"\"componentType\":5123", "\"componentType\":5125"};
    for (int i = 0; i < 2; i++) {
        test_mesh tm;
        make(names[i], &tm);
        size_t n, binlen;
        const unsigned char *bin;
        assert_int_equal(write_path(in_dir("w.glb"), &tm.mesh, NULL, NULL, err), JMF_OK);
        unsigned char *d = test_read_file(in_dir("w.glb"), &n);
        char *json = glb_split(d, n, &bin, &binlen);
        /* the indices accessor is the last one */
        const char *last = strstr(json, "\"type\":\"SCALAR\"");
        assert_non_null(last);
        const char *ct = strstr(json, want[i]);
        assert_non_null(ct);
        assert_true(ct < last);
        free(json);
        free(d);
        test_mesh_free(&tm);
    }
}

static void test_gltf_separate_and_embedded(void **state)
{
    (void)state;
    char err[512];
    test_mesh tm;
    make("octahedron", &tm);
    size_t bytes = 0, n;
    assert_int_equal(write_path(in_dir("sep.gltf"), &tm.mesh, NULL, &bytes, err), JMF_OK);
    assert_int_equal(bytes, (size_t)(file_size(in_dir("sep.gltf")) + file_size(in_dir("sep.bin"))));
    assert_int_equal(file_size(in_dir("sep.bin")), 6 * 32 + 24 * 2);
    char *json = (char *)test_read_file(in_dir("sep.gltf"), &n);
    assert_non_null(strstr(json, "\"uri\": \"sep.bin\""));
    assert_non_null(strstr(json, "\"byteLength\": 240"));
    free(json);

    /* A name that needs percent-encoding in the URI. */
    assert_int_equal(write_path(in_dir("a b#1.gltf"), &tm.mesh, NULL, NULL, err), JMF_OK);
    json = (char *)test_read_file(in_dir("a b#1.gltf"), &n);
    assert_non_null(strstr(json, "\"uri\": \"a%20b%231.bin\""));
    assert_true(file_size(in_dir("a b#1.bin")) > 0);
    free(json);

    jmf_write_options o;
    memset(&o, 0, sizeof o);
    o.embed = 1;
    assert_int_equal(write_path(in_dir("emb.gltf"), &tm.mesh, &o, &bytes, err), JMF_OK);
    assert_int_equal(file_size(in_dir("emb.bin")), -1);
    json = (char *)test_read_file(in_dir("emb.gltf"), &n);
    assert_int_equal(bytes, n);
    assert_non_null(strstr(json, "data:application/octet-stream;base64,"));
    free(json);

    /* Draco in .gltf + .bin, with the extension declared and required. */
    o.embed = 0;
    assert_int_equal(write_path(in_dir("d.draco.gltf"), &tm.mesh, &o, &bytes, err), JMF_OK);
    json = (char *)test_read_file(in_dir("d.draco.gltf"), &n);
    assert_non_null(strstr(json, "\"extensionsRequired\""));
    assert_non_null(strstr(json, "\"KHR_draco_mesh_compression\": {"));
    assert_non_null(strstr(json, "\"uri\": \"d.draco.bin\""));
    free(json);
    unsigned char *drc = test_read_file(in_dir("d.draco.bin"), &n);
    assert_non_null(drc);
    assert_memory_equal(drc, "DRACO", 5);
    free(drc);
    test_mesh_free(&tm);
}

static void test_empty_mesh(void **state)
{
    (void)state;
    char err[512];
    test_mesh tm;
    make("empty", &tm);
    const char *ok[] = {"e.obj", "e.ply", "e.vtk", "e.gltf", "e.glb", "e.draco.glb"};
    for (size_t i = 0; i < 6; i++) {
        assert_int_equal(write_path(in_dir(ok[i]), &tm.mesh, NULL, NULL, err), JMF_OK);
        assert_true(file_size(in_dir(ok[i])) > 0);
    }
    assert_int_equal(file_size(in_dir("e.bin")), -1); /* nothing to put in it */
    size_t n, binlen;
    const unsigned char *bin;
    unsigned char *d = test_read_file(in_dir("e.glb"), &n);
    char *json = glb_split(d, n, &bin, &binlen);
    assert_null(strstr(json, "\"meshes\""));
    assert_non_null(strstr(json, "\"nodes\""));
    assert_int_equal(binlen, 0);
    free(json);
    free(d);
    assert_int_equal(write_path(in_dir("e.drc"), &tm.mesh, NULL, NULL, err), JMF_E_UNSUPPORTED);
    assert_non_null(strstr(err, "e.drc"));
    assert_non_null(strstr(err, "empty mesh"));
    assert_int_equal(file_size(in_dir("e.drc")), -1);
    test_mesh_free(&tm);
}

static void test_drc(void **state)
{
    (void)state;
    char err[512];
    test_mesh tm;
    make("icosphere:3", &tm);
    size_t bytes = 0, n;
    assert_int_equal(write_path(in_dir("i.drc"), &tm.mesh, NULL, &bytes, err), JMF_OK);
    unsigned char *d = test_read_file(in_dir("i.drc"), &n);
    assert_int_equal(bytes, n);
    assert_memory_equal(d, "DRACO", 5);
    assert_true(n < tm.mesh.vertex_count * 32 / 2); /* it does compress */
    free(d);
    jmf_write_options o;
    memset(&o, 0, sizeof o);
    o.draco_position_bits = 31;
    assert_int_equal(write_path(in_dir("j.drc"), &tm.mesh, &o, NULL, err), JMF_E_UNSUPPORTED);
    assert_non_null(strstr(err, "bits"));
    test_mesh_free(&tm);
}

static void test_bad_requests(void **state)
{
    (void)state;
    char err[512];
    test_mesh tm;
    make("octahedron", &tm);
    jmf_write_options o;
    memset(&o, 0, sizeof o);
    o.draco = 1;
    assert_int_equal(write_path(in_dir("x.obj"), &tm.mesh, &o, NULL, err), JMF_E_UNSUPPORTED);
    assert_non_null(strstr(err, "Draco"));
    assert_int_equal(write_path(in_dir("x.stl"), &tm.mesh, NULL, NULL, err), JMF_E_UNSUPPORTED);
    assert_non_null(strstr(err, "x.stl"));
    tm.indices[5] = 6; /* out of range */
    assert_int_equal(write_path(in_dir("x.ply"), &tm.mesh, NULL, NULL, err), JMF_E_FORMAT);
    assert_non_null(strstr(err, "triangle 1"));
    assert_int_equal(file_size(in_dir("x.ply")), -1);
    assert_int_equal(jmf_write_mesh(in_dir("x.ply"), NULL, NULL, NULL, err, sizeof err), JMF_E_FORMAT);
    test_mesh_free(&tm);
}

static void test_generator_stays_one_line(void **state)
{
    (void)state;
    char err[512], gen[400];
    memset(gen, 'g', sizeof gen - 1);
    gen[sizeof gen - 1] = 0;
    memcpy(gen, "evil\nline\r", 10);
    test_mesh tm;
    make("octahedron", &tm);
    jmf_write_options o;
    memset(&o, 0, sizeof o);
    o.generator = gen;
    assert_int_equal(write_path(in_dir("g.obj"), &tm.mesh, &o, NULL, err), JMF_OK);
    assert_int_equal(write_path(in_dir("g.ply"), &tm.mesh, &o, NULL, err), JMF_OK);
    assert_int_equal(write_path(in_dir("g.vtk"), &tm.mesh, &o, NULL, err), JMF_OK);
    readback r;
    read_obj(in_dir("g.obj"), &r, 6, 8); /* only comments, v, vt, vn, f lines */
    assert_readback(&r, &tm.mesh, 6e-7f);
    readback_free(&r);
    read_ply(in_dir("g.ply"), &r);
    assert_readback(&r, &tm.mesh, 0);
    readback_free(&r);
    read_vtk(in_dir("g.vtk"), &r);
    assert_int_equal(r.nt, 8);
    readback_free(&r);
    size_t n;
    char *d = (char *)test_read_file(in_dir("g.obj"), &n);
    assert_int_equal(strncmp(d, "# evil line ggg", 15), 0);
    free(d);
    test_mesh_free(&tm);
}

/* Many attributes with long names (issue 30: PLY's header was a 1 KiB
 * buffer, "generator name too long"; VTK's lines were cut at 512 bytes):
 * whole headers, every property, the data after them. */
static void test_long_attribute_names(void **state)
{
    (void)state;
    enum { NA = 40, LEN = 600 };
    char err[512];
    test_mesh tm;
    make("octahedron", &tm);
    const size_t nv = tm.mesh.vertex_count, nt = tm.mesh.triangle_count;
    jmf_attribute at[NA];
    char *names[NA];
    float *vals = calloc(nv, sizeof *vals);
    assert_non_null(vals);
    for (int a = 0; a < NA; a++) {
        names[a] = malloc(LEN + 8);
        assert_non_null(names[a]);
        int k = sprintf(names[a], "n%02d_", a);
        memset(names[a] + k, 'a', LEN - (size_t)k);
        names[a][LEN] = '\0';
        at[a] = (jmf_attribute){names[a], 1, vals};
    }
    jmf_write_options o;
    memset(&o, 0, sizeof o);
    o.attributes = at;
    o.attribute_count = NA;
    assert_int_equal(write_path(in_dir("long.ply"), &tm.mesh, &o, NULL, err), JMF_OK);
    assert_int_equal(write_path(in_dir("long.vtk"), &tm.mesh, &o, NULL, err), JMF_OK);
    size_t n;
    char *d = (char *)test_read_file(in_dir("long.ply"), &n);
    assert_non_null(d);
    char *end = strstr(d, "end_header\n");
    assert_non_null(end);
    size_t head = (size_t)(end - d) + 11, props = 0;
    for (char *p = d; p < end && (p = strstr(p, "property float ")) != NULL && p < end; p++) props++;
    assert_int_equal(props, 3 + 3 + 2 + NA);
    for (int a = 0; a < NA; a++) {
        char line[LEN + 32];
        snprintf(line, sizeof line, "property float %s\n", names[a]);
        assert_non_null(strstr(d, line));
    }
    assert_int_equal(n, head + nv * 4 * (3 + 3 + 2 + NA) + nt * 13);
    free(d);
    d = (char *)test_read_file(in_dir("long.vtk"), &n);
    assert_non_null(d);
    for (int a = 0; a < NA; a++) {
        char line[LEN + 48];
        snprintf(line, sizeof line, "\n%s 1 %zu float\n", names[a], nv);
        size_t k = strlen(line), i = 0;
        while (i + k <= n && memcmp(d + i, line, k) != 0) i++;
        assert_true(i + k <= n);
    }
    free(d);
    for (int a = 0; a < NA; a++) free(names[a]);
    free(vals);
    test_mesh_free(&tm);
}

/* ---- atomic output ----------------------------------------------------------------------- */

static void test_atomic_commit_and_names(void **state)
{
    (void)state;
    char err[512];
    jmf_atomic_file af;
    const char *path = in_dir("a.txt");
    assert_int_equal(jmf_atomic_open(&af, path, err, sizeof err), JMF_OK);
    char want[600];
    snprintf(want, sizeof want, "%s/.a.txt.jetmesh-tmp-%s-%ld-", g_dir, jmf_atomic_host(), (long)getpid());
    assert_memory_equal(af.temp_path, want, strlen(want));
    assert_int_equal(strlen(af.temp_path), strlen(want) + 8); /* 8 hex digits drawn per process */
    snprintf(want, sizeof want, "%s", af.temp_path);
    /* the name parses back to the output's name, this host and this process */
    jmf_temp_name t;
    const char *base = strrchr(af.temp_path, '/') + 1;
    assert_int_equal(jmf_atomic_temp_parse(base, &t), 1);
    assert_int_equal(t.name_len, strlen("a.txt"));
    assert_memory_equal(base + 1, "a.txt", t.name_len);
    assert_int_equal(t.pid, (long)getpid());
    assert_non_null(t.host);
    assert_int_equal(t.host_len, strlen(jmf_atomic_host()));
    assert_memory_equal(t.host, jmf_atomic_host(), t.host_len);
    /* host names may hold '-'; the older form has no host */
    assert_int_equal(jmf_atomic_temp_parse(".m.glb.jetmesh-tmp-node-07.cluster-4321-0badcafe", &t), 1);
    assert_int_equal(t.pid, 4321);
    assert_int_equal(t.host_len, strlen("node-07.cluster"));
    assert_memory_equal(t.host, "node-07.cluster", t.host_len);
    assert_int_equal(t.name_len, strlen("m.glb"));
    assert_int_equal(jmf_atomic_temp_parse(".m.glb.jetmesh-tmp-4321", &t), 1);
    assert_int_equal(t.pid, 4321);
    assert_null(t.host);
    static const char *const not_temps[] = {"a.txt", ".a.txt", ".jetmesh-tmp-12", ".a.jetmesh-tmp-",
                                            ".a.jetmesh-tmp-12x", "a.jetmesh-tmp-12", ".a.jetmesh-tmp-1234567890",
                                            ".a.jetmesh-tmp-h-12-0badcafX", ".a.jetmesh-tmp--12-0badcafe",
                                            ".a.jetmesh-tmp-h-x-0badcafe", ".a.jetmesh-tmp-h-12-badcafe"};
    for (size_t i = 0; i < sizeof not_temps / sizeof *not_temps; i++)
        assert_int_equal(jmf_atomic_temp_parse(not_temps[i], &t), 0);
    assert_true(file_size(want) == 0);
    assert_int_equal(file_size(path), -1); /* nothing at the target yet */
    assert_int_equal(jmf_atomic_write(&af, "hello\n", 6, err, sizeof err), JMF_OK);
    fputs("world\n", af.fp);
    assert_int_equal(jmf_atomic_commit(&af, err, sizeof err), JMF_OK);
    assert_int_equal(af.bytes, 12);
    assert_true(file_equals(path, "hello\nworld\n"));
    assert_int_equal(temp_files(), 0);
    assert_null(af.fp);

    /* An existing file keeps its permissions. */
    assert_int_equal(chmod(path, 0640), 0);
    assert_int_equal(jmf_atomic_open(&af, path, err, sizeof err), JMF_OK);
    assert_int_equal(jmf_atomic_commit(&af, err, sizeof err), JMF_OK);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0640);
    assert_int_equal(st.st_size, 0);
}

/* A staged output: complete temporaries, nothing at the targets until
 * published (bytes as jmf_write_mesh writes them, the .bin before the
 * .gltf); an abort leaves the old files and no temporary. */
/* Issue 30: an output name of up to 255 bytes works, its temporary's name
 * cut short (the first bytes, whole UTF-8 characters, and a hash) so that
 * it fits the file system's 255 too; short names keep the old form. */
static void test_atomic_long_names(void **state)
{
    (void)state;
    char err[512], name[256], stem[JMF_TEMP_STEM_MAX + 1];
    memset(name, 'c', 250);
    memcpy(name + 250, ".obj", 5);
    jmf_atomic_file af;
    assert_int_equal(jmf_atomic_open(&af, in_dir(name), err, sizeof err), JMF_OK);
    const char *base = strrchr(af.temp_path, '/') + 1;
    assert_true(strlen(base) <= 255);
    jmf_temp_name t;
    assert_int_equal(jmf_atomic_temp_parse(base, &t), 1);
    assert_int_equal(t.name_len, jmf_atomic_temp_stem(name, stem));
    assert_memory_equal(base + 1, stem, t.name_len);
    assert_int_equal(jmf_atomic_write(&af, "x", 1, err, sizeof err), JMF_OK);
    assert_int_equal(jmf_atomic_commit(&af, err, sizeof err), JMF_OK);
    assert_true(file_equals(in_dir(name), "x"));
    assert_int_equal(temp_files(), 0);
    /* the stem: 100 bytes of the name, '~', 16 hex digits; another name,
     * another stem; a name up to JMF_TEMP_STEM_MAX bytes is its own */
    assert_int_equal(strlen(stem), 117);
    assert_memory_equal(stem, name, 100);
    assert_int_equal(stem[100], '~');
    assert_int_equal(strspn(stem + 101, "0123456789abcdef"), 16);
    char other[JMF_TEMP_STEM_MAX + 1];
    name[200] = 'd';
    jmf_atomic_temp_stem(name, other);
    assert_memory_equal(other, stem, 101);
    assert_true(strcmp(other, stem) != 0);
    name[JMF_TEMP_STEM_MAX] = '\0';
    assert_int_equal(jmf_atomic_temp_stem(name, other), JMF_TEMP_STEM_MAX);
    assert_string_equal(other, name);
    /* never inside a UTF-8 character: 83 euro signs (3 bytes each) keep 33 */
    char euros[256];
    for (int i = 0; i < 83; i++) memcpy(euros + 3 * i, "\xe2\x82\xac", 3);
    euros[249] = '\0';
    assert_int_equal(jmf_atomic_temp_stem(euros, other), 99 + 17);
    assert_int_equal(other[99], '~');
    /* a scratch file whose own name is too long (never renamed into place) */
    char scratch[300];
    memset(scratch, 'e', 252);
    memcpy(scratch + 252, ".frames", 8);
    assert_int_equal(jmf_atomic_open(&af, in_dir(scratch), err, sizeof err), JMF_OK);
    jmf_atomic_abort(&af);
    assert_int_equal(temp_files(), 0);
}

static void test_staged_publish_and_abort(void **state)
{
    (void)state;
    char err[512];
    test_mesh tm;
    make("octahedron", &tm);
    size_t want_n, got_n, bytes = 0;
    assert_int_equal(write_path(in_dir("ref.glb"), &tm.mesh, NULL, NULL, err), JMF_OK);
    unsigned char *want = test_read_file(in_dir("ref.glb"), &want_n);

    jmf_staged sg;
    assert_int_equal(jmf_write_mesh_staged(in_dir("st.glb"), &tm.mesh, NULL, &bytes, &sg, err, sizeof err), JMF_OK);
    assert_int_equal(sg.count, 1);
    assert_int_equal(bytes, want_n);
    assert_int_equal(file_size(in_dir("st.glb")), -1);
    assert_int_equal(temp_files(), 1);
    assert_int_equal(jmf_staged_publish(&sg, err, sizeof err), JMF_OK);
    assert_int_equal(temp_files(), 0);
    unsigned char *got = test_read_file(in_dir("st.glb"), &got_n);
    assert_int_equal(got_n, want_n);
    assert_memory_equal(got, want, want_n);
    free(got);

    /* .gltf + .bin: two files staged, the .bin first */
    assert_int_equal(jmf_write_mesh_staged(in_dir("st.gltf"), &tm.mesh, NULL, NULL, &sg, err, sizeof err), JMF_OK);
    assert_int_equal(sg.count, 2);
    assert_non_null(strstr(sg.files[0].final_path, "st.bin"));
    assert_int_equal(temp_files(), 2);
    assert_int_equal(jmf_staged_publish(&sg, err, sizeof err), JMF_OK);
    assert_true(file_size(in_dir("st.gltf")) > 0 && file_size(in_dir("st.bin")) > 0);

    /* abort: the old file stays, no temporary is left */
    spit(in_dir("old.glb"), "old\n");
    assert_int_equal(jmf_write_mesh_staged(in_dir("old.glb"), &tm.mesh, NULL, NULL, &sg, err, sizeof err), JMF_OK);
    jmf_staged_abort(&sg);
    jmf_staged_abort(NULL);
    assert_true(file_equals(in_dir("old.glb"), "old\n"));
    assert_int_equal(temp_files(), 0);
    free(want);
    test_mesh_free(&tm);
}

static void test_atomic_abort_keeps_target(void **state)
{
    (void)state;
    char err[512];
    const char *path = in_dir("keep.obj");
    spit(path, "good\n");
    jmf_atomic_file af;
    assert_int_equal(jmf_atomic_open(&af, path, err, sizeof err), JMF_OK);
    assert_int_equal(jmf_atomic_write(&af, "partial", 7, err, sizeof err), JMF_OK);
    assert_int_equal(temp_files(), 1);
    jmf_atomic_abort(&af);
    assert_true(file_equals(path, "good\n"));
    assert_int_equal(temp_files(), 0);
    jmf_atomic_abort(&af); /* twice is harmless */
    jmf_atomic_abort(NULL);
}

/* jmf_atomic_shutdown (what the signal thread calls): every temporary is
 * gone, the targets untouched, and nothing can be created or renamed
 * afterwards, from any thread. It closes the writer for good, so it runs
 * in a child process. */
static void test_atomic_shutdown(void **state)
{
    (void)state;
    char err[512];
    spit(in_dir("p1"), "one");
    pid_t child = fork();
    assert_true(child >= 0);
    if (child == 0) {
        jmf_atomic_file a, b, c, d;
        int bad = 0;
        bad |= jmf_atomic_open(&a, in_dir("p1"), err, sizeof err) != JMF_OK;
        bad |= jmf_atomic_open(&b, in_dir("p2"), err, sizeof err) != JMF_OK;
        /* the same target twice at once is refused */
        bad |= jmf_atomic_open(&c, in_dir("p1"), err, sizeof err) != JMF_E_IO;
        bad |= strstr(err, "already being written") == NULL;
        bad |= jmf_atomic_write(&b, "two", 3, err, sizeof err) != JMF_OK;
        bad |= jmf_atomic_finish(&b, err, sizeof err) != JMF_OK;
        bad |= temp_files() != 2;
        jmf_atomic_shutdown();
        bad |= temp_files() != 0;
        /* a finished file is not renamed, a new one not created */
        bad |= jmf_atomic_publish(&b, err, sizeof err) != JMF_E_IO;
        bad |= strstr(err, "stopping") == NULL;
        bad |= jmf_atomic_open(&d, in_dir("p3"), err, sizeof err) != JMF_E_IO;
        bad |= strstr(err, "stopping") == NULL;
        jmf_atomic_abort(&a);
        jmf_atomic_shutdown(); /* twice: harmless */
        bad |= temp_files() != 0;
        _exit(bad ? 1 : 0);
    }
    int status = 0;
    assert_int_equal(waitpid(child, &status, 0), child);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0);
    assert_true(file_equals(in_dir("p1"), "one"));
    assert_int_equal(file_size(in_dir("p2")), -1);
    assert_int_equal(file_size(in_dir("p3")), -1);
    assert_int_equal(temp_files(), 0);
}

static void test_atomic_refuses_directory(void **state)
{
    (void)state;
    char err[512];
    test_mesh tm;
    make("octahedron", &tm);
    const char *dir = in_dir("adir");
    assert_int_equal(mkdir(dir, 0755), 0);
    jmf_write_options o;
    memset(&o, 0, sizeof o);
    o.format = JMF_OUT_OBJ;
    assert_int_equal(write_path(dir, &tm.mesh, &o, NULL, err), JMF_E_IO);
    assert_non_null(strstr(err, "adir: is a directory"));
    char slash[600];
    snprintf(slash, sizeof slash, "%s/", in_dir("x.obj"));
    assert_int_equal(write_path(slash, &tm.mesh, NULL, NULL, err), JMF_E_IO);
    jmf_atomic_file af;
    assert_int_equal(jmf_atomic_open(&af, dir, err, sizeof err), JMF_E_IO);
    assert_non_null(strstr(err, "is a directory"));
    assert_int_equal(temp_files(), 0);
    struct stat st;
    assert_int_equal(stat(dir, &st), 0);
    assert_true(S_ISDIR(st.st_mode));

    /* A .gltf that cannot be written leaves its .bin alone too. */
    spit(in_dir("adir2.bin"), "old bin");
    assert_int_equal(mkdir(in_dir("adir2.gltf"), 0755), 0);
    assert_int_equal(write_path(in_dir("adir2.gltf"), &tm.mesh, NULL, NULL, err), JMF_E_IO);
    assert_true(file_equals(in_dir("adir2.bin"), "old bin"));
    assert_int_equal(temp_files(), 0);
    test_mesh_free(&tm);
}

static void test_atomic_missing_parent(void **state)
{
    (void)state;
    char err[512];
    test_mesh tm;
    make("octahedron", &tm);
    const char *path = in_dir("no/such/dir/m.glb");
    assert_int_equal(write_path(path, &tm.mesh, NULL, NULL, err), JMF_E_IO);
    assert_non_null(strstr(err, "no/such/dir/m.glb"));
    assert_non_null(strstr(err, "No such file or directory"));
    test_mesh_free(&tm);
}

/* A write that fails half-way (the file-size limit stands in for a full
 * disk: it works as root, where permissions do not) leaves the existing
 * file as it was and no temporary behind. */
static void test_atomic_failed_write_keeps_target(void **state)
{
    (void)state;
    char err[512];
    test_mesh tm;
    make("grid", &tm);
    const char *formats[] = {"big.obj", "big.ply", "big.vtk", "big.glb", "big.gltf", "big.drc"};
    struct rlimit old, lim;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    for (size_t i = 0; i < 6; i++) {
        const char *path = in_dir(formats[i]);
        spit(path, "the good old file\n");
        lim = old;
        lim.rlim_cur = 100000; /* bytes; every format of the grid is larger */
        assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);
        jmf_status st = write_path(path, &tm.mesh, NULL, NULL, err);
        assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
        if (st != JMF_E_IO) fail_msg("%s: status %d, %s", formats[i], st, err);
        /* a .gltf fails on its .bin, written first */
        const char *named = i == 4 ? "big.bin" : formats[i];
        if (!strstr(err, named)) fail_msg("%s: %s", formats[i], err);
        assert_non_null(strstr(err, "too large")); /* strerror(EFBIG) */
        assert_true(file_equals(path, "the good old file\n"));
        assert_int_equal(temp_files(), 0);
    }
    signal(SIGXFSZ, old_handler);
    test_mesh_free(&tm);
}

static void test_dev_full(void **state)
{
    (void)state;
    char err[512];
    struct stat st;
    if (stat("/dev/full", &st) != 0 || !S_ISCHR(st.st_mode) || access("/dev/full", W_OK) != 0)
        skip();
    test_mesh tm;
    make("grid", &tm);
    jmf_write_options o;
    memset(&o, 0, sizeof o);
    o.format = JMF_OUT_PLY;
    assert_int_equal(write_path("/dev/full", &tm.mesh, &o, NULL, err), JMF_E_IO);
    assert_non_null(strstr(err, "/dev/full"));
    assert_non_null(strstr(err, "No space left on device"));
    assert_int_equal(stat("/dev/full", &st), 0);
    assert_true(S_ISCHR(st.st_mode)); /* still the device */
    test_mesh_free(&tm);
}

static void test_atomic_through_symlink(void **state)
{
    (void)state;
    char err[512];
    spit(in_dir("real.txt"), "old");
    assert_int_equal(symlink("real.txt", in_dir("link.txt")), 0);
    jmf_atomic_file af;
    assert_int_equal(jmf_atomic_open(&af, in_dir("link.txt"), err, sizeof err), JMF_OK);
    assert_int_equal(jmf_atomic_write(&af, "new", 3, err, sizeof err), JMF_OK);
    assert_int_equal(jmf_atomic_commit(&af, err, sizeof err), JMF_OK);
    struct stat st;
    assert_int_equal(lstat(in_dir("link.txt"), &st), 0);
    assert_true(S_ISLNK(st.st_mode));
    assert_true(file_equals(in_dir("real.txt"), "new"));
    /* a dangling link alike: its target is created, the link kept (issue
     * 30: it was replaced by a file); a loop is refused */
    assert_int_equal(symlink("made.txt", in_dir("dangling.txt")), 0);
    assert_int_equal(jmf_atomic_open(&af, in_dir("dangling.txt"), err, sizeof err), JMF_OK);
    assert_int_equal(jmf_atomic_write(&af, "made", 4, err, sizeof err), JMF_OK);
    assert_int_equal(jmf_atomic_commit(&af, err, sizeof err), JMF_OK);
    assert_int_equal(lstat(in_dir("dangling.txt"), &st), 0);
    assert_true(S_ISLNK(st.st_mode));
    assert_true(file_equals(in_dir("made.txt"), "made"));
    assert_int_equal(symlink("loop.txt", in_dir("loop.txt")), 0);
    assert_int_equal(jmf_atomic_open(&af, in_dir("loop.txt"), err, sizeof err), JMF_E_IO);
    assert_non_null(strstr(err, "symbolic link"));
    assert_int_equal(temp_files(), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_format_float_matches_printf),
        cmocka_unit_test(test_format_names),
        cmocka_unit_test(test_meshes_are_closed),
        cmocka_unit_test(test_obj_roundtrip),
        cmocka_unit_test(test_obj_without_attributes),
        cmocka_unit_test(test_ply_roundtrip),
        cmocka_unit_test(test_vtk_roundtrip),
        cmocka_unit_test(test_glb_layout),
        cmocka_unit_test(test_gltf_index_width),
        cmocka_unit_test(test_gltf_separate_and_embedded),
        cmocka_unit_test(test_empty_mesh),
        cmocka_unit_test(test_drc),
        cmocka_unit_test(test_bad_requests),
        cmocka_unit_test(test_generator_stays_one_line),
        cmocka_unit_test(test_long_attribute_names),
        cmocka_unit_test(test_atomic_commit_and_names),
        cmocka_unit_test(test_atomic_long_names),
        cmocka_unit_test(test_atomic_abort_keeps_target),
        cmocka_unit_test(test_atomic_shutdown),
        cmocka_unit_test(test_atomic_refuses_directory),
        cmocka_unit_test(test_staged_publish_and_abort),
        cmocka_unit_test(test_atomic_missing_parent),
        cmocka_unit_test(test_atomic_failed_write_keeps_target),
        cmocka_unit_test(test_dev_full),
        cmocka_unit_test(test_atomic_through_symlink),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
