/* options.c - parses the options of `jetmesh convert` and `jetmesh generate` with getopt_long. */
#include "numbers.h"
#include "options.h"

#include <errno.h>
#include <float.h>
#include <getopt.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_options.h"
#include "platform.h"
#include "scenes.h"
#include "select_options.h"
#include "stats/stats.h"

size_t options_default_max_memory(void)
{
    return platform_physical_memory() / 2;
}

void options_convert_help(FILE *f)
{
    fputs(
        "Usage: jetmesh convert [options] INPUT... -o OUTPUT\n"
        "Meshes particle frames into triangle meshes, one output per input frame.\n"
        "\n"
        "Inputs: files, or patterns: frame_{}.vtk (existing files whose {} part is\n"
        "digits, in numeric order) or frame_%04d.vtk (with --frames: exactly that range);\n"
        "- is standard input (CSV or XYZ there need --input-format).\n"
        "OUTPUT: a file (one frame), a template with {} or %04d (the frame number), or\n"
        "a directory (several frames: DIR/<input name>.<ext>, ext from --format, else glb).\n"
        "\n",
        f);
    mesh_options_help(f, CLI_CONVERT, NULL);
    fputs("\n"
        "Input and output:\n"
        "      --input-format auto|csv|xyz|vtk|vtu|bgeo|ply  (default auto)\n"
        "      --frames START:END[:STEP]  select frame numbers; END is inclusive\n"
        "      --drop-invalid          skip particles with NaN/inf coordinates\n"
        "  -o, --output OUTPUT         output file, template or directory\n"
        "      --format obj|gltf|glb|drc|ply|vtk  (default: from OUTPUT's extension)\n"
        "      --draco                 glTF/GLB: KHR_draco_mesh_compression\n"
        "      --embed                 .gltf: embed the buffer (no .bin beside it)\n"
        "      --z-up                  input is +Z up: rotate to glTF's +Y up\n"
        "      --draco-position-bits N quantisation bits (default 16)\n"
        "      --draco-normal-bits N   (default 10)\n"
        "      --draco-uv-bits N       (default 12)\n"
        "\n"
        "Sequences (Blender, ParaView, the web):\n"
        "      --animate               every frame into the one -o file (.glb or .gltf):\n"
        "                              one node per frame, shown at its time by a STEP\n"
        "                              scale animation; at most 2 GiB (a longer run:\n"
        "                              one file per frame, which Blender streams: see\n"
        "                              jetmesh --blender-script)\n"
        "      --fps F                 frames per second of --animate and of the .pvd\n"
        "                              times, 0.001 to 100000 (default 24)\n"
        "      --pvd                   VTK/PLY sequences: a ParaView collection NAME.pvd\n"
        "                              beside the frames (time -> file)\n"
        "      --time-step DT          .pvd time per frame number (default 1/fps)\n"
        "      --attributes LIST|all   per-particle arrays (velocity,density,...; from\n"
        "                              VTK, VTU, BGEO, PLY or CSV) interpolated to the\n"
        "                              vertices with SPH weights: glTF _VELOCITY-style\n"
        "                              attributes (with --draco too), .drc generic\n"
        "                              attributes, PLY properties, VTK point data\n"
        "\n"
        "Running:\n"
        "      --keep-going            convert every other frame after a failure\n"
        "      --no-sync               do not fsync each output before renaming it into\n"
        "                              place (faster; a crash of the machine may then\n"
        "                              lose recent outputs, a killed run still cannot)\n"
        "      --frame-jobs N          frames converted at once, the threads shared among\n"
        "                              them (output identical); 0 = auto (default: as many\n"
        "                              as threads, at most 16), 1 = one at a time\n"
        "      --resume                skip frames whose output already exists\n"
        "      --shard I/N             convert only share I (0 to N-1) of the frames: positions\n"
        "                              I, I+N, I+2N... (N processes, e.g. a cluster's array\n"
        "                              tasks, together convert every frame once); slurm:\n"
        "                              I and N of this task of a Slurm job array\n"
        "      --stats FILE.csv|FILE.json  per-frame statistics and a summary\n"
        "      --stats-svg FILE.svg    stacked bar chart of time per frame by stage\n"
        "  -q, --quiet                 no per-frame lines, no progress bar\n"
        "  -v, --verbose               parameters and stage times too\n"
        "      --help                  this help\n"
        "      --version               print the version\n"
        "\n"
        "Exit status: 0 all frames converted, 1 some failed, 2 usage error,\n"
        "3 out of memory, over --max-memory, an --animate file over 2 GiB or internal\n"
        "error. See jetmesh(1).\n",
        f);
}

void options_generate_help(FILE *f)
{
    fputs("Usage: jetmesh generate SCENE [N] -o OUTPUT [options]\n"
          "Writes a deterministic synthetic particle scene as CSV or XYZ (by extension).\n"
          "\n"
          "Scenes:\n"
          "  jet       the 125-particle liquid jet, a sequence of frames 0..99\n"
          "  block N   N particles on a cubic lattice of spacing 2R, jittered\n"
          "  spray N   N isolated droplets at least 8R apart\n"
          "  ball N    a ball of about N particles: a lattice of spacing 2R, jittered\n"
          "  droplets N  N groups 24R apart: single particles, pairs, dense clusters,\n"
          "            lines and drops hanging from a sheet by a thin neck\n"
          "\n"
          "Options:\n"
          "  -o, --output OUTPUT         .csv or .xyz file; with {} or %03d, one per frame\n"
          "  -r, --radius R              particle radius (default 0.025)\n"
          "      --seed S                seed of block and spray (default 1; frame F uses S+F)\n"
          "      --frames START:END[:STEP]  frames to write (END inclusive; jet default\n"
          "                              0:99 with a template, else 99)\n"
          "  -q, --quiet                 print nothing but errors\n"
          "      --help                  this help\n",
          f);
}

enum {
    O_FORMAT = 256, O_DRACO, O_EMBED, O_ZUP, O_DPOS, O_DNORM, O_DUV, O_INFORMAT,
    O_FRAMES, O_FRAMEJOBS, O_NOSYNC, O_STATS, O_STATSSVG, O_DROP, O_KEEP, O_RESUME, O_HELP, O_VERSION, O_SEED,
    /* sequences for Blender, ParaView and the web */
    O_ANIMATE = 500, O_FPS, O_TIMESTEP, O_PVD, O_ATTRS
};

/* options of the cluster block (see SHARDS in jetmesh(1)) */
enum { O_SHARD = 400 };

/* convert's own options; the meshing options come from mesh_options.c */
static const struct option convert_own[] = {
    {"shard", required_argument, 0, O_SHARD},
    {"output", required_argument, 0, 'o'},
    {"format", required_argument, 0, O_FORMAT},
    {"draco", no_argument, 0, O_DRACO},
    {"embed", no_argument, 0, O_EMBED},
    {"z-up", no_argument, 0, O_ZUP},
    {"draco-position-bits", required_argument, 0, O_DPOS},
    {"draco-normal-bits", required_argument, 0, O_DNORM},
    {"draco-uv-bits", required_argument, 0, O_DUV},
    {"input-format", required_argument, 0, O_INFORMAT},
    {"frames", required_argument, 0, O_FRAMES},
    {"stats", required_argument, 0, O_STATS},
    {"stats-svg", required_argument, 0, O_STATSSVG},
    {"drop-invalid", no_argument, 0, O_DROP},
    {"keep-going", no_argument, 0, O_KEEP},
    {"no-sync", no_argument, 0, O_NOSYNC},
    {"frame-jobs", required_argument, 0, O_FRAMEJOBS},
    {"resume", no_argument, 0, O_RESUME},
    {"quiet", no_argument, 0, 'q'},
    {"verbose", no_argument, 0, 'v'},
    {"help", no_argument, 0, O_HELP},
    {"version", no_argument, 0, O_VERSION},
    /* sequences for Blender, ParaView and the web */
    {"animate", no_argument, 0, O_ANIMATE},
    {"fps", required_argument, 0, O_FPS},
    {"time-step", required_argument, 0, O_TIMESTEP},
    {"pvd", no_argument, 0, O_PVD},
    {"attributes", required_argument, 0, O_ATTRS},
};
#define NOWN (sizeof convert_own / sizeof convert_own[0])

/* The message for getopt's '?' and ':' results. */
static int getopt_problem(const char *cmd, int c, char **argv)
{
    const char *arg = argv[optind - 1];
    if (c == ':')
        return options_usage_error(cmd, "option '%s' needs a value", arg);
    if (optopt)
        return options_usage_error(cmd, "unknown option '-%c'", optopt);
    return options_usage_error(cmd, "unknown option '%s'", arg);
}

/* --radius of generate: a normal float (jetmesh(1) LIMITS) */
#define LEN_MIN 1.2e-38
/* --fps: the frame numbers (up to 18 digits) over it stay finite floats */
#define FPS_MIN 0.001
#define LEN_MAX 1e30

static int bits(const char *cmd, const char *name, const char *arg, int *out)
{
    long v;
    if (cli_parse_long(arg, 1, 30, &v) != 0)
        return options_usage_error(cmd, "%s must be a whole number from 1 to 30, not '%s'", name, arg);
    *out = (int)v;
    return OPTIONS_RUN;
}

/* The value a handler returns for an option that is not its own. */
#define NOT_MINE 1000

/* A meshing option (mesh_options.c), and what convert notes of it. */
static int convert_mesh_option(convert_options *o, int c, int argc, char **argv, int *radius_given,
                               select_given *sel)
{
    const mesh_option *m = mesh_option_find(c);
    if (!m)
        return NOT_MINE;
    if (mesh_option_is_select(m))
        return select_option("convert", c, optarg, &o->params, sel);
    int rc = mesh_option_parse(m, CLI_CONVERT, optarg, argc, argv, &o->params);
    if (c == 'r')
        *radius_given = 1;
    else if (c == MO_FIELD)
        o->field_auto = strcmp(optarg, "auto") == 0;
    else if (c == MO_THRESHOLD)
        o->threshold_given = 1;
    return rc;
}

/* -o and the options of the written file. */
static int convert_output_option(convert_options *o, int c)
{
    const char *cmd = "convert";
    int k;
    switch (c) {
    case 'o': o->output = optarg; return OPTIONS_RUN;
    case O_FORMAT:
        k = jmf_output_format_parse(optarg);
        if (k < 0)
            return options_usage_error(cmd, "--format is obj, gltf, glb, drc, ply or vtk, not '%s'", optarg);
        o->write.format = (jmf_output_format)k;
        o->format_given = 1;
        return OPTIONS_RUN;
    case O_DRACO: o->write.draco = 1; return OPTIONS_RUN;
    case O_EMBED: o->write.embed = 1; return OPTIONS_RUN;
    case O_ZUP: o->write.z_up = 1; return OPTIONS_RUN;
    case O_DPOS: return bits(cmd, "--draco-position-bits", optarg, &o->write.draco_position_bits);
    case O_DNORM: return bits(cmd, "--draco-normal-bits", optarg, &o->write.draco_normal_bits);
    case O_DUV: return bits(cmd, "--draco-uv-bits", optarg, &o->write.draco_uv_bits);
    case O_NOSYNC: o->write.no_sync = 1; return OPTIONS_RUN;
    default: return NOT_MINE;
    }
}

/* What is read, and how the run goes. */
static int convert_run_option(convert_options *o, int c)
{
    const char *cmd = "convert";
    char err[256];
    long l;
    int k;
    switch (c) {
    case O_INFORMAT:
        k = jmf_input_format_parse(optarg);
        if (k < 0)
            return options_usage_error(cmd, "--input-format is auto, csv, xyz, vtk, vtu, bgeo or ply, not '%s'",
                                       optarg);
        o->read.format = (jmf_input_format)k;
        return OPTIONS_RUN;
    case O_FRAMES:
        if (seq_range_parse(optarg, &o->frames, err, sizeof err) != 0)
            return options_usage_error(cmd, "--frames: %s", err);
        return OPTIONS_RUN;
    case O_STATS:
        o->stats_path = optarg;
        if (!stats_path_ok(optarg))
            return options_usage_error(cmd, "--stats FILE must end in .csv or .json, not '%s'", optarg);
        return OPTIONS_RUN;
    case O_STATSSVG: {
        size_t n = strlen(optarg);
        o->stats_svg = optarg;
        if (n < 5 || strcmp(optarg + n - 4, ".svg") != 0)
            return options_usage_error(cmd, "--stats-svg FILE must end in .svg, not '%s'", optarg);
        return OPTIONS_RUN;
    }
    case O_DROP: o->read.drop_invalid = 1; return OPTIONS_RUN;
    case O_FRAMEJOBS:
        if (cli_parse_long(optarg, 0, CONVERT_MAX_FRAME_JOBS, &l) != 0)
            return options_usage_error(cmd, "--frame-jobs must be a whole number from 0 to %d, not '%s'",
                                       CONVERT_MAX_FRAME_JOBS, optarg);
        o->frame_jobs = (int)l;
        return OPTIONS_RUN;
    case O_KEEP: o->keep_going = 1; return OPTIONS_RUN;
    case O_RESUME: o->resume = 1; return OPTIONS_RUN;
    case O_SHARD:
        if (shard_parse(optarg, &o->shard, err, sizeof err) != 0)
            return options_usage_error(cmd, "%s", err);
        return OPTIONS_RUN;
    case 'q': o->quiet = 1; o->verbose = 0; return OPTIONS_RUN;
    case 'v': o->verbose = 1; o->quiet = 0; return OPTIONS_RUN;
    default: return NOT_MINE;
    }
}

/* Sequences for Blender, ParaView and the web. */
static int convert_sequence_option(convert_options *o, int c)
{
    const char *cmd = "convert";
    double d = 0;
    switch (c) {
    case O_ANIMATE: o->animate = 1; return OPTIONS_RUN;
    case O_FPS:
        /* key times (frame number / fps) stay finite floats */
        if (cli_parse_double(optarg, &d) != 0 || !(d >= FPS_MIN) || d > 100000)
            return options_usage_error(cmd, "--fps must be a number from %g to 100000, not '%s'", FPS_MIN, optarg);
        o->fps = d;
        return OPTIONS_RUN;
    case O_TIMESTEP:
        if (cli_parse_double(optarg, &d) != 0 || !(d >= 1e-30) || d > 1e30)
            return options_usage_error(cmd, "--time-step must be a number from 1e-30 to 1e+30, not '%s'", optarg);
        o->time_step = d;
        return OPTIONS_RUN;
    case O_PVD: o->pvd = 1; return OPTIONS_RUN;
    case O_ATTRS:
        o->attributes = optarg;
        if (!*optarg || strspn(optarg, ", ") == strlen(optarg))
            return options_usage_error(cmd, "--attributes needs names (velocity,density) or all");
        return OPTIONS_RUN;
    default: return NOT_MINE;
    }
}

/* After the options: the operands, what is required, and the options that
 * need or exclude others. */
static int convert_finish(int argc, char **argv, convert_options *o, int radius_given)
{
    const char *cmd = "convert";
    if (o->fps <= 0)
        o->fps = 24.0;
    o->read.attributes = o->attributes;
    o->inputs = argv + optind;
    o->ninputs = (size_t)(argc - optind);
    if (o->ninputs == 0)
        return options_usage_error(cmd, "no input files");
    if (!o->output)
        return options_usage_error(cmd, "no output: give -o OUTPUT");
    if (!radius_given)
        return options_usage_error(cmd, "the particle radius is required: give -r R");
    if (o->field_auto && o->threshold_given)
        return options_usage_error(cmd, "--threshold means a different thing for each field (default 0 "
                                        "metasphere, 0.6 sph): give --field metasphere or --field sph with it");
    if (o->params.anisotropic && o->field_auto) { /* anisotropic kernels are the SPH field's */
        o->field_auto = 0;
        o->params.field = JM_FIELD_SPH;
        if (o->params.method == JM_METHOD_DEFAULT)
            o->params.method = JM_METHOD_MC;
    }
    /* the documented default: mc with the SPH field (the library's own
     * default is mt, the paper's method, whatever the field) */
    if (!o->field_auto && o->params.field == JM_FIELD_SPH && o->params.method == JM_METHOD_DEFAULT)
        o->params.method = JM_METHOD_MC;
    if ((o->params.anisotropic || o->params.aniso_radius > 0) && o->params.field != JM_FIELD_SPH)
        return options_usage_error(cmd, "--anisotropic works on the SPH field only: add --field sph");
    if (o->params.aniso_radius > 0 && !o->params.anisotropic)
        return options_usage_error(cmd, "--anisotropic-radius needs --anisotropic");
    const int mrc = mesh_options_check(cmd, &o->params);
    if (mrc != OPTIONS_RUN)
        return mrc;
    if (o->animate && o->shard.count > 0)
        return options_usage_error(cmd, "--animate writes the whole run into one file, which shards cannot "
                                        "share: convert shards to per-frame files, or animate in one run");
    o->max_memory = o->params.max_bytes; /* --max-memory, or its default */
    o->read.max_bytes = o->max_memory;
    return OPTIONS_RUN;
}

int options_parse_convert(int argc, char **argv, convert_options *o)
{
    const char *cmd = "convert";
    struct option longs[NOWN + MESH_OPTIONS_MAX + 1];
    size_t nlong = NOWN;
    memcpy(longs, convert_own, sizeof convert_own);
    mesh_options_long(CLI_CONVERT, longs, &nlong);
    longs[nlong] = (struct option){0, 0, 0, 0};
    memset(o, 0, sizeof *o);
    o->params.max_bytes = options_default_max_memory();
    o->field_auto = 1;
    int radius_given = 0, rc = OPTIONS_RUN, c;
    select_given sel = {0, 0, 0, 0};
    optind = 0; /* GNU: full reinitialisation */
    opterr = 0;
    while (rc == OPTIONS_RUN && (c = getopt_long(argc, argv, ":r:c:j:o:qv", longs, NULL)) != -1) {
        if (c == O_HELP) {
            options_convert_help(stdout);
            return OPTIONS_DONE;
        }
        if (c == O_VERSION) {
            printf("jetmesh %s\n", JM_VERSION_STRING);
            return OPTIONS_DONE;
        }
        rc = convert_mesh_option(o, c, argc, argv, &radius_given, &sel);
        if (rc == NOT_MINE)
            rc = convert_output_option(o, c);
        if (rc == NOT_MINE)
            rc = convert_run_option(o, c);
        if (rc == NOT_MINE)
            rc = convert_sequence_option(o, c);
        if (rc == NOT_MINE)
            rc = getopt_problem(cmd, c, argv);
    }
    if (rc == OPTIONS_RUN)
        rc = select_finish(cmd, &o->params, &sel);
    if (rc != OPTIONS_RUN)
        return rc;
    return convert_finish(argc, argv, o, radius_given);
}

static const struct option generate_long[] = {
    {"output", required_argument, 0, 'o'},
    {"radius", required_argument, 0, 'r'},
    {"seed", required_argument, 0, O_SEED},
    {"frames", required_argument, 0, O_FRAMES},
    {"quiet", no_argument, 0, 'q'},
    {"help", no_argument, 0, O_HELP},
    {"version", no_argument, 0, O_VERSION},
    {0, 0, 0, 0},
};

int options_parse_generate(int argc, char **argv, generate_options *o)
{
    const char *cmd = "generate";
    memset(o, 0, sizeof *o);
    o->radius = SCENE_DEFAULT_RADIUS;
    o->seed = 1;
    int rc = OPTIONS_RUN, c;
    optind = 0;
    opterr = 0;
    while (rc == OPTIONS_RUN && (c = getopt_long(argc, argv, ":o:r:q", generate_long, NULL)) != -1) {
        double d = 0;
        switch (c) {
        case 'o': o->output = optarg; break;
        case 'r':
            if (cli_parse_double(optarg, &d) != 0 || !(d >= LEN_MIN) || d > LEN_MAX)
                rc = options_usage_error(cmd, "--radius must be a number from %g to %g, not '%s'", LEN_MIN, LEN_MAX,
                                         optarg);
            o->radius = d;
            break;
        case O_SEED: {
            char *end;
            errno = 0;
            unsigned long long s = strtoull(optarg, &end, 10);
            if (!*optarg || *end || errno || optarg[0] == '-')
                rc = options_usage_error(cmd, "--seed must be a whole number from 0 to %llu, not '%s'",
                                         (unsigned long long)UINT64_MAX, optarg);
            o->seed = (uint64_t)s;
            break;
        }
        case O_FRAMES: {
            char err[256];
            if (seq_range_parse(optarg, &o->frames, err, sizeof err) != 0)
                rc = options_usage_error(cmd, "--frames: %s", err);
            break;
        }
        case 'q': o->quiet = 1; break;
        case O_HELP: options_generate_help(stdout); return OPTIONS_DONE;
        case O_VERSION: printf("jetmesh %s\n", JM_VERSION_STRING); return OPTIONS_DONE;
        default: rc = getopt_problem(cmd, c, argv); break;
        }
    }
    if (rc != OPTIONS_RUN)
        return rc;
    int nargs = argc - optind;
    if (nargs < 1)
        return options_usage_error(cmd, "no scene: give jet, block N, spray N, ball N or droplets N");
    o->scene = argv[optind];
    int needs_n = strcmp(o->scene, "block") == 0 || strcmp(o->scene, "spray") == 0 ||
                  strcmp(o->scene, "ball") == 0 || strcmp(o->scene, "droplets") == 0;
    if (!needs_n && strcmp(o->scene, "jet") != 0)
        return options_usage_error(cmd, "unknown scene '%s': give jet, block N, spray N, ball N or droplets N",
                                   o->scene);
    if (needs_n) {
        long n;
        if (nargs < 2)
            return options_usage_error(cmd, "%s needs a particle count N", o->scene);
        if (cli_parse_long(argv[optind + 1], 0, 1000000000L, &n) != 0)
            return options_usage_error(cmd, "N must be a whole number from 0 to 1000000000, not '%s'",
                                       argv[optind + 1]);
        o->count = (size_t)n;
    }
    if (nargs > (needs_n ? 2 : 1))
        return options_usage_error(cmd, "unexpected argument '%s'", argv[optind + (needs_n ? 2 : 1)]);
    if (!o->output)
        return options_usage_error(cmd, "no output: give -o FILE.csv or FILE.xyz");
    return OPTIONS_RUN;
}
