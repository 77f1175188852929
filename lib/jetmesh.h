/* jetmesh.h - public API of the jetmesh isosurface library: particles in, closed triangle mesh out. */
#ifndef JETMESH_H
#define JETMESH_H

/*
 * jetmesh turns a set of particle centres into a closed, manifold, consistently
 * oriented triangle mesh with unit normals and texture coordinates.
 *
 * Usage:
 *
 *     jm_params p = {0};            // zero means default everywhere
 *     p.radius = 0.025f;            // the only required field
 *     jm_context *ctx = NULL;
 *     if (jm_context_create(&p, &ctx) != JM_OK) ...;
 *     jm_particles in = {xyz, n, 0, NULL};   // borrowed, not copied
 *     jm_mesh mesh; jm_stats st;
 *     jm_status s = jm_mesh_particles(ctx, &in, &mesh, &st);
 *     if (s != JM_OK) fprintf(stderr, "%s\n", jm_status_message(s));
 *     ... use mesh.positions, mesh.normals, mesh.uvs, mesh.indices ...
 *     jm_context_free(ctx);       // also frees the mesh
 *
 * Conventions: the library does no file I/O, never prints and never exits.
 * Every call that can fail returns a jm_status; results go through out_
 * pointers, which are left untouched (or zeroed) on failure. Free functions
 * accept NULL. A context may be used by one thread at a time; it owns a
 * pool of worker threads and scratch memory reused from frame to frame.
 *
 * Determinism: the same particles (in the same order) and parameters give
 * bit-identical meshes, whatever the thread count and the CPU's vector
 * extensions.
 *
 * This header is the stable API. Hooks for tests and measurement (forcing
 * a CPU path, sampling without culling) are in jetmesh_testing.h, outside
 * it; deprecated fields are marked DEPRECATED with the release that
 * removes them.
 *
 * ----------------------------------------------------------------------
 * Fields (all lengths below in world units; r = params.radius)
 *
 * JM_FIELD_METASPHERE (the default; the "metasphere" of the 2015 liquid-jet
 * visualisation paper). The solid is the union of
 *   - a ball of radius r around every particle c_i, and
 *   - for every pair (i, j) with |c_j - c_i| = D < L (link distance,
 *     default L = pi*r), a neck: the solid of revolution around the
 *     segment c_i c_j whose radius, at distance l along the segment from
 *     the nearer centre, is rho(l) = r*cos(l/r).
 * rho(0) = r and rho'(0) = 0, and rho osculates the ball's profile
 * sqrt(r^2 - l^2) to second order, so the neck leaves each ball smoothly.
 * The neck's waist rho(D/2) = r*cos(D/(2r)) shrinks to 0 as D -> pi*r, so
 * with the default L the topology changes continuously: two particles
 * 1.5r apart form one body with a waist of 0.73r; 4r apart, two balls.
 * The implicit function, in units of r, is
 *     f(x) = max( max_i (r - |x - c_i|),
 *                 max_{i,j} (rho(l_ij(x)) - q_ij(x)) ) / r
 * where, for the pair (i, j), s = (x - c_i).u with u the unit direction
 * from c_i to c_j, l = min(s, D - s), q = |x - c_i - s*u| (distance to the
 * axis), and the neck term only counts for 0 <= s <= D. f > 0 inside,
 * f = 0 on the surface (threshold default 0; a threshold t offsets the
 * surface inwards by t*r).
 *
 * JM_FIELD_SPH: the SPH colour field as splashsurf defines it,
 *     phi(x) = sum_j V_j W(|x - c_j|, h),  V_j = 1 / sum_k W(|c_j - c_k|, h)
 * with the cubic spline (M4) kernel of smoothing length h (support 2h):
 *     W(d, h) = 1/(pi h^3) * { 1 - 1.5 q^2 + 0.75 q^3   0 <= q < 1
 *                            { 0.25 (2 - q)^3           1 <= q < 2
 *                            { 0                        q >= 2,     q = d/h
 * h = params.smoothing_length * r (default 2r, support 4r); the surface is
 * phi = threshold (default 0.6). phi is about 1 inside bulk fluid.
 *
 * Anisotropic kernels (JM_FIELD_SPH with params.anisotropic = 1; Yu & Turk,
 * "Reconstructing surfaces of particle-based fluids using anisotropic
 * kernels", ACM TOG 32(1), 2013):
 *     phi(x) = sum_j V_j det(G_j) / pi * w(|G_j (x - cbar_j)|)
 * with the same V_j and cubic w (the bracket above; support |G d| < 2).
 * Per particle i, the neighbours j within r_n (aniso_radius * r, default 8r,
 * itself included) weighted by w_ij = 1 - (|c_j - c_i| / r_n)^3 give the
 * weighted mean m_i and covariance C_i = sum w_ij (c_j - m_i)(c_j - m_i)^T /
 * sum w_ij.
 *   - Centre: cbar_i = c_i + lambda max(0, |d| - b) d / |d|, d = m_i - c_i,
 *     b = 0.27 r_n (sum w_ij - 1) / sum w_ij: the paper's (1 - lambda) c_i +
 *     lambda m_i, less the drift b that a flat free surface gives (the mean of
 *     a half-ball lies inside it), which would otherwise shrink every free
 *     surface by about a particle radius. lambda = aniso_smoothing, default 1.
 *   - Kernel: C_i = R diag(s1 >= s2 >= s3) R^T; the axes follow the ratios
 *     s_k / s1 beyond 1/1.5 (min(1, 1.5 s_k / s1): a full neighbourhood
 *     measures up to that much anisotropy, and the particles a layer under
 *     a surface shape no surface, only holes), at least 1 / k_r
 *     (aniso_max_ratio, default 4), scaled to a geometric mean of 1; then
 *     the shortest is raised to at least 0.7 times the rest spacing 2r and
 *     to 0.85 (2r)^2 / T, T = sqrt(12 s3 + (2r)^2) the liquid's thickness
 *     along it (2r L for L layers), the others shrunk alike: layers of
 *     particles overlap above the threshold (no air between them) and a
 *     sheet of one layer keeps its thickness. Scaled by k_s (aniso_scale,
 *     default 1), where the paper scales by an absolute k_s tuned to one
 *     particle spacing; G_i = (1/h) R diag(1/s_k) R^T. Every kernel keeps the
 *     isotropic kernel's integral, and its volume (times k_s^3) except at
 *     rims (below); bulk kernels stay isotropic, free-surface kernels flatten
 *     along the normal and widen along the surface; the longest axis is at
 *     most k_s k_r^(2/3) h.
 *   - Rims: away from m_i (outward), a kernel reaches no further than the
 *     sphere k_s h: the axes longer than k_s shrink alike by the least
 *     fraction that gives that, weighted from none at |d| = 0.5r to all at
 *     1.5r. A sheet's edge then does not widen into the air toward a
 *     droplet beside it and join it.
 *   - Droplets: n_i, the particles within the support 2h counted smoothly
 *     (1 within 3h/2, falling to 0 at 2h in the squared distance; one layer
 *     of particles has 8 to 10, a flat surface 15, bulk 23), blends the
 *     kernel toward the sphere (fully below 2, none from 5: s_k^a, a a
 *     smoothstep) and the centre's move toward nothing (fully below 5, none
 *     from 10): a droplet or small cluster near a sheet keeps its place and
 *     shape, which the sheet's particles in its neighbourhood would set.
 *   - Fewer than N_eps neighbours (aniso_min_neighbours; default 25 at
 *     r_n = 8r, scaled with r_n^3): G_i = I / (k_n h), k_n = aniso_iso_scale
 *     (default 1). Isolated particles are still emitted from the sphere
 *     template (this same kernel, alone).
 * On sheets of 1 to 4 layers and on the shared dam-break frames the mesh
 * holds no closed shell inside the liquid and its volume lies within 4 % of
 * the isotropic mesh's (tests/test_aniso_pockets.c).
 * The sampled band reaches as far as the frame's widest kernel (its box
 * around cbar), so culling stays exact and the mesh closed; normals are the
 * gradient of this field. Blocks and nodes are culled as for the
 * isotropic field (see Culling). It costs about twice the isotropic
 * field's time and 56 more bytes per particle.
 *
 * Culling (SPH, both kernels): a block where an upper bound of the field
 * (each kernel at its nearest distance to the block) stays below the
 * threshold is not sampled, and in blocks inside the fluid nodes whose
 * lower bounds (the nearer particles' kernels) exceed it are not sampled
 * unless next to a node that may be outside. Both bounds carry the float
 * rounding slack, so no cube holding a crossing loses a sample and the mesh
 * is the bytes that sampling every node gives (the proof: docs/culling.md).
 *
 * ----------------------------------------------------------------------
 * Extraction: a global lattice of cubes of edge params.cube_size * r, with
 * a node at the world origin (so meshes of a sequence sit on one lattice),
 * visited sparsely: only blocks of cubes within reach of a particle are
 * sampled, so memory follows the surface band, not the bounding box.
 * JM_METHOD_MT: marching tetrahedra, each cube cut into 6 tetrahedra around
 * its (0,0,0)-(1,1,1) diagonal (the paper's method). JM_METHOD_MC:
 * marching cubes with a table generated so that ambiguous faces always
 * separate the inside corners, which both cubes sharing a face agree on.
 * One vertex per crossed lattice edge, shared by all its triangles: the
 * mesh is closed, manifold and oriented outward (counter-clockwise seen
 * from outside) wherever the surface lies inside the sampled band.
 * Node values exactly equal to the threshold count as outside.
 *
 * Vertex placement: SPH vertices are linearly interpolated between the two
 * node samples (as splashsurf does). Metasphere vertices are refined onto the
 * surface of the two pieces (balls, half-necks) that won at the edge's
 * nodes, by Newton steps on the analytic function; a third piece can still
 * win in the middle of an edge (0.8 % of the jet's vertices would lie 0.02 r
 * to 0.33 r inside the surface), so every piece is also evaluated at every
 * vertex, splatted onto each block's vertices as onto its nodes, and a
 * vertex off the surface by more than 0.0125 r is refined again on all the
 * pieces there: every vertex lies within that of the exact surface. Then,
 * since a triangle with its corners on a curved surface lies inside it by
 * on average sum_e k_e l_e^2 / 24 (k_e the normal curvature along edge e,
 * estimated as dn.dp from the analytic normals), each vertex moves outward by the
 * area-weighted mean of that sag over its triangles, at most a tenth of a
 * cube and under a third of the least altitude of its triangles, so no
 * triangle folds over (no_compensation turns this off). One particle then
 * gives a volume within 1 % of 4/3 pi r^3 at cube size r/4 and within 0.3 %
 * at r/8.
 * Interpolation parameters are kept in [0.01, 0.99], so no two vertices
 * coincide at a node.
 *
 * Normals: SPH, the normalised gradient of phi. Metasphere, the sum of the
 * outward gradients of every ball and neck whose value at the vertex comes
 * within 0.4 of the threshold, each weighted by smoothstep(1 - gap / 0.4)
 * (gap: how far its value lies below the threshold), normalised: the
 * gradient of a smooth maximum of the pieces, which shades every crease as
 * a fillet, smoothly (C1), with no step between neighbouring vertices
 * (every piece is evaluated at every vertex of its block for this). Where
 * the surface bends more sharply than the cubes follow, a normal pointing
 * away from one of its triangles (cosine under 0.02) is turned toward them
 * until it faces them all where possible: on dense lattices over 99.5 % of
 * triangle corners face their triangle.
 *
 * ----------------------------------------------------------------------
 * Numeric domain. The mesh does not depend on the unit of length: the
 * library computes in units of 2^k, the power of two with r / 2^k in
 * [0.5, 1), scaling coordinates and the lengths among the parameters
 * (radius, uv_scale) by 2^-k on the way in and vertex positions by 2^k on
 * the way out. Both are exact in floating point, so a frame and its
 * parameters scaled by any power of two give the same mesh scaled, bit for
 * bit (normals, texture coordinates and triangles the same bits), and
 * r = 1e-25 or r = 1e19 mesh as r = 1 does. What remains:
 *   - the radius must be a normal float: FLT_MIN (1.18e-38) or more
 *     (JM_E_INVALID_ARGUMENT from jm_params_check);
 *   - every coordinate within JM_MAX_CUBES_FROM_ORIGIN (2^16) cube edges of
 *     the origin, where floats are at most 1/128 of a cube apart
 *     (JM_E_NUMERIC_DOMAIN; beyond 1e9 cube edges JM_E_TOO_LARGE, as before);
 *   - the mesh within the float range: the largest |coordinate| plus the
 *     mesh's reach past the particles (the influence radius plus four
 *     blocks: about 36 r for the metasphere, 52 r for sph at the
 *     defaults) below 2^126 = 8.5e37
 *     (JM_E_NUMERIC_DOMAIN; only radii above about 1e36 come near it).
 * jm_estimate_bytes refuses the same frames with the same status.
 *
 * Limits: at most JM_MAX_PARTICLES particles a frame and JM_MAX_VERTICES
 * vertices a mesh (indices are 32 bits); the metasphere numbers its
 * pieces n + links in 32 bits, so n plus the frame's links must stay below
 * 2^32 - 1; beyond any of these JM_E_TOO_LARGE.
 *
 * Memory (params.max_bytes): every heap byte a context takes is counted
 * (its scratch, the workers' growing buffers, the mesh it returns,
 * meshoptimizer's scratch during simplification; freed blocks it keeps for
 * its next frames aside, see Real-time use), and the limit is checked
 * where memory is taken: an allocation that would pass it fails and the
 * frame is refused with JM_E_TOO_LARGE (jm_stats.estimated_bytes then
 * holds the total that allocation needed). The frame's estimate (with the
 * metasphere's links counted exactly, once the neighbour search has counted
 * them) is also checked before the large allocations, so most refusals
 * come before the work.
 * Memory not on the heap (the worker threads' stacks) is not counted.
 *
 * Real-time use (the paper's jet, meshed inside a running simulator): a
 * context keeps the working memory its frames free (blocks of up to 4 MiB,
 * 32 MiB in all, held as malloc holds freed memory: not counted in
 * peak_bytes or against max_bytes) and hands it out again, and the arrays
 * it keeps from frame to frame (the mesh, the workers' scratch, grown alike
 * on every worker) only grow. So once a context has meshed a frame,
 * meshing a frame that needs no more memory (that frame again, or the
 * frames of a sequence once their sizes have been met) makes no heap
 * allocation at all: no malloc, free or mmap, on any number of threads
 * (tests/test_realtime.c: the jet, both fields; not claimed for
 * anisotropic kernels or post-processing, which still allocate).
 *
 * ----------------------------------------------------------------------
 * Selection and clipping (jm_params.particle_aabb_min/max,
 * min_piece_particles, min_piece_volume, mesh_aabb_min/max/clamp; all off
 * by default, and a mesh made without them is the same bytes as before
 * they existed). In pipeline order:
 *   1. particle box: particles outside it are left out before anything
 *      else (a non-finite coordinate is still JM_E_INVALID_PARTICLE);
 *   2. small groups: the particles left are grouped by connectivity (two
 *      closer than L are of one group: union-find over cells of edge L) and
 *      the groups of fewer than min_piece_particles are left out. L is the
 *      metasphere's link distance (or its balls' contact distance
 *      2 r (1 - threshold) where larger): its pieces are then exactly these
 *      groups (though a neck can pinch at a positive threshold); for sph the
 *      kernel support 2h: a group may mesh as a few blobs, and at a low
 *      threshold two groups under 2h apart may join. jm_stats.particles
 *      counts the particles meshed;
 *   3. the mesh as usual (cavities, post-processing), then small pieces:
 *      every connected piece facing outward whose enclosed volume is below
 *      min_piece_volume r^3 goes, and every cavity inside such a piece
 *      (its winding number about the piece) with it;
 *   4. the clip box, last. Without mesh_aabb_clamp every triangle with a
 *      corner outside the box goes, and every vertex no triangle keeps: the
 *      mesh lies in the box and is open where the box cut it (a tank's
 *      walls removed, the free surface kept). With it no triangle goes:
 *      each vertex outside the box moves to the nearest point of the box
 *      (its coordinates clamped), its normal to the box's outward face
 *      normal (the sum of the faces' on an edge or a corner, normalised)
 *      and its texture coordinates follow; a piece with no vertex inside
 *      the box goes whole. The mesh stays closed, manifold and oriented,
 *      the cut closed by flat faces on the box, though a part folded
 *      beyond the box can flatten onto it as overlapping faces.
 * Steps 3 and 4 count in jm_stats.ms_post. Deterministic and the same for
 * any thread count, like the rest.
 */

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define JM_VERSION_MAJOR 0
#define JM_VERSION_MINOR 3
#define JM_VERSION_PATCH 0
#define JM_VERSION_STRING "0.3.0"

/** Every result of the library. JM_OK is 0. */
typedef enum jm_status {
    JM_OK = 0,
    JM_E_INVALID_ARGUMENT, /**< NULL pointer or a parameter out of range */
    JM_E_INVALID_PARTICLE, /**< a coordinate is NaN or infinite */
    JM_E_OUT_OF_MEMORY,    /**< an allocation failed */
    JM_E_TOO_LARGE,        /**< estimate or an allocation over
                                params.max_bytes, a lattice
                                coordinate beyond +-2^30 cubes, or over 3.4e10
                                lattice nodes to sample (a cube size absurdly
                                small for the particles' spread) */
    JM_E_THREAD,           /**< worker threads could not be started */
    JM_E_INTERNAL,         /**< a bug: please report it */
    JM_E_TOO_DENSE,        /**< particles packed far closer than their radius:
                                the neighbour search would check more than
                                JM_MAX_PAIR_CHECKS(n) pairs, or the metasphere
                                would link a particle to over 1000 others on
                                average (many duplicated particles, or a
                                radius far too large for their spacing) */
    JM_E_NUMERIC_DOMAIN    /**< outside the numeric domain (see "Numeric
                                domain" above): a coordinate more than
                                JM_MAX_CUBES_FROM_ORIGIN cube edges from the
                                origin, or a mesh beyond the float range */
} jm_status;

/** Float precision: coordinates farther than this many cube edges
 *  (params.cube_size * r) from the origin are refused with
 *  JM_E_NUMERIC_DOMAIN. The lattice has a node at the origin, and beyond
 *  2^16 cubes the spacing of floats exceeds 1/128 of a cube, so vertices
 *  0.01 cube from a node (the closest they come) start to land on it: on
 *  the jet at 2^17 cubes 5 % of the triangles have zero area. At the
 *  default cube size 0.5 r: 32,768 r. Move such particles nearer the
 *  origin (subtract their centre) before meshing. */
#define JM_MAX_CUBES_FROM_ORIGIN 65536.0

/** The smallest uv_scale, relative to the radius: texture coordinates
 *  (positions over uv_scale) then stay well within the float range for
 *  every frame in the numeric domain. */
#define JM_UV_SCALE_MIN 1e-6

/** The bound on a frame's neighbour-search work: n particles are searched
 *  with at most max(2e9, 4000 n) pair checks, else JM_E_TOO_DENSE, decided
 *  before the search from the particles' cell counts. Bulk fluid at rest
 *  spacing 2r needs about 220 n; 50,000 copies of one particle 2.5e9. */
#define JM_MAX_PAIR_CHECKS(n) ((double)(n) * 4000.0 > 2e9 ? (double)(n) * 4000.0 : 2e9)

/** A static, human-readable message for a status ("ok", ...). Never NULL. */
const char *jm_status_message(jm_status status);

/** The library's version, JM_VERSION_STRING of the build. */
const char *jm_version(void);

typedef enum jm_field {
    JM_FIELD_DEFAULT = 0, /**< = JM_FIELD_METASPHERE */
    JM_FIELD_METASPHERE,
    JM_FIELD_SPH
} jm_field;

typedef enum jm_method {
    JM_METHOD_DEFAULT = 0, /**< = JM_METHOD_MT */
    JM_METHOD_MT,          /**< marching tetrahedra, 6 per cube */
    JM_METHOD_MC           /**< marching cubes */
} jm_method;

/**
 * Texture coordinates. All modes depend only on the vertex's world
 * position (and normal, for BOX) and on the parameters, never on the
 * frame's bounding box, so a texture stays put from frame to frame.
 * s = params.uv_scale (world units per texture repeat).
 */
typedef enum jm_uv_mode {
    JM_UV_DEFAULT = 0, /**< = JM_UV_BOX */
    JM_UV_BOX,         /**< box (tri-planar) projection: the two world axes
                            other than the normal's dominant axis, / s */
    JM_UV_PLANAR,      /**< (x, y) / s if uv_axis is z; (x, z) / s if y;
                            (y, z) / s if x: a projection along uv_axis */
    JM_UV_SPHERICAL,   /**< (atan2(ny, nx)/2pi + 0.5, acos(nz)/pi): from the
                            unit normal, like a matcap/latitude map */
    JM_UV_NONE         /**< no texture coordinates (mesh.uvs = NULL) */
} jm_uv_mode;

/** The most particles a frame may have, and vertices a mesh (2^31 - 1). */
#define JM_MAX_PARTICLES 2147483647u
#define JM_MAX_VERTICES 2147483647u

/** The most worker threads a context starts (jm_params.threads above it is capped). */
#define JM_MAX_THREADS 256

/** Parameters. Zero in any field means its default. */
typedef struct jm_params {
    float radius;           /**< particle radius r, world units; required > 0 */
    float cube_size;        /**< cube edge relative to r; default 0.5 */
    jm_field field;         /**< default JM_FIELD_METASPHERE */
    jm_method method;       /**< default JM_METHOD_MT */
    float threshold;        /**< iso value; default 0 (metasphere), 0.6 (sph) */
    float smoothing_length; /**< sph: h relative to r; default 2 (support 4r) */
    float link_distance;    /**< metasphere: neck link distance relative to r;
                                 default pi */
    int threads;            /**< worker threads; 0 = all cores; at most
                                 JM_MAX_THREADS (more are capped there) */
    jm_uv_mode uv_mode;     /**< default JM_UV_BOX */
    float uv_scale;         /**< world units per texture repeat; default 16r;
                                 else at least JM_UV_SCALE_MIN times radius */
    int uv_axis;            /**< JM_UV_PLANAR projection axis: 1 x, 2 y,
                                 3 z; default (0) z */
    int no_normals;         /**< 1: skip normals (mesh.normals = NULL) */
    int no_templates;       /**< 1: mesh isolated particles through the
                                 lattice too, not from the sphere template */
    int no_compensation;    /**< metasphere: 1 leaves vertices exactly on the
                                 surface (an inscribed mesh, a little small);
                                 default: each vertex moves outward by the
                                 estimated chord sag of its triangles (see
                                 Extraction), so volumes come out unbiased */
    size_t max_bytes;       /**< refuse frames whose estimated working memory
                                 exceeds this, or that would take more (the
                                 limit is checked at every allocation; see
                                 "Memory" above): JM_E_TOO_LARGE; 0 = no limit */
    int keep_cavities;      /**< 1: keep every cavity. Default: a closed
                                 inward-facing shell (a cavity inside the
                                 solid) smaller than one particle's ball,
                                 4/3 pi r^3, is removed: where bulk fluid is
                                 packed a little unevenly the SPH field dips
                                 below the threshold inside the liquid, and
                                 the metasphere leaves such shells between
                                 balls that do not touch; no simulation
                                 resolves a bubble that small. Larger
                                 cavities (real bubbles) are kept. */
    /* sph: Yu-Turk anisotropic kernels (see "Anisotropic kernels" above) */
    int anisotropic;        /**< 1: anisotropic kernels on smoothed centres
                                 (JM_FIELD_SPH only; JM_E_INVALID_ARGUMENT with
                                 the metasphere); 0: the isotropic field */
    float aniso_radius;     /**< r_n, the neighbourhood of the smoothing and
                                 the covariance, relative to r; default and
                                 most 4 smoothing_length (twice the support) */
    float aniso_smoothing;  /**< lambda in [0, 1]; default 1; a negative value
                                 means 0 (centres stay on the particles) */
    float aniso_max_ratio;  /**< k_r in [1, 100]: the largest axis over the
                                 smallest, at most (as covariance eigenvalues);
                                 default 4 (1: isotropic kernels) */
    float aniso_scale;      /**< k_s in [0.05, 4]: the kernels' geometric mean
                                 axis relative to h; default 1 */
    float aniso_iso_scale;  /**< k_n in [0.05, 4]: kernel size relative to h
                                 with fewer than N_eps neighbours; default 1 */
    int aniso_min_neighbours; /**< N_eps: neighbours within r_n (itself not
                                 counted) below which a kernel stays
                                 isotropic; default 25 (r_n / 8r)^3, >= 3 */
    /* ---- post-processing, in this order (all off by default) */
    int smooth_iterations;  /**< iterations of bounded Laplacian smoothing:
                                 as much smoothing as this many steps moving
                                 every vertex to the mean of its neighbours
                                 (splashsurf's iterations in bulk fluid,
                                 Löschner et al. 2023), run in fewer passes
                                 (super time stepping: 25 in 9), each vertex's
                                 move along its unsmoothed normal kept within
                                 0.46 r (a quarter of its piece's thickness
                                 3 V / A where less), so bumps of the
                                 particles' size go while droplets, crests
                                 and ripples higher than that keep their
                                 shape. Then every connected piece is moved
                                 along its normals, within the same band, to
                                 enclose its unsmoothed volume again, and
                                 triangles turned over are taken back toward
                                 their unsmoothed places. Normals become the
                                 smoothed surface's (area-weighted); UVs are
                                 recomputed; triangles and sphere templates
                                 are unchanged. 0 = off; at most 100000 */
    int smooth_normal_iterations; /**< iterations of normal smoothing (each
                                 normal becomes the unit mean of itself and
                                 its neighbours' facing the same side), after
                                 smoothing; a normal that ends past its face
                                 keeps its own. UVs follow. 0 = off; at most
                                 100000 */
    float simplify_error;   /**< simplify the final mesh (meshoptimizer edge
                                 collapses) to at most this geometric error,
                                 relative to r (e.g. 0.1); surviving vertices
                                 keep their positions, normals and UVs. The
                                 result is checked closed and manifold; if a
                                 collapse ever pinched it, the error is halved
                                 (twice) and then the mesh left unsimplified.
                                 Sphere templates of isolated particles are
                                 simplified too, never smoothed. 0 = off */
    /* ---- deprecated: kept until 0.4.0, which removes them */
    int exact_surface;      /**< DEPRECATED, does nothing: metasphere
                                 vertices are always checked against every
                                 piece (see Vertex placement) */
    /* ---- reserved (the slot of a test hook, jetmesh_testing.h) */
    int reserved0;          /**< leave 0 */
    /* ---- what is meshed and kept (all off by default; see "Selection and
     * clipping" below). Boxes in world units, bounds included; a box is
     * off while all six of its numbers are 0, else each must be finite and
     * its min below its max on every axis. */
    float particle_aabb_min[3]; /**< with particle_aabb_max: only the
                                 particles inside this box are meshed (as
                                 splashsurf's --particle-aabb-min/max) */
    float particle_aabb_max[3];
    int min_piece_particles;    /**< particles not meshed in groups of fewer
                                 than this (stray droplets), two particles
                                 being of one group when closer than the
                                 link distance (metasphere: their neck
                                 joins them; or than their balls' contact
                                 distance, when larger) or the kernel
                                 support 2h (sph); 0 or 1 = off */
    float min_piece_volume;     /**< connected pieces of the mesh enclosing
                                 less than this volume, in units of r^3
                                 (one particle's ball: 4.19), removed
                                 after the post-processing, with the
                                 cavities inside them; 0 = off */
    float mesh_aabb_min[3];     /**< with mesh_aabb_max: the clip box, last
                                 of all (as splashsurf's --mesh-aabb-min/max) */
    float mesh_aabb_max[3];
    int mesh_aabb_clamp;        /**< with the clip box: 0 removes every
                                 triangle with a corner outside it (the mesh
                                 is then open along the cut); 1 moves every
                                 vertex outside onto the box instead, which
                                 closes the cut with flat faces on the box
                                 and keeps the mesh closed (pieces with no
                                 vertex inside removed whole) */
    int smooth_implicit;        /**< with smooth_iterations: 1 smooths with
                                 one backward Euler step of the cotangent
                                 Laplacian per 25 iterations (solved by 20
                                 conjugate gradient iterations, with
                                 tangential relaxation around it) instead of
                                 the explicit steps, in the same band (a
                                 quarter narrower inward) and with the same
                                 volume restoration. Its surface does not
                                 hang on how the lattice cut it: the mesh of
                                 a moving input shimmers no more than the
                                 unsmoothed mesh (the explicit steps' about
                                 2.4 times as much). Its post-processing
                                 takes 2.5 to 3 times as long. 0 = off */
} jm_params;

/** Borrowed view of one frame's particles; the library never keeps it. */
typedef struct jm_particles {
    const float *xyz;       /**< x, y, z of the first particle */
    size_t count;           /**< number of particles (0 gives an empty mesh) */
    size_t stride;          /**< bytes from one particle to the next; 0 = 12 */
    const uint32_t *ids;    /**< optional stable ids (NULL: input order). When
                                 given, particles are ordered by id before any
                                 floating-point sum, so the mesh does not
                                 depend on the order the simulator wrote them */
} jm_particles;

/**
 * A mesh. Arrays are owned by the context and stay valid until the next
 * jm_mesh_particles() on the same context or jm_context_free() (the next
 * call may give them back before it starts, so that its peak does not hold
 * the last frame's mesh beside its particles).
 */
typedef struct jm_mesh {
    const float *positions;  /**< 3 floats per vertex */
    const float *normals;    /**< 3 floats per vertex, unit, outward; NULL
                                  exactly when no_normals (an empty mesh too) */
    const float *uvs;        /**< 2 floats per vertex; NULL exactly when
                                  uv_mode is JM_UV_NONE (an empty mesh too) */
    const uint32_t *indices; /**< 3 per triangle, counter-clockwise from outside */
    size_t vertex_count;
    size_t triangle_count;
    float bounds_min[3];     /**< of positions; zeros for an empty mesh */
    float bounds_max[3];
} jm_mesh;

/** What one jm_mesh_particles() call did and cost. Times in milliseconds. */
typedef struct jm_stats {
    double ms_prepare;    /**< validation, sorting into cells, neighbours */
    double ms_field;      /**< densities and field sampling on the band */
    double ms_extract;    /**< marching, welding, stitching blocks */
    double ms_attributes; /**< normals and texture coordinates */
    double ms_total;
    size_t particles;     /**< particles meshed (after particle_aabb and
                               min_piece_particles) */
    size_t isolated;      /**< of which emitted from the sphere template */
    size_t blocks;        /**< lattice blocks sampled */
    size_t cells;         /**< cubes visited */
    size_t vertices;
    size_t triangles;
    size_t estimated_bytes; /**< the pre-allocation estimate of working memory
                               (after a refusal at an allocation over
                               max_bytes: the total it needed, if more) */
    size_t peak_bytes;    /**< peak of the context's own heap during the call
                               (mesh, scratch and meshoptimizer's scratch
                               included; the freed blocks kept for the next
                               frames not: see Real-time use). Isotropic
                               SPH without post-processing gives the
                               particles back behind the sweep of the
                               blocks, which runs in z: the peak holds the
                               mesh and a band of the particles, not all
                               of them */
    int threads;          /**< worker threads used */
    size_t cavities_removed; /**< sub-particle cavities removed (see
                                  jm_params.keep_cavities) */
    double ms_post;       /**< smoothing, normal smoothing, simplification,
                               small pieces and the clip box (not part of
                               the other stages; in ms_total) */
} jm_stats;

typedef struct jm_context jm_context;

/** Creates a context (and its thread pool) for these parameters. */
jm_status jm_context_create(const jm_params *params, jm_context **out_ctx);

/** Replaces the parameters; keeps threads and scratch memory if it can. */
jm_status jm_context_set_params(jm_context *ctx, const jm_params *params);

/** The parameters in force, with every default filled in. */
void jm_context_get_params(const jm_context *ctx, jm_params *out_params);

/** Frees the context, its threads and the last mesh. NULL is allowed. */
void jm_context_free(jm_context *ctx);

/**
 * Meshes one frame. out_mesh receives arrays owned by ctx (see jm_mesh);
 * out_stats may be NULL. Non-finite coordinates give
 * JM_E_INVALID_PARTICLE (filter them before the call if you want to skip
 * them). On failure out_mesh is zeroed.
 */
jm_status jm_mesh_particles(jm_context *ctx, const jm_particles *particles,
                            jm_mesh *out_mesh, jm_stats *out_stats);

/**
 * Estimates the working memory (bytes) jm_mesh_particles() would need for
 * these particles, without meshing. Cheap: one pass over the particles.
 * The metasphere's links (24 bytes each) are estimated from the particles'
 * mean density over their bounds: about right for bulk fluid, up to twice
 * too many for jets and sheets. Refuses what jm_mesh_particles refuses
 * before meshing: NaN and infinite coordinates, a short stride, the numeric
 * domain.
 */
jm_status jm_estimate_bytes(jm_context *ctx, const jm_particles *particles,
                            size_t *out_bytes);

/** jm_choose_field's boundary: a mean of this many neighbours or more
 *  within the link distance is bulk fluid. */
#define JM_AUTO_BULK_NEIGHBOURS 6.0f

/**
 * Picks the field and method that suit these particles, as `jetmesh
 * convert` does when --field is not given (--field auto): the metasphere
 * with marching tetrahedra for sparse, chain-like frames (a jet, spray,
 * droplets: what the metasphere was made for) and the SPH colour field with
 * marching cubes for bulk fluid (where the metasphere leaves cavities
 * between balls that do not touch). The measure, returned in
 * *out_neighbours, is the mean number of other particles within the link
 * distance (params->link_distance * radius, default pi r) of a particle,
 * over up to 4096 particles taken evenly through the input; bulk when it is
 * JM_AUTO_BULK_NEIGHBOURS (6) or more. A jet column 1.5r apart has about 4;
 * bulk fluid at rest spacing 2r has 18 inside and 9 to 13 on its surface.
 * Only radius and link_distance of params are used (it must be valid for
 * jm_context_create). Deterministic; one pass over the particles plus
 * bounded neighbour scans. Any out_ pointer may be NULL. Pick once per
 * sequence (say from its first frame) so that a run never switches field
 * half-way.
 */
jm_status jm_choose_field(const jm_params *params, const jm_particles *particles, jm_field *out_field,
                          jm_method *out_method, float *out_neighbours);

/**
 * Evaluates the implicit function (the same value the lattice samples, in
 * the units described above) and its gradient at point p by brute force
 * over all particles: O(n), for tests and probing, not for bulk use.
 * out_gradient may be NULL.
 */
jm_status jm_field_eval(const jm_params *params, const jm_particles *particles,
                        const float p[3], float *out_value, float out_gradient[3]);

/**
 * Which member of jm_params jm_params_check() refused, and what it accepts,
 * so that a caller can name its own option ("--cube-size") and the range.
 */
typedef struct jm_param_problem {
    const char *field;    /**< the member's name as in jm_params ("cube_size",
                               "threshold", ...; an array's element with its
                               index: "mesh_aabb_max[1]"); NULL for a NULL
                               params */
    double value;         /**< the value given (enums and ints as numbers) */
    double min, max;      /**< the accepted range of the value given (0, the
                               default, is also accepted where the member
                               says so); +-HUGE_VAL when unbounded */
    int min_excluded;     /**< 1: min itself is refused (radius > 0) */
    int max_excluded;     /**< 1: max itself is refused */
    const char *accepted; /**< the accepted values in words, static, never
                               NULL on failure: "0.001 to 100 (times radius;
                               0 = the default 0.5)" */
} jm_param_problem;

/**
 * Checks every member of params against the ranges jm_context_create(),
 * jm_context_set_params() and jm_field_eval() accept (they use this very
 * function). JM_OK, or JM_E_INVALID_ARGUMENT with *out_problem (may be NULL)
 * describing the first member out of range, in the order of the struct
 * (radius first); on JM_OK *out_problem is zeroed. The threshold's range
 * depends on the field: above -1 and below 1 for the metasphere, above 0
 * (or 0, the default) for sph. Only the parameters are checked: a frame
 * can still be refused later with JM_E_TOO_LARGE.
 */
jm_status jm_params_check(const jm_params *params, jm_param_problem *out_problem);

/** One per-particle quantity (velocity, density, ...) to carry onto the
 *  vertices of a mesh, for jm_interpolate_attributes. */
typedef struct jm_attribute {
    int components;               /**< values per particle and per vertex, 1 to 16
                                       (at most 64 over all attributes of a call) */
    const float *particle_values; /**< components per particle, in the order of
                                       the particles (finite) */
    float *vertex_values;         /**< the caller's array of components per
                                       vertex: filled by the call */
} jm_attribute;

/**
 * Interpolates per-particle values to mesh vertices (e.g. the velocity, for
 * motion blur or colouring by speed) with normalised SPH weights, as
 * splashsurf interpolates attributes:
 *     a(v) = sum_j a_j W(|v - c_j|, h) / sum_j W(|v - c_j|, h)
 * over the particles within the support 2h of v, W the cubic spline of the
 * SPH field above and h = params->smoothing_length * radius (default 2r),
 * whichever field made the mesh. A vertex with no particle within 2h takes
 * the values of its nearest particle (the first in input order on a tie).
 * positions: 3 floats per vertex (a jm_mesh's positions, in the particles'
 * coordinates). Only radius and smoothing_length of params are used (it
 * must be valid for jm_context_create). No particles: zeros. Deterministic
 * (the sums run in a fixed order, in double precision, on the calling
 * thread); memory about 12 bytes per particle plus a hash of cells, freed
 * before it returns. Non-finite coordinates give JM_E_INVALID_PARTICLE.
 * Needs no context; jm_context_interpolate below does the same on a
 * context's threads several times faster.
 */
jm_status jm_interpolate_attributes(const jm_params *params, const jm_particles *particles,
                                    const float *positions, size_t vertex_count,
                                    jm_attribute *attributes, size_t attribute_count);

/**
 * jm_interpolate_attributes on a context: the same weights, support and
 * nearest-particle fallback, with the context's parameters (radius and
 * smoothing_length) on its threads, for a fraction of the cost (about an
 * eighth of the meshing's time on a 6,859-particle frame, where
 * jm_interpolate_attributes takes three quarters of it). Call it after
 * jm_mesh_particles with the same particles and that mesh's positions:
 *     jm_attribute vel = {3, velocities, vertex_velocities};
 *     jm_context_interpolate(ctx, &in, mesh.positions, mesh.vertex_count, &vel, 1);
 * (any positions are accepted). Particles the context's selection leaves
 * out of the mesh (particle_aabb_min/max, min_piece_particles) are left out
 * of the sums too. The vertices are bucketed by cells of edge 2h and each
 * bucket gathers its particles once; sums in float, in 8 lanes in a fixed
 * order: deterministic, the same bits for any thread count, and within a
 * few float roundings of jm_interpolate_attributes (relative 1e-6 of the
 * largest value on real frames). Memory, counted against max_bytes and
 * freed before it returns: at most (32 + 4 T) bytes per particle (T: the
 * attributes' components), 8 per vertex, a hash of the vertices' cells
 * and each thread's gathered particles. The mesh is left untouched.
 * A vertex out of reach finds its nearest particle over the cells around
 * it (jm_interpolate_attributes scans every particle for it).
 * JM_E_INVALID_PARTICLE for a non-finite particle coordinate,
 * JM_E_INVALID_ARGUMENT for a non-finite vertex coordinate or the
 * arguments jm_interpolate_attributes refuses, JM_E_TOO_LARGE for
 * particles or vertices spread over more than 2^21 cells of edge 2h.
 */
jm_status jm_context_interpolate(jm_context *ctx, const jm_particles *particles, const float *positions,
                                 size_t vertex_count, jm_attribute *attributes, size_t attribute_count);

#ifdef __cplusplus
}
#endif
#endif /* JETMESH_H */
