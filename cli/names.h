/* names.h - the names of fields, methods and other option values, one table each, as the CLI parses and prints them. */
#ifndef JETMESH_CLI_NAMES_H
#define JETMESH_CLI_NAMES_H

#include <stddef.h>

#include "../lib/jetmesh.h"

/* Which commands accept a name (or an option: mesh_options.h). */
#define CLI_CONVERT 1u
#define CLI_BENCH 2u

/* --field sph-aniso of bench: the SPH field with anisotropic kernels (a
 * bench case's value only; the library sees JM_FIELD_SPH and
 * params.anisotropic) */
#define CLI_FIELD_SPH_ANISO ((jm_field)(JM_FIELD_SPH + 100))

/* One value's name. A table ends with a NULL name. */
typedef struct cli_name {
    const char *name;   /* as given and printed: "metasphere" */
    const char *column; /* bench's table column (4 characters at most; fields only) */
    int value;          /* JM_FIELD_*, JM_METHOD_*, ... */
    unsigned cmds;      /* CLI_CONVERT | CLI_BENCH: who accepts it */
} cli_name;

extern const cli_name cli_fields[];  /* auto, metasphere, sph, sph-aniso */
extern const cli_name cli_methods[]; /* mt, mc */
extern const cli_name cli_uv_modes[]; /* box, planar, spherical, none */
extern const cli_name cli_uv_axes[];  /* x, y, z */

/* The entry of t named s that cmd accepts: NULL if none. */
const cli_name *cli_name_find(const cli_name *t, unsigned cmd, const char *s);

/* The names cmd accepts in words: "a, b or c", into buf. */
const char *cli_name_list(const cli_name *t, unsigned cmd, char *buf, size_t len);

/* The name of value in t (the first entry with it; NULL if none). */
const char *cli_name_of(const cli_name *t, int value);

/* A field's and a method's name as reports print them: "metasphere" for
 * JM_FIELD_DEFAULT, "mt" for JM_METHOD_DEFAULT. */
const char *cli_field_name(jm_field f);
const char *cli_method_name(jm_method m);
/* The field's column in bench's table: "meta", "sph", "sphA". */
const char *cli_field_column(jm_field f);

#endif
