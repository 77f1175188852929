/* bench_run.h - running `jetmesh bench` cases: loading an input, timing one case, progress on stderr. */
#ifndef JETMESH_CLI_BENCH_RUN_H
#define JETMESH_CLI_BENCH_RUN_H

#include "bench_internal.h"

/** Generates the scene or reads the file of in: in->loaded 1, or -1 with
 *  in->err set. */
void bench_load_input(const bench_opts *o, bench_input *in);

/** Frees what bench_load_input loaded. */
void bench_free_input(bench_input *in);

/** Meshes in (loaded) with the parameters of c on one context: o->warmup
 *  untimed runs, then timed runs until o->repeat and o->min_time are
 *  reached or o->max_repeat is, each mesh also written into wdir when
 *  o has --write. Fills c: ok, or !ok with c->err. */
void bench_run_case(const bench_opts *o, const bench_input *in, bench_case *c, const char *wdir);

/** Removes every file in dir (the written mesh and a .gltf's .bin). */
void bench_empty_dir(const char *dir);

/** Replaces the progress line on stderr by the printf-style message, only
 *  on a terminal and without -q; fmt NULL clears it. */
void bench_progress(const bench_opts *o, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

#endif
