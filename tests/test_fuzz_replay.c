/* test_fuzz_replay.c - replays the saved fuzz corpus and crash inputs (tests/fuzz/{corpus,crashes}/<fmt>/) through the readers, and mesh/ through the meshing target. */
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

#include "../formats/reader.h"
#include "util/files.h"

/* the meshing target's body, its broken invariants failing the test */
static const char *mesh_input; /* the file being replayed, for messages */
#define FUZZ_MESH_FAIL(what) fail_msg("%s: %s", mesh_input, what)
#include "fuzz/fuzz_mesh_common.h"

static size_t replayed;

/* The repository root: JETMESH_ROOT, else the current directory. */
static const char *repo_root(void)
{
    const char *r = getenv("JETMESH_ROOT");
    return r && *r ? r : ".";
}

/* The format a folder name stands for; AUTO for "auto" (and anything else). */
static jmf_input_format dir_format(const char *name)
{
    int f = jmf_input_format_parse(name);
    return f > 0 ? (jmf_input_format)f : JMF_IN_AUTO;
}

/* One input, as the fuzz target of its folder reads it: a valid status and a consistent frame. */
static void replay_one(const char *path, const unsigned char *d, size_t n, jmf_input_format f, const char *name)
{
    int drop;
    /* 0, 1: drop_invalid off/on; 2, 3: the same with every attribute asked for */
    for (drop = 0; drop < 4; drop++) {
        jmf_read_options o;
        jmf_frame fr;
        char err[512];
        jmf_status st;
        size_t i;
        memset(&o, 0, sizeof o);
        o.format = f;
        o.drop_invalid = drop & 1;
        o.attributes = drop >= 2 ? "all" : NULL;
        o.max_bytes = 64u << 20; /* as in tests/fuzz/fuzz_common.h */
        st = jmf_read_particles_mem(d, n, name, &o, &fr, err, sizeof err);
        if ((int)st < JMF_OK || st > JMF_E_LIMIT) fail_msg("%s: status %d out of range", path, (int)st);
        if (st != JMF_OK) {
            if (strncmp(err, name, strlen(name)) != 0 || strchr(err, '\n'))
                fail_msg("%s: malformed message '%s'", path, err);
            if (fr.xyz || fr.ids || fr.count) fail_msg("%s: failed read left a frame", path);
            continue;
        }
        if ((fr.count == 0) != (fr.xyz == NULL)) fail_msg("%s: count %zu with xyz %p", path, fr.count, (void *)fr.xyz);
        for (i = 0; i < 3 * fr.count; i++)
            if (!isfinite(fr.xyz[i])) fail_msg("%s: non-finite coordinate %zu", path, i);
        if (!(drop & 1) && fr.dropped) fail_msg("%s: dropped without drop_invalid", path);
        for (i = 0; i < fr.attribute_count; i++) {
            const jmf_attribute *a = &fr.attributes[i];
            size_t k;
            if (a->components < 1 || a->components > 4 || !a->name || !*a->name)
                fail_msg("%s: attribute %zu malformed", path, i);
            for (k = 0; k < fr.count * (size_t)a->components; k++)
                if (!isfinite(a->values[k])) fail_msg("%s: attribute %s value %zu not finite", path, a->name, k);
        }
        if (drop < 2 && (fr.attribute_count || fr.array_names)) fail_msg("%s: attributes not asked for", path);
        jmf_frame_free(&fr);
    }
}

static size_t replay_dir(const char *kind)
{
    char top[4096];
    DIR *d;
    struct dirent *e;
    size_t files = 0;
    snprintf(top, sizeof top, "%s/tests/fuzz/%s", repo_root(), kind);
    d = opendir(top);
    if (!d) return 0;
    while ((e = readdir(d)) != NULL) {
        char sub[4400];
        DIR *sd;
        struct dirent *fe;
        jmf_input_format f;
        if (e->d_name[0] == '.') continue;
        snprintf(sub, sizeof sub, "%s/%s", top, e->d_name);
        sd = opendir(sub);
        if (!sd) continue;
        f = dir_format(e->d_name);
        while ((fe = readdir(sd)) != NULL) {
            char path[4800];
            struct stat sb;
            unsigned char *buf;
            size_t n;
            if (fe->d_name[0] == '.') continue;
            snprintf(path, sizeof path, "%s/%s", sub, fe->d_name);
            if (stat(path, &sb) != 0 || !S_ISREG(sb.st_mode)) continue;
            buf = test_read_file(path, &n);
            assert_non_null(buf);
            if (strcmp(e->d_name, "mesh") == 0) {
                /* as fuzz_mesh: CSV meshed at bounded parameters */
                mesh_input = path;
                fuzz_mesh(buf, n);
            } else if (f == JMF_IN_AUTO) {
                /* as fuzz_auto: by magic, then by two extensions */
                replay_one(path, buf, n, f, "frame.unknown");
                replay_one(path, buf, n, f, "frame.csv.gz");
                replay_one(path, buf, n, f, "frame.xyz");
            } else {
                char name[64];
                snprintf(name, sizeof name, "particles.%s", jmf_input_format_name(f));
                replay_one(path, buf, n, f, name);
            }
            free(buf);
            files++;
        }
        closedir(sd);
    }
    closedir(d);
    return files;
}

static void test_replay_corpus(void **state)
{
    size_t n;
    (void)state;
    n = replay_dir("corpus");
    replayed += n;
    print_message("replayed %zu corpus inputs\n", n);
    if (n == 0) {
        print_message("no tests/fuzz/corpus here (run from the repository root or set JETMESH_ROOT); skipping\n");
        skip();
    }
}

static void test_replay_crashes(void **state)
{
    size_t n;
    (void)state;
    n = replay_dir("crashes");
    print_message("replayed %zu crash inputs\n", n);
    if (n == 0) skip();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_replay_corpus),
        cmocka_unit_test(test_replay_crashes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
