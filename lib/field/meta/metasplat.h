/* metasplat.h - the metasphere sampled on a block's nodes: every ball and half-neck splatted onto the node rows it reaches, rows no piece reaches left unwritten. */
#ifndef JETMESH_METASPLAT_H
#define JETMESH_METASPLAT_H
#include "field/field.h"

/* What jm_meta_sample left in a node row (rows[k n + j], j and k < n). */
enum {
    JM_ROW_UNSET = 0, /* no piece reaches it, nor any row next to it: f and win
                         not written (every node is below the floor) */
    JM_ROW_FLOOR = 1, /* no piece reaches it, a row next to it is reached:
                         every node at the floor, win UINT32_MAX */
    JM_ROW_SPLAT = 2  /* a piece reached it: f and win hold the maximum */
};

/* Samples the metasphere on nodes x[i], y[j], z[k] (i, j, k < n, n >= 9):
 * node (i, j, k) at f[(k n + j) n + i] and the piece that gave it in win
 * (UINT32_MAX where clamped at the floor; jm_prim_eval names the pieces),
 * but only in the rows a piece reaches and the rows next to them (rows:
 * the state of each). A cube touches only its own four rows, so every cube
 * with a node in a reached row reads written values; the others are
 * outside. The AVX2 path runs 8 nodes a step, the others 4: the same
 * bits. */
void jm_meta_sample(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float *x, const float *y,
                    const float *z, int n, float *f, uint32_t *win, uint8_t *rows);
#endif
