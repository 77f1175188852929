/* stats_merge.c - `jetmesh stats merge`: one report and one chart from the --stats files of a run's shards. */
#include "stats_merge.h"

#include <getopt.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../../lib/jetmesh.h"
#include "../convert.h"
#include "../options.h"
#include "../platform.h"
#include "../sequence.h"
#include "stats.h"
#include "stats_read.h"

void stats_merge_help(FILE *f)
{
    fputs("Usage: jetmesh stats merge STATS... -o OUT.csv|OUT.json [--svg OUT.svg]\n"
          "Merges the --stats reports (CSV or JSON) of the shards of one run (convert\n"
          "--shard I/N) into one report, rows in frame order, each frame once, and the\n"
          "summary recomputed over all of them.\n"
          "\n"
          "A frame found in several files keeps one row: an ok row over a skipped one\n"
          "(a --resume run found the output) over a failed one; between rows of the same\n"
          "status, the file named later wins. A frame converted (ok) in two files is an\n"
          "error: the shards overlap, or a run was repeated without --resume.\n"
          "wall_seconds is the longest file's (the shards' run when they ran at once);\n"
          "the summary adds shards and shards_wall_seconds, the sum of the files'; the\n"
          "field, method and field_choice are kept when every file has the same ones\n"
          "(a warning otherwise).\n"
          "\n"
          "Options:\n"
          "  -o, --output FILE           the merged report: .csv or .json\n"
          "      --svg FILE.svg          the merged chart (as --stats-svg draws it)\n"
          "  -q, --quiet                 no summary line\n"
          "      --help                  this help\n"
          "\n"
          "Exit status: 0 merged, 1 a file unreadable or a frame converted twice, 2 usage\n"
          "error (an output that is an input too), 3 out of memory. See SHARDS in jetmesh(1).\n",
          f);
}

/* A row read, with the file it came from. */
typedef struct row {
    stats_record *rec;
    size_t file;
} row;

static int rank(stats_status s)
{
    return s == STATS_OK ? 2 : s == STATS_SKIPPED ? 1 : 0;
}

static int cmp_row(const void *a, const void *b)
{
    const row *x = a, *y = b;
    if (x->rec->index != y->rec->index)
        return x->rec->index < y->rec->index ? -1 : 1;
    int c = seq_natural_cmp(x->rec->input, y->rec->input);
    if (c == 0)
        c = strcmp(x->rec->input, y->rec->input);
    if (c)
        return c;
    /* within a frame: file order, then the order in the file (stable) */
    if (x->file != y->file)
        return x->file < y->file ? -1 : 1;
    return x->rec < y->rec ? -1 : x->rec > y->rec;
}

static int same_frame(const row *a, const row *b)
{
    return a->rec->index == b->rec->index && strcmp(a->rec->input, b->rec->input) == 0;
}

/* Copies rec into a new record of out. 0 or -1 (out of memory). */
static int copy_record(stats_log *out, const stats_record *rec)
{
    stats_record *d = stats_add(out, rec->index, rec->input, rec->output);
    if (!d)
        return -1;
    char *in = d->input, *o = d->output;
    *d = *rec;
    d->input = in;
    d->output = o;
    d->error = NULL;
    if (rec->error) {
        d->error = strdup(rec->error);
        if (!d->error)
            return -1;
    }
    return 0;
}

/* Refuses an output that is one of the inputs (the same file, however it
 * is spelled: device and inode), as convert does (issue 30: `stats merge
 * a.csv b.csv -o a.csv` replaced its own input), and -o and --svg naming
 * one file. */
static int refuse_inputs(const char *cmd, char *const *files, size_t nfiles, const char *out, const char *svg)
{
    const char *outs[2] = {out, svg};
    struct stat so, si;
    if (svg && (strcmp(out, svg) == 0 || (stat(out, &so) == 0 && stat(svg, &si) == 0 && so.st_dev == si.st_dev &&
                                          so.st_ino == si.st_ino)))
        return options_usage_error(cmd, "-o and --svg would both write %s", svg);
    for (int k = 0; k < 2; k++) {
        if (!outs[k] || stat(outs[k], &so) != 0)
            continue;
        for (size_t f = 0; f < nfiles; f++)
            if (stat(files[f], &si) == 0 && si.st_dev == so.st_dev && si.st_ino == so.st_ino)
                return options_usage_error(cmd, "refusing to overwrite the input file %s (with %s)", files[f],
                                           outs[k]);
    }
    return EXIT_ALL_OK;
}

static const struct option merge_long[] = {
    {"output", required_argument, 0, 'o'},
    {"svg", required_argument, 0, 's'},
    {"quiet", no_argument, 0, 'q'},
    {"help", no_argument, 0, 'h'},
    {0, 0, 0, 0},
};

/* The command line of `stats merge`. */
typedef struct merge_args {
    const char *out, *svg;
    int quiet;
    char **files;
    size_t nfiles;
} merge_args;

/* Reads argv into a: OPTIONS_RUN, OPTIONS_DONE (--help printed) or a usage
 * error (printed). */
static int merge_parse(int argc, char **argv, merge_args *a)
{
    const char *cmd = "stats merge";
    int c;
    memset(a, 0, sizeof *a);
    optind = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:q", merge_long, NULL)) != -1) {
        switch (c) {
        case 'o': a->out = optarg; break;
        case 's': a->svg = optarg; break;
        case 'q': a->quiet = 1; break;
        case 'h': stats_merge_help(stdout); return OPTIONS_DONE;
        case ':': return options_usage_error(cmd, "option '%s' needs a value", argv[optind - 1]);
        default: return options_usage_error(cmd, "unknown option '%s'", argv[optind - 1]);
        }
    }
    a->nfiles = (size_t)(argc - optind);
    a->files = argv + optind;
    if (a->nfiles == 0)
        return options_usage_error(cmd, "no statistics files to merge");
    if (!a->out)
        return options_usage_error(cmd, "no output: give -o FILE.csv or FILE.json");
    if (!stats_path_ok(a->out))
        return options_usage_error(cmd, "-o FILE must end in .csv or .json, not '%s'", a->out);
    int clash = refuse_inputs(cmd, a->files, a->nfiles, a->out, a->svg);
    return clash == EXIT_ALL_OK ? OPTIONS_RUN : clash;
}

/* What the files' summaries say together. */
typedef struct run_summary {
    stats_read_summary first; /* the first file's */
    int same_field;           /* every file names the same field and method */
    double wall_max, wall_sum;
} run_summary;

/* Reads every file into in, first[f] its first record. EXIT_ALL_OK or
 * EXIT_SOME_FAILED (printed). */
static int merge_read(const merge_args *a, stats_log *in, size_t *first, run_summary *run)
{
    const char *cmd = "stats merge";
    char err[1400];
    run->same_field = 1;
    for (size_t f = 0; f < a->nfiles; f++) {
        stats_read_summary rs;
        first[f] = in->count;
        if (stats_read(a->files[f], in, &rs, err, sizeof err) != 0) {
            fprintf(stderr, "jetmesh %s: %s\n", cmd, err);
            return EXIT_SOME_FAILED;
        }
        double wall = rs.wall_seconds;
        run->wall_sum += wall;
        if (wall > run->wall_max)
            run->wall_max = wall;
        /* the field of the run: kept when every file says the same */
        const stats_read_summary *r0 = &run->first;
        if (f == 0)
            run->first = rs;
        else if (strcmp(rs.field, r0->field) != 0 || strcmp(rs.method, r0->method) != 0) {
            if (run->same_field && !a->quiet)
                fprintf(stderr, "jetmesh %s: warning: %s was meshed with field %s, method %s, but %s with %s, %s\n",
                        cmd, a->files[0], r0->field[0] ? r0->field : "?", r0->method[0] ? r0->method : "?",
                        a->files[f], rs.field[0] ? rs.field : "?", rs.method[0] ? rs.method : "?");
            run->same_field = 0;
        }
    }
    first[a->nfiles] = in->count;
    return EXIT_ALL_OK;
}

/* One row per frame of in into merged (see stats_merge_help). EXIT_ALL_OK,
 * EXIT_SOME_FAILED (a frame converted twice, printed) or EXIT_RESOURCE. */
static int merge_rows(const merge_args *a, const stats_log *in, const size_t *first, stats_log *merged)
{
    row *rows = malloc((in->count ? in->count : 1) * sizeof *rows);
    if (!rows)
        return EXIT_RESOURCE;
    for (size_t f = 0, i = 0; f < a->nfiles; f++)
        for (; i < first[f + 1]; i++)
            rows[i] = (row){&in->items[i], f};
    qsort(rows, in->count, sizeof *rows, cmp_row);
    int rc = EXIT_ALL_OK;
    for (size_t i = 0; i < in->count && rc == EXIT_ALL_OK;) {
        size_t j = i + 1, best = i;
        for (; j < in->count && same_frame(&rows[i], &rows[j]); j++) {
            if (rows[j].rec->status == STATS_OK && rows[best].rec->status == STATS_OK) {
                fprintf(stderr,
                        "jetmesh stats merge: frame %ld (%s) was converted in both %s and %s: the shards overlap, "
                        "or a run was repeated without --resume; merge only one of them\n",
                        rows[j].rec->index, rows[j].rec->input, a->files[rows[best].file], a->files[rows[j].file]);
                rc = EXIT_SOME_FAILED;
                break;
            }
            if (rank(rows[j].rec->status) >= rank(rows[best].rec->status))
                best = j; /* the later file wins a tie */
        }
        if (rc == EXIT_ALL_OK && copy_record(merged, rows[best].rec) != 0)
            rc = EXIT_RESOURCE;
        i = j;
    }
    free(rows);
    return rc;
}

/* Writes the merged report, its chart and the summary line. */
static int merge_write(const merge_args *a, const stats_log *merged, const run_summary *run)
{
    const char *cmd = "stats merge";
    char err[1400];
    stats_summary sum;
    stats_summarize(merged, run->wall_max * 1000.0, &sum);
    sum.shards = a->nfiles;
    sum.shards_wall_seconds = run->wall_sum;
    sum.neighbours = -1;
    if (a->nfiles && run->same_field && run->first.field[0] && run->first.method[0]) {
        sum.field = run->first.field;
        sum.method = run->first.method;
        sum.field_choice = run->first.field_choice[0] ? run->first.field_choice : "given";
    }
    platform_make_dirs(a->out, 1); /* a failure shows when writing */
    if (stats_write(a->out, merged, &sum, err, sizeof err) != 0) {
        fprintf(stderr, "jetmesh %s: cannot write the report: %s\n", cmd, err);
        return EXIT_SOME_FAILED;
    }
    if (a->svg) {
        platform_make_dirs(a->svg, 1);
        if (stats_write_svg(a->svg, merged, &sum, err, sizeof err) != 0) {
            fprintf(stderr, "jetmesh %s: cannot write the chart: %s\n", cmd, err);
            return EXIT_SOME_FAILED;
        }
    }
    if (!a->quiet)
        printf("merged %zu file%s: %zu frames (%zu ok, %zu failed, %zu skipped) -> %s%s%s\n", a->nfiles,
               a->nfiles == 1 ? "" : "s", sum.frames, sum.ok, sum.failed, sum.skipped, a->out, a->svg ? ", " : "",
               a->svg ? a->svg : "");
    return EXIT_ALL_OK;
}

static int merge(int argc, char **argv)
{
    merge_args a;
    int rc = merge_parse(argc, argv, &a);
    if (rc != OPTIONS_RUN)
        return rc == OPTIONS_DONE ? EXIT_ALL_OK : rc;
    stats_log in, merged;
    memset(&in, 0, sizeof in);
    memset(&merged, 0, sizeof merged);
    run_summary run;
    memset(&run, 0, sizeof run);
    size_t *first = calloc(a.nfiles + 1, sizeof *first); /* each file's first record */
    rc = first ? merge_read(&a, &in, first, &run) : EXIT_RESOURCE;
    if (rc == EXIT_ALL_OK)
        rc = merge_rows(&a, &in, first, &merged);
    if (rc == EXIT_ALL_OK)
        rc = merge_write(&a, &merged, &run);
    if (rc == EXIT_RESOURCE)
        fprintf(stderr, "jetmesh stats merge: out of memory\n");
    free(first);
    stats_free(&in);
    stats_free(&merged);
    return rc;
}

int cmd_stats(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "help") == 0) {
        stats_merge_help(argc < 2 ? stderr : stdout);
        return argc < 2 ? EXIT_USAGE : EXIT_ALL_OK;
    }
    if (strcmp(argv[1], "merge") == 0)
        return merge(argc - 1, argv + 1);
    fprintf(stderr, "jetmesh stats: unknown subcommand '%s': give merge\n"
                    "Try 'jetmesh stats --help' for more information.\n",
            argv[1]);
    return EXIT_USAGE;
}
