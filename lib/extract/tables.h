/* tables.h - marching cubes / marching tetrahedra case tables, generated at first use. */
#ifndef JETMESH_TABLES_H
#define JETMESH_TABLES_H
#include <stdint.h>

/* The 7 lattice edge directions from a node: x, y, z, xy, xz, yz, xyz. */
extern const int jm_dir[7][3];

/* The 19 edges of a cube (12 axis edges, 6 face diagonals from each face's
 * lowest corner, 1 body diagonal): start corner (bit 0 x, 1 y, 2 z) and
 * direction index into jm_dir. */
extern const uint8_t jm_cube_edge_corner[19];
extern const uint8_t jm_cube_edge_dir[19];

typedef struct jm_case_table {
    uint8_t ntri[256];
    uint8_t edges[256][36]; /* 3 cube-edge indices per triangle, CCW from outside */
    /* the same triangles over the configuration's distinct edges, in order
     * of first use: nedge of them in uedge, the corners as indices into it */
    uint8_t nedge[256];
    uint8_t uedge[256][19];
    uint8_t local[256][36];
} jm_case_table;

/* Tables for cube configurations (bit c set = corner c inside). */
const jm_case_table *jm_table_mc(void);
const jm_case_table *jm_table_mt(void);
/* 1 if every marching cubes polygon was fanned without in-face diagonals. */
int jm_tables_consistent(void);

#endif
