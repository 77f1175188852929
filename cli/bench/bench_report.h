/* bench_report.h - the two reports of `jetmesh bench`: the table on stdout (bench_table.c) and the JSON document (bench_json.c). */
#ifndef JETMESH_CLI_BENCH_REPORT_H
#define JETMESH_CLI_BENCH_REPORT_H

#include <stdio.h>

#include "bench_internal.h"
#include "bench_machine.h"

/** The table's title lines and column header, on stdout. */
void bench_table_header(const bench_opts *o, const bench_machine *m);

/** One row of the table on stdout, flushed: case c of input in, or FAILED. */
void bench_table_row(const bench_opts *o, const bench_input *in, const bench_case *c);

/** The notes under the table on stdout: units, an RSS peak that could not be
 *  reset, how many cases failed. */
void bench_table_footer(const bench_opts *o, const bench_case *cases, size_t ncases, int failed);

/** The whole JSON document of a run (machine, settings, every case) into f. */
void bench_json_doc(FILE *f, const bench_opts *o, const bench_machine *m, const bench_case *cases,
                    size_t ncases, int failed);

#endif
