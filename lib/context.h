/* context.h - the context: parameters, threads, workers' scratch, the mesh's output arrays, kept across frames. */
#ifndef JETMESH_CONTEXT_H
#define JETMESH_CONTEXT_H
#include "frame.h"

/* The sphere template (isolated particles) given back. */
void jm_context_drop_template(jm_context *ctx);
/* The output arrays grown to hold nv vertices and ni indices: 0 if out of
 * memory (the arrays stay as they were). */
int jm_context_reserve(jm_context *ctx, size_t nv, size_t ni);
/* After a frame: the output arrays shrunk to the mesh where that moves pages. */
void jm_context_trim(jm_context *ctx);
/* Before a frame of n particles: the last mesh's big arrays given back where
 * the frame releases its grid. */
void jm_context_drop_mesh(jm_context *ctx, size_t n);
/* One scratch per thread, for the configured block size. */
jm_status jm_context_scratch(jm_context *ctx);
#endif
