/* bench_options.h - the options of `jetmesh bench`: parsing with defaults filled in, --help, and value names. */
#ifndef JETMESH_CLI_BENCH_OPTIONS_H
#define JETMESH_CLI_BENCH_OPTIONS_H

#include "bench_internal.h"

/** Parses argv (argv[0] = "bench") into o, every list filled with its
 *  default and threads sorted ascending. OPTIONS_RUN, OPTIONS_DONE (--help
 *  printed) or a usage error (message printed), as options.h. */
int bench_parse_options(int argc, char **argv, bench_opts *o);

#endif
