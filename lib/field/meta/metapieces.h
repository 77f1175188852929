/* metapieces.h - every metasphere piece that can reach a block, handed to a visitor with the block's parts it reaches. */
#ifndef JETMESH_METAPIECES_H
#define JETMESH_METAPIECES_H
#include "field/meta/metaprobe.h"

/* What a splat over a block's pieces does with each (jm_probe_pieces). */
typedef struct jm_piece_visitor {
    float rb; /* how far a ball reaches, and a neck from its axis */
    float rn; /* a neck's reach from its axis when half its length is at most pi/2 r */
    void (*ball)(void *ctx, const int lo[3], const int hi[3], const float *q);
    void (*link)(void *ctx, const int lo[3], const int hi[3], const float *q, const float *u, float D, float rr2);
    void *ctx;
} jm_piece_visitor;

/* Every piece of the particles in hood that can reach the block (B cubes a
 * side, nodes x, y, z), in the hood's order: each non-isolated particle's
 * ball, with the parts [lo, hi] its box (rb about it) reaches, and each of
 * its links once, both half-necks at once from the lower end (or from this
 * end when the other lies outside the block's influence), with the parts
 * its box reaches (rr, from rn or rb, about the segment) and rr^2. */
void jm_probe_pieces(const jm_grid *g, const jm_config *c, const jm_hood *hood, int B, int pc, const float *x, const float *y,
                     const float *z, const jm_piece_visitor *v);
#endif
