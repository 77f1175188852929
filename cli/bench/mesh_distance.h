/* mesh_distance.h - distances from points to a triangle mesh through a uniform grid of its triangles (flicker figure, mesh comparisons). */
#ifndef JETMESH_CLI_BENCH_MESH_DISTANCE_H
#define JETMESH_CLI_BENCH_MESH_DISTANCE_H

#include <stddef.h>
#include <stdint.h>

typedef struct md_grid md_grid;

/** Buckets the nt triangles idx (3 per triangle, into pos: 3 floats per
 *  vertex) into cubic cells of edge `cell` (world units; 0 picks twice the
 *  mean edge length). NULL when out of memory or nt is 0. The mesh must
 *  outlive the grid. */
md_grid *md_build(const float *pos, const uint32_t *idx, size_t nt, double cell);

/** The distance from p to the nearest triangle; `limit` when none lies
 *  within it (the search stops there). */
double md_distance(const md_grid *g, const double p[3], double limit);

void md_free(md_grid *g);

/** The distance from p to the triangle a, b, c (each 3 doubles). */
double md_point_triangle(const double p[3], const double a[3], const double b[3], const double c[3]);

#endif
