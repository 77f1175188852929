/* farm.h - runs frame jobs on worker threads ahead of their turn, for a caller that takes the results in order. */
#ifndef JETMESH_CLI_FARM_H
#define JETMESH_CLI_FARM_H

#include <stddef.h>

/** Does job i on worker w (0 <= w < workers). Returns 0, or nonzero to stop
 *  the farm: no job starts after this one (the caller then does the rest). */
typedef int (*farm_fn)(void *user, int w, size_t i);

typedef struct farm farm;

/** Starts `workers` threads that take jobs 0..n-1 in order, never more than
 *  `window` jobs ahead of the last one the caller took (farm_taken). NULL if
 *  no thread could start (then do the jobs yourself). */
farm *farm_start(size_t n, int workers, size_t window, farm_fn fn, void *user);

/** Waits until job i is done (1), or until it is certain no worker will do
 *  it (0: the farm stopped before it started). Take jobs in order. */
int farm_wait(farm *f, size_t i);

/** The caller has taken jobs 0..i: workers may run up to i + window. */
void farm_taken(farm *f, size_t i);

/** Lets no further job start, waits for the running ones and frees the
 *  farm. Accepts NULL. */
void farm_stop(farm *f);

#endif
