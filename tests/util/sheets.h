/* sheets.h - thin sheets of particles (1 to a few layers) with droplets beside them, for the anisotropic tests. */
#ifndef JETMESH_TESTS_SHEETS_H
#define JETMESH_TESTS_SHEETS_H

#include <stddef.h>

/* The droplets test_sheet puts over a sheet's top face or beside its rim,
 * in order: their particle counts (a single, a pair, a cluster of 4 and one
 * of 7). */
#define TEST_SHEET_DROPLETS 4
extern const int test_sheet_drop_size[TEST_SHEET_DROPLETS];

/**
 * A square sheet of side x side particles per layer, `layers` layers in z,
 * spacing 2r, each coordinate moved by up to +-jitter r from a linear
 * congruential sequence started at seed (0: an exact lattice), the sheet
 * tilted by a few degrees off the axes so that it is not aligned with the
 * lattice of cubes. With droplets 1, small clusters float over its top
 * face, their nearest particle `gap` r above the top layer (a sheet's own
 * spacing is 2); with droplets 2, beside its rim in its mid-plane, their
 * nearest particle `gap` r out from the last column. malloc'd into *out
 * (free it); the particle count, 0 for no memory. dc (may be NULL) gets
 * each droplet's centre (3 floats a droplet).
 */
size_t test_sheet(int layers, int side, float r, float jitter, unsigned seed, int droplets, float gap, float **out,
                  float *dc);

#endif
