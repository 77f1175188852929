/* mesh_options.h - the meshing options of convert and bench in one table: names, arguments, ranges, help lines, the jm_params member each sets. */
#ifndef JETMESH_CLI_MESH_OPTIONS_H
#define JETMESH_CLI_MESH_OPTIONS_H

#include <getopt.h>
#include <stddef.h>
#include <stdio.h>

#include "../lib/jetmesh.h"
#include "names.h"
#include "select_options.h"

/* getopt_long's values of the options without a letter (select_options.h
 * takes 600 and up) */
enum {
    MO_FIELD = 700, MO_METHOD, MO_THRESHOLD, MO_SMOOTHING_LENGTH, MO_LINK, MO_UV, MO_UVSCALE, MO_NONORMALS,
    MO_NOTEMPLATES, MO_UVAXIS, MO_KEEPCAV, MO_NOCOMP, MO_EXACT, MO_MAXMEM, MO_ANISO, MO_ANISO_RADIUS,
    MO_SMOOTH, MO_SMOOTH_NORMALS, MO_SMOOTH_IMPLICIT, MO_SIMPLIFY
};

/* How an option's argument is read. */
typedef enum {
    MO_FLAG,   /* no argument: the int member set to 1 */
    MO_FLOAT,  /* a number in [lo, hi]: a float member */
    MO_ISO,    /* a number, 0 or at least lo in size: a float member */
    MO_WHOLE,  /* a whole number in [lo, hi]: an int member */
    MO_COUNT,  /* a whole number in [lo, hi] that may be left out (dflt): an int member */
    MO_NAME,   /* a name of the table names: an int-sized (enum) member */
    MO_SIZE,   /* a size (options_parse_size): a size_t member */
    MO_SELECT, /* a selection option with an argument: select_option() reads it */
    MO_SELECT_FLAG /* one without */
} mo_kind;

/* What bench does differently (bench's lists are checked loosely: the
 * library refuses the rest per case). */
typedef struct mo_bench {
    int list;          /* a comma list of values (bench_options.c keeps them) */
    double lo, hi;     /* its range when range is set */
    const char *range;
} mo_bench;

/* One option. */
typedef struct mesh_option {
    const char *name;    /* the long name, without -- */
    int key;             /* getopt_long's value: its letter, or MO_* */
    mo_kind kind;
    unsigned cmds;       /* CLI_CONVERT | CLI_BENCH */
    double lo, hi, dflt; /* the accepted range; dflt: MO_COUNT left out */
    const char *range;   /* the range in error messages ("from 0 to 1000") */
    const cli_name *names; /* MO_NAME */
    size_t member;       /* offsetof(jm_params, ...) */
    mo_bench bench;
    const char *section; /* convert's --help: a heading printed before it */
    const char *help;    /* convert's --help lines (NULL: none) */
    const char *bench_help; /* bench's (NULL: listed with another) */
} mesh_option;

/* A parsed value, before it is stored. */
typedef struct mo_value {
    double d; /* MO_FLOAT, MO_ISO */
    long l;   /* MO_WHOLE, MO_COUNT, MO_NAME, MO_FLAG */
    size_t z; /* MO_SIZE */
} mo_value;

/* The option whose getopt value is key (NULL: not a meshing option). */
const mesh_option *mesh_option_find(int key);

/* Appends cmd's options to a getopt_long table at out[*n] (room for
 * MESH_OPTIONS_MAX entries). */
#define MESH_OPTIONS_MAX 40
void mesh_options_long(unsigned cmd, struct option *out, size_t *n);

/* Reads one value of option o for cmd from arg (bench: one item of a
 * list). MO_COUNT reads the next word of argv when it is a number
 * (cli_optional_long). OPTIONS_RUN, or a usage error (printed). */
int mesh_option_value(const mesh_option *o, unsigned cmd, const char *arg, int argc, char **argv, mo_value *v);

/* 1 if o is a selection or clipping option (select_options.h reads them,
 * checking them together at the end). */
static inline int mesh_option_is_select(const mesh_option *o)
{
    return o->kind == MO_SELECT || o->kind == MO_SELECT_FLAG;
}

/* Stores v into p's member of o. */
void mesh_option_store(const mesh_option *o, const mo_value *v, jm_params *p);

/* mesh_option_value, then mesh_option_store. */
int mesh_option_parse(const mesh_option *o, unsigned cmd, const char *arg, int argc, char **argv, jm_params *p);

/* The meshing options' rules across options, for convert and bench alike:
 * OPTIONS_RUN, or a usage error of cmd (options_usage_error). */
int mesh_options_check(const char *cmd, const jm_params *p);

/* Prints cmd's help lines: names NULL: every option of convert in table
 * order with the section headings; else the options named, in that order
 * (a NULL-terminated list). */
void mesh_options_help(FILE *f, unsigned cmd, const char *const *names);

#endif
