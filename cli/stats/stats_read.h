/* stats_read.h - reads a --stats report (CSV or JSON) back into per-frame records. */
#ifndef JETMESH_CLI_STATS_READ_H
#define JETMESH_CLI_STATS_READ_H

#include <stddef.h>

#include "stats.h"

/** What a report's summary says of its run. */
typedef struct stats_read_summary {
    double wall_seconds;   /**< 0 when absent */
    char field[16];        /**< "" when absent */
    char method[8];
    char field_choice[8];
} stats_read_summary;

/**
 * Appends the frames of the report at path to log and fills *sum from its
 * summary. The format is told by the
 * content: JSON starts with '{', else CSV as stats_write() writes it
 * (columns found by their header names, unknown ones ignored; "index" and
 * "status" required; "# summary" lines read for wall_seconds, field, method, field_choice).
 * 0, or -1 with a message naming the file and line.
 */
int stats_read(const char *path, stats_log *log, stats_read_summary *sum, char *err, size_t errlen);

#endif
