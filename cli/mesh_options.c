/* mesh_options.c - the meshing options of convert and bench in one table: names, arguments, ranges, help lines, the jm_params member each sets. */
#include "mesh_options.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "numbers.h"
#include "options.h"

#define BOTH (CLI_CONVERT | CLI_BENCH)
#define M(member) offsetof(jm_params, member)
/* The smallest length an option takes: a normal float (0 would mean "the
 * default"; subnormals lose their digits), as jetmesh(1) LIMITS says. A
 * length's message names the range the library accepts (issue 30); the CLI
 * refuses only what is outside [LEN_MIN, LEN_MAX], the library checks the
 * rest (jm_params_check, worded by param_errors_describe). */
#define LEN_MIN 1.2e-38
#define LEN_MAX 1e30
/* bench's lists: any positive number up to 1e6 (the library refuses the rest per case) */
#define LOOSE(range) {1, DBL_TRUE_MIN, 1e6, range}

static const mesh_option table[] = {
    {"radius", 'r', MO_FLOAT, BOTH, LEN_MIN, LEN_MAX, 0, "from 1.2e-38 to 1e+30", NULL, M(radius), {0, 0, 0, NULL},
     "Meshing:\n",
     "  -r, --radius R              particle radius in world units (required)\n",
     "  -r, --radius R              particle radius (default 0.025); scenes are\n"
     "                              generated with it\n"},
    {"cube-size", 'c', MO_FLOAT, BOTH, LEN_MIN, LEN_MAX, 0, "from 0.001 to 100 (times R)", NULL, M(cube_size),
     LOOSE("from 0.001 to 100 (times R)"), NULL,
     "  -c, --cube-size C           lattice cube edge, relative to R (default 0.5)\n",
     "  -c, --cube-size LIST        cube edge relative to R (default 0.5)\n"},
    {"field", MO_FIELD, MO_NAME, BOTH, 0, 0, 0, NULL, cli_fields, M(field), {1, 0, 0, NULL}, NULL,
     "      --field auto|metasphere|sph  implicit function (default auto: metasphere\n"
     "                              for sparse frames such as jets and spray, sph\n"
     "                              for bulk fluid, chosen once from the first frame)\n",
     "      --field LIST            metasphere, sph, sph-aniso (sph with --anisotropic)\n"
     "                              (default metasphere)\n"},
    {"method", MO_METHOD, MO_NAME, BOTH, 0, 0, 0, NULL, cli_methods, M(method), {1, 0, 0, NULL}, NULL,
     "      --method mt|mc          marching tetrahedra or cubes (default mt with the\n"
     "                              metasphere, mc with sph)\n",
     "      --method LIST           mt, mc (default mt)\n"},
    {"threshold", MO_THRESHOLD, MO_ISO, BOTH, LEN_MIN, 0, 0,
     "above -1 and below 1 for the metasphere, above 0 for sph (0: the field's default; else at least 1.2e-38 "
     "in size)", NULL, M(threshold),
     {0, 0, 0, "above -1 and below 1 for the metasphere, above 0 for sph (0: the field's default)"}, NULL,
     "      --threshold T           iso value (default 0 metasphere, 0.6 sph)\n",
     "      --threshold T           iso value (default 0 metasphere, 0.6 sph)\n"},
    {"smoothing-length", MO_SMOOTHING_LENGTH, MO_FLOAT, BOTH, LEN_MIN, LEN_MAX, 0, "from 0.05 to 100 (times R)", NULL,
     M(smoothing_length), {0, DBL_TRUE_MIN, 1e6, "from 0.05 to 100 (times R)"}, NULL,
     "      --smoothing-length L    sph kernel length h, relative to R (default 2)\n",
     "      --smoothing-length L    sph kernel length h relative to R (default 2)\n"},
    {"link-distance", MO_LINK, MO_FLOAT, BOTH, LEN_MIN, LEN_MAX, 0, "from 1.2e-38 to 1e+30 (times R)", NULL,
     M(link_distance), {0, LEN_MIN, 1e6, "from 1.2e-38 to 1e+06 (times R)"}, NULL,
     "      --link-distance L       metasphere neck link distance, relative to R (default pi)\n",
     "      --link-distance L       metasphere link distance relative to R (default pi)\n"},
    {"threads", 'j', MO_WHOLE, BOTH, 0, 4096, 0, "from 0 to 4096", NULL, M(threads), {1, 0, 0, NULL}, NULL,
     "  -j, --threads N             worker threads; 0 = all cores (default 0)\n",
     "  -j, --threads LIST          worker threads; 0 = all cores (default 1,CORES)\n"},
    {"uv", MO_UV, MO_NAME, CLI_CONVERT, 0, 0, 0, NULL, cli_uv_modes, M(uv_mode), {0, 0, 0, NULL}, NULL,
     "      --uv box|planar|spherical|none  texture coordinates (default box)\n", NULL},
    {"uv-scale", MO_UVSCALE, MO_FLOAT, CLI_CONVERT, LEN_MIN, LEN_MAX, 0, "from 1e-06 R to 1e+30 (world units)", NULL,
     M(uv_scale), {0, 0, 0, NULL}, NULL,
     "      --uv-scale S            world units per texture repeat (default 16 R;\n"
     "                              at least 1e-6 R)\n", NULL},
    {"no-normals", MO_NONORMALS, MO_FLAG, CLI_CONVERT, 0, 0, 0, NULL, NULL, M(no_normals), {0, 0, 0, NULL}, NULL,
     "      --no-normals            write no normals\n", NULL},
    {"no-templates", MO_NOTEMPLATES, MO_FLAG, CLI_CONVERT, 0, 0, 0, NULL, NULL, M(no_templates), {0, 0, 0, NULL},
     NULL, "      --no-templates          mesh isolated particles through the lattice too\n", NULL},
    {"uv-axis", MO_UVAXIS, MO_NAME, CLI_CONVERT, 0, 0, 0, NULL, cli_uv_axes, M(uv_axis), {0, 0, 0, NULL}, NULL,
     "      --uv-axis x|y|z         --uv planar: the projection axis (default z)\n", NULL},
    {"keep-cavities", MO_KEEPCAV, MO_FLAG, CLI_CONVERT, 0, 0, 0, NULL, NULL, M(keep_cavities), {0, 0, 0, NULL},
     NULL,
     "      --keep-cavities         keep closed inner shells smaller than a particle\n"
     "                              (removed by default: sub-particle bubbles)\n", NULL},
    {"no-compensation", MO_NOCOMP, MO_FLAG, CLI_CONVERT, 0, 0, 0, NULL, NULL, M(no_compensation), {0, 0, 0, NULL},
     NULL,
     "      --no-compensation       metasphere: leave vertices on the surface (no\n"
     "                              chord-sag offset; the mesh is then a bit small)\n", NULL},
    /* deprecated (issue 33): accepted, does nothing, removed in 0.4.0 */
    {"exact-surface", MO_EXACT, MO_FLAG, CLI_CONVERT, 0, 0, 0, NULL, NULL, M(exact_surface), {0, 0, 0, NULL}, NULL,
     "      --exact-surface         deprecated: does nothing (metasphere vertices are\n"
     "                              always on the exact surface); removed in 0.4.0\n", NULL},
    {"max-memory", MO_MAXMEM, MO_SIZE, CLI_CONVERT, 0, 0, 0,
     "a size of 0 (no limit) or more, like 2G or 500M (K, M, G, T: powers of 1024)", NULL, M(max_bytes),
     {0, 0, 0, NULL}, NULL,
     "      --max-memory SIZE       refuse frames needing more (e.g. 2G, 500M; 0 = no\n"
     "                              limit; default half the physical memory)\n", NULL},
    {"anisotropic", MO_ANISO, MO_FLAG, CLI_CONVERT, 0, 0, 0, NULL, NULL, M(anisotropic), {0, 0, 0, NULL}, NULL,
     "      --anisotropic           sph: Yu-Turk anisotropic kernels on smoothed centres:\n"
     "                              flat surfaces look like liquid, not particles\n"
     "                              (slower; for final renders of --field sph)\n", NULL},
    {"anisotropic-radius", MO_ANISO_RADIUS, MO_FLOAT, CLI_CONVERT, LEN_MIN, LEN_MAX, 0,
     "from 0.1 to 4 times --smoothing-length (times R; 8 at the defaults)", NULL, M(aniso_radius), {0, 0, 0, NULL},
     NULL, "      --anisotropic-radius N  its neighbourhood radius, relative to R (default 8)\n", NULL},
    /* --smooth and --smooth-normals without a number: splashsurf's
     * recommended 25 smoothing and 10 normal iterations */
    {"smooth", MO_SMOOTH, MO_COUNT, BOTH, 0, 100000, 25, "from 0 to 100000", NULL, M(smooth_iterations),
     {0, 0, 0, NULL}, "\nPost-processing (off by default; in this order):\n",
     "      --smooth [N]            N iterations of Laplacian smoothing (default 25,\n"
     "                              as splashsurf's 25): bumps of particle size\n"
     "                              removed, no point moved over 0.5 R along its\n"
     "                              normal, each piece's volume restored\n",
     "      --smooth [N], --smooth-normals [N], --smooth-implicit, --simplify E\n"
     "                              post-processing, as convert\n"},
    {"smooth-normals", MO_SMOOTH_NORMALS, MO_COUNT, BOTH, 0, 100000, 10, "from 0 to 100000", NULL,
     M(smooth_normal_iterations), {0, 0, 0, NULL}, NULL,
     "      --smooth-normals [N]    N iterations of normal smoothing (default 10)\n", NULL},
    {"smooth-implicit", MO_SMOOTH_IMPLICIT, MO_FLAG, BOTH, 0, 0, 0, NULL, NULL, M(smooth_implicit), {0, 0, 0, NULL},
     NULL,
     "      --smooth-implicit       with --smooth: the steady smoother, for animations:\n"
     "                              a moving liquid's surface shimmers no more than\n"
     "                              unsmoothed (post-processing 2.5 to 3x as long)\n",
     NULL},
    {"simplify", MO_SIMPLIFY, MO_FLOAT, BOTH, 0, 1000, 0, "from 0 to 1000", NULL, M(simplify_error),
     {0, 0, 0, NULL}, NULL,
     "      --simplify E            fewer triangles, at most E*R from the mesh (e.g. 0.1)\n", NULL},
    /* selection and clipping: select_options.c reads them */
    {"particle-aabb-min", SO_PAABB_MIN, MO_SELECT, BOTH, 0, 0, 0, NULL, NULL, 0, {0, 0, 0, NULL},
     "\nSelection and clipping (off by default; boxes in world units):\n",
     "      --particle-aabb-min X,Y,Z  with --particle-aabb-max X,Y,Z: mesh only the\n"
     "                              particles inside this box\n",
     "      --particle-aabb-min X,Y,Z, --particle-aabb-max X,Y,Z, --min-piece-particles N,\n"
     "      --min-piece-volume V, --mesh-aabb-min X,Y,Z, --mesh-aabb-max X,Y,Z,\n"
     "      --mesh-aabb-clamp-vertices  selection and clipping, as convert\n"},
    {"particle-aabb-max", SO_PAABB_MAX, MO_SELECT, BOTH, 0, 0, 0, NULL, NULL, 0, {0, 0, 0, NULL}, NULL, NULL, NULL},
    {"min-piece-particles", SO_MIN_PARTICLES, MO_SELECT, BOTH, 0, 0, 0, NULL, NULL, 0, {0, 0, 0, NULL}, NULL,
     "      --min-piece-particles N  leave out groups of fewer than N particles\n"
     "                              (stray droplets; one group: particles within the\n"
     "                              link distance, sph: the kernel support, 4 R)\n", NULL},
    {"min-piece-volume", SO_MIN_VOLUME, MO_SELECT, BOTH, 0, 0, 0, NULL, NULL, 0, {0, 0, 0, NULL}, NULL,
     "      --min-piece-volume V    remove mesh pieces enclosing less than V R^3 (one\n"
     "                              particle's ball: 4.19) after post-processing\n", NULL},
    {"mesh-aabb-min", SO_MAABB_MIN, MO_SELECT, BOTH, 0, 0, 0, NULL, NULL, 0, {0, 0, 0, NULL}, NULL,
     "      --mesh-aabb-min X,Y,Z   with --mesh-aabb-max X,Y,Z: clip the mesh to this\n"
     "                              box, last: triangles with a corner outside are\n"
     "                              removed, the mesh is open along the cut (a\n"
     "                              tank's walls removed)\n", NULL},
    {"mesh-aabb-max", SO_MAABB_MAX, MO_SELECT, BOTH, 0, 0, 0, NULL, NULL, 0, {0, 0, 0, NULL}, NULL, NULL, NULL},
    {"mesh-aabb-clamp-vertices", SO_MAABB_CLAMP, MO_SELECT_FLAG, BOTH, 0, 0, 0, NULL, NULL, 0, {0, 0, 0, NULL}, NULL,
     "      --mesh-aabb-clamp-vertices  close the cut instead: the vertices outside\n"
     "                              move onto the box, the mesh stays closed\n", NULL},
};
#define NOPTS (sizeof table / sizeof table[0])

_Static_assert(NOPTS <= MESH_OPTIONS_MAX, "MESH_OPTIONS_MAX too small");
_Static_assert(sizeof(jm_field) == sizeof(int) && sizeof(jm_method) == sizeof(int) && sizeof(jm_uv_mode) == sizeof(int),
               "MO_NAME stores an int");

const mesh_option *mesh_option_find(int key)
{
    for (size_t i = 0; i < NOPTS; i++)
        if (table[i].key == key)
            return &table[i];
    return NULL;
}

void mesh_options_long(unsigned cmd, struct option *out, size_t *n)
{
    for (size_t i = 0; i < NOPTS; i++) {
        const mesh_option *o = &table[i];
        if (!(o->cmds & cmd))
            continue;
        int arg = o->kind == MO_FLAG || o->kind == MO_SELECT_FLAG ? no_argument
                  : o->kind == MO_COUNT                          ? optional_argument
                                                                 : required_argument;
        out[(*n)++] = (struct option){o->name, arg, 0, o->key};
    }
}

/* The words of a number option's message: a list's items are "numbers". */
static const char *noun(const mesh_option *o, int list)
{
    if (o->kind == MO_WHOLE || o->kind == MO_COUNT)
        return list ? "whole numbers" : "a whole number";
    return list ? "numbers" : "a number";
}

static int number_value(const mesh_option *o, unsigned cmd, const char *arg, mo_value *v)
{
    const int bench = cmd == CLI_BENCH, list = bench && o->bench.list;
    const int own = bench && o->bench.range; /* bench's own range */
    const double lo = own ? o->bench.lo : o->lo, hi = own ? o->bench.hi : o->hi;
    const char *range = own ? o->bench.range : o->range;
    int bad;
    if (o->kind == MO_WHOLE)
        bad = cli_parse_long(arg, (long)lo, (long)hi, &v->l) != 0;
    else {
        bad = cli_parse_double(arg, &v->d) != 0;
        if (!bad && o->kind == MO_ISO) /* 0 (the default) or a normal float in size */
            bad = v->d != 0.0 && fabs(v->d) < lo;
        else if (!bad)
            bad = !(v->d >= lo) || !(v->d <= hi);
    }
    if (bad)
        return options_usage_error(bench ? "bench" : "convert", "--%s must be %s %s, not '%s'", o->name,
                                   noun(o, list), range, arg);
    return OPTIONS_RUN;
}

int mesh_option_value(const mesh_option *o, unsigned cmd, const char *arg, int argc, char **argv, mo_value *v)
{
    const char *cmdname = cmd == CLI_BENCH ? "bench" : "convert";
    memset(v, 0, sizeof *v);
    switch (o->kind) {
    case MO_FLAG: v->l = 1; return OPTIONS_RUN;
    case MO_FLOAT:
    case MO_ISO:
    case MO_WHOLE: return number_value(o, cmd, arg, v);
    case MO_COUNT: {
        const char *word;
        if (cli_optional_long(arg, argc, argv, &optind, (long)o->lo, (long)o->hi, (long)o->dflt, &v->l, &word) != 0)
            return options_usage_error(cmdname, "--%s must be %s %s, not '%s'", o->name, noun(o, 0), o->range,
                                       word);
        return OPTIONS_RUN;
    }
    case MO_NAME: {
        const cli_name *e = cli_name_find(o->names, cmd, arg);
        char words[128];
        if (!e)
            return options_usage_error(cmdname, "--%s is %s, not '%s'", o->name,
                                       cli_name_list(o->names, cmd, words, sizeof words), arg);
        v->l = e->value;
        return OPTIONS_RUN;
    }
    case MO_SIZE:
        if (options_parse_size(arg, &v->z) != 0)
            return options_usage_error(cmdname, "--%s must be %s, not '%s'", o->name, o->range, arg);
        return OPTIONS_RUN;
    case MO_SELECT:
    case MO_SELECT_FLAG: break; /* select_option() */
    }
    return options_usage_error(cmdname, "internal: option --%s has no kind", o->name);
}

void mesh_option_store(const mesh_option *o, const mo_value *v, jm_params *p)
{
    char *at = (char *)p + o->member;
    switch (o->kind) {
    case MO_FLOAT:
    case MO_ISO: {
        float f = (float)v->d;
        memcpy(at, &f, sizeof f);
        break;
    }
    case MO_FLAG:
    case MO_WHOLE:
    case MO_COUNT:
    case MO_NAME: { /* int, or an enum of int's size */
        int i = (int)v->l;
        memcpy(at, &i, sizeof i);
        break;
    }
    case MO_SIZE: memcpy(at, &v->z, sizeof v->z); break;
    case MO_SELECT:
    case MO_SELECT_FLAG: break;
    }
}

int mesh_option_parse(const mesh_option *o, unsigned cmd, const char *arg, int argc, char **argv, jm_params *p)
{
    mo_value v;
    int rc = mesh_option_value(o, cmd, arg, argc, argv, &v);
    if (rc == OPTIONS_RUN)
        mesh_option_store(o, &v, p);
    return rc;
}

int mesh_options_check(const char *cmd, const jm_params *p)
{
    if (p->smooth_implicit && p->smooth_iterations == 0)
        return options_usage_error(cmd, "--smooth-implicit needs --smooth");
    return OPTIONS_RUN;
}

static void help_one(FILE *f, unsigned cmd, const mesh_option *o)
{
    const char *h = cmd == CLI_BENCH ? o->bench_help : o->help;
    if (h)
        fputs(h, f);
}

void mesh_options_help(FILE *f, unsigned cmd, const char *const *names)
{
    if (!names) {
        for (size_t i = 0; i < NOPTS; i++)
            if (table[i].cmds & cmd) {
                if (table[i].section)
                    fputs(table[i].section, f);
                help_one(f, cmd, &table[i]);
            }
        return;
    }
    for (; *names; names++)
        for (size_t i = 0; i < NOPTS; i++)
            if (strcmp(table[i].name, *names) == 0)
                help_one(f, cmd, &table[i]);
}
