/* test_text_read.c - the CLI's JSON and CSV readers (cli/text/): decoding, nesting, quoting, and errors that name the line. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdlib.h>
#include <string.h>

#include "../cli/text/csv_read.h"
#include "../cli/text/json_read.h"

static char err[256];

static text_cursor at(const char *text)
{
    text_cursor r = {"t.json", text, text + strlen(text), text, err, sizeof err};
    err[0] = '\0';
    return r;
}

static void test_json_string_escapes(void **state)
{
    (void)state;
    /* escapes, a surrogate pair (U+1F600 in 4 bytes), a lone surrogate */
    text_cursor r = at("  \"a\\n\\t\\\"\\/\\u00e9\\ud83d\\ude00\\ud800x\"");
    char *s = NULL;
    assert_int_equal(json_string(&r, &s), 0);
    assert_string_equal(s, "a\n\t\"/\xc3\xa9\xf0\x9f\x98\x80\xef\xbf\xbdx");
    assert_true(r.p == r.end);
    free(s);
    r = at("\n\n\"bad \\u12G4\"");
    assert_int_equal(json_string(&r, &s), -1);
    assert_string_equal(err, "t.json:3: a bad \\u escape in a JSON string");
    r = at("\"open");
    assert_int_equal(json_string(&r, &s), -1);
    assert_string_equal(err, "t.json:1: a JSON string does not end");
}

static int count_member(text_cursor *r, const char *key, void *user)
{
    char *t;
    int cont;
    if (json_scalar(r, &t, &cont) != 0)
        return -1;
    if (cont)
        return json_skip_container(r);
    /* null gives NULL; numbers and literals their text */
    if (strcmp(key, "n") == 0)
        assert_null(t);
    if (strcmp(key, "x") == 0)
        assert_string_equal(t, "-1.5e3");
    free(t);
    (*(int *)user)++;
    return 0;
}

static void test_json_members_and_skip(void **state)
{
    (void)state;
    int n = 0;
    text_cursor r = at("{\"n\": null, \"x\": -1.5e3, \"deep\": [[{\"a\": [1, {}]}], []], \"t\": true}");
    assert_int_equal(json_members(&r, count_member, &n), 0);
    assert_int_equal(n, 3); /* the scalars; "deep" skipped whole */
    assert_true(r.p == r.end);
    /* 64 levels are skipped, 70 refused */
    char deep[256];
    for (int depth = 64; depth <= 70; depth += 6) {
        memset(deep, '[', (size_t)depth);
        memset(deep + depth, ']', (size_t)depth);
        deep[2 * depth] = '\0';
        r = at(deep);
        assert_int_equal(json_skip(&r), depth == 64 ? 0 : -1);
    }
    assert_string_equal(err, "t.json:1: JSON nested too deeply");
    r = at("{\"a\" 1}");
    n = 0;
    assert_int_equal(json_members(&r, count_member, &n), -1);
    assert_string_equal(err, "t.json:1: expected ':' in the JSON");
}

static int sum_element(text_cursor *r, void *user)
{
    char *t;
    int cont;
    if (json_scalar(r, &t, &cont) != 0 || cont || !t)
        return -1;
    *(long *)user += strtol(t, NULL, 10);
    free(t);
    return 0;
}

static void test_json_elements(void **state)
{
    (void)state;
    long sum = 0;
    text_cursor r = at("[1, 2,\n 3 ]");
    assert_int_equal(json_elements(&r, sum_element, &sum), 0);
    assert_int_equal(sum, 6);
    r = at("[]");
    assert_int_equal(json_elements(&r, sum_element, &sum), 0);
    r = at("[1,\n2}");
    assert_int_equal(json_elements(&r, sum_element, &sum), -1);
    assert_string_equal(err, "t.json:2: expected ']' in the JSON");
}

static void test_csv_quoting(void **state)
{
    (void)state;
    text_cursor r = at("1,\"a,b\",\"say \"\"hi\"\"\",\"two\nlines\"\r\nx,,\"\"\n");
    char **f = NULL;
    size_t n = 0;
    assert_int_equal(csv_read_line(&r, &f, &n), 0);
    assert_int_equal(n, 4);
    assert_string_equal(f[0], "1");
    assert_string_equal(f[1], "a,b");
    assert_string_equal(f[2], "say \"hi\"");
    assert_string_equal(f[3], "two\nlines");
    csv_free_fields(f, n);
    assert_int_equal(csv_read_line(&r, &f, &n), 0); /* CRLF ended the line */
    assert_int_equal(n, 3);
    assert_string_equal(f[0], "x");
    assert_string_equal(f[1], "");
    assert_string_equal(f[2], "");
    csv_free_fields(f, n);
    assert_true(r.p == r.end);
    r = at("a,b\n1,\"open\n");
    assert_int_equal(csv_read_line(&r, &f, &n), 0);
    csv_free_fields(f, n);
    assert_int_equal(csv_read_line(&r, &f, &n), -1);
    assert_null(f);
    assert_string_equal(err, "t.json:2: a quoted field does not end");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_json_string_escapes),
        cmocka_unit_test(test_json_members_and_skip),
        cmocka_unit_test(test_json_elements),
        cmocka_unit_test(test_csv_quoting),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
