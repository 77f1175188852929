/* test_reader_claims.c - files that claim more than they hold, rows past their count, CDATA, the attribute component limit (issue 30). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../formats/reader.h"

/* Reads text (n bytes) as name with the attributes asked for and max_bytes. */
static jmf_status rd(const void *d, size_t n, const char *name, const char *attrs, size_t max_bytes, jmf_frame *fr,
                     char *err, size_t errlen)
{
    jmf_read_options o;
    memset(&o, 0, sizeof o);
    o.attributes = attrs;
    o.max_bytes = max_bytes;
    return jmf_read_particles_mem(d, n, name, &o, fr, err, errlen);
}

/* The read fails with want, leaves no frame, and its message holds both needles. */
static void expect(const void *d, size_t n, const char *name, const char *attrs, size_t max_bytes, jmf_status want,
                   const char *needle1, const char *needle2)
{
    jmf_frame fr;
    char err[600];
    jmf_status st = rd(d, n, name, attrs, max_bytes, &fr, err, sizeof err);
    if (st != want) fail_msg("%s: expected status %d, got %d (%s)", name, (int)want, (int)st, err);
    assert_null(fr.xyz);
    assert_int_equal(fr.count, 0);
    if (strncmp(err, name, strlen(name)) != 0) fail_msg("message '%s' does not start with %s", err, name);
    if (needle1 && !strstr(err, needle1)) fail_msg("message '%s' lacks '%s'", err, needle1);
    if (needle2 && !strstr(err, needle2)) fail_msg("message '%s' lacks '%s'", err, needle2);
}

static void expect_text(const char *text, const char *name, const char *attrs, jmf_status want, const char *n1,
                        const char *n2)
{
    expect(text, strlen(text), name, attrs, 0, want, n1, n2);
}

static size_t b64(const unsigned char *in, size_t n, char *out)
{
    static const char al[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t k = 0;
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)in[i] << 16 | (i + 1 < n ? (unsigned)in[i + 1] << 8 : 0) | (i + 2 < n ? in[i + 2] : 0);
        out[k++] = al[v >> 18 & 63];
        out[k++] = al[v >> 12 & 63];
        out[k++] = i + 1 < n ? al[v >> 6 & 63] : '=';
        out[k++] = i + 2 < n ? al[v & 63] : '=';
    }
    out[k] = '\0';
    return k;
}

static void le64(unsigned char *p, uint64_t v)
{
    for (int i = 0; i < 8; i++) p[i] = (unsigned char)(v >> (8 * i));
}

/* A VTU whose inline base64 Points claim 2^31 points (UInt64 header) over 24
 * bytes of data: truncated (exit 1), whatever the limit, never "over the
 * limit" (exit 3). */
static void test_vtu_base64_claims(void **state)
{
    (void)state;
    unsigned char raw[8 + 24] = {0};
    char enc[64], vtu[1024];
    le64(raw, (uint64_t)12 << 31);
    b64(raw, sizeof raw, enc);
    int n = snprintf(vtu, sizeof vtu,
                     "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt64\">\n"
                     "<UnstructuredGrid><Piece NumberOfPoints=\"2147483648\">\n<Points><DataArray type=\"Float32\" "
                     "NumberOfComponents=\"3\" format=\"binary\">%s</DataArray></Points>\n</Piece>"
                     "</UnstructuredGrid></VTKFile>\n",
                     enc);
    expect(vtu, (size_t)n, "lie.vtu", NULL, 0, JMF_E_FORMAT, "lie.vtu: byte ", "truncated Points");
    expect(vtu, (size_t)n, "lie.vtu", NULL, (size_t)100 << 40, JMF_E_FORMAT, "lie.vtu: byte ", "truncated Points");
    expect(vtu, (size_t)n, "lie.vtu", NULL, 1000, JMF_E_FORMAT, "lie.vtu: byte ", "truncated Points");

    /* zlib: one block of 10 compressed bytes claiming 1 GiB */
    unsigned char zraw[4 * 8 + 10] = {0};
    uint64_t bytes = (uint64_t)12 * 89478485; /* 1073741820 */
    le64(zraw, 1);
    le64(zraw + 8, bytes);
    le64(zraw + 16, bytes);
    le64(zraw + 24, 10);
    char zenc[128];
    b64(zraw, sizeof zraw, zenc);
    n = snprintf(vtu, sizeof vtu,
                 "<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">"
                 "<UnstructuredGrid><Piece NumberOfPoints=\"89478485\"><Points><DataArray type=\"Float32\" "
                 "NumberOfComponents=\"3\" format=\"binary\">%s</DataArray></Points></Piece></UnstructuredGrid>"
                 "</VTKFile>",
                 zenc);
    expect(vtu, (size_t)n, "zlie.vtu", NULL, 0, JMF_E_FORMAT, "zlie.vtu: byte ", "cannot hold");
    expect(vtu, (size_t)n, "zlie.vtu", NULL, 1000, JMF_E_FORMAT, "zlie.vtu: byte ", "cannot hold");
}

/* Legacy VTK arrays claiming 10^15 tuples: truncated at their line or byte,
 * not out of memory. */
static void test_vtk_claims(void **state)
{
    (void)state;
    static const char head[] = "# vtk DataFile Version 4.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 2 float\n"
                               "0 0 0 1 1 1\nPOINT_DATA 2\n";
    char f[1024];
    snprintf(f, sizeof f, "%sFIELD FieldData 1\nvelocity 3 1000000000000000 float\n1 2 3 4 5 6\n", head);
    expect_text(f, "field.vtk", "velocity", JMF_E_FORMAT, "field.vtk:10:", "truncated FIELD array");
    expect_text(f, "field.vtk", "all", JMF_E_FORMAT, "field.vtk:10:", "truncated FIELD array");
    /* POINT_DATA before POINTS cannot be compared with a point count */
    expect_text("# vtk DataFile Version 4.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINT_DATA 1000000000000000\n"
                "SCALARS density float 1\nLOOKUP_TABLE default\n1 2\n",
                "scalars.vtk", "density", JMF_E_FORMAT, "scalars.vtk:", "truncated SCALARS");
    expect_text("# vtk DataFile Version 4.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINT_DATA 1000000000000000\n"
                "VECTORS velocity float\n1 2 3\n",
                "vectors.vtk", "velocity", JMF_E_FORMAT, "vectors.vtk:", "truncated attribute");
    static const char bin[] = "# vtk DataFile Version 4.1\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 1 float\n"
                              "\0\0\0\0\0\0\0\0\0\0\0\0\nPOINT_DATA 1\nFIELD FieldData 1\n"
                              "velocity 3 1000000000000000 float\n\0\0\0\0";
    expect(bin, sizeof bin - 1, "field.vtk", "velocity", 0, JMF_E_FORMAT, "field.vtk: byte ", "truncated FIELD array");
}

/* PLY: the vertex element claiming 10^18 rows with an attribute asked for,
 * ascii and binary: truncated, not out of memory. */
static void test_ply_claims(void **state)
{
    (void)state;
    expect_text("ply\nformat ascii 1.0\nelement vertex 1000000000000000000\nproperty float x\nproperty float y\n"
                "property float z\nproperty float density\nend_header\n0 0 0 1\n",
                "claim.ply", "density", JMF_E_FORMAT, "claim.ply:3:", "truncated");
    static const char bin[] = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000000000\n"
                              "property float x\nproperty float y\nproperty float z\nproperty float density\n"
                              "end_header\n\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0";
    expect(bin, sizeof bin - 1, "claim.ply", "all", 0, JMF_E_FORMAT, "claim.ply: byte ", "truncated");
}

/* PLY with more rows than its header declares is refused, as VTK is,
 * naming where the extra data starts; blanks after the last row are fine. */
static void test_ply_rows_past_count(void **state)
{
    (void)state;
    static const char head[] = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                               "property float z\nend_header\n";
    char f[512];
    snprintf(f, sizeof f, "%s0 0 0\n1 1 1\n2 2 2\n3 3 3\n", head);
    expect_text(f, "rows.ply", NULL, JMF_E_FORMAT, "rows.ply:10:", "data after the last element");
    snprintf(f, sizeof f, "%s0 0 0\n1 1 1\n\n  \n", head);
    jmf_frame fr;
    char err[512];
    assert_int_equal(rd(f, strlen(f), "blank.ply", NULL, 0, &fr, err, sizeof err), JMF_OK);
    assert_int_equal(fr.count, 2);
    jmf_frame_free(&fr);
    static const char bhead[] = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
                                "property float y\nproperty float z\nend_header\n";
    char bin[256], at[64];
    memcpy(bin, bhead, sizeof bhead - 1);
    memset(bin + sizeof bhead - 1, 0, 24); /* two rows */
    snprintf(at, sizeof at, "rows.ply: byte %zu:", sizeof bhead - 1 + 12);
    expect(bin, sizeof bhead - 1 + 24, "rows.ply", NULL, 0, JMF_E_FORMAT, at, "data after the last");
}

/* A DataArray's content in a CDATA section is its text; an empty one is
 * reported where it is, not at byte 0. */
static void test_vtu_cdata(void **state)
{
    (void)state;
    static const char head[] = "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"2\">"
                               "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">";
    static const char tail[] = "</DataArray></Points></Piece></UnstructuredGrid></VTKFile>";
    char f[1024];
    snprintf(f, sizeof f, "%s<![CDATA[0 0 0 1 1 1]]>%s", head, tail);
    jmf_frame fr;
    char err[512];
    assert_int_equal(rd(f, strlen(f), "cdata.vtu", NULL, 0, &fr, err, sizeof err), JMF_OK);
    assert_int_equal(fr.count, 2);
    assert_true(fr.xyz[3] == 1.0f && fr.xyz[5] == 1.0f);
    jmf_frame_free(&fr);
    char at[64];
    snprintf(at, sizeof at, "empty.vtu: byte %zu:", strlen(head));
    snprintf(f, sizeof f, "%s<![CDATA[ ]]>%s", head, tail);
    expect_text(f, "empty.vtu", NULL, JMF_E_FORMAT, at, "truncated Points");
    snprintf(f, sizeof f, "%s%s", head, tail);
    expect_text(f, "empty.vtu", NULL, JMF_E_FORMAT, at, "truncated Points");
    snprintf(f, sizeof f, "%s1 2 3<![CDATA[4 5 6]]>%s", head, tail);
    expect_text(f, "split.vtu", NULL, JMF_E_UNSUPPORTED, "split.vtu: byte ", "split");
    snprintf(f, sizeof f, "%s<![CDATA[0 0 0 1 1 1", head);
    expect_text(f, "open.vtu", NULL, JMF_E_FORMAT, "open.vtu: byte ", "]]>");
}

/* More attribute components than a frame carries are refused at the
 * header (the CSV's line 1), naming the limit; exactly the limit reads. */
static void test_component_limit(void **state)
{
    (void)state;
    const size_t cols = 20000;
    char *f = malloc(cols * 12 + 64);
    assert_non_null(f);
    for (size_t have = JMF_MAX_ATTRIBUTE_COMPONENTS; have <= cols; have = have == cols ? cols + 1 : cols) {
        size_t k = (size_t)sprintf(f, "x,y,z");
        for (size_t i = 0; i < have; i++) k += (size_t)sprintf(f + k, ",a%zu", i);
        k += (size_t)sprintf(f + k, "\n0,0,0");
        for (size_t i = 0; i < have; i++) k += (size_t)sprintf(f + k, ",1");
        f[k++] = '\n';
        jmf_frame fr;
        char err[512];
        jmf_status st = rd(f, k, "wide.csv", "all", 0, &fr, err, sizeof err);
        if (have == JMF_MAX_ATTRIBUTE_COMPONENTS) {
            if (st != JMF_OK) fail_msg("%zu columns: %s", have, err);
            assert_int_equal(fr.attribute_count, JMF_MAX_ATTRIBUTE_COMPONENTS);
            jmf_frame_free(&fr);
        } else {
            expect(f, k, "wide.csv", "all", 0, JMF_E_UNSUPPORTED, "wide.csv:1:", "limit of 64");
        }
    }
    free(f);
    /* legacy VTK: 17 FIELD arrays of 4 components, the 17th refused at its line */
    char v[4096];
    size_t k = (size_t)sprintf(v, "# vtk DataFile Version 4.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 1 float\n"
                                  "0 0 0\nPOINT_DATA 1\nFIELD FieldData 17\n");
    for (int i = 0; i < 17; i++) k += (size_t)sprintf(v + k, "q%d 4 1 float\n1 2 3 4\n", i);
    expect(v, k, "field.vtk", "all", 0, JMF_E_UNSUPPORTED, "field.vtk:41:", "limit of 64");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vtu_base64_claims),
        cmocka_unit_test(test_vtk_claims),
        cmocka_unit_test(test_ply_claims),
        cmocka_unit_test(test_ply_rows_past_count),
        cmocka_unit_test(test_vtu_cdata),
        cmocka_unit_test(test_component_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
