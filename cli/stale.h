/* stale.h - removes the hidden temporaries that killed runs left beside this run's outputs. */
#ifndef JETMESH_CLI_STALE_H
#define JETMESH_CLI_STALE_H

#include <stddef.h>

/** Removes every "DIR/.NAME.jetmesh-tmp-HOST-PID-RAND" (the atomic
 *  writer's temporary) whose DIR/NAME is one of the n outputs, or the .bin
 *  beside a .gltf output (or NAME the STEM of a long name,
 *  jmf_atomic_temp_stem), written on this host by a PID that is no live
 *  process: what a SIGKILL or a crash left behind. Another host's
 *  temporaries (a shared file system) are kept. Reads each output directory once. Returns how many it removed. */
size_t stale_remove(char *const *outputs, size_t n);

#endif
