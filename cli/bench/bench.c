/* bench.c - `jetmesh bench`: times jm_mesh_particles on synthetic scenes or input files, per stage, as a table or JSON. */
#include "bench.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench_internal.h"
#include "bench_machine.h"
#include "bench_options.h"
#include "bench_report.h"
#include "bench_run.h"
#include "../options.h"
#include "../signals.h"

static int is_spray(const bench_input *in)
{
    return in->kind == IN_SPRAY;
}

static int same_but(const bench_case *a, const bench_case *b)
{
    return a->input == b->input && a->field == b->field && a->method == b->method && a->cube == b->cube;
}

/* Fills cases with every case, in the order they run; returns how many. */
static size_t list_cases(const bench_opts *o, bench_case *cases)
{
    size_t ncases = 0;
    for (size_t i = 0; i < o->ninputs; i++) {
        int tpl[2], ntpl = 0;
        tpl_mode mode = o->templates;
        if (mode == TPL_AUTO)
            mode = is_spray(&o->inputs[i]) ? TPL_BOTH : TPL_ON;
        if (mode == TPL_BOTH) { /* the general path first: the baseline */
            tpl[ntpl++] = 0;
            tpl[ntpl++] = 1;
        } else
            tpl[ntpl++] = mode == TPL_ON;
        for (size_t fi = 0; fi < o->nfields; fi++)
            for (size_t mi = 0; mi < o->nmethods; mi++)
                for (size_t ci = 0; ci < o->ncubes; ci++)
                    for (int ti = 0; ti < ntpl; ti++)
                        for (size_t ji = 0; ji < o->nthreads; ji++) {
                            bench_case *c = &cases[ncases++];
                            c->input = i;
                            c->field = o->fields[fi];
                            c->method = o->methods[mi];
                            c->cube = o->cubes[ci];
                            c->templates = tpl[ti];
                            c->threads = o->threads[ji];
                        }
    }
    return ncases;
}

/* The speed-ups of case k (ok) over the earlier cases it differs from only
 * in threads (vs. 1 thread) or templates (on vs. off). */
static void set_speedups(bench_case *cases, size_t k)
{
    bench_case *c = &cases[k];
    for (size_t b = 0; b < k; b++) {
        const bench_case *base = &cases[b];
        if (!base->ok || !same_but(base, c))
            continue;
        if (c->threads > 1 && base->threads == 1 && base->templates == c->templates)
            c->speedup_threads = base->st[ST_TOTAL].median / c->st[ST_TOTAL].median;
        if (c->templates && !base->templates && base->threads == c->threads)
            c->speedup_templates = base->st[ST_TOTAL].median / c->st[ST_TOTAL].median;
    }
}

int cmd_bench(int argc, char **argv)
{
    bench_opts *o = calloc(1, sizeof *o);
    if (!o) {
        fprintf(stderr, "jetmesh bench: out of memory\n");
        return 1;
    }
    int rc = bench_parse_options(argc, argv, o);
    if (rc != OPTIONS_RUN) {
        free(o);
        return rc == OPTIONS_DONE ? 0 : 2;
    }

    /* every case, in the order they run: at most 2 template settings an input */
    size_t cap = 0;
    for (size_t i = 0; i < o->ninputs; i++)
        cap += o->nfields * o->nmethods * o->ncubes * 2 * o->nthreads;
    bench_case *cases = calloc(cap ? cap : 1, sizeof *cases);
    if (!cases) {
        fprintf(stderr, "jetmesh bench: out of memory\n");
        free(o);
        return 1;
    }
    size_t ncases = list_cases(o, cases);

    bench_machine m;
    bench_machine_info(&m);
    char wdir[4096] = "";
    if (o->write_format >= 0) {
        const char *base = o->write_dir ? o->write_dir : getenv("TMPDIR");
        if (!base || !*base)
            base = "/tmp";
        snprintf(wdir, sizeof wdir, "%s/jetmesh-bench.XXXXXX", base);
        if (!mkdtemp(wdir)) {
            fprintf(stderr, "jetmesh bench: cannot create a directory in %s: %s\n", base, strerror(errno));
            free(cases);
            free(o);
            return 1;
        }
        signals_install_cleanup();
    }

    if (!o->json)
        bench_table_header(o, &m);
    int failed = 0;
    size_t loaded_for = (size_t)-1;
    for (size_t k = 0; k < ncases; k++) {
        bench_case *c = &cases[k];
        bench_input *in = &o->inputs[c->input];
        if (loaded_for != c->input) { /* one input in memory at a time */
            if (loaded_for != (size_t)-1)
                bench_free_input(&o->inputs[loaded_for]);
            bench_progress(o, "bench: loading %s", in->name);
            bench_load_input(o, in);
            bench_progress(o, NULL);
            if (in->loaded != 1)
                fprintf(stderr, "jetmesh bench: %s\n", in->err);
            loaded_for = c->input;
        }
        bench_run_case(o, in, c, wdir);
        if (!c->ok) {
            failed++;
            if (in->loaded == 1) /* a load failure was told once above */
                fprintf(stderr, "jetmesh bench: %s: %s\n", in->name, c->err);
        } else
            set_speedups(cases, k);
        if (!o->json)
            bench_table_row(o, in, c);
    }
    if (loaded_for != (size_t)-1)
        bench_free_input(&o->inputs[loaded_for]);
    if (wdir[0]) {
        bench_empty_dir(wdir);
        rmdir(wdir);
    }

    if (o->json)
        bench_json_doc(stdout, o, &m, cases, ncases, failed);
    else
        bench_table_footer(o, cases, ncases, failed);
    if (o->json_out) {
        FILE *f = fopen(o->json_out, "w");
        if (!f) {
            fprintf(stderr, "jetmesh bench: %s: %s\n", o->json_out, strerror(errno));
            failed++;
        } else {
            bench_json_doc(f, o, &m, cases, ncases, failed);
            if (fclose(f) != 0) {
                fprintf(stderr, "jetmesh bench: %s: write error\n", o->json_out);
                failed++;
            }
        }
    }
    fflush(stdout);
    free(cases);
    free(o);
    return failed ? 1 : 0;
}
