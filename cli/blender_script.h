/* blender_script.h - `jetmesh --blender-script`: where the Blender importer of sequences is. */
#ifndef JETMESH_CLI_BLENDER_SCRIPT_H
#define JETMESH_CLI_BLENDER_SCRIPT_H

/** Prints the path of jetmesh_blender.py (installed in PREFIX/share/jetmesh,
 *  or share/jetmesh of the source tree beside build/) and how to run it;
 *  returns the exit status (3 when it cannot be found). */
int blender_script_print(void);

#endif
