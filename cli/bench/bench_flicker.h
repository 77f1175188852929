/* bench_flicker.h - the flicker figure of `jetmesh bench --flicker K`: how far the meshes of a translated input differ from translated copies. */
#ifndef JETMESH_CLI_BENCH_FLICKER_H
#define JETMESH_CLI_BENCH_FLICKER_H

#include "bench_internal.h"

/** Meshes the input of c with ctx K times (o->flicker), frame k moved by
 *  k / K of a cube along (1, 0.618, 0.382) (each axis a different
 *  fraction), moves each mesh back and measures the distance of its
 *  vertices from frame 0's surface: c->flicker_p99 and c->flicker_max, in
 *  r. A mesher that follows the particles gives translated copies (0); the
 *  figure is the shimmer a sequence shows beyond the particles' motion.
 *  0, or -1 with c->err set. */
int bench_flicker(const bench_opts *o, const bench_input *in, jm_context *ctx, bench_case *c);

#endif
