/* meshcheck.h - test helpers: closedness, manifoldness, orientation, volume, components of a mesh. */
#ifndef JETMESH_TESTS_MESHCHECK_H
#define JETMESH_TESTS_MESHCHECK_H
#include "../../lib/jetmesh.h"
#include <stddef.h>

typedef struct mc_report {
    int closed;          /* every directed edge has exactly one opposite */
    int edge_manifold;   /* no directed edge appears twice */
    int vertex_manifold; /* the triangles around every vertex form one fan */
    int no_degenerate;   /* no triangle repeats a vertex */
    int all_referenced;  /* every vertex is used by a triangle */
    int normals_ok;      /* unit normals (if any) */
    size_t normals_away; /* normals more than 90 degrees from their faces' */
    size_t components;   /* connected components (through shared vertices) */
    double volume;       /* signed volume: positive when oriented outward */
    double area;
    char problem[256];   /* first problem found, for messages */
} mc_report;

/* Analyses mesh; returns 1 if closed, manifold, oriented (volume > 0),
 * non-degenerate, fully referenced and with unit normals (if present).
 * How many normals lean away from their faces is left to the caller. */
int mc_check(const jm_mesh *mesh, mc_report *out);

/* Connected components whose signed volume is negative: closed shells
 * facing inward, i.e. cavities inside the solid. *out_components (may be
 * NULL) gets the number of components. (size_t)-1 if out of memory. */
size_t mc_cavities(const jm_mesh *mesh, size_t *out_components);

/* A mesh's shells (connected components) and how they nest, for air
 * pockets: a shell inside another (a cavity, or anything in one) is "inner". */
typedef struct mc_shells {
    size_t components;
    size_t inner;          /* shells enclosed by another shell (ray parity) */
    size_t negative;       /* shells of negative signed volume */
    double inner_area;     /* total area of the inner shells */
    double inner_volume;   /* their signed volumes summed */
    double volume;         /* signed volume of the whole mesh */
    size_t corners;        /* triangle corners (3 per triangle) */
    size_t corners_away;   /* corners whose vertex normal makes more than 90
                              degrees with the triangle's normal */
} mc_shells;

/* One shell of a mesh. */
typedef struct mc_shell {
    double volume, area;
    double lo[3], hi[3]; /* its box */
    int inner;
} mc_shell;

/* Fills *out for mesh (normals may be NULL: corners_away stays 0). A shell
 * is inner when a ray from one of its vertices crosses another shell an odd
 * number of times (only shells whose box holds its box are tried). With
 * list, *list gets the shells (malloc'd, out->components of them, in the
 * order of their first triangles; free it). 0 if out of memory. */
int mc_shell_check(const jm_mesh *mesh, mc_shells *out, mc_shell **list);

/* How many of the n points xyz lie inside shell number `shell` (in
 * mc_shell_check's order) by ray parity: air pockets hold particle centres,
 * real bubbles none. (size_t)-1 if out of memory. */
size_t mc_points_in_shell(const jm_mesh *mesh, size_t shell, const float *xyz, size_t n);

/* Deterministic pseudo-random numbers for tests. */
unsigned mc_rand(unsigned *state);
float mc_randf(unsigned *state); /* [0, 1) */
#endif
