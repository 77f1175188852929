/* field.h - what every field reads: the cells around a block (its hood), node spans, the metasphere's pieces evaluated at a point. */
#ifndef JETMESH_FIELD_H
#define JETMESH_FIELD_H
#include "grid/grid.h"

/* The cells of the particle grid around one block, as a small dense array. */
#include <string.h>

typedef struct jm_hood {
    int64_t c0[3];      /* absolute coordinates of the first cell */
    int n[3];           /* cells per axis */
    uint32_t *range;    /* 2 per cell: first, end (sorted particle indices) */
    size_t cap;         /* entries allocated (cells) */
    size_t particles;   /* particles in range (isolated ones too) */
    size_t live;        /* sph: the particles not isolated, and */
    double wsum;        /* their weight sum (the grid's cell_live, cell_wsum) */
    jm_mem *mem;        /* counts range (NULL: uncounted) */
} jm_hood;

/* floor and ceil without libm calls (x within int range) */
static inline int ifloor(float x)
{
    int t = (int)x;
    return t - (x < (float)t);
}
static inline int iceil(float x)
{
    int t = (int)x;
    return t + (x > (float)t);
}

/* index range [*a, *b) of the n nodes t[i] = t[0] + i h (as rounded) within
 * [lo, hi]; the estimate from the spacing is corrected against t[] itself */
static inline void node_span(const float *t, int n, float inv_h, float lo, float hi, int *a, int *b)
{
    float flo = (lo - t[0]) * inv_h, fhi = (hi - t[0]) * inv_h;
    if (flo > (float)n) flo = (float)n;
    if (fhi < -1.0f) fhi = -1.0f;
    int i = iceil(flo < 0.0f ? 0.0f : flo);
    int j = ifloor(fhi > (float)n ? (float)n : fhi) + 1;
    if (i > n) i = n;
    if (j > n) j = n;
    while (i < n && t[i] < lo) i++;
    while (i > 0 && t[i - 1] >= lo) i--;
    while (j > 0 && t[j - 1] > hi) j--;
    while (j < n && t[j] <= hi) j++;
    *a = i;
    *b = j > i ? j : i;
}

/* The first cell coordinate, on one axis, of the hood of a box whose low
 * end on that axis is lo (jm_hood_build: the cells within the influence
 * radius, and one more). */
static inline int64_t jm_hood_cell_lo(const jm_grid *g, const jm_config *c, float lo)
{
    return (int64_t)floorf((lo - c->influence) * g->inv_cell) - 1;
}

/* The hood's cells (their index range [*c0, *c1] along axis a, from 0)
 * that can hold a particle within [lo - R, hi + R]: a particle at x lies in
 * the grid's cell floor(x / cell) (grid.c), so a 64th of R more on each
 * side is far more than rounding can move a boundary (R = 0: the cells
 * that meet [lo, hi]). */
static inline void jm_hood_cell_span(const jm_grid *g, const jm_hood *hood, int a, float lo, float hi, float R,
                                     int *c0, int *c1)
{
    const float m = R + R * (1.0f / 64.0f);
    const int64_t l = (int64_t)floorf((lo - m) * g->inv_cell) - hood->c0[a];
    const int64_t h = (int64_t)floorf((hi + m) * g->inv_cell) - hood->c0[a];
    *c0 = l < 0 ? 0 : (int)l;
    *c1 = h >= hood->n[a] ? hood->n[a] - 1 : (int)h;
}

/* Sizes hood for the box [lo, hi] (its first cell and extent on each axis,
 * room for its cells' ranges); 0 when out of memory. */
int jm_hood_size(jm_hood *hood, const jm_grid *g, const jm_config *c, const float lo[3], const float hi[3]);
/* Fills hood with the cells within the influence radius of the box [lo, hi]. */
int jm_hood_build(jm_hood *hood, const jm_grid *g, const jm_config *c, const float lo[3], const float hi[3]);

/* Row length of the padded sampling buffer (n^2 rows): a multiple of 8 with
 * room for a run of 8 starting at any of the n nodes. */
#define JM_PAD(n) (((n) + 14) & ~7)
#define JM_PAD_MAX 64


/* Metasphere primitive id: a sorted particle index (its ball) or n + e for
 * the half-neck of link e. Returns its value at p; out (may be NULL) gets its
 * outward unit normal, out_glen (may be NULL) its gradient's length (per
 * world unit). */
float jm_prim_eval(const jm_grid *g, const jm_config *c, uint32_t id, const float p[3], float out[3], float *out_glen);

/* sin(t) for t in [0, pi/2], |error| < 1e-6, no libm call */
static inline float jm_sin_quarter(float t)
{
    float t2 = t * t;
    return t * (1.0f + t2 * (-1.0f / 6 + t2 * (1.0f / 120 + t2 * (-1.0f / 5040 + t2 * (1.0f / 362880)))));
}

/* How far a splat reaches from a neck's axis, D its link's length: up to
 * pi/2 r along its axis a half-neck beats its own ball only closer than r to
 * the axis (field.c), so a short link uses short_reach (about r), a long one
 * reach. The node splat, the probe and the crease normals share the rule. */
static inline float jm_neck_reach(float r, float D, float short_reach, float reach)
{
    return 0.5f * D <= 1.5707f * r ? short_reach : reach;
}
/* cos(t) for t in [0, pi/2], |error| < 2e-7, no libm call */
static inline float jm_cos_quarter(float t)
{
    float t2 = t * t;
    return 1.0f + t2 * (-0.5f + t2 * (1.0f / 24 + t2 * (-1.0f / 720 + t2 * (1.0f / 40320 - t2 * (1.0f / 3628800)))));
}
#endif
