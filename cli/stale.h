/* stale.h - removes the hidden temporaries that killed runs left beside this run's outputs. */
#ifndef JETMESH_CLI_STALE_H
#define JETMESH_CLI_STALE_H

#include <stddef.h>

/** Removes every "DIR/.NAME.jetmesh-tmp-PID" (the atomic writer's temporary)
 *  whose DIR/NAME is one of the n outputs, or the .bin beside a .gltf
 *  output, and whose PID is no live process: what a SIGKILL or a crash left
 *  behind. Reads each output directory once. Returns how many it removed. */
size_t stale_remove(char *const *outputs, size_t n);

#endif
