/* meshmetrics.h - figures of a mesh against a reference: smoothness, distance, outline pull-in, pieces' volume and roundness. */
#ifndef JETMESH_TESTS_MESHMETRICS_H
#define JETMESH_TESTS_MESHMETRICS_H
#include <stddef.h>
#include <stdint.h>

typedef struct mm_mesh {
    float *pos;    /* 3 per vertex */
    float *nrm;    /* 3 per vertex, or NULL */
    uint32_t *idx; /* 3 per triangle */
    size_t nv, nt;
    int owned;     /* 1: mm_mesh_free frees the arrays */
} mm_mesh;

/* Reads a Wavefront OBJ (v, vn, f with a, a/b, a//c, a/b/c; polygons as
 * fans; a vertex's normal is the last vn a face gives it). 0 on success,
 * else -1 and a message in err. */
int mm_read_obj(const char *path, mm_mesh *m, char *err, size_t errlen);
void mm_mesh_free(mm_mesh *m);

/* One connected piece (through shared vertices). */
typedef struct mm_piece {
    double volume, area;  /* signed volume: negative for an inner shell */
    double c[3];          /* area-weighted centroid of the surface */
    double ext[3];        /* principal extents, descending: the square roots of
                           * the eigenvalues of the surface's second moments */
    double roundness;     /* ext[2] / ext[0]: 1 for a sphere */
    size_t nv;
} mm_piece;

/* The pieces of m, ordered by their smallest vertex; *lab (may be NULL)
 * gets each vertex's piece. Returns their number; *out is malloc'ed. */
size_t mm_pieces(const mm_mesh *m, mm_piece **out, uint32_t **lab);

double mm_volume(const mm_mesh *m);
double mm_area(const mm_mesh *m);

/* Mean and 95th percentile (degrees) of the angle between the normals of
 * the two triangles of each edge that has exactly two (degenerate
 * triangles' edges left out). */
void mm_dihedral(const mm_mesh *m, double *mean, double *p95);

/* Distances from the vertices of m to the surface of ref (point to
 * triangle): the 50th and 99th percentiles and the maximum. */
void mm_distances(const mm_mesh *m, const mm_mesh *ref, double *p50, double *p99, double *max);

/* Outline pull-in. Both meshes are projected along each axis onto a raster
 * of pixel px (world units); S0 is ref's silhouette, S1 m's. A pixel of S0
 * outside S1 has pulled in by its distance to S1. pull is the largest such
 * distance over the three projections; pull99 the 99th percentile over the
 * pixels on S0's outline (0 where S1 still covers them); push the largest
 * distance of a pixel of S1 from S0 (outward growth). World units. */
void mm_outline(const mm_mesh *ref, const mm_mesh *m, double px, double *pull, double *pull99, double *push);

/* The largest inward move of a side of the bounding box (world units). */
double mm_bbox_pull(const mm_mesh *ref, const mm_mesh *m);

/* Normals against the faces: the 95th percentile (degrees) of the angle
 * between each vertex normal and its fan's area-weighted normal, and the
 * fraction over 90 degrees. 0 and 0 without normals. */
void mm_normals(const mm_mesh *m, double *p95, double *away);

/* A ball's figures, over the vertices of piece `which` (lab from
 * mm_pieces; lab NULL: all): the standard deviation of the distance from
 * their centroid, and the 95th percentile (degrees) of the angle of the
 * normals (the file's, else the fans') from the radial direction. */
void mm_sphere(const mm_mesh *m, const uint32_t *lab, uint32_t which, double *sd, double *p95);

/* Pieces of m matched to those of ref (outer shells only, volume > 0): each
 * of ref's to the nearest of m's centroid within its largest extent (at least
 * min_dist). */
typedef struct mm_match {
    size_t ref_pieces, pieces; /* outer shells of each */
    size_t lost;               /* ref's without a match */
    size_t extra;              /* m's matched by none */
    double min_volume;         /* least volume ratio m / ref over the matches */
    double min_round;          /* least roundness ratio m / ref */
    size_t under85;            /* matches keeping under 85 % of their volume */
    double worst_c[3];         /* ref centroid of the least volume ratio */
    double round_c[3];         /* ref centroid of the least roundness ratio */
    double round_ref, round_m; /* their roundness */
} mm_match;
void mm_match_pieces(const mm_piece *ref, size_t nref, const mm_piece *p, size_t np, double min_dist, mm_match *out);
#endif
