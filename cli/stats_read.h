/* stats_read.h - reads a --stats report (CSV or JSON) back into per-frame records. */
#ifndef JETMESH_CLI_STATS_READ_H
#define JETMESH_CLI_STATS_READ_H

#include <stddef.h>

#include "stats.h"

/**
 * Appends the frames of the report at path to log and sets *wall_seconds
 * to its summary's wall_seconds (0 when absent). The format is told by the
 * content: JSON starts with '{', else CSV as stats_write() writes it
 * (columns found by their header names, unknown ones ignored; "index" and
 * "status" required; "# summary" lines read for wall_seconds).
 * 0, or -1 with a message naming the file and line.
 */
int stats_read(const char *path, stats_log *log, double *wall_seconds, char *err, size_t errlen);

#endif
