/* param_errors.h - explains refused meshing parameters, oversized frames and empty meshes by the options that set them. */
#ifndef JETMESH_CLI_PARAM_ERRORS_H
#define JETMESH_CLI_PARAM_ERRORS_H

#include <stddef.h>

#include "../lib/jetmesh.h"

/** The command-line option that sets a jm_params member ("cube_size" ->
 *  "--cube-size"); the member's name itself when no option sets it. */
const char *param_option_name(const char *field);

/** If jm_params_check() refuses p, writes "--cube-size 0.0005 is out of
 *  range: it accepts 0.001 to 100 (...)" into msg and returns -1; else 0. */
int param_errors_describe(const jm_params *p, char *msg, size_t len);

/** Explains a frame refused with JM_E_TOO_LARGE: how much it needs against
 *  --max-memory (max_memory, 0 = none) and the machine's memory, and which
 *  option to change: --cube-size (with a size that fits, when one is found
 *  by jm_estimate_bytes) when even the machine cannot hold it, else
 *  --max-memory or --cube-size. est: the library's estimate (0 = unknown). */
void param_errors_too_large(char *msg, size_t len, const char *path, const jm_params *p,
                            const jm_particles *parts, size_t est, size_t max_memory);

/** Explains a frame refused with JM_E_NUMERIC_DOMAIN: its farthest
 *  coordinate from the origin in cube edges against JM_MAX_CUBES_FROM_ORIGIN
 *  (move the particles nearer the origin, or a larger --cube-size), or a
 *  mesh beyond the float range (a smaller unit of length). */
void param_errors_domain(char *msg, size_t len, const char *path, const jm_params *p, const jm_particles *parts);

/** Prints a warning on stderr for a frame whose particles gave no triangle:
 *  the threshold and cube size to look at. */
void param_errors_warn_empty(long index, const char *path, size_t particles, const jm_params *p);

/** Prints a warning on stderr for a frame converted with no particles at
 *  all (issue 30: such a frame is converted, to an empty mesh, but says so):
 *  the file held none, or --drop-invalid dropped every one. */
void param_errors_warn_no_particles(long index, const char *path, size_t dropped);

#endif
