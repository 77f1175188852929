/* bench.c - `jetmesh bench`: times jm_mesh_particles on synthetic scenes or input files, per stage, as a table or JSON. */
#include "numbers.h"
#include "bench.h"

#include <dirent.h>
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "../formats/reader.h"
#include "../formats/writer.h"
#include "../lib/jetmesh.h"
#include "options.h"
#include "platform.h"
#include "scenes.h"
#include "signals.h"

#define CMD "bench"
#define MAX_LIST 16

/* ------------------------------------------------------------------ */
/* Inputs: a synthetic scene or a file, loaded into memory once.       */

typedef enum { IN_JET, IN_BLOCK, IN_SPRAY, IN_FILE } input_kind;

typedef struct bench_input {
    input_kind kind;
    size_t n;          /* block/spray N */
    int frame;         /* jet frame */
    const char *path;  /* IN_FILE: into argv */
    char name[96];     /* "jet", "block:100000", or the file's base name */
    float *xyz;
    uint32_t *ids;
    size_t count;
    int loaded;        /* 1 loaded, -1 failed */
    char err[300];
} bench_input;

/* ------------------------------------------------------------------ */
/* Samples and their summary.                                          */

enum { ST_TOTAL, ST_PREPARE, ST_FIELD, ST_EXTRACT, ST_ATTR, ST_WALL, ST_WRITE, ST_COUNT };
static const char *const stage_key[ST_COUNT] = {"total", "prepare",  "field", "extract",
                                                "attributes", "wall", "write"};

typedef struct summary {
    double median, min, max, mean, p10, p90, q1, q3;
} summary;

typedef struct samples {
    double *v;
    size_t n, cap;
} samples;

static int samples_push(samples *s, double x)
{
    if (s->n == s->cap) {
        size_t cap = s->cap ? s->cap * 2 : 64;
        double *v = realloc(s->v, cap * sizeof *v);
        if (!v)
            return -1;
        s->v = v;
        s->cap = cap;
    }
    s->v[s->n++] = x;
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Nearest rank: the ceil(q n)-th smallest (1-based), at least the first. */
static double rank(const double *sorted, size_t n, double q)
{
    size_t k = (size_t)ceil(q * (double)n);
    if (k < 1)
        k = 1;
    if (k > n)
        k = n;
    return sorted[k - 1];
}

/* Sorts s in place and summarises it; the median of an even count is the
 * mean of the middle two. */
static void summarize(samples *s, summary *out)
{
    memset(out, 0, sizeof *out);
    if (s->n == 0)
        return;
    qsort(s->v, s->n, sizeof *s->v, cmp_double);
    size_t n = s->n;
    double sum = 0;
    for (size_t i = 0; i < n; i++)
        sum += s->v[i];
    out->mean = sum / (double)n;
    out->min = s->v[0];
    out->max = s->v[n - 1];
    out->median = n % 2 ? s->v[n / 2] : 0.5 * (s->v[n / 2 - 1] + s->v[n / 2]);
    out->p10 = rank(s->v, n, 0.10);
    out->p90 = rank(s->v, n, 0.90);
    out->q1 = rank(s->v, n, 0.25);
    out->q3 = rank(s->v, n, 0.75);
}

/* ------------------------------------------------------------------ */
/* Cases.                                                              */

typedef struct bench_case {
    size_t input;
    jm_field field;
    jm_method method;
    double cube;
    int threads;      /* asked for */
    int templates;    /* 1 on, 0 off (no_templates) */
    jm_params params; /* in force, defaults filled in */
    int ran, ok;
    char err[320];
    size_t reps;
    summary st[ST_COUNT];
    int has_write;
    size_t write_bytes;
    jm_stats last;
    size_t lib_peak, rss_peak;
    int rss_reset;              /* 1: the RSS peak was reset before the case */
    double speedup_threads;     /* vs. the same case with 1 thread; 0 = none */
    double speedup_templates;   /* no_templates median / this median; 0 = none */
} bench_case;

typedef enum { TPL_AUTO, TPL_ON, TPL_OFF, TPL_BOTH } tpl_mode;

typedef struct bench_opts {
    bench_input inputs[64];
    size_t ninputs;
    jm_field fields[2];
    size_t nfields;
    jm_method methods[2];
    size_t nmethods;
    double cubes[MAX_LIST];
    size_t ncubes;
    int threads[MAX_LIST];
    size_t nthreads;
    double radius, smoothing, threshold, link;
    int threshold_given;
    double min_time;
    long repeat, warmup, max_repeat;
    tpl_mode templates;
    int write_format; /* -1: no --write */
    int write_draco;
    char write_ext[16];
    const char *write_dir;
    int json;
    const char *json_out;
    uint64_t seed;
    jmf_read_options read;
    int quiet;
} bench_opts;

/* ------------------------------------------------------------------ */
/* Help and option parsing.                                            */

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
        "      --field LIST            metasphere, sph (default metasphere)\n"
        "      --method LIST           mt, mc (default mt)\n"
        "  -r, --radius R              particle radius (default 0.025); scenes are\n"
        "                              generated with it\n"
        "  -c, --cube-size LIST        cube edge relative to R (default 0.5)\n"
        "      --smoothing-length L    sph kernel length h relative to R (default 2)\n"
        "      --threshold T           iso value (default 0 metasphere, 0.6 sph)\n"
        "      --link-distance L       metasphere link distance relative to R (default pi)\n"
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
    else
        return options_usage_error(CMD, "%s is metasphere or sph, not '%s'", opt, s);
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
    if (cli_parse_double(s, &v) != 0 || !(v > 0) || v > 1e6)
        return options_usage_error(CMD, "%s must be a number above 0, not '%s'", opt, s);
    if (o->ncubes >= MAX_LIST)
        return options_usage_error(CMD, "%s: at most %d values", opt, MAX_LIST);
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
    if (o->nthreads >= MAX_LIST)
        return options_usage_error(CMD, "%s: at most %d values", opt, MAX_LIST);
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
    B_JSONOUT, B_HELP
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
    {0, 0, 0, 0},
};

static int parse_opts(int argc, char **argv, bench_opts *o)
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
                    return options_usage_error(CMD, "%s needs a particle count N, not '%s'",
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
                return options_usage_error(CMD, "bad scene '%s': jet[:FRAME], block:N or spray:N", optarg);
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
            if (cli_parse_double(optarg, &d) != 0 || !(d > 0) || d > 1e30)
                return options_usage_error(CMD, "--radius must be a number above 0, not '%s'", optarg);
            o->radius = d;
            break;
        case B_SMOOTH:
            if (cli_parse_double(optarg, &d) != 0 || !(d > 0) || d > 1e6)
                return options_usage_error(CMD, "--smoothing-length must be a number above 0, not '%s'",
                                           optarg);
            o->smoothing = d;
            break;
        case B_LINK:
            if (cli_parse_double(optarg, &d) != 0 || !(d > 0) || d > 1e6)
                return options_usage_error(CMD, "--link-distance must be a number above 0, not '%s'",
                                           optarg);
            o->link = d;
            break;
        case B_THRESHOLD:
            if (cli_parse_double(optarg, &d) != 0)
                return options_usage_error(CMD, "--threshold must be a number, not '%s'", optarg);
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
                return options_usage_error(CMD, "--seed must be a whole number, not '%s'", optarg);
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
                return options_usage_error(CMD, "--min-time must be seconds >= 0, not '%s'", optarg);
            o->min_time = d;
            break;
        case B_REPEAT:
            if (cli_parse_long(optarg, 1, 100000000, &l) != 0)
                return options_usage_error(CMD, "--repeat must be a whole number >= 1, not '%s'", optarg);
            o->repeat = l;
            break;
        case B_MAXREPEAT:
            if (cli_parse_long(optarg, 1, 100000000, &l) != 0)
                return options_usage_error(CMD, "--max-repeat must be a whole number >= 1, not '%s'",
                                           optarg);
            o->max_repeat = l;
            break;
        case B_WARMUP:
            if (cli_parse_long(optarg, 1, 1000000, &l) != 0)
                return options_usage_error(CMD, "--warmup must be a whole number >= 1, not '%s'", optarg);
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
            if (optopt)
                return options_usage_error(CMD, "unknown option '-%c'", optopt);
            return options_usage_error(CMD, "unknown option '%s'", argv[optind - 1]);
        }
    }
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

/* ------------------------------------------------------------------ */
/* Loading.                                                            */

static void load_input(const bench_opts *o, bench_input *in)
{
    scene_points pts = {0};
    int r = 0;
    in->loaded = -1;
    switch (in->kind) {
    case IN_JET: r = scene_jet(in->frame, o->radius, &pts); break;
    case IN_BLOCK: r = scene_block(in->n, o->radius, o->seed, &pts); break;
    case IN_SPRAY: r = scene_spray(in->n, o->radius, o->seed, &pts); break;
    case IN_FILE: {
        jmf_frame fr;
        char err[256];
        jmf_status s = jmf_read_particles(in->path, &o->read, &fr, err, sizeof err);
        if (s != JMF_OK) {
            snprintf(in->err, sizeof in->err, "%s", err);
            return;
        }
        in->xyz = fr.xyz;
        in->ids = fr.ids;
        in->count = fr.count;
        in->loaded = 1;
        return;
    }
    }
    if (r != 0) {
        snprintf(in->err, sizeof in->err, "out of memory generating the scene");
        return;
    }
    in->xyz = pts.xyz;
    in->count = pts.count;
    in->loaded = 1;
}

static void free_input(bench_input *in)
{
    free(in->xyz);
    free(in->ids);
    in->xyz = NULL;
    in->ids = NULL;
}

/* ------------------------------------------------------------------ */
/* Machine.                                                            */

typedef struct machine {
    char cpu[160];
    int cores;
    size_t memory;
    char os[160];
    char date[40];
} machine;

static void machine_info(machine *m)
{
    memset(m, 0, sizeof *m);
    snprintf(m->cpu, sizeof m->cpu, "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (f) {
        char line[512];
        while (fgets(line, sizeof line, f)) {
            if (strncmp(line, "model name", 10) == 0 || strncmp(line, "Model", 5) == 0) {
                char *colon = strchr(line, ':');
                if (!colon)
                    continue;
                colon++;
                while (*colon == ' ' || *colon == '\t')
                    colon++;
                size_t n = strcspn(colon, "\r\n");
                while (n > 0 && colon[n - 1] == ' ')
                    n--;
                if (n > 0) {
                    snprintf(m->cpu, sizeof m->cpu, "%.*s", (int)n, colon);
                    break;
                }
            }
        }
        fclose(f);
    }
    m->cores = platform_cores();
    m->memory = platform_physical_memory();
    struct utsname u;
    if (uname(&u) == 0)
        snprintf(m->os, sizeof m->os, "%.40s %.64s %.32s", u.sysname, u.release, u.machine);
    time_t now = time(NULL);
    struct tm tm;
    if (gmtime_r(&now, &tm))
        strftime(m->date, sizeof m->date, "%Y-%m-%dT%H:%M:%SZ", &tm);
}

/* ------------------------------------------------------------------ */
/* Running one case.                                                   */

/* Makes the process's peak RSS start from now (Linux >= 4.0); 1 if it did. */
static int reset_peak_rss(void)
{
#ifdef __GLIBC__
    malloc_trim(0);
#endif
    FILE *f = fopen("/proc/self/clear_refs", "w");
    if (!f)
        return 0;
    int ok = fputs("5", f) >= 0;
    if (fclose(f) != 0)
        ok = 0;
    return ok;
}

/* Removes every file in dir (the written mesh and a .gltf's .bin). */
static void empty_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    char path[4096];
    while ((e = readdir(d))) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        unlink(path);
    }
    closedir(d);
}

static int is_spray(const bench_input *in)
{
    return in->kind == IN_SPRAY;
}

static void progress(const bench_opts *o, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void progress(const bench_opts *o, const char *fmt, ...)
{
    static int shown = 0;
    if (o->quiet || !isatty(2))
        return;
    if (!fmt) {
        if (shown)
            fputs("\r\033[K", stderr);
        shown = 0;
        return;
    }
    va_list ap;
    va_start(ap, fmt);
    fputs("\r\033[K", stderr);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fflush(stderr);
    shown = 1;
}

static const char *field_name(jm_field f) { return f == JM_FIELD_SPH ? "sph" : "metasphere"; }
static const char *method_name(jm_method m) { return m == JM_METHOD_MC ? "mc" : "mt"; }

static void run_case(const bench_opts *o, const bench_input *in, bench_case *c, const char *wdir)
{
    samples s[ST_COUNT];
    memset(s, 0, sizeof s);
    jm_context *ctx = NULL;
    c->ran = 1;
    c->ok = 0;
    c->has_write = o->write_format >= 0;

    jm_params p;
    memset(&p, 0, sizeof p);
    p.radius = (float)o->radius;
    p.cube_size = (float)c->cube;
    p.field = c->field;
    p.method = c->method;
    if (o->threshold_given)
        p.threshold = (float)o->threshold;
    p.smoothing_length = (float)o->smoothing;
    p.link_distance = (float)o->link;
    p.threads = c->threads;
    p.no_templates = !c->templates;

    if (in->loaded != 1) {
        snprintf(c->err, sizeof c->err, "%s", in->err);
        return;
    }
    c->rss_reset = reset_peak_rss();
    jm_status js = jm_context_create(&p, &ctx);
    if (js != JM_OK) {
        snprintf(c->err, sizeof c->err, "jm_context_create: %s", jm_status_message(js));
        return;
    }
    jm_context_get_params(ctx, &c->params);

    jm_particles parts = {in->xyz, in->count, 0, in->ids};
    jmf_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = o->write_format >= 0 ? (jmf_output_format)o->write_format : JMF_OUT_AUTO;
    wo.draco = o->write_draco;
    char wpath[4200];
    snprintf(wpath, sizeof wpath, "%s/mesh.%s", wdir ? wdir : ".", o->write_ext);

    double start = platform_now_ms();
    long total_runs = 0;
    for (;;) {
        int timed = total_runs >= o->warmup;
        if (timed) {
            double elapsed = platform_now_ms() - start;
            if ((long)c->reps >= o->repeat && elapsed >= o->min_time * 1e3)
                break;
            if ((long)c->reps >= o->max_repeat)
                break;
        }
        jm_mesh mesh;
        jm_stats st;
        double t0 = platform_now_ms();
        js = jm_mesh_particles(ctx, &parts, &mesh, &st);
        double t1 = platform_now_ms();
        if (js != JM_OK) {
            snprintf(c->err, sizeof c->err, "jm_mesh_particles: %s", jm_status_message(js));
            goto out;
        }
        double tw = 0;
        if (c->has_write) {
            char err[300];
            size_t bytes = 0;
            double w0 = platform_now_ms();
            jmf_status ws = jmf_write_mesh(wpath, &mesh, &wo, &bytes, err, sizeof err);
            tw = platform_now_ms() - w0;
            empty_dir(wdir);
            if (ws != JMF_OK) {
                snprintf(c->err, sizeof c->err, "write: %s", err);
                goto out;
            }
            c->write_bytes = bytes;
        }
        if (st.peak_bytes > c->lib_peak)
            c->lib_peak = st.peak_bytes;
        total_runs++;
        if (!timed) {
            start = platform_now_ms(); /* the floor counts timed runs only */
            continue;
        }
        c->last = st;
        if (samples_push(&s[ST_TOTAL], st.ms_total) || samples_push(&s[ST_PREPARE], st.ms_prepare) ||
            samples_push(&s[ST_FIELD], st.ms_field) || samples_push(&s[ST_EXTRACT], st.ms_extract) ||
            samples_push(&s[ST_ATTR], st.ms_attributes) || samples_push(&s[ST_WALL], t1 - t0) ||
            (c->has_write && samples_push(&s[ST_WRITE], tw))) {
            snprintf(c->err, sizeof c->err, "out of memory recording samples");
            goto out;
        }
        c->reps++;
        if (c->reps == 1 || c->reps % 64 == 0)
            progress(o, "bench: %s %s %s c%.3g %dT%s: run %zu", in->name, field_name(c->field),
                     method_name(c->method), c->cube, c->threads, c->templates ? "" : " no-templates",
                     c->reps);
    }
    for (int k = 0; k < ST_COUNT; k++)
        summarize(&s[k], &c->st[k]);
    c->rss_peak = platform_peak_rss();
    c->ok = 1;
out:
    progress(o, NULL);
    jm_context_free(ctx);
    for (int k = 0; k < ST_COUNT; k++)
        free(s[k].v);
}

/* ------------------------------------------------------------------ */
/* The table.                                                          */

static const char *fmt_ms(double ms, char *buf, size_t len)
{
    if (!isfinite(ms))
        snprintf(buf, len, "-");
    else if (ms >= 1000)
        snprintf(buf, len, "%.0f", ms);
    else if (ms >= 100)
        snprintf(buf, len, "%.1f", ms);
    else if (ms >= 10)
        snprintf(buf, len, "%.2f", ms);
    else if (ms >= 1)
        snprintf(buf, len, "%.3f", ms);
    else
        snprintf(buf, len, "%.4f", ms);
    return buf;
}

static const char *fmt_rate(double v, char *buf, size_t len)
{
    if (!isfinite(v) || v <= 0)
        snprintf(buf, len, "-");
    else if (v >= 1e9)
        snprintf(buf, len, "%.2fG", v / 1e9);
    else if (v >= 1e6)
        snprintf(buf, len, "%.2fM", v / 1e6);
    else if (v >= 1e3)
        snprintf(buf, len, "%.1fk", v / 1e3);
    else
        snprintf(buf, len, "%.0f", v);
    return buf;
}

static const char *fmt_mib(size_t bytes, char *buf, size_t len)
{
    snprintf(buf, len, "%.1f", (double)bytes / (1024.0 * 1024.0));
    return buf;
}

static const char *fmt_ratio(double r, char *buf, size_t len)
{
    if (r > 0 && isfinite(r))
        snprintf(buf, len, "%.2fx", r);
    else
        snprintf(buf, len, "-");
    return buf;
}

static void print_header(const bench_opts *o, const machine *m)
{
    char mem[32];
    printf("jetmesh %s bench  %s\n", jm_version(), m->date);
    printf("machine: %s, %d cores, %s, %s\n", m->cpu, m->cores,
           platform_format_bytes(m->memory, mem, sizeof mem), m->os);
    printf("timing: after %ld warm-up run%s, at least %ld run%s and %.3g s per case; radius %g\n\n",
           o->warmup, o->warmup == 1 ? "" : "s", o->repeat, o->repeat == 1 ? "" : "s", o->min_time,
           o->radius);
    printf("%-22s %-4s %-2s %4s %3s %-3s %6s | %9s %9s %9s | %9s %9s %9s %9s", "case", "fld", "mt",
           "cube", "thr", "tpl", "runs", "total", "min", "p90", "prepare", "field", "extract", "attrs");
    if (o->write_format >= 0)
        printf(" %9s", "write");
    printf(" | %8s %8s | %9s %9s | %8s %8s | %6s %6s\n", "part/s", "tri/s", "verts", "tris", "lib MiB",
           "RSS MiB", "x1T", "xtpl");
}

static void print_row(const bench_opts *o, const bench_input *in, const bench_case *c)
{
    char name[23]; /* a long file name keeps its first 10 and last 11 characters */
    size_t len = strlen(in->name);
    if (len > 22)
        snprintf(name, sizeof name, "%.10s~%s", in->name, in->name + len - 11);
    else
        snprintf(name, sizeof name, "%s", in->name);
    printf("%-22s %-4s %-2s %4.2g %3d %-3s ", name, c->field == JM_FIELD_SPH ? "sph" : "meta",
           method_name(c->method), c->cube, c->threads, c->templates ? "on" : "off");
    if (!c->ok) {
        printf("FAILED: %s\n", c->err);
        fflush(stdout);
        return;
    }
    char a[32], b[32], d[32], e[32], f[32], g[32], h[32];
    printf("%6zu | %9s %9s %9s | %9s %9s %9s %9s", c->reps, fmt_ms(c->st[ST_TOTAL].median, a, sizeof a),
           fmt_ms(c->st[ST_TOTAL].min, b, sizeof b), fmt_ms(c->st[ST_TOTAL].p90, d, sizeof d),
           fmt_ms(c->st[ST_PREPARE].median, e, sizeof e), fmt_ms(c->st[ST_FIELD].median, f, sizeof f),
           fmt_ms(c->st[ST_EXTRACT].median, g, sizeof g), fmt_ms(c->st[ST_ATTR].median, h, sizeof h));
    if (o->write_format >= 0)
        printf(" %9s", fmt_ms(c->st[ST_WRITE].median, a, sizeof a));
    double sec = c->st[ST_TOTAL].median / 1e3;
    printf(" | %8s %8s | %9zu %9zu | %8s %8s | %6s %6s\n",
           fmt_rate(sec > 0 ? (double)c->last.particles / sec : 0, a, sizeof a),
           fmt_rate(sec > 0 ? (double)c->last.triangles / sec : 0, b, sizeof b), c->last.vertices,
           c->last.triangles, fmt_mib(c->lib_peak, d, sizeof d), fmt_mib(c->rss_peak, e, sizeof e),
           fmt_ratio(c->speedup_threads, f, sizeof f), fmt_ratio(c->speedup_templates, g, sizeof g));
    fflush(stdout);
}

/* ------------------------------------------------------------------ */
/* JSON.                                                               */

static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '"' || *p == '\\')
            fprintf(f, "\\%c", *p);
        else if (*p == '\n')
            fputs("\\n", f);
        else if (*p == '\t')
            fputs("\\t", f);
        else if (*p < 0x20)
            fprintf(f, "\\u%04x", *p);
        else
            fputc(*p, f);
    }
    fputc('"', f);
}

static void json_num(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.9g", v);
    else
        fputs("null", f);
}

static void json_opt(FILE *f, double v) /* 0 = not applicable */
{
    if (v > 0)
        json_num(f, v);
    else
        fputs("null", f);
}

static void json_summary(FILE *f, const summary *s)
{
    fputs("{\"median\": ", f);
    json_num(f, s->median);
    fputs(", \"min\": ", f);
    json_num(f, s->min);
    fputs(", \"p10\": ", f);
    json_num(f, s->p10);
    fputs(", \"q1\": ", f);
    json_num(f, s->q1);
    fputs(", \"q3\": ", f);
    json_num(f, s->q3);
    fputs(", \"p90\": ", f);
    json_num(f, s->p90);
    fputs(", \"max\": ", f);
    json_num(f, s->max);
    fputs(", \"mean\": ", f);
    json_num(f, s->mean);
    fputs("}", f);
}

static void json_case(FILE *f, const bench_opts *o, const bench_input *in, const bench_case *c)
{
    const char *kind = in->kind == IN_JET ? "jet" : in->kind == IN_BLOCK ? "block"
                                                   : in->kind == IN_SPRAY ? "spray" : "file";
    fputs("    {\"name\": ", f);
    json_str(f, in->name);
    fprintf(f, ", \"kind\": \"%s\"", kind);
    if (in->kind == IN_FILE) {
        fputs(", \"path\": ", f);
        json_str(f, in->path);
    } else if (in->kind == IN_JET)
        fprintf(f, ", \"frame\": %d", in->frame);
    else
        fprintf(f, ", \"n\": %zu, \"seed\": %llu", in->n, (unsigned long long)o->seed);
    fprintf(f, ",\n     \"field\": \"%s\", \"method\": \"%s\", \"radius\": ", field_name(c->field),
            method_name(c->method));
    json_num(f, o->radius);
    fputs(", \"cube_size\": ", f);
    json_num(f, c->cube);
    const jm_params *p = &c->params;
    if (c->ran && p->radius > 0) {
        fputs(", \"threshold\": ", f);
        json_num(f, p->threshold);
        fputs(", \"smoothing_length\": ", f);
        json_num(f, p->smoothing_length);
        fputs(", \"link_distance\": ", f);
        json_num(f, p->link_distance);
    }
    fprintf(f, ", \"threads\": %d, \"templates\": %s,\n", c->threads, c->templates ? "true" : "false");
    fprintf(f, "     \"status\": \"%s\", \"error\": ", c->ok ? "ok" : "failed");
    if (c->ok)
        fputs("null", f);
    else
        json_str(f, c->err);
    if (!c->ok) {
        fputs("}", f);
        return;
    }
    const jm_stats *st = &c->last;
    double sec = c->st[ST_TOTAL].median / 1e3;
    fprintf(f, ", \"repetitions\": %zu, \"warmup\": %ld, \"threads_used\": %d,\n", c->reps, o->warmup,
            st->threads);
    fprintf(f, "     \"particles\": %zu, \"isolated\": %zu, \"blocks\": %zu, \"cells\": %zu, "
               "\"vertices\": %zu, \"triangles\": %zu,\n",
            st->particles, st->isolated, st->blocks, st->cells, st->vertices, st->triangles);
    fputs("     \"particles_per_s\": ", f);
    json_num(f, sec > 0 ? (double)st->particles / sec : NAN);
    fputs(", \"triangles_per_s\": ", f);
    json_num(f, sec > 0 ? (double)st->triangles / sec : NAN);
    fprintf(f, ",\n     \"estimated_bytes\": %zu, \"lib_peak_bytes\": %zu, \"peak_rss_bytes\": %zu, "
               "\"peak_rss_reset\": %s,\n",
            st->estimated_bytes, c->lib_peak, c->rss_peak, c->rss_reset ? "true" : "false");
    fputs("     \"ms\": {\n", f);
    for (int k = 0; k < ST_COUNT; k++) {
        fprintf(f, "       \"%s\": ", stage_key[k]);
        if (k == ST_WRITE && !c->has_write)
            fputs("null", f);
        else
            json_summary(f, &c->st[k]);
        fputs(k + 1 < ST_COUNT ? ",\n" : "\n", f);
    }
    fputs("     },\n     \"write\": ", f);
    if (c->has_write) {
        fputs("{\"format\": ", f);
        json_str(f, o->write_ext);
        fprintf(f, ", \"bytes\": %zu, \"fraction_of_total\": ", c->write_bytes);
        double w = c->st[ST_WRITE].median, t = c->st[ST_TOTAL].median;
        json_num(f, w + t > 0 ? w / (w + t) : NAN);
        fputs("}", f);
    } else
        fputs("null", f);
    fputs(",\n     \"speedup_vs_1_thread\": ", f);
    json_opt(f, c->speedup_threads);
    fputs(", \"template_speedup\": ", f);
    json_opt(f, c->speedup_templates);
    fputs("}", f);
}

static void json_doc(FILE *f, const bench_opts *o, const machine *m, const bench_case *cases,
                     size_t ncases, int failed)
{
    fputs("{\n", f);
    fprintf(f, "  \"jetmesh_version\": \"%s\",\n", jm_version());
    fputs("  \"date\": ", f);
    json_str(f, m->date);
    fputs(",\n  \"machine\": {\"cpu_model\": ", f);
    json_str(f, m->cpu);
    fprintf(f, ", \"cores\": %d, \"memory_bytes\": %zu, \"os\": ", m->cores, m->memory);
    json_str(f, m->os);
    fputs("},\n  \"settings\": {\"min_time_s\": ", f);
    json_num(f, o->min_time);
    fprintf(f, ", \"repeat\": %ld, \"max_repeat\": %ld, \"warmup\": %ld, \"write\": ", o->repeat,
            o->max_repeat, o->warmup);
    if (o->write_format >= 0)
        json_str(f, o->write_ext);
    else
        fputs("null", f);
    fputs(", \"radius\": ", f);
    json_num(f, o->radius);
    fputs("},\n", f);
    fprintf(f, "  \"failed\": %d,\n  \"cases\": [\n", failed);
    for (size_t i = 0; i < ncases; i++) {
        json_case(f, o, &o->inputs[cases[i].input], &cases[i]);
        fputs(i + 1 < ncases ? ",\n" : "\n", f);
    }
    fputs("  ]\n}\n", f);
}

/* ------------------------------------------------------------------ */
/* The command.                                                        */

static int same_but(const bench_case *a, const bench_case *b)
{
    return a->input == b->input && a->field == b->field && a->method == b->method && a->cube == b->cube;
}

int cmd_bench(int argc, char **argv)
{
    bench_opts *o = calloc(1, sizeof *o);
    if (!o) {
        fprintf(stderr, "jetmesh bench: out of memory\n");
        return 1;
    }
    int rc = parse_opts(argc, argv, o);
    if (rc != OPTIONS_RUN) {
        free(o);
        return rc == OPTIONS_DONE ? 0 : 2;
    }

    /* every case, in the order they run */
    size_t cap = 0, ncases = 0;
    for (size_t i = 0; i < o->ninputs; i++)
        cap += o->nfields * o->nmethods * o->ncubes * 2 * o->nthreads;
    bench_case *cases = calloc(cap ? cap : 1, sizeof *cases);
    if (!cases) {
        fprintf(stderr, "jetmesh bench: out of memory\n");
        free(o);
        return 1;
    }
    for (size_t i = 0; i < o->ninputs; i++) {
        int tpl[2], ntpl = 0;
        tpl_mode mode = o->templates;
        if (mode == TPL_AUTO)
            mode = is_spray(&o->inputs[i]) ? TPL_BOTH : TPL_ON;
        if (mode == TPL_BOTH) { /* the general path first: the baseline */
            tpl[ntpl++] = 0;
            tpl[ntpl++] = 1;
        } else
            tpl[ntpl++] = mode == TPL_ON;
        for (size_t fi = 0; fi < o->nfields; fi++)
            for (size_t mi = 0; mi < o->nmethods; mi++)
                for (size_t ci = 0; ci < o->ncubes; ci++)
                    for (int ti = 0; ti < ntpl; ti++)
                        for (size_t ji = 0; ji < o->nthreads; ji++) {
                            bench_case *c = &cases[ncases++];
                            c->input = i;
                            c->field = o->fields[fi];
                            c->method = o->methods[mi];
                            c->cube = o->cubes[ci];
                            c->templates = tpl[ti];
                            c->threads = o->threads[ji];
                        }
    }

    machine m;
    machine_info(&m);
    char wdir[4096] = "";
    if (o->write_format >= 0) {
        const char *base = o->write_dir ? o->write_dir : getenv("TMPDIR");
        if (!base || !*base)
            base = "/tmp";
        snprintf(wdir, sizeof wdir, "%s/jetmesh-bench.XXXXXX", base);
        if (!mkdtemp(wdir)) {
            fprintf(stderr, "jetmesh bench: cannot create a directory in %s: %s\n", base, strerror(errno));
            free(cases);
            free(o);
            return 1;
        }
        signals_install_cleanup();
    }

    if (!o->json)
        print_header(o, &m);
    int failed = 0;
    size_t loaded_for = (size_t)-1;
    for (size_t k = 0; k < ncases; k++) {
        bench_case *c = &cases[k];
        bench_input *in = &o->inputs[c->input];
        if (loaded_for != c->input) { /* one input in memory at a time */
            if (loaded_for != (size_t)-1)
                free_input(&o->inputs[loaded_for]);
            progress(o, "bench: loading %s", in->name);
            load_input(o, in);
            progress(o, NULL);
            if (in->loaded != 1)
                fprintf(stderr, "jetmesh bench: %s\n", in->err);
            loaded_for = c->input;
        }
        run_case(o, in, c, wdir);
        if (!c->ok) {
            failed++;
            if (in->loaded == 1) /* a load failure was told once above */
                fprintf(stderr, "jetmesh bench: %s: %s\n", in->name, c->err);
        } else {
            for (size_t b = 0; b < k; b++) {
                const bench_case *base = &cases[b];
                if (!base->ok || !same_but(base, c))
                    continue;
                if (c->threads > 1 && base->threads == 1 && base->templates == c->templates)
                    c->speedup_threads = base->st[ST_TOTAL].median / c->st[ST_TOTAL].median;
                if (c->templates && !base->templates && base->threads == c->threads)
                    c->speedup_templates = base->st[ST_TOTAL].median / c->st[ST_TOTAL].median;
            }
        }
        if (!o->json)
            print_row(o, in, c);
    }
    if (loaded_for != (size_t)-1)
        free_input(&o->inputs[loaded_for]);
    if (wdir[0]) {
        empty_dir(wdir);
        rmdir(wdir);
    }

    if (!o->json) {
        printf("\ntimes in ms; total: median, min, p90 over the timed runs; stages: medians");
        if (o->write_format >= 0)
            printf(" (write: %s, not part of total)", o->write_ext);
        printf(".\n");
        int unreset = 0;
        for (size_t k = 0; k < ncases; k++)
            unreset |= cases[k].ok && !cases[k].rss_reset;
        if (unreset)
            printf("RSS peak: the kernel refused a reset, so it is the process's peak so far.\n");
        if (failed)
            printf("%d case%s failed.\n", failed, failed == 1 ? "" : "s");
    }
    if (o->json)
        json_doc(stdout, o, &m, cases, ncases, failed);
    if (o->json_out) {
        FILE *f = fopen(o->json_out, "w");
        if (!f) {
            fprintf(stderr, "jetmesh bench: %s: %s\n", o->json_out, strerror(errno));
            failed++;
        } else {
            json_doc(f, o, &m, cases, ncases, failed);
            if (fclose(f) != 0) {
                fprintf(stderr, "jetmesh bench: %s: write error\n", o->json_out);
                failed++;
            }
        }
    }
    fflush(stdout);
    free(cases);
    free(o);
    return failed ? 1 : 0;
}
