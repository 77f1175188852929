/* pvd.h - the ParaView collection (.pvd: time -> file) written beside a VTK or PLY sequence. */
#ifndef JETMESH_CLI_PVD_H
#define JETMESH_CLI_PVD_H

#include <stddef.h>

/** "dir/fluid_{}.vtk" -> "dir/fluid.pvd" (the template's placeholder and the
 *  separator before it dropped; "dir/" -> "dir/sequence.pvd"). malloc'd. */
char *pvd_path_for(const char *output);

/** Writes path atomically: one DataSet per file, files[i] at times[i], named
 *  relative to the .pvd's directory when they are under it. 0 on success;
 *  else -1 with a message in err. */
int pvd_write(const char *path, char *const *files, const double *times, size_t n, int no_sync, char *err,
              size_t errlen);

#endif
