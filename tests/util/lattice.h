/* lattice.h - jittered cubic lattices of particles for the tests, the same for a seed on every machine. */
#ifndef JETMESH_TESTS_LATTICE_H
#define JETMESH_TESTS_LATTICE_H

#include <stddef.h>
#include <stdint.h>

/**
 * side^3 particles (x fastest, then y, then z) at spacing, each coordinate
 * moved by jitter * (u - 1/2), u in [0, 1) from a linear congruential
 * sequence started at seed, one number a coordinate. The array holds
 * extra particles more (left uninitialised) after them, for the caller.
 * malloc'd (free it); NULL for no memory.
 */
float *test_lattice(int side, float spacing, float jitter, uint32_t seed, size_t extra);

#endif
