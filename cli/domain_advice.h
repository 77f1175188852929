/* domain_advice.h - explains particles too far from the origin or spread too wide for the lattice: what is wrong and what would help. */
#ifndef JETMESH_CLI_DOMAIN_ADVICE_H
#define JETMESH_CLI_DOMAIN_ADVICE_H

#include <stddef.h>

#include "../lib/jetmesh.h"

/** 1 if a coordinate of parts is more than JM_MAX_CUBES_FROM_ORIGIN cube
 *  edges (p's --cube-size times -r) from the origin: no memory helps. */
int domain_outside(const jm_params *p, const jm_particles *parts);

/** "PATH: outside the numeric domain: ..." for such a frame: where the
 *  particles are, how far the lattice reaches at this --cube-size and at
 *  the largest, and what would help: a --cube-size that reaches them,
 *  moving them nearer the origin (their centre), or, when they span more
 *  than any cube size reaches, splitting the frame. */
void domain_advice(char *msg, size_t len, const char *path, const jm_params *p, const jm_particles *parts);

#endif
