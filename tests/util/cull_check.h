/* cull_check.h - culling tests' shared parts: the same mesh bytes with culling on and off, on the real frames and on a lattice block with holes. */
#ifndef JETMESH_TESTS_CULL_CHECK_H
#define JETMESH_TESTS_CULL_CHECK_H

#include <stddef.h>
#include "../../lib/jetmesh.h"

/**
 * Meshes the count particles xyz with p and culling off (1 thread), then
 * with culling on at 1 and 2 threads. Returns 0 when every culled mesh has
 * the same vertex and triangle counts and the same positions, normals, uvs
 * and indices, byte for byte, and the reference has triangles; *out_triangles
 * gets its triangle count. Otherwise -1, with why in err (naming `what`).
 */
int cull_same_bytes(const char *what, const jm_params *p, const float *xyz, size_t count, size_t *out_triangles,
                    char *err, size_t errsz);

/**
 * A jittered lattice block (24^3 sites, spacing 2r) with a spherical
 * cavity, a perforated wall and a slot, and a lone pair above it: culling
 * next to cavities, thin walls and particles on block faces. Returns the
 * malloc'd positions (*n of them), or NULL for no memory.
 */
float *cull_holed_block(float r, size_t *n);

/** The real frames of the culling tests (under ../shared/data); the first
 * two are the bench frames. */
#define CULL_FRAMES 5
extern const char *const cull_frames[CULL_FRAMES];

/**
 * One case of a culling test: variant v on real frame k (cull_frames) with
 * method me. Fills p (zeroed beforehand) and the case's name in what;
 * returns 0 to skip the case.
 */
typedef int (*cull_case)(size_t k, int me, int v, jm_params *p, char *what, size_t whatsz);

/**
 * cull_same_bytes on the variants 0..nvariants-1 of every real frame and
 * method (mt, mc) that fill keeps, printing each case's triangle count.
 * Returns 0 when every case passes, 1 when no real frame is found (nothing
 * ran), -1 with why in err at the first that fails. With JETMESH_TEST_SMALL
 * set in the environment, the first two (the bench frames) are left out.
 */
int cull_real_frames(int nvariants, cull_case fill, char *err, size_t errsz);

/**
 * cull_same_bytes on cull_holed_block (r = 0.025), SPH (anisotropic where
 * asked), mt and mc, with the default threshold and lattice and with a
 * thinner threshold (0.35) and a finer lattice (cube 0.4). 0, or -1 with
 * why in err.
 */
int cull_holed_block_cases(int anisotropic, char *err, size_t errsz);

#endif
