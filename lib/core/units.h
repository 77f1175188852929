/* units.h - the library's unit of length: a power of two near the radius, so no result depends on the user's unit. */
#ifndef JETMESH_UNITS_H
#define JETMESH_UNITS_H
#include "core/internal.h"

/*
 * jm_mesh_particles works in units of 2^k, 2^k the power of two with
 * r / 2^k in [0.5, 1): coordinates and every length parameter are
 * multiplied by 2^-k on the way in and vertex positions by 2^k on the way
 * out. Multiplying by a power of two is exact in IEEE arithmetic (barring
 * overflow and subnormals), and the meshing code mixes no absolute length
 * into its arithmetic (its only constants are ratios, relative to r or h,
 * and "far away" paddings whose kernels vanish anyway), so every value it
 * computes is the world's value times 2^-k, exactly: the mesh is the same
 * bytes as if computed in the user's unit, but squared lengths cannot
 * overflow (r = 1e10: the sag's cross products) or underflow (r = 1e-25:
 * reach^2) whatever that unit is.
 *
 * What remains is the numeric domain (jetmesh.h, "Numeric domain"):
 * a normal float radius (jm_params_check), coordinates within
 * JM_MAX_CUBES_FROM_ORIGIN cube edges of the origin (float precision of
 * the lattice), and a mesh within the float range.
 */

/* k: r = m 2^k with m in [0.5, 1). r must be finite and above 0. */
int jm_unit_exponent(float radius);

/* The parameters in units of 2^k: radius, uv_scale and the boxes (the only
 * members in world units) times 2^-k. */
void jm_unit_params(const jm_params *world, int k, jm_params *units);

/* The filled-in parameters back in world units (radius and boxes as the
 * user gave them in world). */
void jm_unit_world_params(jm_params *filled, int k, const jm_params *world);

/* Checks the frame's particle bounds lo, hi (in units) against the numeric
 * domain for configuration c (in units, k its exponent): JM_OK or
 * JM_E_NUMERIC_DOMAIN. reach: how far (in units) the mesh may extend past
 * the particles. */
jm_status jm_unit_check(const jm_config *c, const float lo[3], const float hi[3], double reach);

/* How far (in units) past the particles the mesh of configuration c can
 * reach: the influence (for anisotropic kernels their widest possible
 * reach) plus four blocks (the band, the sag compensation, smoothing). */
double jm_unit_reach(const jm_config *c);

/* Vertex positions (3 floats each) back to world units. */
void jm_unit_restore(float *pos, size_t nv, int k);
#endif
