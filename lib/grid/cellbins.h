/* cellbins.h - points binned into cubic cells: a counting sort by cell, the cells found by their coordinates. */
#ifndef JETMESH_CELLBINS_H
#define JETMESH_CELLBINS_H
#include "core/internal.h"

typedef struct jm_cellbins {
    jm_hashmap map;    /* relative cell key -> cell (when dense is NULL) */
    uint32_t *dense;   /* cell of each relative coordinate, x fastest (UINT32_MAX: empty) */
    size_t ndense;
    uint32_t *start;   /* ncells + 1 offsets into items */
    uint32_t *items;   /* the points by cell, in index order within a cell */
    int32_t *coord;    /* 3 per cell: its coordinates relative to lo */
    size_t n, ncells;
    int64_t lo[3], span[3]; /* the cells' coordinates: lo to lo + span */
    float inv;         /* 1 / the cells' edge */
} jm_cellbins;

/* Bins the n points pos[3 i .. 3 i + 2] (finite; n < 2^32 - 1) into cells
 * of edge `cell`, numbered in order of first appearance: JM_OK,
 * JM_E_OUT_OF_MEMORY, or JM_E_TOO_LARGE for a spread over 2^21 cells. b is
 * freed by jm_cellbins_free whatever the result. */
jm_status jm_cellbins_build(jm_cellbins *b, jm_mem *mem, const float *pos, size_t n, float cell);
void jm_cellbins_free(jm_cellbins *b, jm_mem *mem);

/* The cell coordinate of x (floor(x / edge), as the binning computed it). */
static inline int64_t jm_cellbins_coord(const jm_cellbins *b, float x)
{
    return (int64_t)floorf(x * b->inv);
}

/* The cell at coordinates relative to lo (any, in range or not), or UINT32_MAX. */
static inline uint32_t jm_cellbins_find(const jm_cellbins *b, int64_t x, int64_t y, int64_t z)
{
    if (x < 0 || y < 0 || z < 0 || x > b->span[0] || y > b->span[1] || z > b->span[2]) return UINT32_MAX;
    if (b->dense)
        return b->dense[((size_t)z * (size_t)(b->span[1] + 1) + (size_t)y) * (size_t)(b->span[0] + 1) + (size_t)x];
    return jm_hashmap_get(&b->map, jm_key3(x, y, z));
}
#endif
