/* bench_stats.h - timing samples of `jetmesh bench` and their summary (median, spread, nearest-rank percentiles). */
#ifndef JETMESH_CLI_BENCH_STATS_H
#define JETMESH_CLI_BENCH_STATS_H

#include <stddef.h>

/** A growing list of samples; zero-initialised is empty; free(v) when done. */
typedef struct bench_samples {
    double *v;
    size_t n, cap;
} bench_samples;

/** The summary of a list of samples (all 0 for none). */
typedef struct bench_summary {
    double median, min, max, mean, p10, p90, q1, q3;
} bench_summary;

/** Appends x; 0, or -1 out of memory (s unchanged). */
int bench_samples_push(bench_samples *s, double x);

/** Sorts s in place and summarises it: percentiles by nearest rank, the
 *  median of an even count the mean of the middle two. */
void bench_summarize(bench_samples *s, bench_summary *out);

#endif
