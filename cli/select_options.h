/* select_options.h - reads the options that choose what is meshed and kept (particle box, small pieces, mesh clip box), for convert and bench (their names and help: mesh_options.c). */
#ifndef JETMESH_CLI_SELECT_OPTIONS_H
#define JETMESH_CLI_SELECT_OPTIONS_H

#include "../lib/jetmesh.h"

enum {
    SO_PAABB_MIN = 600, SO_PAABB_MAX, SO_MAABB_MIN, SO_MAABB_MAX, SO_MAABB_CLAMP, SO_MIN_PARTICLES, SO_MIN_VOLUME,
    SO_END
};

/* Which of them were given. */
typedef struct select_given {
    int pmin, pmax, mmin, mmax;
} select_given;

/* Parses option c's argument into p's members: OPTIONS_RUN, or a usage
 * error (printed) for cmd. */
int select_option(const char *cmd, int c, const char *arg, jm_params *p, select_given *g);

/* After every option: the boxes given whole (min with max), the clamp with
 * a clip box, and the ranges jm_params_check accepts, in words naming the
 * options (param_errors.c): OPTIONS_RUN or a usage error (printed). */
int select_finish(const char *cmd, const jm_params *p, const select_given *g);

/* 1 if p selects particles or clips or removes pieces (a mesh may then be
 * empty without the threshold being to blame). */
int select_any(const jm_params *p);

/* Copies the members these options set from src into dst. */
void select_copy(jm_params *dst, const jm_params *src);

#endif
