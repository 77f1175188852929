/* test_sequence.c - cmocka tests for the CLI's frame patterns, --frames ranges and output naming. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The CLI is not an archive the tests link with: compile its sequence logic in. */
#include "../cli/sequence.c"

static char tmpdir[256];

static void touch(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs("0,0,0\n", f);
    fclose(f);
}

static int setup_dir(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/jetmesh-test-seq-XXXXXX");
    if (!mkdtemp(tmpdir))
        return -1;
    return 0;
}

static int teardown_dir(void **state)
{
    (void)state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    return system(cmd) == 0 ? 0 : -1;
}

static char *pat(const char *name)
{
    static char buf[512];
    snprintf(buf, sizeof buf, "%s/%s", tmpdir, name);
    return buf;
}

static void test_natural_order(void **state)
{
    (void)state;
    assert_true(seq_natural_cmp("frame_2", "frame_10") < 0);
    assert_true(seq_natural_cmp("frame_10", "frame_2") > 0);
    assert_true(seq_natural_cmp("frame_10", "frame_10") == 0);
    assert_true(seq_natural_cmp("a", "a1") < 0);
    assert_true(seq_natural_cmp("a9b", "a10a") < 0);
    assert_true(seq_natural_cmp("x007", "x7") != 0); /* equal value, still a total order */
    assert_true(seq_natural_cmp("x007", "x8") < 0);
}

static void test_range_parse(void **state)
{
    (void)state;
    seq_range r;
    char err[256];
    assert_int_equal(seq_range_parse("0:9", &r, err, sizeof err), 0);
    assert_int_equal(r.start, 0);
    assert_int_equal(r.end, 9);
    assert_int_equal(r.step, 1);
    assert_true(r.set);
    assert_int_equal(seq_range_parse("10:20:5", &r, err, sizeof err), 0);
    assert_true(seq_range_contains(&r, 10));
    assert_true(seq_range_contains(&r, 15));
    assert_true(seq_range_contains(&r, 20)); /* END is inclusive */
    assert_false(seq_range_contains(&r, 12));
    assert_false(seq_range_contains(&r, 25));
    assert_false(seq_range_contains(&r, 5));
    assert_int_equal(seq_range_parse("7", &r, err, sizeof err), 0);
    assert_int_equal(r.start, 7);
    assert_int_equal(r.end, 7);
    seq_range unset = {0, 0, 1, 0};
    assert_true(seq_range_contains(&unset, 123456));

    const char *bad[] = {"", "9:0", "a:b", "0:9:0", "0:9:-1", "1:2:3:4", "-1:5",
                         "1:", ":5", "1:x", "3:4junk", "0x1:2", "1 :2"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        err[0] = 0;
        assert_int_equal(seq_range_parse(bad[i], &r, err, sizeof err), -1);
        assert_true(strlen(err) > 0);
    }
    assert_int_equal(seq_range_parse("9:0", &r, err, sizeof err), -1);
    assert_non_null(strstr(err, "inclusive"));
}

static void test_kinds(void **state)
{
    (void)state;
    assert_int_equal(seq_kind_of("frame.vtk"), SEQ_PLAIN);
    assert_int_equal(seq_kind_of("frame_{}.vtk"), SEQ_BRACES);
    assert_int_equal(seq_kind_of("frame_%04d.vtk"), SEQ_PRINTF);
    assert_int_equal(seq_kind_of("frame_%d.vtk"), SEQ_PRINTF);
    assert_int_equal(seq_kind_of("100%%_%d.vtk"), SEQ_PRINTF);
    assert_int_equal(seq_kind_of("100%.vtk"), SEQ_PLAIN);
    assert_int_equal(seq_kind_of("a_%s.vtk"), SEQ_PLAIN);
    assert_int_equal(seq_kind_of("{}_{}.vtk"), SEQ_INVALID);
    assert_int_equal(seq_kind_of("{}_%03d.vtk"), SEQ_INVALID);
    assert_true(seq_is_template("out/{}.glb"));
    assert_false(seq_is_template("out/"));
}

static void test_braces_natural_order(void **state)
{
    (void)state;
    touch("frame_10.csv");
    touch("frame_2.csv");
    touch("frame_1.csv");
    touch("frame_x.csv");
    touch("frame_.csv");
    touch("frame_3.csv.bak");
    touch("other_4.csv");
    char *in[] = {pat("frame_{}.csv")};
    seq_list l = {0};
    char err[256];
    assert_int_equal(seq_expand(in, 1, NULL, &l, err, sizeof err), 0);
    assert_int_equal(l.count, 3);
    assert_int_equal(l.items[0].index, 1);
    assert_int_equal(l.items[1].index, 2);
    assert_int_equal(l.items[2].index, 10);
    assert_string_equal(l.items[2].path, pat("frame_10.csv"));
    assert_string_equal(l.items[1].digits, "2");
    seq_list_free(&l);

    seq_range r;
    assert_int_equal(seq_range_parse("2:10", &r, err, sizeof err), 0);
    char *in2[] = {pat("frame_{}.csv")};
    assert_int_equal(seq_expand(in2, 1, &r, &l, err, sizeof err), 0);
    assert_int_equal(l.count, 2);
    assert_int_equal(l.items[0].index, 2);
    assert_int_equal(l.items[1].index, 10);
    seq_list_free(&l);
}

static void test_braces_keeps_padding(void **state)
{
    (void)state;
    touch("jet_007.csv");
    touch("jet_010.csv");
    touch("jet_008.csv");
    char *in[] = {pat("jet_{}.csv")};
    seq_list l = {0};
    char err[256];
    assert_int_equal(seq_expand(in, 1, NULL, &l, err, sizeof err), 0);
    assert_int_equal(l.count, 3);
    assert_string_equal(l.items[0].digits, "007");
    assert_int_equal(l.items[0].index, 7);
    assert_int_equal(l.items[2].index, 10);
    char *o = seq_substitute("out/m_{}.glb", l.items[0].index, l.items[0].digits);
    assert_string_equal(o, "out/m_007.glb");
    free(o);
    seq_list_free(&l);
}

static void test_printf_scan_and_range(void **state)
{
    (void)state;
    touch("p_0001.vtk");
    touch("p_0002.vtk");
    touch("p_0012.vtk");
    touch("p_12.vtk");    /* not printed by %04d */
    touch("p_00003.vtk"); /* neither */
    char *in[] = {pat("p_%04d.vtk")};
    seq_list l = {0};
    char err[256];
    assert_int_equal(seq_expand(in, 1, NULL, &l, err, sizeof err), 0);
    assert_int_equal(l.count, 3);
    assert_int_equal(l.items[0].index, 1);
    assert_int_equal(l.items[1].index, 2);
    assert_int_equal(l.items[2].index, 12);
    seq_list_free(&l);

    /* with --frames the pattern names exactly the range, existing or not */
    seq_range r;
    assert_int_equal(seq_range_parse("0:6:3", &r, err, sizeof err), 0);
    assert_int_equal(seq_expand(in, 1, &r, &l, err, sizeof err), 0);
    assert_int_equal(l.count, 3);
    assert_string_equal(l.items[0].path, pat("p_0000.vtk"));
    assert_string_equal(l.items[2].path, pat("p_0006.vtk"));
    assert_int_equal(l.items[2].index, 6);
    seq_list_free(&l);
}

static void test_errors(void **state)
{
    (void)state;
    seq_list l = {0};
    char err[512];
    char *none[] = {pat("nothing_{}.csv")};
    assert_int_equal(seq_expand(none, 1, NULL, &l, err, sizeof err), -1);
    assert_non_null(strstr(err, "no files match"));
    char *twice[] = {pat("a_{}_{}.csv")};
    assert_int_equal(seq_expand(twice, 1, NULL, &l, err, sizeof err), -1);
    char *indir[] = {"/tmp/dir_{}/a.csv"};
    assert_int_equal(seq_expand(indir, 1, NULL, &l, err, sizeof err), -1);
    assert_non_null(strstr(err, "file name"));
    assert_int_equal(l.count, 0);
    seq_list_free(&l);
}

static void test_plain_paths(void **state)
{
    (void)state;
    char *in[] = {"data/frame_0042.vtk", "data/start.csv", "x/y/z.v2.csv.gz", "b.csv"};
    seq_list l = {0};
    char err[256];
    assert_int_equal(seq_expand(in, 4, NULL, &l, err, sizeof err), 0);
    assert_int_equal(l.count, 4);
    assert_int_equal(l.items[0].index, 42); /* the number in the name */
    assert_string_equal(l.items[0].digits, "0042");
    assert_int_equal(l.items[1].index, 1); /* no number: its position */
    assert_null(l.items[1].digits);
    assert_int_equal(l.items[2].index, 2); /* "z.v2": the last run of digits */
    assert_int_equal(l.items[3].index, 3);
    seq_list_free(&l);

    seq_range r;
    assert_int_equal(seq_range_parse("40:50", &r, err, sizeof err), 0);
    assert_int_equal(seq_expand(in, 4, &r, &l, err, sizeof err), 0);
    assert_int_equal(l.count, 1);
    assert_int_equal(l.items[0].index, 42);
    seq_list_free(&l);
}

static void test_output_templates(void **state)
{
    (void)state;
    char *s = seq_substitute("out/frame_{}.glb", 12, NULL);
    assert_string_equal(s, "out/frame_12.glb");
    free(s);
    s = seq_substitute("out/frame_%04d.glb", 12, "12");
    assert_string_equal(s, "out/frame_0012.glb");
    free(s);
    s = seq_substitute("out/frame_%d.glb", 12, "0012");
    assert_string_equal(s, "out/frame_12.glb");
    free(s);
    s = seq_substitute("out/100%%_%03d.obj", 5, NULL);
    assert_string_equal(s, "out/100%_005.obj");
    free(s);
    s = seq_substitute("mesh_{}/100%.obj", 5, NULL);
    assert_string_equal(s, "mesh_5/100%.obj");
    free(s);
}

static void test_directory_naming(void **state)
{
    (void)state;
    char *s = seq_in_directory("out", "a/b/frame_1.csv", "glb");
    assert_string_equal(s, "out/frame_1.glb");
    free(s);
    s = seq_in_directory("out/", "frame_1.csv.gz", "obj");
    assert_string_equal(s, "out/frame_1.obj");
    free(s);
    s = seq_in_directory("out//", "noext", "ply");
    assert_string_equal(s, "out/noext.ply");
    free(s);
    s = seq_in_directory("/", "x.y.vtu", "vtk");
    assert_string_equal(s, "/x.y.vtk");
    free(s);
    s = seq_stem(".hidden");
    assert_string_equal(s, ".hidden");
    free(s);
    long idx = -1;
    char *digits = NULL;
    assert_false(seq_number_in_name("dir9/plain.csv", &idx, &digits));
    assert_true(seq_number_in_name("dir/run3_frame12.csv", &idx, &digits));
    assert_int_equal(idx, 12);
    assert_string_equal(digits, "12");
    free(digits);
    /* the number after "frame" wins over a later one */
    assert_true(seq_number_in_name("double_dam_break_frame_26_4732_particles.vtk", &idx, &digits));
    assert_int_equal(idx, 26);
    free(digits);
    assert_true(seq_number_in_name("Frame-0007.bgeo.gz", &idx, &digits));
    assert_int_equal(idx, 7);
    assert_string_equal(digits, "0007");
    free(digits);
    assert_true(seq_number_in_name("ParticleData_Fluid_31.vtk", &idx, &digits));
    assert_int_equal(idx, 31);
    free(digits);
    assert_true(seq_number_in_name("frames/frameA_9.csv", &idx, &digits)); /* "frameA": not followed by digits */
    assert_int_equal(idx, 9);
    free(digits);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_natural_order),
        cmocka_unit_test(test_range_parse),
        cmocka_unit_test(test_kinds),
        cmocka_unit_test(test_braces_natural_order),
        cmocka_unit_test(test_braces_keeps_padding),
        cmocka_unit_test(test_printf_scan_and_range),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_plain_paths),
        cmocka_unit_test(test_output_templates),
        cmocka_unit_test(test_directory_naming),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
