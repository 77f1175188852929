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
#include "../numbers.h"
#include "../options.h"
#include "../platform.h"
#include "../scenes.h"
#include "../select_options.h"

#define CMD "bench"

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
        "      --scene SCENE           add a scene (repeatable; same as the operand)\n"
        "      --field LIST            metasphere, sph, sph-aniso (sph with --anisotropic)\n"
        "                              (default metasphere)\n"
        "      --method LIST           mt, mc (default mt)\n"
        "  -r, --radius R              particle radius (default 0.025); scenes are\n"
        "                              generated with it\n"
        "  -c, --cube-size LIST        cube edge relative to R (default 0.5)\n"
        "      --smoothing-length L    sph kernel length h relative to R (default 2)\n"
        "      --threshold T           iso value (default 0 metasphere, 0.6 sph)\n"
        "      --link-distance L       metasphere link distance relative to R (default pi)\n"
        "      --smooth [N], --smooth-normals [N], --simplify E  post-processing, as convert\n"
        "      --particle-aabb-min X,Y,Z, --particle-aabb-max X,Y,Z, --min-piece-particles N,\n"
        "      --min-piece-volume V, --mesh-aabb-min X,Y,Z, --mesh-aabb-max X,Y,Z,\n"
        "      --mesh-aabb-clamp-vertices  selection and clipping, as convert\n"
        "  -j, --threads LIST          worker threads; 0 = all cores (default 1,CORES)\n"
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

/* Splits a comma list into items; calls one(item) for each. */
typedef int (*item_fn)(bench_opts *o, const char *opt, const char *item);

static int each_item(bench_opts *o, const char *opt, const char *list, item_fn one)
{
    char buf[256];
    if (strlen(list) >= sizeof buf)
        return options_usage_error(CMD, "%s: list too long", opt);
    strcpy(buf, list);
    char *save = NULL;
    int any = 0;
    for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        int rc = one(o, opt, t);
        if (rc != OPTIONS_RUN)
            return rc;
        any = 1;
    }
    if (!any)
        return options_usage_error(CMD, "%s needs a value", opt);
    return OPTIONS_RUN;
}

static int item_field(bench_opts *o, const char *opt, const char *s)
{
    jm_field f;
    if (strcmp(s, "metasphere") == 0)
        f = JM_FIELD_METASPHERE;
    else if (strcmp(s, "sph") == 0)
        f = JM_FIELD_SPH;
    else if (strcmp(s, "sph-aniso") == 0)
        f = BENCH_FIELD_SPH_ANISO;
    else
        return options_usage_error(CMD, "%s is metasphere, sph or sph-aniso, not '%s'", opt, s);
    for (size_t i = 0; i < o->nfields; i++)
        if (o->fields[i] == f)
            return OPTIONS_RUN;
    o->fields[o->nfields++] = f;
    return OPTIONS_RUN;
}

static int item_method(bench_opts *o, const char *opt, const char *s)
{
    jm_method m;
    if (strcmp(s, "mt") == 0)
        m = JM_METHOD_MT;
    else if (strcmp(s, "mc") == 0)
        m = JM_METHOD_MC;
    else
        return options_usage_error(CMD, "%s is mt or mc, not '%s'", opt, s);
    for (size_t i = 0; i < o->nmethods; i++)
        if (o->methods[i] == m)
            return OPTIONS_RUN;
    o->methods[o->nmethods++] = m;
    return OPTIONS_RUN;
}

static int item_cube(bench_opts *o, const char *opt, const char *s)
{
    double v;
    if (cli_parse_double(s, &v) != 0 || !(v > 0) || v > 1e6) /* the library refuses the rest, per case */
        return options_usage_error(CMD, "%s must be numbers from 0.001 to 100 (times R), not '%s'", opt, s);
    if (o->ncubes >= BENCH_MAX_LIST)
        return options_usage_error(CMD, "%s: at most %d values", opt, BENCH_MAX_LIST);
    o->cubes[o->ncubes++] = v;
    return OPTIONS_RUN;
}

static int item_threads(bench_opts *o, const char *opt, const char *s)
{
    long v;
    if (cli_parse_long(s, 0, 4096, &v) != 0)
        return options_usage_error(CMD, "%s must be whole numbers from 0 to 4096, not '%s'", opt, s);
    if (v == 0)
        v = platform_cores();
    for (size_t i = 0; i < o->nthreads; i++)
        if (o->threads[i] == (int)v)
            return OPTIONS_RUN;
    if (o->nthreads >= BENCH_MAX_LIST)
        return options_usage_error(CMD, "%s: at most %d values", opt, BENCH_MAX_LIST);
    o->threads[o->nthreads++] = (int)v;
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
    B_SCENE = 256, B_FIELD, B_METHOD, B_SMOOTH, B_THRESHOLD, B_LINK, B_TEMPLATES, B_SEED,
    B_INFORMAT, B_MINTIME, B_REPEAT, B_MAXREPEAT, B_WARMUP, B_WRITE, B_WRITEDIR, B_JSON,
    B_JSONOUT, B_HELP,
    B_POST_SMOOTH, B_POST_NSMOOTH, B_POST_SIMPLIFY, B_FLICKER
};

static const struct option bench_long[] = {
    {"scene", required_argument, 0, B_SCENE},
    {"field", required_argument, 0, B_FIELD},
    {"method", required_argument, 0, B_METHOD},
    {"radius", required_argument, 0, 'r'},
    {"cube-size", required_argument, 0, 'c'},
    {"smoothing-length", required_argument, 0, B_SMOOTH},
    {"threshold", required_argument, 0, B_THRESHOLD},
    {"link-distance", required_argument, 0, B_LINK},
    {"threads", required_argument, 0, 'j'},
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
    {"smooth", optional_argument, 0, B_POST_SMOOTH},
    {"smooth-normals", optional_argument, 0, B_POST_NSMOOTH},
    {"simplify", required_argument, 0, B_POST_SIMPLIFY},
    SELECT_LONG_OPTIONS,
    {"flicker", required_argument, 0, B_FLICKER},
    {0, 0, 0, 0},
};

int bench_parse_options(int argc, char **argv, bench_opts *o)
{
    memset(o, 0, sizeof *o);
    o->radius = SCENE_DEFAULT_RADIUS;
    o->min_time = 1.0;
    o->repeat = 5;
    o->warmup = 1;
    o->max_repeat = 100000;
    o->write_format = -1;
    o->seed = 1;
    o->templates = TPL_AUTO;

    bench_input pending; /* a bare "block"/"spray" waiting for its N */
    int have_pending = 0, rc = OPTIONS_RUN, c;
    select_given sel = {0, 0, 0, 0};
    optind = 0;
    opterr = 0;
    while (rc == OPTIONS_RUN && (c = getopt_long(argc, argv, "-:r:c:j:q", bench_long, NULL)) != -1) {
        double d;
        long l;
        int needs = 0;
        bench_input in;
        if (have_pending && c != 1)
            return options_usage_error(CMD, "%s needs a particle count N: %s N or %s:N",
                                       pending.kind == IN_BLOCK ? "block" : "spray",
                                       pending.kind == IN_BLOCK ? "block" : "spray",
                                       pending.kind == IN_BLOCK ? "block" : "spray");
        switch (c) {
        case 1: /* an operand, in order */
            if (have_pending) {
                if (parse_count(optarg, &pending.n) != 0)
                    return options_usage_error(CMD, "%s needs a particle count N from 1 to 2e9 (1k, 1M), not '%s'",
                                               pending.kind == IN_BLOCK ? "block" : "spray", optarg);
                snprintf(pending.name, sizeof pending.name, "%s:%zu",
                         pending.kind == IN_BLOCK ? "block" : "spray", pending.n);
                have_pending = 0;
                rc = add_input(o, &pending);
                break;
            }
            /* fall through */
        case B_SCENE: {
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
                rc = add_input(o, &in);
            } else if (needs) {
                pending = in;
                have_pending = 1;
            } else
                rc = add_input(o, &in);
            break;
        }
        case B_FIELD: rc = each_item(o, "--field", optarg, item_field); break;
        case B_METHOD: rc = each_item(o, "--method", optarg, item_method); break;
        case 'c': rc = each_item(o, "--cube-size", optarg, item_cube); break;
        case 'j': rc = each_item(o, "--threads", optarg, item_threads); break;
        case 'r':
            if (cli_parse_double(optarg, &d) != 0 || !(d >= 1.2e-38) || d > 1e30)
                return options_usage_error(CMD, "--radius must be a number from 1.2e-38 to 1e+30, not '%s'", optarg);
            o->radius = d;
            break;
        case B_POST_SMOOTH:
        case B_POST_NSMOOTH: {
            long l;
            const char *word;
            if (cli_optional_long(optarg, argc, argv, &optind, 0, 100000,
                                  c == B_POST_SMOOTH ? OPTIONS_SMOOTH_DEFAULT : OPTIONS_SMOOTH_NORMALS_DEFAULT, &l,
                                  &word) != 0)
                return options_usage_error(CMD, "%s must be a whole number from 0 to 100000, not '%s'",
                                           c == B_POST_SMOOTH ? "--smooth" : "--smooth-normals", word);
            if (c == B_POST_SMOOTH)
                o->smooth_iters = (int)l;
            else
                o->smooth_normal_iters = (int)l;
            break;
        }
        case B_FLICKER: {
            long l;
            if (cli_parse_long(optarg, 0, 1000, &l) != 0 || l == 1)
                return options_usage_error(CMD, "--flicker must be 0 or a whole number of frames from 2 to 1000, "
                                           "not '%s'", optarg);
            o->flicker = (int)l;
            break;
        }
        case B_POST_SIMPLIFY:
            if (cli_parse_double(optarg, &d) != 0 || !(d >= 0) || d > 1000)
                return options_usage_error(CMD, "--simplify must be a number from 0 to 1000, not '%s'", optarg);
            o->simplify = d;
            break;
        case B_SMOOTH:
            if (cli_parse_double(optarg, &d) != 0 || !(d > 0) || d > 1e6)
                return options_usage_error(CMD, "--smoothing-length must be a number from 0.05 to 100 (times R), "
                                           "not '%s'", optarg);
            o->smoothing = d;
            break;
        case B_LINK:
            if (cli_parse_double(optarg, &d) != 0 || !(d >= 1.2e-38) || d > 1e6)
                return options_usage_error(CMD, "--link-distance must be a number from 1.2e-38 to 1e+06 (times R), "
                                           "not '%s'", optarg);
            o->link = d;
            break;
        case B_THRESHOLD:
            if (cli_parse_double(optarg, &d) != 0)
                return options_usage_error(CMD, "--threshold must be a number above -1 and below 1 for the "
                                           "metasphere, above 0 for sph (0: the field's default), not '%s'", optarg);
            o->threshold = d;
            o->threshold_given = 1;
            break;
        case B_TEMPLATES:
            if (strcmp(optarg, "auto") == 0)
                o->templates = TPL_AUTO;
            else if (strcmp(optarg, "on") == 0)
                o->templates = TPL_ON;
            else if (strcmp(optarg, "off") == 0)
                o->templates = TPL_OFF;
            else if (strcmp(optarg, "both") == 0)
                o->templates = TPL_BOTH;
            else
                return options_usage_error(CMD, "--templates is auto, on, off or both, not '%s'", optarg);
            break;
        case B_SEED: {
            char *end;
            errno = 0;
            unsigned long long s = strtoull(optarg, &end, 10);
            if (!*optarg || *end || errno || optarg[0] == '-')
                return options_usage_error(CMD, "--seed must be a whole number from 0 to %llu, not '%s'",
                                           (unsigned long long)UINT64_MAX, optarg);
            o->seed = s;
            break;
        }
        case B_INFORMAT: {
            int k = jmf_input_format_parse(optarg);
            if (k < 0)
                return options_usage_error(
                    CMD, "--input-format is auto, csv, xyz, vtk, vtu, bgeo or ply, not '%s'", optarg);
            o->read.format = (jmf_input_format)k;
            break;
        }
        case B_MINTIME:
            if (cli_parse_double(optarg, &d) != 0 || d < 0 || d > 1e6)
                return options_usage_error(CMD, "--min-time must be seconds from 0 to 1e+06, not '%s'", optarg);
            o->min_time = d;
            break;
        case B_REPEAT:
            if (cli_parse_long(optarg, 1, 100000000, &l) != 0)
                return options_usage_error(CMD, "--repeat must be a whole number from 1 to 100000000, not '%s'",
                                           optarg);
            o->repeat = l;
            break;
        case B_MAXREPEAT:
            if (cli_parse_long(optarg, 1, 100000000, &l) != 0)
                return options_usage_error(CMD, "--max-repeat must be a whole number from 1 to 100000000, not '%s'",
                                           optarg);
            o->max_repeat = l;
            break;
        case B_WARMUP:
            if (cli_parse_long(optarg, 1, 1000000, &l) != 0)
                return options_usage_error(CMD, "--warmup must be a whole number from 1 to 1000000, not '%s'",
                                           optarg);
            o->warmup = l;
            break;
        case B_WRITE: rc = parse_write(o, optarg); break;
        case B_WRITEDIR: o->write_dir = optarg; break;
        case B_JSON: o->json = 1; break;
        case B_JSONOUT: o->json_out = optarg; break;
        case 'q': o->quiet = 1; break;
        case B_HELP: bench_help(stdout); return OPTIONS_DONE;
        case ':': return options_usage_error(CMD, "option '%s' needs a value", argv[optind - 1]);
        default:
            if (select_is_option(c)) {
                rc = select_option(CMD, c, optarg, &o->select, &sel);
                break;
            }
            if (optopt)
                return options_usage_error(CMD, "unknown option '-%c'", optopt);
            return options_usage_error(CMD, "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (rc == OPTIONS_RUN)
        rc = select_finish(CMD, &o->select, &sel);
    if (rc != OPTIONS_RUN)
        return rc;
    if (have_pending)
        return options_usage_error(CMD, "%s needs a particle count N",
                                   pending.kind == IN_BLOCK ? "block" : "spray");
    if (o->max_repeat < o->repeat)
        o->max_repeat = o->repeat;
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

const char *bench_field_name(jm_field f)
{
    return f == JM_FIELD_SPH ? "sph" : f == BENCH_FIELD_SPH_ANISO ? "sph-aniso" : "metasphere";
}
const char *bench_method_name(jm_method m) { return m == JM_METHOD_MC ? "mc" : "mt"; }
