/* stats_merge.h - `jetmesh stats merge`: one report and one chart from the --stats files of a run's shards. */
#ifndef JETMESH_CLI_STATS_MERGE_H
#define JETMESH_CLI_STATS_MERGE_H

#include <stdio.h>

/** Runs `jetmesh stats ...` (argv[0] = "stats"); returns the exit status. */
int cmd_stats(int argc, char **argv);

void stats_merge_help(FILE *f);

#endif
