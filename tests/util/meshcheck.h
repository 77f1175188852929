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

/* Deterministic pseudo-random numbers for tests. */
unsigned mc_rand(unsigned *state);
float mc_randf(unsigned *state); /* [0, 1) */
#endif
