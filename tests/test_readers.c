/* test_readers.c - tests of the particle readers: real frames from ../shared, CSV edge cases, truncation, corruption, messages. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "../formats/reader.h"
#include "util/files.h"

/* ---------------------------------------------------------------- helpers */

static char shared_root[4096];

/* The shared data directory (JETMESH_SHARED, else $JETMESH_ROOT/../shared, else ../shared); NULL if missing. */
static const char *shared_dir(void)
{
    struct stat sb;
    const char *env = getenv("JETMESH_SHARED");
    const char *root = getenv("JETMESH_ROOT");
    if (env && *env) snprintf(shared_root, sizeof shared_root, "%s", env);
    else if (root && *root) snprintf(shared_root, sizeof shared_root, "%s/../shared", root);
    else snprintf(shared_root, sizeof shared_root, "../shared");
    {
        char p[4200];
        snprintf(p, sizeof p, "%s/data", shared_root);
        if (stat(p, &sb) != 0 || !S_ISDIR(sb.st_mode)) return NULL;
    }
    return shared_root;
}

/* Skips the calling test when the shared data is not there. */
#define NEED_SHARED()                                                                   \
    do {                                                                                \
        if (!shared_dir()) {                                                            \
            print_message("shared data not found (set JETMESH_SHARED); skipping\n");   \
            skip();                                                                     \
        }                                                                               \
    } while (0)

static void data_path(char *buf, size_t n, const char *rel)
{
    snprintf(buf, n, "%s/data/%s", shared_dir(), rel);
}

static unsigned char *slurp_shared(const char *rel, size_t *size)
{
    char p[4300];
    unsigned char *d;
    data_path(p, sizeof p, rel);
    d = test_read_file(p, size);
    assert_non_null(d);
    return d;
}

static jmf_status rd(const void *d, size_t n, const char *name, jmf_input_format fmt, int drop, jmf_frame *fr,
                     char *err, size_t errlen)
{
    jmf_read_options o;
    memset(&o, 0, sizeof o);
    o.format = fmt;
    o.drop_invalid = drop;
    return jmf_read_particles_mem(d, n, name, &o, fr, err, errlen);
}

static jmf_status rds(const char *text, const char *name, int drop, jmf_frame *fr, char *err)
{
    return rd(text, strlen(text), name, JMF_IN_AUTO, drop, fr, err, 512);
}

/* A message must be one line, start with the file name and not end in a newline. */
static void check_message(const char *err, const char *name)
{
    size_t n = strlen(err);
    assert_true(n > 0);
    assert_int_equal(strncmp(err, name, strlen(name)), 0);
    assert_null(strchr(err, '\n'));
    assert_true(err[n - 1] != ' ');
}

static void expect_fail_n(const char *text, size_t len, const char *name, jmf_status want, const char *needle1,
                          const char *needle2)
{
    jmf_frame fr;
    char err[512];
    jmf_status st = rd(text, len, name, JMF_IN_AUTO, 0, &fr, err, sizeof err);
    if (st != want) fail_msg("%s: expected status %d, got %d (%s)", name, (int)want, (int)st, err);
    assert_null(fr.xyz);
    assert_int_equal(fr.count, 0);
    check_message(err, name);
    if (needle1 && !strstr(err, needle1)) fail_msg("message '%s' lacks '%s'", err, needle1);
    if (needle2 && !strstr(err, needle2)) fail_msg("message '%s' lacks '%s'", err, needle2);
}

static void expect_fail(const char *text, const char *name, jmf_status want, const char *needle1,
                        const char *needle2)
{
    expect_fail_n(text, strlen(text), name, want, needle1, needle2);
}

/* For literals with NUL bytes in them. */
#define EXPECT_FAIL_LIT(lit, name, want, n1, n2) expect_fail_n(lit, sizeof(lit) - 1, name, want, n1, n2)

static void expect_points(const char *text, const char *name, size_t count, const float *xyz)
{
    jmf_frame fr;
    char err[512];
    jmf_status st = rds(text, name, 0, &fr, err);
    if (st != JMF_OK) fail_msg("%s: expected success, got %d: %s", name, (int)st, err);
    assert_int_equal(fr.count, count);
    if (xyz && count) assert_memory_equal(fr.xyz, xyz, 3 * count * sizeof(float));
    jmf_frame_free(&fr);
}

static void all_finite(const jmf_frame *fr)
{
    size_t i;
    for (i = 0; i < 3 * fr->count; i++) assert_true(isfinite(fr->xyz[i]));
}

static unsigned char *gzip_mem(const void *src, size_t n, size_t *outn)
{
    z_stream zs;
    size_t cap = compressBound((uLong)n) + 64;
    unsigned char *out = malloc(cap);
    assert_non_null(out);
    memset(&zs, 0, sizeof zs);
    assert_int_equal(deflateInit2(&zs, 9, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY), Z_OK);
    zs.next_in = (Bytef *)(uintptr_t)src;
    zs.avail_in = (uInt)n;
    zs.next_out = out;
    zs.avail_out = (uInt)cap;
    assert_int_equal(deflate(&zs, Z_FINISH), Z_STREAM_END);
    *outn = zs.total_out;
    deflateEnd(&zs);
    return out;
}

static char tmpdir[256];

static const char *tmp_path(const char *name)
{
    static char p[512];
    if (!tmpdir[0]) {
        snprintf(tmpdir, sizeof tmpdir, "/tmp/jetmesh_readers_XXXXXX");
        assert_non_null(mkdtemp(tmpdir));
    }
    snprintf(p, sizeof p, "%s/%s", tmpdir, name);
    return p;
}

static void write_file(const char *path, const void *d, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(d, 1, n, f), n);
    fclose(f);
}

/* ---------------------------------------------------------- shared frames */

/*
 * The particle counts of ../shared/data/README.md. partio's scatter.bgeo holds
 * 25 points (its header says 0x19); the README's "5" is true of the other three
 * partio test files. The meshes cube.ply/cube_normals.ply give their 24 vertices.
 */
static const struct expect {
    const char *file;
    size_t count;
    jmf_input_format format;
    int compressed, ids;
} frames[] = {
    { "splashsurf/bunny_frame_14_7705_particles.vtk", 7706, JMF_IN_VTK, 0, 1 },
    { "splashsurf/dam_break_frame_9_6859_particles.bgeo", 6859, JMF_IN_BGEO, 1, 1 },
    { "splashsurf/dam_break_frame_23_24389_particles.bgeo", 24389, JMF_IN_BGEO, 1, 0 },
    { "splashsurf/double_dam_break_frame_01_4732_particles.vtk", 4732, JMF_IN_VTK, 0, 1 },
    { "splashsurf/double_dam_break_frame_26_4732_particles.vtk", 4732, JMF_IN_VTK, 0, 1 },
    { "splashsurf/ParticleData_Fluid_5.vtk", 4732, JMF_IN_VTK, 0, 1 },
    { "splashsurf/ParticleData_Fluid_50.bgeo", 4732, JMF_IN_BGEO, 1, 1 },
    { "splashsurf/hilbert_46843_particles.bgeo", 46843, JMF_IN_BGEO, 1, 0 },
    { "splashsurf/octocat_32614_particles.bgeo", 32614, JMF_IN_BGEO, 1, 0 },
    { "splashsurf/pentagonal_hexecontahedron_32286_particles.bgeo", 32286, JMF_IN_BGEO, 1, 0 },
    { "splashsurf/hilbert2_7954_particles.vtk", 7954, JMF_IN_VTK, 0, 1 },
    { "splashsurf/hilbert2_18856_particles.vtk", 18856, JMF_IN_VTK, 0, 1 },
    { "splashsurf/sailors_knot_19539_particles.vtk", 19539, JMF_IN_VTK, 0, 1 },
    { "splashsurf/cube_2366_particles.vtk", 2366, JMF_IN_VTK, 0, 0 },
    { "splashsurf/free_particles_1000_particles.vtk", 1000, JMF_IN_VTK, 0, 0 },
    { "splashsurf/free_particles_125_particles.vtk", 125, JMF_IN_VTK, 0, 0 },
    { "splashsurf/ParticleData_Random_1000.vtk", 1000, JMF_IN_VTK, 0, 0 },
    { "splashsurf/cube_8_particles.vtk", 8, JMF_IN_VTK, 0, 0 },
    { "splashsurf/cube_8_particles.vtu", 8, JMF_IN_VTU, 0, 0 },
    { "splashsurf/fluid_250_particles.vtu", 250, JMF_IN_VTU, 0, 0 },
    { "splashsurf/fluid_encoded_250_particles.vtu", 250, JMF_IN_VTU, 0, 0 },
    { "splashsurf/cube.ply", 24, JMF_IN_PLY, 0, 0 },
    { "splashsurf/cube_normals.ply", 24, JMF_IN_PLY, 0, 0 },
    { "splishsplash_models/bunny.bgeo", 7706, JMF_IN_BGEO, 1, 1 },
    { "partio_testfiles/base.bgeo", 5, JMF_IN_BGEO, 0, 1 },
    { "partio_testfiles/json.bgeo", 5, JMF_IN_BGEO, 0, 1 },
    { "partio_testfiles/test.bgeo", 5, JMF_IN_BGEO, 0, 1 },
    { "partio_testfiles/scatter.bgeo", 25, JMF_IN_BGEO, 0, 1 },
    { "derived/dam_break_frame_23_24389_particles.xyz", 24389, JMF_IN_XYZ, 0, 0 },
};

static void test_shared_counts(void **state)
{
    size_t i;
    (void)state;
    NEED_SHARED();
    for (i = 0; i < sizeof frames / sizeof frames[0]; i++) {
        char p[4300], err[512];
        jmf_frame fr;
        jmf_status st;
        data_path(p, sizeof p, frames[i].file);
        st = jmf_read_particles(p, NULL, &fr, err, sizeof err);
        if (st != JMF_OK) fail_msg("%s: status %d: %s", frames[i].file, (int)st, err);
        if (fr.count != frames[i].count)
            fail_msg("%s: %zu particles, expected %zu", frames[i].file, fr.count, frames[i].count);
        assert_int_equal(fr.format, frames[i].format);
        assert_int_equal(fr.compressed, frames[i].compressed);
        assert_int_equal(fr.ids != NULL, frames[i].ids);
        assert_int_equal(fr.dropped, 0);
        all_finite(&fr);
        jmf_frame_free(&fr);
    }
}

static void test_shared_every_particle_file_listed(void **state)
{
    /* every particle file in the shared folders must be in the table above */
    static const char *const dirs[] = { "splashsurf", "splishsplash_models", "partio_testfiles", "derived" };
    size_t d, i, seen = 0;
    (void)state;
    NEED_SHARED();
    for (d = 0; d < 4; d++) {
        char p[4300];
        DIR *dir;
        struct dirent *e;
        data_path(p, sizeof p, dirs[d]);
        dir = opendir(p);
        assert_non_null(dir);
        while ((e = readdir(dir)) != NULL) {
            const char *dot = strrchr(e->d_name, '.');
            char rel[600];
            int found = 0;
            if (!dot || strcmp(dot, ".obj") == 0 || e->d_name[0] == '.') continue;
            snprintf(rel, sizeof rel, "%s/%s", dirs[d], e->d_name);
            for (i = 0; i < sizeof frames / sizeof frames[0]; i++)
                if (strcmp(frames[i].file, rel) == 0) found = 1;
            if (!found) fail_msg("%s is not in the count table", rel);
            seen++;
        }
        closedir(dir);
    }
    assert_int_equal(seen, sizeof frames / sizeof frames[0]);
}

static void read_shared(const char *rel, jmf_frame *fr)
{
    char p[4300], err[512];
    jmf_status st;
    data_path(p, sizeof p, rel);
    st = jmf_read_particles(p, NULL, fr, err, sizeof err);
    if (st) fail_msg("%s: %s", rel, err);
}

static void test_shared_cross_format(void **state)
{
    jmf_frame a, b;
    size_t i;
    (void)state;
    NEED_SHARED();
    /* the derived .xyz is the .bgeo it was converted from, particle for particle */
    read_shared("derived/dam_break_frame_23_24389_particles.xyz", &a);
    read_shared("splashsurf/dam_break_frame_23_24389_particles.bgeo", &b);
    assert_int_equal(a.count, b.count);
    assert_memory_equal(a.xyz, b.xyz, 3 * a.count * sizeof(float));
    jmf_frame_free(&a);
    jmf_frame_free(&b);
    /* the 5.1 ASCII VTK and the zlib VTU of the same 8 particles (double -> float) */
    read_shared("splashsurf/cube_8_particles.vtk", &a);
    read_shared("splashsurf/cube_8_particles.vtu", &b);
    assert_int_equal(a.count, 8);
    assert_memory_equal(a.xyz, b.xyz, 3 * 8 * sizeof(float));
    assert_true(fabsf(a.xyz[1] - 0.4995095f) < 1e-7f);
    jmf_frame_free(&a);
    jmf_frame_free(&b);
    /* appended raw + zlib vs appended base64 uncompressed */
    read_shared("splashsurf/fluid_250_particles.vtu", &a);
    read_shared("splashsurf/fluid_encoded_250_particles.vtu", &b);
    assert_int_equal(a.count, 250);
    assert_memory_equal(a.xyz, b.xyz, 3 * 250 * sizeof(float));
    for (i = 0; i < 250; i++) { /* within the L2-norm RangeMin/RangeMax the file states */
        const float *q = a.xyz + 3 * i;
        double r = sqrt((double)q[0] * q[0] + (double)q[1] * q[1] + (double)q[2] * q[2]);
        assert_true(r > 0.44061 && r < 5.14884);
    }
    jmf_frame_free(&a);
    jmf_frame_free(&b);
}

static void test_shared_spot_values(void **state)
{
    jmf_frame fr;
    (void)state;
    NEED_SHARED();
    /* first two points and ids of a SPlisHSPlasH binary VTK (checked with Python's struct) */
    read_shared("splashsurf/ParticleData_Fluid_5.vtk", &fr);
    assert_true(fr.xyz[0] == (float)0.8229686617851257);
    assert_true(fr.xyz[1] == (float)0.04062836617231369);
    assert_true(fr.xyz[2] == (float)0.8229687213897705);
    assert_true(fr.xyz[3] == (float)0.8078259229660034);
    assert_non_null(fr.ids);
    assert_int_equal(fr.ids[0], 2392);
    assert_int_equal(fr.ids[1], 2379);
    assert_int_equal(fr.ids[2], 2405);
    jmf_frame_free(&fr);
    /* partio base.bgeo: points (0.1 i, 0.1 i + 0.1, 0.1 i + 0.2), ids 0..4 */
    read_shared("partio_testfiles/base.bgeo", &fr);
    assert_int_equal(fr.count, 5);
    assert_true(fr.xyz[0] == 0.0f && fr.xyz[1] == 0.1f && fr.xyz[2] == 0.2f);
    assert_true(fr.xyz[12] == 0.4f && fr.xyz[13] == 0.5f && fr.xyz[14] == 0.6f);
    assert_int_equal(fr.ids[4], 4);
    jmf_frame_free(&fr);
    /* the cube mesh vertices are the corners of [-1, 1]^3 */
    read_shared("splashsurf/cube.ply", &fr);
    {
        size_t i;
        for (i = 0; i < 3 * fr.count; i++) assert_true(fr.xyz[i] == 1.0f || fr.xyz[i] == -1.0f);
    }
    jmf_frame_free(&fr);
}

static void test_samples_real(void **state)
{
    jmf_frame fr;
    char err[512];
    jmf_status st;
    char p[4300];
    const char *root = getenv("JETMESH_ROOT");
    (void)state;
    snprintf(p, sizeof p, "%s/samples/real/double_dam_break_frame_26_4732_particles.vtk", root && *root ? root : ".");
    st = jmf_read_particles(p, NULL, &fr, err, sizeof err);
    if (st == JMF_E_IO) {
        print_message("samples/real not found from this directory; skipping\n");
        skip();
    }
    if (st) fail_msg("%s", err);
    assert_int_equal(fr.count, 4732);
    assert_non_null(fr.ids);
    all_finite(&fr);
    if (shared_dir()) { /* the copy is the shared frame */
        jmf_frame orig;
        read_shared("splashsurf/double_dam_break_frame_26_4732_particles.vtk", &orig);
        assert_int_equal(orig.count, fr.count);
        assert_memory_equal(orig.xyz, fr.xyz, 3 * fr.count * sizeof(float));
        jmf_frame_free(&orig);
    }
    jmf_frame_free(&fr);
}

/* ---------------------------------------------------------------- CSV */

static void test_csv_header_and_separators(void **state)
{
    static const float two[6] = { 1, 2, 3, 4.5f, -5, 6e-3f };
    (void)state;
    expect_points("x,y,z\n1,2,3\n4.5,-5,6e-3\n", "a.csv", 2, two);
    expect_points("1,2,3\n4.5,-5,6e-3\n", "a.csv", 2, two);
    expect_points("x;y;z\n1;2;3\n4.5;-5;6e-3\n", "a.csv", 2, two);
    expect_points("x\ty\tz\n1\t2\t3\n4.5\t-5\t6e-3\n", "a.tsv", 2, two);
    expect_points("  1   2  3\n4.5 -5 6e-3   \n", "a.txt", 2, two);
    expect_points("x, y, z\n 1 , 2 , 3\n4.5,-5,6e-3\n", "a.csv", 2, two);
    expect_points("\"x\",\"y\",\"z\"\n1,2,3\n4.5,-5,6e-3\n", "a.csv", 2, two);
}

static void test_csv_comments_blank_crlf(void **state)
{
    static const float two[6] = { 1, 2, 3, 4, 5, 6 };
    (void)state;
    expect_points("# written by a test\r\n\r\nx,y,z\r\n# a comment\r\n1,2,3\r\n\r\n   \r\n4,5,6\r\n", "a.csv", 2, two);
    expect_points("\xef\xbb\xbfx,y,z\n1,2,3\n4,5,6", "bom.csv", 2, two); /* BOM, no final newline */
    expect_points("  # indented comment\n1 2 3\n\t\n4 5 6\n", "a.csv", 2, two);
}

static void test_csv_column_names(void **state)
{
    static const float p[3] = { 1, 2, 3 };
    jmf_frame fr;
    char err[512];
    (void)state;
    expect_points("id,vx,pos_x,pos_y,pos_z\n7,9,1,2,3\n", "a.csv", 1, p);
    expect_points("density,Points:0,Points:1,Points:2\n1000,1,2,3\n", "paraview.csv", 1, p);
    expect_points("X,Y,Z\n1,2,3\n", "a.csv", 1, p);
    expect_points("z,y,x\n3,2,1\n", "a.csv", 1, p);
    expect_points("px,py,pz,x,y,z\n9,9,9,1,2,3\n", "exact_wins.csv", 1, p);
    expect_points("position.x,position.y,position.z\n1,2,3\n", "a.csv", 1, p);
    /* no names: the first three numeric columns (a text column is skipped) */
    expect_points("a,b,c,d\n1,2,3,4\n", "a.csv", 1, p);
    expect_points("phase,a,b,c\nwater,1,2,3\n", "a.csv", 1, p);
    expect_points("water,1,2,3\n", "a.csv", 1, p);
    /* ids */
    assert_int_equal(rds("x,y,z,id\n1,2,3,10\n4,5,6,11\n", "ids.csv", 0, &fr, err), JMF_OK);
    assert_non_null(fr.ids);
    assert_int_equal(fr.ids[0], 10);
    assert_int_equal(fr.ids[1], 11);
    jmf_frame_free(&fr);
    /* a negative id is not an id: the frame has none, the points stay */
    assert_int_equal(rds("x,y,z,id\n1,2,3,-1\n", "ids.csv", 0, &fr, err), JMF_OK);
    assert_null(fr.ids);
    assert_int_equal(fr.count, 1);
    jmf_frame_free(&fr);
    expect_fail("x,y,w\n1,2,3\n", "partial.csv", JMF_E_FORMAT, "partial.csv:1:", "missing z");
    expect_fail("a,b\n1,2\n", "two.csv", JMF_E_FORMAT, "two.csv:1:", "at least 3");
}

static void test_csv_errors(void **state)
{
    (void)state;
    expect_fail("x,y,z\n1,2,3\n4,5\n", "ragged.csv", JMF_E_FORMAT, "ragged.csv:3:", "expected 3");
    expect_fail("1,2,3\n4,5,6,7\n", "ragged2.csv", JMF_E_FORMAT, "ragged2.csv:2:", "found 4");
    expect_fail("# c\n\nx,y,z\n1,2,3\n4,abc,6\n", "text.csv", JMF_E_FORMAT, "text.csv:5:", "'abc'");
    expect_fail("x,y,z\n1,,3\n", "emptyfield.csv", JMF_E_FORMAT, "emptyfield.csv:2:", "expected a number");
    expect_fail("x,y,z\n1,2,3\n1,2,3e999\n", "big.csv", JMF_E_FORMAT, "big.csv:3:", "non-finite");
    /* hexadecimal is not CSV: strtod would read 0x10 as 16 */
    expect_fail("x,y,z\n1,2,3\n0x10,2,3\n", "hex.csv", JMF_E_FORMAT, "hex.csv:3:", "'0x10'");
    expect_fail("x,y,z\n1,2,0X1p3\n", "hexf.csv", JMF_E_FORMAT, "hexf.csv:2:", "'0X1p3'");
    expect_fail("x,y,z\n1,2,3\n1,\x01,3\n", "ctl.csv", JMF_E_FORMAT, "ctl.csv:3:", "control byte");
    expect_fail("1 2\n", "few.csv", JMF_E_FORMAT, "few.csv:1:", "at least 3");
    expect_fail("x,y,z,id\n1,2,3,seven\n", "id.csv", JMF_E_FORMAT, "id.csv:2:", "integer id");
}

static void test_csv_nan(void **state)
{
    jmf_frame fr;
    char err[512];
    const char *text = "x,y,z,id\n1,1,1,10\nnan,0,0,11\n2,2,2,12\n0,inf,0,13\n3,3,-Infinity,14\n";
    (void)state;
    expect_fail(text, "nan.csv", JMF_E_FORMAT, "nan.csv:3:", "non-finite");
    assert_int_equal(rds(text, "nan.csv", 1, &fr, err), JMF_OK);
    assert_int_equal(fr.count, 2);
    assert_int_equal(fr.dropped, 3);
    assert_true(fr.xyz[0] == 1 && fr.xyz[3] == 2);
    assert_non_null(fr.ids);
    assert_int_equal(fr.ids[0], 10);
    assert_int_equal(fr.ids[1], 12);
    jmf_frame_free(&fr);
    /* everything dropped: a valid empty frame */
    assert_int_equal(rds("nan nan nan\n", "allnan.csv", 1, &fr, err), JMF_OK);
    assert_int_equal(fr.count, 0);
    assert_int_equal(fr.dropped, 1);
    assert_null(fr.xyz);
}

static void test_csv_empty_and_header_only(void **state)
{
    jmf_frame fr;
    char err[512];
    (void)state;
    assert_int_equal(rd("", 0, "empty.csv", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
    assert_string_equal(err, "empty.csv: empty file (0 bytes)");
    assert_int_equal(rds("x,y,z\n", "header.csv", 0, &fr, err), JMF_OK);
    assert_int_equal(fr.count, 0);
    assert_null(fr.xyz);
    assert_string_equal(err, "");
    assert_int_equal(rds("# nothing here\n\n", "comments.csv", 0, &fr, err), JMF_OK);
    assert_int_equal(fr.count, 0);
    assert_int_equal(fr.format, JMF_IN_CSV);
}

/* ------------------------------------------------------- other formats */

static void test_xyz_sizes(void **state)
{
    float v[6] = { 1, 2, 3, 4, 5, 6 };
    unsigned char buf[30];
    jmf_frame fr;
    char err[512];
    (void)state;
    memcpy(buf, v, sizeof v); /* the tests run on little-endian hosts */
    assert_int_equal(rd(buf, 24, "a.xyz", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_OK);
    assert_int_equal(fr.count, 2);
    assert_memory_equal(fr.xyz, v, sizeof v);
    jmf_frame_free(&fr);
    assert_int_equal(rd(buf, 25, "a.xyz", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
    check_message(err, "a.xyz");
    assert_non_null(strstr(err, "a.xyz: byte 24:"));
    assert_non_null(strstr(err, "multiple of 12"));
    v[4] = NAN;
    memcpy(buf, v, sizeof v);
    assert_int_equal(rd(buf, 24, "nan.xyz", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
    assert_non_null(strstr(err, "nan.xyz: byte 12:"));
    assert_int_equal(rd(buf, 24, "nan.xyz", JMF_IN_AUTO, 1, &fr, err, sizeof err), JMF_OK);
    assert_int_equal(fr.count, 1);
    assert_int_equal(fr.dropped, 1);
    jmf_frame_free(&fr);
}

static size_t put_be64(unsigned char *b, size_t n, uint64_t u)
{
    int k;
    for (k = 7; k >= 0; k--) b[n++] = (unsigned char)(u >> (8 * k));
    return n;
}

static void test_vtk_ascii_and_variants(void **state)
{
    static const float p[6] = { 0, 0, 0, 1, 2, 3 };
    jmf_frame fr;
    char err[512];
    (void)state;
    const char *legacy =
        "# vtk DataFile Version 3.0\nparticles\nASCII\n\nDATASET POLYDATA\nPOINTS 2 double\n0 0 0\n1 2 3\n"
        "VERTICES 2 4\n1 0\n1 1\nPOINT_DATA 2\nSCALARS id int 1\nLOOKUP_TABLE default\n5 6\n"
        "VECTORS v float\n0 0 0 1 1 1\nFIELD f 2\nrho 1 2 float\n1 2\nNULL_ARRAY\nCELL_DATA 2\nSCALARS c float\n1 2\n";
    assert_int_equal(rds(legacy, "a.vtk", 0, &fr, err), JMF_OK);
    assert_int_equal(fr.count, 2);
    assert_memory_equal(fr.xyz, p, sizeof p);
    assert_non_null(fr.ids);
    assert_int_equal(fr.ids[1], 6);
    jmf_frame_free(&fr);
    /* 5.1 with OFFSETS/CONNECTIVITY and METADATA */
    expect_points("# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 2 float\n0 0 0 1 2 3\n"
                  "METADATA\nINFORMATION 0\n\nCELLS 3 2\nOFFSETS vtktypeint64\n0 1 2\nCONNECTIVITY vtktypeint64\n0 1\n"
                  "CELL_TYPES 2\n1 1\n",
                  "b.vtk", 2, p);
    /* zero points is a valid empty frame */
    expect_points("# vtk DataFile Version 4.2\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 0 float\n\nCELLS 0 0\n\n"
                  "CELL_TYPES 0\n\n",
                  "empty.vtk", 0, NULL);
    /* 5.1 BINARY: big-endian doubles, int64 OFFSETS/CONNECTIVITY, a FIELD array named id */
    {
        static const char h[] = "# vtk DataFile Version 5.1\nvtk output\nBINARY\nDATASET UNSTRUCTURED_GRID\n"
                                "POINTS 2 double\n";
        static const char c[] = "\nCELLS 3 2\nOFFSETS vtktypeint64\n";
        static const char k[] = "\nCONNECTIVITY vtktypeint64\n";
        static const char t[] = "\nCELL_TYPES 2\n";
        static const char f[] = "\nPOINT_DATA 2\nFIELD FieldData 1\nid 1 2 vtktypeint64\n";
        unsigned char b[1024];
        size_t n = 0, i;
        int64_t ints[3] = { 0, 1, 2 };
        memcpy(b, h, sizeof h - 1), n = sizeof h - 1;
        for (i = 0; i < 6; i++) { /* p[] as big-endian doubles */
            double v = p[i];
            uint64_t u;
            memcpy(&u, &v, 8);
            n = put_be64(b, n, u);
        }
        memcpy(b + n, c, sizeof c - 1), n += sizeof c - 1;
        for (i = 0; i < 3; i++) n = put_be64(b, n, (uint64_t)ints[i]);
        memcpy(b + n, k, sizeof k - 1), n += sizeof k - 1;
        for (i = 0; i < 2; i++) n = put_be64(b, n, (uint64_t)ints[i]);
        memcpy(b + n, t, sizeof t - 1), n += sizeof t - 1;
        for (i = 0; i < 2; i++) { b[n++] = 0; b[n++] = 0; b[n++] = 0; b[n++] = 1; }
        memcpy(b + n, f, sizeof f - 1), n += sizeof f - 1;
        for (i = 0; i < 2; i++) n = put_be64(b, n, (uint64_t)ints[i] + 40);
        b[n++] = '\n';
        assert_int_equal(rd(b, n, "bin51.vtk", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_OK);
        assert_int_equal(fr.count, 2);
        assert_memory_equal(fr.xyz, p, sizeof p);
        assert_non_null(fr.ids);
        assert_int_equal(fr.ids[0], 40);
        assert_int_equal(fr.ids[1], 41);
        jmf_frame_free(&fr);
        assert_int_equal(rd(b, n - 5, "bin51.vtk", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
        assert_non_null(strstr(err, "bin51.vtk: byte "));
    }
    expect_fail("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0\n1 x 3\n", "bad.vtk",
                JMF_E_FORMAT, "bad.vtk:7:", "'x'");
    expect_fail("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0\n1 2\n", "short.vtk",
                JMF_E_FORMAT, "short.vtk:7:", "expected 6 values");
    expect_fail("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 nan\n", "nan.vtk",
                JMF_E_FORMAT, "nan.vtk:6:", "non-finite");
    expect_fail("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\nBOGUS 1\n", "kw.vtk",
                JMF_E_FORMAT, "kw.vtk:7:", "unknown keyword 'BOGUS'");
    expect_fail("# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n", "sp.vtk",
                JMF_E_UNSUPPORTED, "sp.vtk", "no POINTS");
    expect_fail("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0 1 1 1\nPOINT_DATA 3\n",
                "pd.vtk", JMF_E_FORMAT, "pd.vtk:7:", "POINT_DATA 3");
}

static void test_ply_variants(void **state)
{
    static const float p[6] = { 0, 0, 0, 1, 2, 3 };
    unsigned char bin[512];
    size_t n;
    jmf_frame fr;
    char err[512];
    (void)state;
    /* ascii with an element before the vertices and a list after them */
    expect_points("ply\nformat ascii 1.0\ncomment c\nelement camera 1\nproperty float a\nproperty list uchar int l\n"
                  "element vertex 2\nproperty uchar r\nproperty double x\nproperty double y\nproperty double z\n"
                  "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                  "7 3 1 2 3\n255 0 0 0\n0 1 2 3\n3 0 1 1\n",
                  "a.ply", 2, p);
    /* big-endian binary with int16 coordinates and an id */
    {
        static const char hdr[] = "ply\r\nformat binary_big_endian 1.0\r\nelement vertex 2\r\nproperty short x\r\n"
                                  "property short y\r\nproperty short z\r\nproperty uint id\r\nend_header\r\n";
        static const unsigned char body[] = { 0, 0, 0, 0, 0, 0, 0, 0, 0, 9, 0, 1, 0, 2, 0, 3, 0, 0, 0, 10 };
        n = strlen(hdr);
        memcpy(bin, hdr, n);
        memcpy(bin + n, body, sizeof body);
        assert_int_equal(rd(bin, n + sizeof body, "b.ply", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_OK);
        assert_int_equal(fr.count, 2);
        assert_memory_equal(fr.xyz, p, sizeof p);
        assert_non_null(fr.ids);
        assert_int_equal(fr.ids[0], 9);
        assert_int_equal(fr.ids[1], 10);
        jmf_frame_free(&fr);
        assert_int_equal(rd(bin, n + sizeof body - 1, "b.ply", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
        assert_non_null(strstr(err, "b.ply: byte "));
    }
    expect_points("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                  "end_header\n",
                  "empty.ply", 0, NULL);
    expect_fail("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n",
                "noz.ply", JMF_E_FORMAT, "noz.ply:3:", "'z'");
    expect_fail("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                "end_header\n1 2 3\n4 five 6\n",
                "txt.ply", JMF_E_FORMAT, "txt.ply:9:", "'five'");
    expect_fail("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "hdr.ply", JMF_E_FORMAT, "hdr.ply:",
                "end_header");
}

static const char vtu_head[] = "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                               "byte_order=\"LittleEndian\" header_type=\"UInt32\"%s>\n<UnstructuredGrid>\n"
                               "<Piece NumberOfPoints=\"2\" NumberOfCells=\"0\">\n<Points>\n"
                               "<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"%s\">\n";
static const char vtu_tail[] = "\n</DataArray>\n</Points>\n<PointData><DataArray type=\"Int32\" Name=\"id\" "
                               "format=\"ascii\">4 5</DataArray></PointData>\n</Piece>\n</UnstructuredGrid>\n"
                               "</VTKFile>\n";

static size_t b64(const unsigned char *s, size_t n, char *out)
{
    static const char t[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t i, k = 0;
    for (i = 0; i < n; i += 3) {
        unsigned v = (unsigned)s[i] << 16 | (i + 1 < n ? (unsigned)s[i + 1] << 8 : 0) | (i + 2 < n ? s[i + 2] : 0);
        out[k++] = t[v >> 18 & 63];
        out[k++] = t[v >> 12 & 63];
        out[k++] = i + 1 < n ? t[v >> 6 & 63] : '=';
        out[k++] = i + 2 < n ? t[v & 63] : '=';
    }
    out[k] = 0;
    return k;
}

static void check_vtu(const char *doc, const char *name)
{
    static const float p[6] = { 0, 0, 0, 1, 2, 3 };
    jmf_frame fr;
    char err[512];
    jmf_status st = rds(doc, name, 0, &fr, err);
    if (st) fail_msg("%s: %s", name, err);
    assert_int_equal(fr.count, 2);
    assert_memory_equal(fr.xyz, p, sizeof p);
    assert_non_null(fr.ids);
    assert_int_equal(fr.ids[1], 5);
    jmf_frame_free(&fr);
}

static void test_vtu_inline(void **state)
{
    static const float p[6] = { 0, 0, 0, 1, 2, 3 };
    char doc[4096], enc[512], enc2[512];
    unsigned char raw[64], z[128];
    uLongf zn = sizeof z;
    uint32_t h[4];
    (void)state;
    /* ascii */
    snprintf(doc, sizeof doc, vtu_head, "", "ascii");
    strcat(doc, "0 0 0\n1 2 3");
    strcat(doc, vtu_tail);
    check_vtu(doc, "ascii.vtu");
    /* base64, header and data in one encoding */
    h[0] = sizeof p;
    memcpy(raw, h, 4);
    memcpy(raw + 4, p, sizeof p);
    b64(raw, 4 + sizeof p, enc);
    snprintf(doc, sizeof doc, vtu_head, "", "binary");
    strcat(doc, enc);
    strcat(doc, vtu_tail);
    check_vtu(doc, "b64.vtu");
    /* base64, header and data encoded separately (as VTK does with compression) */
    b64(raw, 4, enc);
    b64((const unsigned char *)p, sizeof p, enc2);
    snprintf(doc, sizeof doc, vtu_head, "", "binary");
    strcat(doc, enc);
    strcat(doc, enc2);
    strcat(doc, vtu_tail);
    check_vtu(doc, "b64split.vtu");
    /* zlib: one block */
    assert_int_equal(compress(z, &zn, (const Bytef *)p, sizeof p), Z_OK);
    h[0] = 1;
    h[1] = sizeof p;
    h[2] = sizeof p;
    h[3] = (uint32_t)zn;
    b64((const unsigned char *)h, 16, enc);
    b64(z, zn, enc2);
    snprintf(doc, sizeof doc, vtu_head, " compressor=\"vtkZLibDataCompressor\"", "binary");
    strcat(doc, enc);
    strcat(doc, enc2);
    strcat(doc, vtu_tail);
    check_vtu(doc, "zlib.vtu");
    /* a wrong compressed size is an error, not a crash */
    h[3] = (uint32_t)zn - 3;
    b64((const unsigned char *)h, 16, enc);
    snprintf(doc, sizeof doc, vtu_head, " compressor=\"vtkZLibDataCompressor\"", "binary");
    strcat(doc, enc);
    strcat(doc, enc2);
    strcat(doc, vtu_tail);
    expect_fail(doc, "badz.vtu", JMF_E_FORMAT, "badz.vtu: byte ", NULL);
    /* too few ascii values */
    snprintf(doc, sizeof doc, vtu_head, "", "ascii");
    strcat(doc, "0 0 0\n1 2");
    strcat(doc, vtu_tail);
    expect_fail(doc, "few.vtu", JMF_E_FORMAT, "few.vtu: byte ", "expected 6 values");
    /* no end tag */
    snprintf(doc, sizeof doc, vtu_head, "", "ascii");
    strcat(doc, "0 0 0\n1 2 3</DataArray></Points></Piece>");
    expect_fail(doc, "cut.vtu", JMF_E_FORMAT, "cut.vtu: byte ", "</VTKFile>");
    /* zero points */
    expect_points("<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"0\"><Points>"
                  "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\"></DataArray></Points>"
                  "</Piece></UnstructuredGrid></VTKFile>",
                  "empty.vtu", 0, NULL);
}

/* ------------------------------------------------- truncation and damage */

/*
 * Prefixes that are themselves complete files of the format, which a reader
 * must accept: XYZ prefixes of whole triples; VTK prefixes that end between
 * sections (a VTK file may end after any section); any prefix that only
 * drops trailing blanks.
 */
static int complete_prefix(jmf_input_format f, const unsigned char *d, size_t size, size_t len)
{
    static const char *const kws[] = { "CELLS", "CELL_TYPES", "POINT_DATA", "CELL_DATA", "FIELD", "SCALARS",
                                       "LOOKUP_TABLE", "VECTORS", "METADATA" };
    size_t i = len, k;
    while (i < size && (d[i] == ' ' || d[i] == '\n' || d[i] == '\r' || d[i] == '\t')) i++;
    if (i == size) return 1;
    if (f == JMF_IN_XYZ) return len % 12 == 0;
    if (f != JMF_IN_VTK || (len > 0 && d[len - 1] != '\n' && i == len)) return 0;
    for (k = 0; k < sizeof kws / sizeof kws[0]; k++) {
        size_t n = strlen(kws[k]);
        if (size - i > n && memcmp(d + i, kws[k], n) == 0 && (d[i + n] == ' ' || d[i + n] == '\n')) return 1;
    }
    return 0;
}

/* Every prefix (all of them for small files; for big ones the first and last 400 and ~1500 in between). */
static void check_prefixes(const char *rel, jmf_input_format f, size_t full_count)
{
    size_t size, len, stride, tested = 0, accepted = 0;
    unsigned char *d;
    char name[600];
    d = slurp_shared(rel, &size);
    snprintf(name, sizeof name, "%s", rel);
    stride = size <= 40000 ? 1 : size / 1500;
    for (len = 1; len < size; len++) {
        jmf_frame fr;
        char err[512];
        jmf_status st;
        if (len > 400 && len + 400 < size && len % stride != 0) continue;
        tested++;
        st = rd(d, len, name, JMF_IN_AUTO, 0, &fr, err, sizeof err);
        if (st == JMF_OK) {
            if (!complete_prefix(f, d, size, len))
                fail_msg("%s: prefix of %zu of %zu bytes accepted with %zu particles", rel, len, size, fr.count);
            if (f == JMF_IN_VTK) assert_int_equal(fr.count, full_count);
            accepted++;
            jmf_frame_free(&fr);
            continue;
        }
        if (st != JMF_E_FORMAT)
            fail_msg("%s: prefix of %zu bytes: status %d (%s), expected JMF_E_FORMAT", rel, len, (int)st, err);
        check_message(err, name);
        assert_null(fr.xyz);
    }
    print_message("%s: %zu prefixes tested, %zu complete files among them\n", rel, tested, accepted);
    free(d);
}

static void test_truncated_prefixes(void **state)
{
    (void)state;
    NEED_SHARED();
    check_prefixes("derived/dam_break_frame_23_24389_particles.xyz", JMF_IN_XYZ, 24389);
    check_prefixes("splashsurf/ParticleData_Random_1000.vtk", JMF_IN_VTK, 1000);
    check_prefixes("splashsurf/free_particles_125_particles.vtk", JMF_IN_VTK, 125);
    check_prefixes("splashsurf/bunny_frame_14_7705_particles.vtk", JMF_IN_VTK, 7706);
    check_prefixes("partio_testfiles/base.bgeo", JMF_IN_BGEO, 5);
    check_prefixes("partio_testfiles/json.bgeo", JMF_IN_BGEO, 5);
    check_prefixes("partio_testfiles/test.bgeo", JMF_IN_BGEO, 5);
    check_prefixes("partio_testfiles/scatter.bgeo", JMF_IN_BGEO, 25);
    check_prefixes("splashsurf/dam_break_frame_9_6859_particles.bgeo", JMF_IN_BGEO, 6859);
    check_prefixes("splishsplash_models/bunny.bgeo", JMF_IN_BGEO, 7706);
    check_prefixes("splashsurf/cube.ply", JMF_IN_PLY, 24);
    check_prefixes("splashsurf/cube_8_particles.vtu", JMF_IN_VTU, 8);
    check_prefixes("splashsurf/fluid_250_particles.vtu", JMF_IN_VTU, 250);
    check_prefixes("splashsurf/fluid_encoded_250_particles.vtu", JMF_IN_VTU, 250);
}

static void test_truncated_raw_bgeo_inside_gzip(void **state)
{
    /* prefixes of the decompressed bunny (points, then a particle primitive) re-gzipped */
    size_t size, n, len;
    unsigned char *gz, *raw;
    jmf_frame fr;
    char err[512];
    z_stream zs;
    (void)state;
    NEED_SHARED();
    gz = slurp_shared("splishsplash_models/bunny.bgeo", &size);
    raw = malloc(1 << 20);
    assert_non_null(raw);
    memset(&zs, 0, sizeof zs);
    assert_int_equal(inflateInit2(&zs, 16 + MAX_WBITS), Z_OK);
    zs.next_in = gz;
    zs.avail_in = (uInt)size;
    zs.next_out = raw;
    zs.avail_out = 1 << 20;
    assert_int_equal(inflate(&zs, Z_FINISH), Z_STREAM_END);
    n = zs.total_out;
    inflateEnd(&zs);
    for (len = n - 300; len < n; len++) { /* the primitive and the end marker */
        size_t zn;
        unsigned char *z = gzip_mem(raw, len, &zn);
        assert_int_equal(rd(z, zn, "cut.bgeo", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
        assert_non_null(strstr(err, "(decompressed)"));
        free(z);
    }
    free(raw);
    free(gz);
}

static void test_corrupt_gzip(void **state)
{
    size_t size, i;
    unsigned char *d;
    jmf_frame fr;
    char err[512];
    const char *p;
    (void)state;
    NEED_SHARED();
    d = slurp_shared("splashsurf/dam_break_frame_9_6859_particles.bgeo", &size);
    for (i = size / 2; i < size / 2 + 16; i++) d[i] ^= 0x5a;
    p = tmp_path("corrupt.bgeo");
    write_file(p, d, size);
    assert_int_equal(jmf_read_particles(p, NULL, &fr, err, sizeof err), JMF_E_FORMAT);
    check_message(err, p);
    assert_non_null(strstr(err, "gzip"));
    assert_non_null(strstr(err, ": byte "));
    assert_null(fr.xyz);
    /* a damaged CRC in the trailer */
    free(d);
    d = slurp_shared("splashsurf/dam_break_frame_9_6859_particles.bgeo", &size);
    d[size - 6] ^= 1;
    assert_int_equal(rd(d, size, "crc.bgeo", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
    assert_non_null(strstr(err, "gzip"));
    /* only the magic */
    assert_int_equal(rd("\x1f\x8b", 2, "magic.gz", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
    assert_non_null(strstr(err, "truncated gzip"));
    free(d);
    unlink(p);
}

static void test_wrong_magic(void **state)
{
    jmf_frame fr;
    char err[512];
    (void)state;
    assert_int_equal(rd("Bgxx V\0\0\0\x05", 10, "a.bgeo", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
    assert_non_null(strstr(err, "a.bgeo: byte 0:"));
    assert_non_null(strstr(err, "magic"));
    expect_fail("plx\nformat ascii 1.0\n", "a.ply", JMF_E_FORMAT, "a.ply:1:", "magic");
    expect_fail("# vtk DataFileVersion 3.0\n", "a.vtk", JMF_E_FORMAT, "a.vtk:1:", "expected");
    expect_fail("hello", "a.vtu", JMF_E_FORMAT, "a.vtu: byte 0:", "VTKFile");
    expect_fail("<?xml version=\"1.0\"?><html></html>", "b.vtu", JMF_E_FORMAT, "b.vtu: byte ", "expected <VTKFile>");
    expect_fail("something", "a.dat", JMF_E_UNSUPPORTED, "a.dat", "unknown particle format");
    expect_fail("\x7fNSJ....", "new.bgeo", JMF_E_UNSUPPORTED, "new.bgeo", "bhclassic");
    /* the magic wins over the extension */
    expect_points("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n1 2 3\n", "really_vtk.csv", 1,
                  NULL);
}

/* A BGEO header with the given point count and no attributes, then `npts` points and the end marker. */
static size_t make_bgeo(unsigned char *b, int32_t count, size_t npts)
{
    size_t n = 0, i, k;
    int32_t counts[8] = { count, 0, 0, 0, 0, 0, 0, 0 };
    memcpy(b, "BgeoV\0\0\0\x05", 9);
    n = 9;
    for (i = 0; i < 8; i++, n += 4) {
        uint32_t u = (uint32_t)counts[i];
        b[n] = (unsigned char)(u >> 24); b[n + 1] = (unsigned char)(u >> 16);
        b[n + 2] = (unsigned char)(u >> 8); b[n + 3] = (unsigned char)u;
    }
    for (i = 0; i < npts; i++)
        for (k = 0; k < 4; k++, n += 4) { /* 1.0f = 3f800000 */
            b[n] = 0x3f; b[n + 1] = 0x80; b[n + 2] = 0; b[n + 3] = 0;
        }
    b[n++] = 0x00;
    b[n++] = 0xff;
    return n;
}

static void test_counts_too_large_and_overflow(void **state)
{
    unsigned char b[256];
    size_t n;
    jmf_frame fr;
    char err[512];
    (void)state;
    n = make_bgeo(b, 3, 3);
    assert_int_equal(rd(b, n, "ok.bgeo", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_OK);
    assert_int_equal(fr.count, 3);
    jmf_frame_free(&fr);
    n = make_bgeo(b, 0, 0);
    assert_int_equal(rd(b, n, "zero.bgeo", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_OK);
    assert_int_equal(fr.count, 0);
    n = make_bgeo(b, 1000, 3);
    assert_int_equal(rd(b, n, "big.bgeo", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
    assert_non_null(strstr(err, "big.bgeo: byte 41:"));
    assert_non_null(strstr(err, "1000 points"));
    n = make_bgeo(b, INT32_MAX, 3);
    assert_int_equal(rd(b, n, "max.bgeo", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
    n = make_bgeo(b, -5, 3);
    assert_int_equal(rd(b, n, "neg.bgeo", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
    assert_non_null(strstr(err, "neg.bgeo: byte 9:"));
    assert_non_null(strstr(err, "negative point count"));

    EXPECT_FAIL_LIT("# vtk DataFile Version 4.1\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 1000000 float\n\x3f\x80\0\0",
                "big.vtk", JMF_E_FORMAT, "big.vtk: byte ", "truncated POINTS");
    expect_fail("# vtk DataFile Version 4.1\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 18446744073709551615 float\n",
                "ovf.vtk", JMF_E_FORMAT, "ovf.vtk: byte ", "overflow");
    expect_fail("# vtk DataFile Version 4.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 99999999999999999999999 float\n",
                "ovf2.vtk", JMF_E_FORMAT, "ovf2.vtk:5:", "point count");
    EXPECT_FAIL_LIT("ply\nformat binary_little_endian 1.0\nelement vertex 6148914691236517206\nproperty float x\n"
                "property float y\nproperty float z\nend_header\n\0\0\0\0",
                "ovf.ply", JMF_E_FORMAT, "ovf.ply: byte ", "truncated");
    EXPECT_FAIL_LIT("ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty float x\nproperty float y\n"
                "property float z\nend_header\n\0\0\0\0\0\0\0\0\0\0\0\0",
                "big.ply", JMF_E_FORMAT, "big.ply: byte ", "100 rows");
    EXPECT_FAIL_LIT("<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt64\"><UnstructuredGrid>"
                "<Piece NumberOfPoints=\"6148914691236517206\"><Points><DataArray type=\"Float64\" "
                "NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/></Points></Piece></UnstructuredGrid>"
                "<AppendedData encoding=\"raw\">_\x10\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0</AppendedData></VTKFile>",
                "ovf.vtu", JMF_E_FORMAT, "ovf.vtu: byte ", "overflow");
    EXPECT_FAIL_LIT("<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>"
                "<Piece NumberOfPoints=\"1000\"><Points><DataArray type=\"Float32\" "
                "NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/></Points></Piece></UnstructuredGrid>"
                "<AppendedData encoding=\"raw\">_\x0c\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0</AppendedData></VTKFile>",
                "big.vtu", JMF_E_FORMAT, "big.vtu: byte ", "12000");
}

static void test_nan_binary(void **state)
{
    unsigned char b[256];
    size_t n = make_bgeo(b, 3, 3);
    jmf_frame fr;
    char err[512];
    (void)state;
    b[41 + 16 + 4] = 0x7f; /* y of point 1 = 0x7f800000: +inf */
    b[41 + 16 + 5] = 0x80;
    assert_int_equal(rd(b, n, "inf.bgeo", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
    assert_non_null(strstr(err, "inf.bgeo: byte 57:"));
    assert_non_null(strstr(err, "non-finite"));
    assert_int_equal(rd(b, n, "inf.bgeo", JMF_IN_AUTO, 1, &fr, err, sizeof err), JMF_OK);
    assert_int_equal(fr.count, 2);
    assert_int_equal(fr.dropped, 1);
    jmf_frame_free(&fr);
}

static void test_paths(void **state)
{
    jmf_frame fr;
    char err[512];
    const char *dir;
    (void)state;
    assert_int_equal(jmf_read_particles("/nonexistent/dir/frame.bgeo", NULL, &fr, err, sizeof err), JMF_E_IO);
    check_message(err, "/nonexistent/dir/frame.bgeo");
    assert_null(fr.xyz);
    dir = tmp_path("");
    assert_int_equal(jmf_read_particles(dir, NULL, &fr, err, sizeof err), JMF_E_IO);
    assert_non_null(strstr(err, "directory"));
    check_message(err, dir);
    write_file(tmp_path("empty.vtk"), "", 0);
    assert_int_equal(jmf_read_particles(tmp_path("empty.vtk"), NULL, &fr, err, sizeof err), JMF_E_FORMAT);
    assert_non_null(strstr(err, "empty.vtk: empty file (0 bytes)"));
    unlink(tmp_path("empty.vtk"));
    /* a tiny error buffer is still terminated */
    {
        char small[8];
        memset(small, 'x', sizeof small);
        assert_int_equal(jmf_read_particles("/nonexistent/x.csv", NULL, &fr, small, sizeof small), JMF_E_IO);
        assert_int_equal(strlen(small), 7);
    }
}

static void test_gzip_detection_and_limits(void **state)
{
    const char *csv = "x,y,z\n1,2,3\n";
    size_t zn, i;
    unsigned char *z, *zeros;
    jmf_frame fr;
    char err[512];
    jmf_read_options o;
    (void)state;
    z = gzip_mem(csv, strlen(csv), &zn);
    assert_int_equal(rd(z, zn, "f.csv.gz", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_OK);
    assert_int_equal(fr.count, 1);
    assert_int_equal(fr.compressed, 1);
    assert_int_equal(fr.format, JMF_IN_CSV);
    jmf_frame_free(&fr);
    assert_int_equal(rd(z, zn, "f.gz", JMF_IN_CSV, 0, &fr, err, sizeof err), JMF_OK);
    jmf_frame_free(&fr);
    free(z);
    /* a bomb: 16 MiB of zeros is a few KiB of gzip */
    zeros = calloc(16 << 20, 1);
    assert_non_null(zeros);
    z = gzip_mem(zeros, 16 << 20, &zn);
    assert_true(zn < 100000);
    memset(&o, 0, sizeof o);
    o.max_bytes = 1 << 20;
    assert_int_equal(jmf_read_particles_mem(z, zn, "bomb.xyz", &o, &fr, err, sizeof err), JMF_E_LIMIT);
    assert_non_null(strstr(err, "max_bytes"));
    /* without a limit the zeros are 16 MiB / 12 of particles at the origin... but not a multiple of 12 */
    assert_int_equal(rd(z, zn, "bomb.xyz", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
    assert_non_null(strstr(err, "(decompressed)"));
    free(z);
    free(zeros);
    /* plain input over max_bytes */
    o.max_bytes = 4;
    assert_int_equal(jmf_read_particles_mem(csv, strlen(csv), "big.csv", &o, &fr, err, sizeof err), JMF_E_LIMIT);
    /* two gzip members are one stream (as cat a.gz b.gz makes) */
    {
        size_t n1, n2;
        unsigned char *a = gzip_mem("1 2 3\n", 6, &n1), *b = gzip_mem("4 5 6\n", 6, &n2), *c = malloc(n1 + n2 + 4);
        memcpy(c, a, n1);
        memcpy(c + n1, b, n2);
        assert_int_equal(rd(c, n1 + n2, "two.csv", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_OK);
        assert_int_equal(fr.count, 2);
        jmf_frame_free(&fr);
        memcpy(c + n1 + n2, "junk", 4);
        assert_int_equal(rd(c, n1 + n2 + 4, "junk.csv", JMF_IN_AUTO, 0, &fr, err, sizeof err), JMF_E_FORMAT);
        assert_non_null(strstr(err, "after the end of the gzip stream"));
        free(a); free(b); free(c);
    }
    for (i = 0; i <= JMF_IN_PLY; i++)
        assert_int_equal(jmf_input_format_parse(jmf_input_format_name((jmf_input_format)i)), (int)i);
    assert_int_equal(jmf_input_format_parse("BGEO"), JMF_IN_BGEO);
    assert_int_equal(jmf_input_format_parse("obj"), -1);
    assert_int_equal(jmf_input_format_parse(NULL), -1);
    jmf_frame_free(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shared_counts),
        cmocka_unit_test(test_shared_every_particle_file_listed),
        cmocka_unit_test(test_shared_cross_format),
        cmocka_unit_test(test_shared_spot_values),
        cmocka_unit_test(test_samples_real),
        cmocka_unit_test(test_csv_header_and_separators),
        cmocka_unit_test(test_csv_comments_blank_crlf),
        cmocka_unit_test(test_csv_column_names),
        cmocka_unit_test(test_csv_errors),
        cmocka_unit_test(test_csv_nan),
        cmocka_unit_test(test_csv_empty_and_header_only),
        cmocka_unit_test(test_xyz_sizes),
        cmocka_unit_test(test_vtk_ascii_and_variants),
        cmocka_unit_test(test_ply_variants),
        cmocka_unit_test(test_vtu_inline),
        cmocka_unit_test(test_truncated_prefixes),
        cmocka_unit_test(test_truncated_raw_bgeo_inside_gzip),
        cmocka_unit_test(test_corrupt_gzip),
        cmocka_unit_test(test_wrong_magic),
        cmocka_unit_test(test_counts_too_large_and_overflow),
        cmocka_unit_test(test_nan_binary),
        cmocka_unit_test(test_paths),
        cmocka_unit_test(test_gzip_detection_and_limits),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    if (tmpdir[0]) rmdir(tmpdir);
    return rc;
}
