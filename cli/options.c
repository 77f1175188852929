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

#include "platform.h"
#include "scenes.h"
#include "select_options.h"
#include "stats/stats.h"

int options_usage_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "jetmesh %s: ", cmd);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\nTry 'jetmesh %s --help' for more information.\n", cmd);
    return OPTIONS_USAGE;
}

int options_parse_size(const char *s, size_t *out)
{
    if (!s || !*s)
        return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || !isfinite(v) || v < 0 || end == s)
        return -1;
    double mul = 1;
    switch (*end) {
    case 'k': case 'K': mul = 1024.0; end++; break;
    case 'm': case 'M': mul = 1024.0 * 1024; end++; break;
    case 'g': case 'G': mul = 1024.0 * 1024 * 1024; end++; break;
    case 't': case 'T': mul = 1024.0 * 1024 * 1024 * 1024; end++; break;
    default: break;
    }
    if (mul > 1 && *end == 'i')
        end++;
    if (*end == 'B' || *end == 'b')
        end++;
    if (*end)
        return -1;
    double bytes = v * mul;
    if (bytes >= 18446744073709551615.0 || bytes > (double)(size_t)-1)
        return -1;
    *out = (size_t)bytes;
    return 0;
}

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
        "\n"
        "Meshing:\n"
        "  -r, --radius R              particle radius in world units (required)\n"
        "  -c, --cube-size C           lattice cube edge, relative to R (default 0.5)\n"
        "      --field auto|metasphere|sph  implicit function (default auto: metasphere\n"
        "                              for sparse frames such as jets and spray, sph\n"
        "                              for bulk fluid, chosen once from the first frame)\n"
        "      --method mt|mc          marching tetrahedra or cubes (default mt with the\n"
        "                              metasphere, mc with sph)\n"
        "      --threshold T           iso value (default 0 metasphere, 0.6 sph)\n"
        "      --smoothing-length L    sph kernel length h, relative to R (default 2)\n"
        "      --link-distance L       metasphere neck link distance, relative to R (default pi)\n"
        "  -j, --threads N             worker threads; 0 = all cores (default 0)\n"
        "      --uv box|planar|spherical|none  texture coordinates (default box)\n"
        "      --uv-scale S            world units per texture repeat (default 16 R;\n"
        "                              at least 1e-6 R)\n"
        "      --no-normals            write no normals\n"
        "      --no-templates          mesh isolated particles through the lattice too\n"
        "      --uv-axis x|y|z         --uv planar: the projection axis (default z)\n"
        "      --keep-cavities         keep closed inner shells smaller than a particle\n"
        "                              (removed by default: sub-particle bubbles)\n"
        "      --no-compensation       metasphere: leave vertices on the surface (no\n"
        "                              chord-sag offset; the mesh is then a bit small)\n"
        "      --exact-surface         deprecated: does nothing (metasphere vertices are\n"
        "                              always on the exact surface); removed in 0.4.0\n"
        "      --max-memory SIZE       refuse frames needing more (e.g. 2G, 500M; 0 = no\n"
        "                              limit; default half the physical memory)\n"
        "      --anisotropic           sph: Yu-Turk anisotropic kernels on smoothed centres:\n"
        "                              flat surfaces look like liquid, not particles\n"
        "                              (slower; for final renders of --field sph)\n"
        "      --anisotropic-radius N  its neighbourhood radius, relative to R (default 8)\n"
        "\n"
        "Post-processing (off by default; in this order):\n"
        "      --smooth [N]            N iterations of Laplacian smoothing (default 25,\n"
        "                              as splashsurf's 25): bumps of particle size\n"
        "                              removed, no point moved over 0.5 R along its\n"
        "                              normal, each piece's volume restored\n"
        "      --smooth-normals [N]    N iterations of normal smoothing (default 10)\n"
        "      --simplify E            fewer triangles, at most E*R from the mesh (e.g. 0.1)\n"
        "\n",
        f);
    select_help(f);
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
    O_FIELD = 256, O_METHOD, O_THRESHOLD, O_SMOOTH, O_LINK, O_UV, O_UVSCALE, O_NONORMALS,
    O_NOTEMPLATES, O_UVAXIS, O_NOCOMP, O_KEEPCAV, O_FORMAT, O_DRACO, O_EMBED, O_ZUP, O_DPOS, O_DNORM, O_DUV, O_INFORMAT,
    O_FRAMES, O_FRAMEJOBS, O_NOSYNC, O_STATS, O_STATSSVG, O_DROP, O_KEEP, O_RESUME, O_MAXMEM, O_HELP, O_VERSION, O_SEED,
    O_ANISO, O_ANISO_RADIUS, O_POST_SMOOTH, O_POST_NSMOOTH, O_POST_SIMPLIFY, O_EXACT,
    /* sequences for Blender, ParaView and the web */
    O_ANIMATE = 500, O_FPS, O_TIMESTEP, O_PVD, O_ATTRS
};

/* options of the cluster block (see SHARDS in jetmesh(1)) */
enum { O_SHARD = 400 };

static const struct option convert_long[] = {
    {"shard", required_argument, 0, O_SHARD},
    {"radius", required_argument, 0, 'r'},
    {"cube-size", required_argument, 0, 'c'},
    {"field", required_argument, 0, O_FIELD},
    {"method", required_argument, 0, O_METHOD},
    {"threshold", required_argument, 0, O_THRESHOLD},
    {"smoothing-length", required_argument, 0, O_SMOOTH},
    {"link-distance", required_argument, 0, O_LINK},
    {"threads", required_argument, 0, 'j'},
    {"uv", required_argument, 0, O_UV},
    {"uv-scale", required_argument, 0, O_UVSCALE},
    {"no-normals", no_argument, 0, O_NONORMALS},
    {"no-templates", no_argument, 0, O_NOTEMPLATES},
    {"uv-axis", required_argument, 0, O_UVAXIS},
    {"no-compensation", no_argument, 0, O_NOCOMP},
    {"keep-cavities", no_argument, 0, O_KEEPCAV},
    {"exact-surface", no_argument, 0, O_EXACT},
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
    {"max-memory", required_argument, 0, O_MAXMEM},
    {"anisotropic", no_argument, 0, O_ANISO},
    {"anisotropic-radius", required_argument, 0, O_ANISO_RADIUS},
    {"smooth", optional_argument, 0, O_POST_SMOOTH},
    {"smooth-normals", optional_argument, 0, O_POST_NSMOOTH},
    {"simplify", required_argument, 0, O_POST_SIMPLIFY},
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
    SELECT_LONG_OPTIONS,
    {0, 0, 0, 0},
};

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

/* The smallest length an option takes: a normal float (0 would mean "the
 * default"; subnormals lose their digits), as jetmesh(1) LIMITS says. */
#define LEN_MIN 1.2e-38
/* --fps: the frame numbers (up to 18 digits) over it stay finite floats */
#define FPS_MIN 0.001
#define LEN_MAX 1e30

/* A length: a normal float up to LEN_MAX, else a usage error naming the
 * option's range (issue 30: every numeric option's message names what it
 * accepts); the library checks the rest of that range (jm_params_check,
 * worded by param_errors_describe). */
static int length(const char *cmd, const char *name, const char *arg, const char *range, float *out)
{
    double v;
    if (cli_parse_double(arg, &v) != 0 || !(v >= LEN_MIN) || !(v <= LEN_MAX))
        return options_usage_error(cmd, "%s must be a number from %s, not '%s'", name, range, arg);
    *out = (float)v;
    return OPTIONS_RUN;
}

static int bits(const char *cmd, const char *name, const char *arg, int *out)
{
    long v;
    if (cli_parse_long(arg, 1, 30, &v) != 0)
        return options_usage_error(cmd, "%s must be a whole number from 1 to 30, not '%s'", name, arg);
    *out = (int)v;
    return OPTIONS_RUN;
}

int options_parse_convert(int argc, char **argv, convert_options *o)
{
    const char *cmd = "convert";
    memset(o, 0, sizeof *o);
    o->max_memory = options_default_max_memory();
    o->field_auto = 1;
    int radius_given = 0, rc = OPTIONS_RUN;
    select_given sel = {0, 0, 0, 0};
    optind = 0; /* GNU: full reinitialisation */
    opterr = 0;
    int c;
    while (rc == OPTIONS_RUN &&
           (c = getopt_long(argc, argv, ":r:c:j:o:qv", convert_long, NULL)) != -1) {
        double d = 0;
        long l = 0;
        int k;
        switch (c) {
        case 'r':
            rc = length(cmd, "--radius", optarg, "1.2e-38 to 1e+30", &o->params.radius);
            radius_given = 1;
            break;
        case 'c': rc = length(cmd, "--cube-size", optarg, "0.001 to 100 (times R)", &o->params.cube_size); break;
        case O_FIELD:
            o->field_auto = 0;
            if (strcmp(optarg, "metasphere") == 0)
                o->params.field = JM_FIELD_METASPHERE;
            else if (strcmp(optarg, "sph") == 0)
                o->params.field = JM_FIELD_SPH;
            else if (strcmp(optarg, "auto") == 0) {
                o->params.field = JM_FIELD_DEFAULT;
                o->field_auto = 1;
            } else
                rc = options_usage_error(cmd, "--field is auto, metasphere or sph, not '%s'", optarg);
            break;
        case O_METHOD:
            if (strcmp(optarg, "mt") == 0)
                o->params.method = JM_METHOD_MT;
            else if (strcmp(optarg, "mc") == 0)
                o->params.method = JM_METHOD_MC;
            else
                rc = options_usage_error(cmd, "--method is mt or mc, not '%s'", optarg);
            break;
        case O_THRESHOLD:
            if (cli_parse_double(optarg, &d) != 0 || (d != 0.0 && fabs(d) < LEN_MIN))
                rc = options_usage_error(cmd, "--threshold must be a number above -1 and below 1 for the "
                                         "metasphere, above 0 for sph (0: the field's default; else at least "
                                         "%g in size), not '%s'", LEN_MIN, optarg);
            o->params.threshold = (float)d;
            o->threshold_given = 1;
            break;
        case O_SMOOTH:
            rc = length(cmd, "--smoothing-length", optarg, "0.05 to 100 (times R)", &o->params.smoothing_length);
            break;
        case O_LINK:
            rc = length(cmd, "--link-distance", optarg, "1.2e-38 to 1e+30 (times R)", &o->params.link_distance);
            break;
        case 'j':
            if (cli_parse_long(optarg, 0, 4096, &l) != 0)
                rc = options_usage_error(cmd, "--threads must be a whole number from 0 to 4096, not '%s'",
                                         optarg);
            o->params.threads = (int)l;
            break;
        case O_UV:
            if (strcmp(optarg, "box") == 0)
                o->params.uv_mode = JM_UV_BOX;
            else if (strcmp(optarg, "planar") == 0)
                o->params.uv_mode = JM_UV_PLANAR;
            else if (strcmp(optarg, "spherical") == 0)
                o->params.uv_mode = JM_UV_SPHERICAL;
            else if (strcmp(optarg, "none") == 0)
                o->params.uv_mode = JM_UV_NONE;
            else
                rc = options_usage_error(cmd, "--uv is box, planar, spherical or none, not '%s'", optarg);
            break;
        case O_UVSCALE:
            rc = length(cmd, "--uv-scale", optarg, "1e-06 R to 1e+30 (world units)", &o->params.uv_scale);
            break;
        case O_NONORMALS: o->params.no_normals = 1; break;
        case O_NOTEMPLATES: o->params.no_templates = 1; break;
        case O_NOCOMP: o->params.no_compensation = 1; break;
        case O_KEEPCAV: o->params.keep_cavities = 1; break;
        case O_POST_SMOOTH:
        case O_POST_NSMOOTH: {
            const char *word;
            if (cli_optional_long(optarg, argc, argv, &optind, 0, 100000,
                                  c == O_POST_SMOOTH ? OPTIONS_SMOOTH_DEFAULT : OPTIONS_SMOOTH_NORMALS_DEFAULT, &l,
                                  &word) != 0)
                rc = options_usage_error(cmd, "%s must be a whole number from 0 to 100000, not '%s'",
                                         c == O_POST_SMOOTH ? "--smooth" : "--smooth-normals", word);
            else if (c == O_POST_SMOOTH)
                o->params.smooth_iterations = (int)l;
            else
                o->params.smooth_normal_iterations = (int)l;
            break;
        }
        case O_POST_SIMPLIFY:
            if (cli_parse_double(optarg, &d) != 0 || !(d >= 0) || d > 1000)
                rc = options_usage_error(cmd, "--simplify must be a number from 0 to 1000, not '%s'", optarg);
            else
                o->params.simplify_error = (float)d;
            break;
        case O_EXACT: o->params.exact_surface = 1; break;
        case O_UVAXIS:
            if (!strcmp(optarg, "x")) o->params.uv_axis = 1;
            else if (!strcmp(optarg, "y")) o->params.uv_axis = 2;
            else if (!strcmp(optarg, "z")) o->params.uv_axis = 3;
            else rc = options_usage_error(cmd, "--uv-axis is x, y or z, not '%s'", optarg);
            break;
        case 'o': o->output = optarg; break;
        case O_FORMAT:
            k = jmf_output_format_parse(optarg);
            if (k < 0)
                rc = options_usage_error(cmd, "--format is obj, gltf, glb, drc, ply or vtk, not '%s'",
                                         optarg);
            else {
                o->write.format = (jmf_output_format)k;
                o->format_given = 1;
            }
            break;
        case O_DRACO: o->write.draco = 1; break;
        case O_EMBED: o->write.embed = 1; break;
        case O_ZUP: o->write.z_up = 1; break;
        case O_DPOS: rc = bits(cmd, "--draco-position-bits", optarg, &o->write.draco_position_bits); break;
        case O_DNORM: rc = bits(cmd, "--draco-normal-bits", optarg, &o->write.draco_normal_bits); break;
        case O_DUV: rc = bits(cmd, "--draco-uv-bits", optarg, &o->write.draco_uv_bits); break;
        case O_INFORMAT:
            k = jmf_input_format_parse(optarg);
            if (k < 0)
                rc = options_usage_error(
                    cmd, "--input-format is auto, csv, xyz, vtk, vtu, bgeo or ply, not '%s'", optarg);
            else
                o->read.format = (jmf_input_format)k;
            break;
        case O_FRAMES: {
            char err[256];
            if (seq_range_parse(optarg, &o->frames, err, sizeof err) != 0)
                rc = options_usage_error(cmd, "--frames: %s", err);
            break;
        }
        case O_STATS:
            if (!stats_path_ok(optarg))
                rc = options_usage_error(cmd, "--stats FILE must end in .csv or .json, not '%s'", optarg);
            o->stats_path = optarg;
            break;
        case O_STATSSVG: {
            size_t n = strlen(optarg);
            if (n < 5 || strcmp(optarg + n - 4, ".svg") != 0)
                rc = options_usage_error(cmd, "--stats-svg FILE must end in .svg, not '%s'", optarg);
            o->stats_svg = optarg;
            break;
        }
        case O_DROP: o->read.drop_invalid = 1; break;
        case O_NOSYNC: o->write.no_sync = 1; break;
        case O_FRAMEJOBS:
            if (cli_parse_long(optarg, 0, CONVERT_MAX_FRAME_JOBS, &l) != 0)
                rc = options_usage_error(cmd, "--frame-jobs must be a whole number from 0 to %d, not '%s'",
                                         CONVERT_MAX_FRAME_JOBS, optarg);
            o->frame_jobs = (int)l;
            break;
        case O_KEEP: o->keep_going = 1; break;
        case O_RESUME: o->resume = 1; break;
        case O_SHARD: {
            char err[256];
            if (shard_parse(optarg, &o->shard, err, sizeof err) != 0)
                rc = options_usage_error(cmd, "%s", err);
            break;
        }
        case O_MAXMEM:
            if (options_parse_size(optarg, &o->max_memory) != 0)
                rc = options_usage_error(cmd, "--max-memory must be a size of 0 (no limit) or more, like 2G or "
                                         "500M (K, M, G, T: powers of 1024), not '%s'", optarg);
            break;
        case O_ANISO: o->params.anisotropic = 1; break;
        case O_ANISO_RADIUS:
            rc = length(cmd, "--anisotropic-radius", optarg,
                        "0.1 to 4 times --smoothing-length (times R; 8 at the defaults)", &o->params.aniso_radius);
            break;
        case 'q': o->quiet = 1; o->verbose = 0; break;
        case 'v': o->verbose = 1; o->quiet = 0; break;
        case O_HELP: options_convert_help(stdout); return OPTIONS_DONE;
        case O_VERSION: printf("jetmesh %s\n", JM_VERSION_STRING); return OPTIONS_DONE;
        /* sequences for Blender, ParaView and the web */
        case O_ANIMATE: o->animate = 1; break;
        case O_FPS:
            /* key times (frame number / fps) stay finite floats */
            if (cli_parse_double(optarg, &d) != 0 || !(d >= FPS_MIN) || d > 100000)
                rc = options_usage_error(cmd, "--fps must be a number from %g to 100000, not '%s'", FPS_MIN,
                                         optarg);
            o->fps = d;
            break;
        case O_TIMESTEP:
            if (cli_parse_double(optarg, &d) != 0 || !(d >= 1e-30) || d > 1e30)
                rc = options_usage_error(cmd, "--time-step must be a number from 1e-30 to 1e+30, not '%s'", optarg);
            o->time_step = d;
            break;
        case O_PVD: o->pvd = 1; break;
        case O_ATTRS:
            if (!*optarg || strspn(optarg, ", ") == strlen(optarg))
                rc = options_usage_error(cmd, "--attributes needs names (velocity,density) or all");
            o->attributes = optarg;
            break;
        default:
            rc = select_is_option(c) ? select_option(cmd, c, optarg, &o->params, &sel) : getopt_problem(cmd, c, argv);
            break;
        }
    }
    if (rc == OPTIONS_RUN)
        rc = select_finish(cmd, &o->params, &sel);
    if (rc != OPTIONS_RUN)
        return rc;
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
    if (o->animate && o->shard.count > 0)
        return options_usage_error(cmd, "--animate writes the whole run into one file, which shards cannot "
                                        "share: convert shards to per-frame files, or animate in one run");
    o->params.max_bytes = o->max_memory;
    o->read.max_bytes = o->max_memory;
    return OPTIONS_RUN;
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
