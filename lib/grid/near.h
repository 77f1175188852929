/* near.h - the grid build's shared pieces: a particle's cell, the cells around a cell and the particles in them. */
#ifndef JETMESH_NEAR_H
#define JETMESH_NEAR_H
#include "grid/grid.h"
#include <math.h>
#include <stdatomic.h>
#include <string.h>

#define GP(g, i) (&(g)->pos[3 * (size_t)(i)])

/* A particle's coordinates in the library's unit (units.h): times s, an
 * exact power of two. */
static inline void load_units(float p[3], const char *src, float s)
{
    memcpy(p, src, 3 * sizeof(float));
    p[0] *= s;
    p[1] *= s;
    p[2] *= s;
}

/* The neighbour data's passes over the cells (density.c, links.c). */
typedef struct {
    jm_grid *g;
    const jm_config *c;
    int range;        /* cells to scan each side for the isolation test */
    float iso2;       /* squared isolation radius */
    uint32_t *counts; /* metasphere: links per particle */
    float **soa;      /* per worker: neighbours of a cell as x[], y[], z[] */
    size_t *soa_cap;  /* per worker: floats per coordinate array */
    atomic_int failed; /* set by any worker */
    jm_mem *mem;      /* the context's accounting */
} jm_nb_job;

/* The particle ranges of the (up to 27) non-empty cells around cell ci. */
static inline int jm_near_ranges(const jm_grid *g, size_t ci, uint32_t r[27][2])
{
    const int32_t *cc = &g->cell_coord[3 * ci];
    int k = 0;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                uint32_t nc = jm_grid_cell(g, (int64_t)cc[0] + dx, (int64_t)cc[1] + dy, (int64_t)cc[2] + dz);
                if (nc == UINT32_MAX) continue;
                r[k][0] = g->cell_start[nc];
                r[k][1] = g->cell_start[nc + 1];
                k++;
            }
    return k;
}

/* Visits the particles of the cells within `range` of cell ci. */
#define FOR_NEAR_CELLS(g, ci, range, ...)                                              \
    do {                                                                                \
        const int32_t *cc_ = &(g)->cell_coord[3 * (size_t)(ci)];                        \
        for (int dz_ = -(range); dz_ <= (range); dz_++)                                 \
            for (int dy_ = -(range); dy_ <= (range); dy_++)                             \
                for (int dx_ = -(range); dx_ <= (range); dx_++) {                       \
                    uint32_t nc_ = jm_grid_cell((g), (int64_t)cc_[0] + dx_,             \
                                                (int64_t)cc_[1] + dy_, (int64_t)cc_[2] + dz_); \
                    if (nc_ == UINT32_MAX) continue;                                    \
                    for (uint32_t j = (g)->cell_start[nc_]; j < (g)->cell_start[nc_ + 1]; j++) { \
                        __VA_ARGS__                                                            \
                    }                                                                   \
                }                                                                       \
    } while (0)

/* Is particle i (in cell ci) without any other particle closer than sqrt(iso2)? */
static inline int jm_lonely(const jm_grid *g, uint32_t ci, uint32_t i, int range, float iso2)
{
    const float *p = GP(g, i);
    FOR_NEAR_CELLS(g, ci, range, {
        if (j == i) continue;
        const float *q = GP(g, j);
        float dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
        if (dx * dx + dy * dy + dz * dz < iso2) return 0;
    });
    return 1;
}

/* The dense index's entry of the cell holding p (in the library's unit;
 * within the particles' box, which the index covers: floorf is monotone
 * and the box bounds p). */
static inline uint32_t *dense_slot(const jm_grid *g, const float p[3])
{
    const size_t d0 = (size_t)((int64_t)floorf(p[0] * g->inv_cell) - g->dense_lo[0]);
    const size_t d1 = (size_t)((int64_t)floorf(p[1] * g->inv_cell) - g->dense_lo[1]);
    const size_t d2 = (size_t)((int64_t)floorf(p[2] * g->inv_cell) - g->dense_lo[2]);
    return &g->dense[(d2 * (size_t)g->dense_n[1] + d1) * (size_t)g->dense_n[0] + d0];
}

#endif
