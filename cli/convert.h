/* convert.h - the `jetmesh convert` command: particle frames in, one mesh file per frame out. */
#ifndef JETMESH_CLI_CONVERT_H
#define JETMESH_CLI_CONVERT_H

/* Exit statuses of jetmesh (see EXIT STATUS in jetmesh(1)). */
#define EXIT_ALL_OK 0     /* every frame converted (or skipped by --resume) */
#define EXIT_SOME_FAILED 1 /* at least one frame failed */
#define EXIT_USAGE 2      /* bad option, missing -r, refusing to overwrite an input... */
#define EXIT_RESOURCE 3   /* out of memory, over --max-memory, internal error */

/** Runs `jetmesh convert` (argv[0] = "convert"); returns the exit status. */
int cmd_convert(int argc, char **argv);

#endif
