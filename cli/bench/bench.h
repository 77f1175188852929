/* bench.h - the `jetmesh bench` command: timings of the library on synthetic scenes or input files. */
#ifndef JETMESH_CLI_BENCH_H
#define JETMESH_CLI_BENCH_H

/** Runs `jetmesh bench` (argv[0] = "bench"); returns the exit status. */
int cmd_bench(int argc, char **argv);

#endif
