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
 * bit-identical meshes, whatever the thread count.
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
 * nodes, by Newton steps on the analytic function; a third piece winning
 * only mid-edge is missed (0.8 % of the jet's vertices lie 0.02 r to 0.33 r
 * inside the surface) unless exact_surface is set, which evaluates every
 * piece near each vertex and refines again with any that beats the surface
 * there: every vertex then lies on the exact surface. Then, since a
 * triangle with its corners on a curved surface lies inside it by on average
 * sum_e k_e l_e^2 / 24 (k_e the normal curvature along edge e, estimated as
 * dn.dp from the analytic normals), each vertex moves outward by the
 * area-weighted mean of that sag over its triangles, at most a tenth of a
 * cube (no_compensation turns this off). One particle then gives a volume
 * within 1 % of 4/3 pi r^3 at cube size r/4 and within 0.3 % at r/8.
 * Interpolation parameters are kept in [0.01, 0.99], so no two vertices
 * coincide at a node.
 *
 * Normals: SPH, the normalised gradient of phi. Metasphere, the outward
 * unit normals of the pieces within 0.5 h/r of the maximum (h the cube
 * edge: what the field changes over half a cube), weighted by smoothstep(1 - gap / width), so shading turns
 * smoothly across the creases where pieces meet instead of jumping (the
 * two edge pieces; every piece near the vertex with exact_surface). Where
 * the surface bends more sharply than the cubes follow, a normal pointing
 * away from one of its triangles (cosine under 0.02) is turned toward them
 * until it faces them all where possible: on dense lattices over 99.5 % of
 * triangle corners face their triangle.
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
    JM_E_TOO_LARGE,        /**< estimate over params.max_bytes, a lattice
                                coordinate beyond +-2^30 cubes, or over 3.4e10
                                lattice nodes to sample (a cube size absurdly
                                small for the particles' spread) */
    JM_E_THREAD,           /**< worker threads could not be started */
    JM_E_INTERNAL          /**< a bug: please report it */
} jm_status;

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
    int threads;            /**< worker threads; 0 = all cores */
    jm_uv_mode uv_mode;     /**< default JM_UV_BOX */
    float uv_scale;         /**< world units per texture repeat; default 16r */
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
                                 exceeds this (JM_E_TOO_LARGE); 0 = no limit */
    int exact_surface;      /**< metasphere: 1 checks every piece near each
                                 vertex, not only the two that won at its
                                 edge's nodes (see Vertex placement): every
                                 vertex on the exact surface, normals blended
                                 over all the pieces meeting there; about
                                 1.7 times the instructions of the jet */
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
 * jm_mesh_particles() on the same context or jm_context_free().
 */
typedef struct jm_mesh {
    const float *positions;  /**< 3 floats per vertex */
    const float *normals;    /**< 3 floats per vertex, unit, outward; or NULL */
    const float *uvs;        /**< 2 floats per vertex; or NULL */
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
    size_t particles;     /**< particles meshed */
    size_t isolated;      /**< of which emitted from the sphere template */
    size_t blocks;        /**< lattice blocks sampled */
    size_t cells;         /**< cubes visited */
    size_t vertices;
    size_t triangles;
    size_t estimated_bytes; /**< the pre-allocation estimate of working memory */
    size_t peak_bytes;    /**< peak of the context's own heap during the call
                               (mesh included) */
    int threads;          /**< worker threads used */
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
 */
jm_status jm_estimate_bytes(jm_context *ctx, const jm_particles *particles,
                            size_t *out_bytes);

/**
 * Evaluates the implicit function (the same value the lattice samples, in
 * the units described above) and its gradient at point p by brute force
 * over all particles: O(n), for tests and probing, not for bulk use.
 * out_gradient may be NULL.
 */
jm_status jm_field_eval(const jm_params *params, const jm_particles *particles,
                        const float p[3], float *out_value, float out_gradient[3]);

#ifdef __cplusplus
}
#endif
#endif /* JETMESH_H */
