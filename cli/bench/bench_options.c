/* bench_options.c - parses the options and operands of `jetmesh bench` (scenes, input files, lists) and prints its --help. */
#include "bench_options.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../formats/writer.h"
#include "../mesh_options.h"
#include "../numbers.h"
#include "../options.h"
#include "../platform.h"
#include "../scenes.h"
#include "../select_options.h"

#define CMD "bench"

/* The meshing options in bench's --help, in this order. */
static const char *const mesh_names[] = {"field", "method", "radius", "cube-size", "smoothing-length",
                                         "threshold", "link-distance", "smooth", "particle-aabb-min",
                                         "threads", NULL};

static void bench_help(FILE *f)
{
    fputs(
        "Usage: jetmesh bench [options] [SCENE | INPUT]...\n"
        "Times the library: meshes each case repeatedly on one reused context and\n"
        "prints the median and spread of the total and of every stage.\n"
        "\n"
        "Cases: every input x field x method x cube size x templates x threads.\n"
        "Inputs are synthetic scenes or particle files (any format convert reads);\n"
        "without any, the suite is: jet block:100000 spray:10000.\n"
        "  jet | jet:F         the 125-particle liquid jet, frame F (default 99)\n"
        "  block:N | block N   N particles on a jittered lattice of spacing 2R\n"
        "  spray:N | spray N   N isolated droplets (run with templates on and off)\n"
        "  N may end in k (x1000) or M (x1000000): block:1M. A scene name wins over a\n"
        "  file of that name; write ./jet for the file.\n"
        "\n"
        "Options (LIST: one value or a comma list, e.g. mt,mc or 1,2):\n"
        "      --scene SCENE           add a scene (repeatable; same as the operand)\n",
        f);
    mesh_options_help(f, CLI_BENCH, mesh_names);
    fputs(
        "      --templates auto|on|off|both  sphere templates for isolated particles\n"
        "                              (auto: both for spray scenes, on otherwise)\n"
        "      --seed S                seed of block and spray (default 1)\n"
        "      --input-format FMT      auto, csv, xyz, vtk, vtu, bgeo, ply (default auto)\n"
        "\n"
        "Timing:\n"
        "      --min-time S            keep repeating until S seconds (default 1.0)\n"
        "      --repeat N              at least N timed runs (default 5)\n"
        "      --max-repeat N          at most N timed runs (default 100000)\n"
        "      --warmup N              untimed runs first, at least 1 (default 1)\n"
        "      --write FORMAT          also time writing each mesh (obj, gltf, glb,\n"
        "                              drc, ply, vtk, draco.glb) into a temporary\n"
        "                              file: the 'write' stage, not part of total\n"
        "      --write-dir DIR         where (default $TMPDIR or /tmp)\n"
        "      --flicker K             also mesh each input K times, moved by 1/K of a\n"
        "                              cube more each time, and measure how far each\n"
        "                              mesh moved back lies from the first (flicker,\n"
        "                              in R: 0 for translated copies)\n"
        "\n"
        "Output:\n"
        "      --json                  one JSON document on stdout instead of the table\n"
        "      --json-out FILE         also write that JSON document to FILE\n"
        "  -q, --quiet                 no progress line on stderr\n"
        "      --help                  this help\n"
        "\n"
        "The table: times in ms; total = jm_stats.ms_total: median, min and p90 of the\n"
        "timed runs; prepare/field/extract/attrs/write: medians; part/s and tri/s from\n"
        "the median total; lib peak = jm_stats.peak_bytes (max over runs); RSS peak =\n"
        "the process's peak resident set during the case (reset before each case where\n"
        "the kernel allows); x1T = speed-up over the same case with 1 thread;\n"
        "xtpl = speed-up of templates on over off.\n"
        "\n"
        "Exit status: 0 every case ran, 1 a case failed, 2 usage error.\n",
        f);
}

/* A particle count: digits with an optional k or M suffix, or 1e6. */
static int parse_count(const char *s, size_t *out)
{
    if (!s || !*s || *s == '-' || *s == '+')
        return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || errno || !isfinite(v))
        return -1;
    if (*end == 'k' || *end == 'K') {
        v *= 1e3;
        end++;
    } else if (*end == 'M' || *end == 'm') {
        v *= 1e6;
        end++;
    }
    if (*end || !(v >= 1) || v > 2e9 || v != floor(v))
        return -1;
    *out = (size_t)v;
    return 0;
}

/* Scene name of spec ("jet", "block:1M"): 0 a scene (count parsed if given,
 * *needs_n set if block/spray came bare), -1 not a scene name, -2 bad N. */
static int parse_scene(const char *spec, bench_input *in, int *needs_n)
{
    const char *colon = strchr(spec, ':');
    size_t len = colon ? (size_t)(colon - spec) : strlen(spec);
    memset(in, 0, sizeof *in);
    *needs_n = 0;
    if (len == 3 && strncmp(spec, "jet", 3) == 0) {
        in->kind = IN_JET;
        in->frame = SCENE_JET_FRAMES - 1;
        if (colon) {
            long f;
            if (cli_parse_long(colon + 1, 0, 1000000, &f) != 0)
                return -2;
            in->frame = (int)f;
            snprintf(in->name, sizeof in->name, "jet:%d", in->frame);
        } else
            snprintf(in->name, sizeof in->name, "jet");
        return 0;
    }
    if ((len == 5 && strncmp(spec, "block", 5) == 0) || (len == 5 && strncmp(spec, "spray", 5) == 0)) {
        in->kind = spec[0] == 'b' ? IN_BLOCK : IN_SPRAY;
        if (!colon) {
            *needs_n = 1;
            return 0;
        }
        if (parse_count(colon + 1, &in->n) != 0)
            return -2;
        snprintf(in->name, sizeof in->name, "%s:%zu", in->kind == IN_BLOCK ? "block" : "spray", in->n);
        return 0;
    }
    return -1;
}

static int add_input(bench_opts *o, const bench_input *in)
{
    if (o->ninputs >= sizeof o->inputs / sizeof o->inputs[0])
        return options_usage_error(CMD, "too many inputs (at most %zu)",
                                   sizeof o->inputs / sizeof o->inputs[0]);
    o->inputs[o->ninputs++] = *in;
    return OPTIONS_RUN;
}

/* One value of a list option (--field, --method, --cube-size, --threads)
 * added to its list. */
static int list_item(bench_opts *o, const mesh_option *m, const char *s)
{
    mo_value v;
    int rc = mesh_option_value(m, CLI_BENCH, s, 0, NULL, &v);
    if (rc != OPTIONS_RUN)
        return rc;
    switch (m->key) {
    case MO_FIELD:
        for (size_t i = 0; i < o->nfields; i++)
            if (o->fields[i] == (jm_field)v.l)
                return OPTIONS_RUN;
        o->fields[o->nfields++] = (jm_field)v.l;
        return OPTIONS_RUN;
    case MO_METHOD:
        for (size_t i = 0; i < o->nmethods; i++)
            if (o->methods[i] == (jm_method)v.l)
                return OPTIONS_RUN;
        o->methods[o->nmethods++] = (jm_method)v.l;
        return OPTIONS_RUN;
    case 'c':
        if (o->ncubes >= BENCH_MAX_LIST)
            return options_usage_error(CMD, "--%s: at most %d values", m->name, BENCH_MAX_LIST);
        o->cubes[o->ncubes++] = v.d;
        return OPTIONS_RUN;
    default: /* --threads */
        if (v.l == 0)
            v.l = platform_cores();
        for (size_t i = 0; i < o->nthreads; i++)
            if (o->threads[i] == (int)v.l)
                return OPTIONS_RUN;
        if (o->nthreads >= BENCH_MAX_LIST)
            return options_usage_error(CMD, "--%s: at most %d values", m->name, BENCH_MAX_LIST);
        o->threads[o->nthreads++] = (int)v.l;
        return OPTIONS_RUN;
    }
}

/* Splits a comma list into its items. */
static int each_item(bench_opts *o, const mesh_option *m, const char *list)
{
    char buf[256];
    if (strlen(list) >= sizeof buf)
        return options_usage_error(CMD, "--%s: list too long", m->name);
    strcpy(buf, list);
    char *save = NULL;
    int any = 0;
    for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        int rc = list_item(o, m, t);
        if (rc != OPTIONS_RUN)
            return rc;
        any = 1;
    }
    if (!any)
        return options_usage_error(CMD, "--%s needs a value", m->name);
    return OPTIONS_RUN;
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

static int parse_write(bench_opts *o, const char *s)
{
    char name[16];
    int draco = 0;
    if (strlen(s) >= sizeof name)
        goto bad;
    strcpy(name, s);
    if (strncmp(name, "draco.", 6) == 0) {
        draco = 1;
        memmove(name, name + 6, strlen(name + 6) + 1);
    }
    int k = jmf_output_format_parse(name);
    if (k < 0 || (draco && k != JMF_OUT_GLB && k != JMF_OUT_GLTF))
        goto bad;
    o->write_format = k;
    o->write_draco = draco;
    memcpy(o->write_ext, s, strlen(s) + 1); /* shorter than name[16] */
    return OPTIONS_RUN;
bad:
    return options_usage_error(CMD, "--write is obj, gltf, glb, drc, ply, vtk, draco.glb or draco.gltf, not '%s'",
                               s);
}

enum {
    B_SCENE = 256, B_TEMPLATES, B_SEED, B_INFORMAT, B_MINTIME, B_REPEAT, B_MAXREPEAT, B_WARMUP, B_WRITE,
    B_WRITEDIR, B_JSON, B_JSONOUT, B_HELP, B_FLICKER
};

/* bench's own options; the meshing options come from mesh_options.c */
static const struct option bench_own[] = {
    {"scene", required_argument, 0, B_SCENE},
    {"templates", required_argument, 0, B_TEMPLATES},
    {"seed", required_argument, 0, B_SEED},
    {"input-format", required_argument, 0, B_INFORMAT},
    {"min-time", required_argument, 0, B_MINTIME},
    {"repeat", required_argument, 0, B_REPEAT},
    {"max-repeat", required_argument, 0, B_MAXREPEAT},
    {"warmup", required_argument, 0, B_WARMUP},
    {"write", required_argument, 0, B_WRITE},
    {"write-dir", required_argument, 0, B_WRITEDIR},
    {"json", no_argument, 0, B_JSON},
    {"json-out", required_argument, 0, B_JSONOUT},
    {"quiet", no_argument, 0, 'q'},
    {"help", no_argument, 0, B_HELP},
    {"flicker", required_argument, 0, B_FLICKER},
};
#define NOWN (sizeof bench_own / sizeof bench_own[0])

/* The value a handler returns for an option that is not its own. */
#define NOT_MINE 1000

/* Where the parse stands: a bare "block"/"spray" waiting for its N. */
typedef struct parse_state {
    bench_input pending;
    int have_pending;
    select_given sel;
} parse_state;

static const char *kind_name(const bench_input *in)
{
    return in->kind == IN_BLOCK ? "block" : "spray";
}

/* An operand or --scene: a scene, its N, or an input file. */
static int input_option(bench_opts *o, parse_state *st, int c)
{
    bench_input in;
    int needs = 0;
    if (c == 1 && st->have_pending) {
        if (parse_count(optarg, &st->pending.n) != 0)
            return options_usage_error(CMD, "%s needs a particle count N from 1 to 2e9 (1k, 1M), not '%s'",
                                       kind_name(&st->pending), optarg);
        snprintf(st->pending.name, sizeof st->pending.name, "%s:%zu", kind_name(&st->pending), st->pending.n);
        st->have_pending = 0;
        return add_input(o, &st->pending);
    }
    int r = parse_scene(optarg, &in, &needs);
    if (r == -2)
        return options_usage_error(CMD, "bad scene '%s': jet[:FRAME] (FRAME from 0 to 1000000), block:N or "
                                   "spray:N (N from 1 to 2e9, 1k, 1M)", optarg);
    if (r == -1) {
        if (c == B_SCENE)
            return options_usage_error(CMD, "--scene is jet, block N or spray N, not '%s'", optarg);
        memset(&in, 0, sizeof in);
        in.kind = IN_FILE;
        in.path = optarg;
        const char *base = strrchr(optarg, '/');
        snprintf(in.name, sizeof in.name, "%s", base ? base + 1 : optarg);
        return add_input(o, &in);
    }
    if (needs) {
        st->pending = in;
        st->have_pending = 1;
        return OPTIONS_RUN;
    }
    return add_input(o, &in);
}

/* A meshing option (mesh_options.c): a list, or a value of o->params. */
static int meshing_option(bench_opts *o, parse_state *st, int c, int argc, char **argv)
{
    const mesh_option *m = mesh_option_find(c);
    if (!m || !(m->cmds & CLI_BENCH))
        return NOT_MINE;
    if (mesh_option_is_select(m))
        return select_option(CMD, c, optarg, &o->params, &st->sel);
    if (m->bench.list)
        return each_item(o, m, optarg);
    mo_value v;
    int rc = mesh_option_value(m, CLI_BENCH, optarg, argc, argv, &v);
    if (rc != OPTIONS_RUN)
        return rc;
    mesh_option_store(m, &v, &o->params);
    if (c == 'r')
        o->radius = v.d; /* scenes are generated with the double */
    return OPTIONS_RUN;
}

/* What the cases are made of besides the meshing options. */
static int case_option(bench_opts *o, int c)
{
    long l;
    switch (c) {
    case B_FLICKER:
        if (cli_parse_long(optarg, 0, 1000, &l) != 0 || l == 1)
            return options_usage_error(CMD, "--flicker must be 0 or a whole number of frames from 2 to 1000, "
                                       "not '%s'", optarg);
        o->flicker = (int)l;
        return OPTIONS_RUN;
    case B_TEMPLATES: {
        static const char *const names[] = {"auto", "on", "off", "both"};
        static const tpl_mode modes[] = {TPL_AUTO, TPL_ON, TPL_OFF, TPL_BOTH};
        for (int k = 0; k < 4; k++)
            if (strcmp(optarg, names[k]) == 0) {
                o->templates = modes[k];
                return OPTIONS_RUN;
            }
        return options_usage_error(CMD, "--templates is auto, on, off or both, not '%s'", optarg);
    }
    case B_SEED: {
        char *end;
        errno = 0;
        unsigned long long s = strtoull(optarg, &end, 10);
        if (!*optarg || *end || errno || optarg[0] == '-')
            return options_usage_error(CMD, "--seed must be a whole number from 0 to %llu, not '%s'",
                                       (unsigned long long)UINT64_MAX, optarg);
        o->seed = s;
        return OPTIONS_RUN;
    }
    case B_INFORMAT: {
        int k = jmf_input_format_parse(optarg);
        if (k < 0)
            return options_usage_error(CMD, "--input-format is auto, csv, xyz, vtk, vtu, bgeo or ply, not '%s'",
                                       optarg);
        o->read.format = (jmf_input_format)k;
        return OPTIONS_RUN;
    }
    default: return NOT_MINE;
    }
}

/* Timing and output. */
static int timing_option(bench_opts *o, int c)
{
    double d;
    long l;
    switch (c) {
    case B_MINTIME:
        if (cli_parse_double(optarg, &d) != 0 || d < 0 || d > 1e6)
            return options_usage_error(CMD, "--min-time must be seconds from 0 to 1e+06, not '%s'", optarg);
        o->min_time = d;
        return OPTIONS_RUN;
    case B_REPEAT:
    case B_MAXREPEAT:
        if (cli_parse_long(optarg, 1, 100000000, &l) != 0)
            return options_usage_error(CMD, "%s must be a whole number from 1 to 100000000, not '%s'",
                                       c == B_REPEAT ? "--repeat" : "--max-repeat", optarg);
        *(c == B_REPEAT ? &o->repeat : &o->max_repeat) = l;
        return OPTIONS_RUN;
    case B_WARMUP:
        if (cli_parse_long(optarg, 1, 1000000, &l) != 0)
            return options_usage_error(CMD, "--warmup must be a whole number from 1 to 1000000, not '%s'", optarg);
        o->warmup = l;
        return OPTIONS_RUN;
    case B_WRITE: return parse_write(o, optarg);
    case B_WRITEDIR: o->write_dir = optarg; return OPTIONS_RUN;
    case B_JSON: o->json = 1; return OPTIONS_RUN;
    case B_JSONOUT: o->json_out = optarg; return OPTIONS_RUN;
    case 'q': o->quiet = 1; return OPTIONS_RUN;
    default: return NOT_MINE;
    }
}

/* getopt's problems: a missing value, an option that is not bench's. */
static int getopt_problem(int c, char **argv)
{
    if (c == ':')
        return options_usage_error(CMD, "option '%s' needs a value", argv[optind - 1]);
    if (optopt)
        return options_usage_error(CMD, "unknown option '-%c'", optopt);
    return options_usage_error(CMD, "unknown option '%s'", argv[optind - 1]);
}

/* After the options: every list filled with its default. */
static int bench_finish(bench_opts *o, const parse_state *st)
{
    int rc = select_finish(CMD, &o->params, &st->sel);
    if (rc != OPTIONS_RUN)
        return rc;
    if (st->have_pending)
        return options_usage_error(CMD, "%s needs a particle count N", kind_name(&st->pending));
    if (o->max_repeat < o->repeat)
        o->max_repeat = o->repeat;
    const int mrc = mesh_options_check(CMD, &o->params);
    if (mrc != OPTIONS_RUN)
        return mrc;
    if (o->ninputs == 0) {
        const char *suite[] = {"jet", "block:100000", "spray:10000"};
        for (size_t i = 0; i < 3; i++) {
            bench_input in;
            int needs;
            parse_scene(suite[i], &in, &needs);
            add_input(o, &in);
        }
    }
    if (o->nfields == 0)
        o->fields[o->nfields++] = JM_FIELD_METASPHERE;
    if (o->nmethods == 0)
        o->methods[o->nmethods++] = JM_METHOD_MT;
    if (o->ncubes == 0)
        o->cubes[o->ncubes++] = 0.5;
    if (o->nthreads == 0) {
        o->threads[o->nthreads++] = 1;
        if (platform_cores() > 1)
            o->threads[o->nthreads++] = platform_cores();
    }
    /* 1 thread first, so every other thread count finds its baseline */
    qsort(o->threads, o->nthreads, sizeof o->threads[0], cmp_int);
    return OPTIONS_RUN;
}

int bench_parse_options(int argc, char **argv, bench_opts *o)
{
    struct option longs[NOWN + MESH_OPTIONS_MAX + 1];
    size_t nlong = NOWN;
    memcpy(longs, bench_own, sizeof bench_own);
    mesh_options_long(CLI_BENCH, longs, &nlong);
    longs[nlong] = (struct option){0, 0, 0, 0};
    memset(o, 0, sizeof *o);
    o->radius = SCENE_DEFAULT_RADIUS;
    o->min_time = 1.0;
    o->repeat = 5;
    o->warmup = 1;
    o->max_repeat = 100000;
    o->write_format = -1;
    o->seed = 1;
    o->templates = TPL_AUTO;

    parse_state st;
    memset(&st, 0, sizeof st);
    int rc = OPTIONS_RUN, c;
    optind = 0;
    opterr = 0;
    while (rc == OPTIONS_RUN && (c = getopt_long(argc, argv, "-:r:c:j:q", longs, NULL)) != -1) {
        if (st.have_pending && c != 1)
            return options_usage_error(CMD, "%s needs a particle count N: %s N or %s:N", kind_name(&st.pending),
                                       kind_name(&st.pending), kind_name(&st.pending));
        if (c == B_HELP) {
            bench_help(stdout);
            return OPTIONS_DONE;
        }
        rc = c == 1 || c == B_SCENE ? input_option(o, &st, c) : meshing_option(o, &st, c, argc, argv);
        if (rc == NOT_MINE)
            rc = case_option(o, c);
        if (rc == NOT_MINE)
            rc = timing_option(o, c);
        if (rc == NOT_MINE)
            rc = getopt_problem(c, argv);
    }
    if (rc != OPTIONS_RUN)
        return rc;
    return bench_finish(o, &st);
}
