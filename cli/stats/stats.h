/* stats.h - per-frame statistics records of a conversion, their summary, and the CSV/JSON/SVG reports. */
#ifndef JETMESH_CLI_STATS_H
#define JETMESH_CLI_STATS_H

#include <stddef.h>

typedef enum stats_status {
    STATS_OK = 0,
    STATS_FAILED,
    STATS_SKIPPED /* --resume: the output already existed */
} stats_status;

/** One frame. Times in milliseconds; sizes in bytes. */
typedef struct stats_record {
    long index;
    char *input;
    char *output;
    size_t particles, dropped, vertices, triangles, bytes;
    double ms_read, ms_field, ms_extract, ms_attributes, ms_write, ms_total;
    double ms_post; /* smoothing, simplification, small pieces, clip box (jm_stats.ms_post);
                       read + field + extract + attributes + post + write = total */
    size_t peak_rss_bytes, lib_peak_bytes;
    stats_status status;
    char *error; /* NULL unless failed */
} stats_record;

typedef struct stats_log {
    stats_record *items;
    size_t count, cap;
} stats_log;

/** The end-of-run summary. Percentiles over the frames converted (ok):
 *  median of an even count is the mean of the middle two; p95 is the
 *  nearest rank, the ceil(0.95 n)-th smallest. */
typedef struct stats_summary {
    size_t frames, ok, failed, skipped;
    double ms_min, ms_median, ms_p95, ms_max; /* of ms_total; 0 when ok == 0 */
    double wall_seconds;      /* the whole run */
    double frames_per_second; /* ok / wall_seconds */
    const char *field;        /* "metasphere" or "sph"; NULL: not written */
    const char *method;       /* "mt" or "mc" */
    const char *field_choice; /* "auto" (chosen from the first frame) or "given" */
    double neighbours;        /* the measure of the choice; < 0: not measured */
    /* `jetmesh stats merge` only (written when shards > 0): the files
     * merged and the sum of their wall_seconds (wall_seconds is then the
     * longest file's) */
    size_t shards;
    double shards_wall_seconds;
} stats_summary;

/** Appends a zeroed record for a frame (strings copied); NULL if out of memory. */
stats_record *stats_add(stats_log *log, long index, const char *input, const char *output);

/** Marks a record failed with a copy of msg. */
void stats_fail(stats_record *r, const char *msg);

void stats_free(stats_log *log);

void stats_summarize(const stats_log *log, double wall_ms, stats_summary *out);

/** "ok", "failed", "skipped". */
const char *stats_status_name(stats_status s);

/** Writes the report named by path's extension: ".csv" or ".json"
 *  (atomically). 0, or -1 with a message naming the file. */
int stats_write(const char *path, const stats_log *log, const stats_summary *sum,
                char *err, size_t errlen);

/** 1 if path ends in .csv or .json (what stats_write accepts). */
int stats_path_ok(const char *path);

/** Writes a stacked bar chart of each frame's time by stage (read, field,
 *  extract, attributes, post, write) as standalone SVG (atomically). 0 or -1. */
int stats_write_svg(const char *path, const stats_log *log, const stats_summary *sum,
                    char *err, size_t errlen);

#endif
