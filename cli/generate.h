/* generate.h - the `jetmesh generate` command: writes synthetic scenes as CSV or XYZ particle files. */
#ifndef JETMESH_CLI_GENERATE_H
#define JETMESH_CLI_GENERATE_H

/** Runs `jetmesh generate` (argv[0] = "generate"); returns the exit status. */
int cmd_generate(int argc, char **argv);

#endif
