/* lattice.c - jittered cubic lattices of particles for the tests, the same for a seed on every machine. */
#include "lattice.h"
#include <stdlib.h>

float *test_lattice(int side, float spacing, float jitter, uint32_t seed, size_t extra)
{
    const size_t n = (size_t)side * side * side;
    float *xyz = malloc(3 * (n + extra) * sizeof *xyz);
    if (!xyz) return NULL;
    size_t k = 0;
    for (int z = 0; z < side; z++)
        for (int y = 0; y < side; y++)
            for (int x = 0; x < side; x++, k++) {
                const int c[3] = {x, y, z};
                for (int a = 0; a < 3; a++) {
                    seed = seed * 1664525u + 1013904223u;
                    xyz[3 * k + a] = spacing * (float)c[a] + jitter * ((float)(seed >> 8) / 16777216.0f - 0.5f);
                }
            }
    return xyz;
}
