/* bench.c - PLACEHOLDER for `jetmesh bench` until the benchmark engineer replaces this file. */
#include "bench.h"

#include <stdio.h>

/* PLACEHOLDER: the real benchmark (scenes jet, block N, spray N, inputs;
 * --json, --repeat, --min-time, --threads, --field, --method) replaces it. */
int cmd_bench(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "jetmesh bench: not yet implemented\n");
    return 2;
}
