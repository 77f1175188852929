/* bench_table.c - prints the results of `jetmesh bench` as a table: a header, one row per case, notes under it. */
#include "bench_report.h"

#include <math.h>
#include <string.h>

#include "bench_options.h"
#include "../platform.h"

static const char *fmt_ms(double ms, char *buf, size_t len)
{
    if (!isfinite(ms))
        snprintf(buf, len, "-");
    else if (ms >= 1000)
        snprintf(buf, len, "%.0f", ms);
    else if (ms >= 100)
        snprintf(buf, len, "%.1f", ms);
    else if (ms >= 10)
        snprintf(buf, len, "%.2f", ms);
    else if (ms >= 1)
        snprintf(buf, len, "%.3f", ms);
    else
        snprintf(buf, len, "%.4f", ms);
    return buf;
}

static const char *fmt_rate(double v, char *buf, size_t len)
{
    if (!isfinite(v) || v <= 0)
        snprintf(buf, len, "-");
    else if (v >= 1e9)
        snprintf(buf, len, "%.2fG", v / 1e9);
    else if (v >= 1e6)
        snprintf(buf, len, "%.2fM", v / 1e6);
    else if (v >= 1e3)
        snprintf(buf, len, "%.1fk", v / 1e3);
    else
        snprintf(buf, len, "%.0f", v);
    return buf;
}

static const char *fmt_mib(size_t bytes, char *buf, size_t len)
{
    snprintf(buf, len, "%.1f", (double)bytes / (1024.0 * 1024.0));
    return buf;
}

static const char *fmt_ratio(double r, char *buf, size_t len)
{
    if (r > 0 && isfinite(r))
        snprintf(buf, len, "%.2fx", r);
    else
        snprintf(buf, len, "-");
    return buf;
}

void bench_table_header(const bench_opts *o, const bench_machine *m)
{
    char mem[32];
    printf("jetmesh %s bench  %s\n", jm_version(), m->date);
    printf("machine: %s%s%s%s, %d cores, %s, %s\n", m->cpu, *m->detail ? " (" : "", m->detail, *m->detail ? ")" : "", m->cores,
           platform_format_bytes(m->memory, mem, sizeof mem), m->os);
    printf("timing: after %ld warm-up run%s, at least %ld run%s and %.3g s per case; radius %g\n\n",
           o->warmup, o->warmup == 1 ? "" : "s", o->repeat, o->repeat == 1 ? "" : "s", o->min_time,
           o->radius);
    printf("%-22s %-4s %-2s %4s %3s %-3s %6s | %9s %9s %9s | %9s %9s %9s %9s", "case", "fld", "mt",
           "cube", "thr", "tpl", "runs", "total", "min", "p90", "prepare", "field", "extract", "attrs");
    if (o->write_format >= 0)
        printf(" %9s", "write");
    printf(" | %8s %8s | %9s %9s | %8s %8s | %6s %6s\n", "part/s", "tri/s", "verts", "tris", "lib MiB",
           "RSS MiB", "x1T", "xtpl");
}

void bench_table_row(const bench_opts *o, const bench_input *in, const bench_case *c)
{
    char name[23]; /* a long file name keeps its first 10 and last 11 characters */
    size_t len = strlen(in->name);
    if (len > 22)
        snprintf(name, sizeof name, "%.10s~%s", in->name, in->name + len - 11);
    else
        snprintf(name, sizeof name, "%s", in->name);
    printf("%-22s %-4s %-2s %4.2g %3d %-3s ", name, cli_field_column(c->field),
           cli_method_name(c->method), c->cube, c->threads, c->templates ? "on" : "off");
    if (!c->ok) {
        printf("FAILED: %s\n", c->err);
        fflush(stdout);
        return;
    }
    char a[32], b[32], d[32], e[32], f[32], g[32], h[32];
    printf("%6zu | %9s %9s %9s | %9s %9s %9s %9s", c->reps, fmt_ms(c->st[ST_TOTAL].median, a, sizeof a),
           fmt_ms(c->st[ST_TOTAL].min, b, sizeof b), fmt_ms(c->st[ST_TOTAL].p90, d, sizeof d),
           fmt_ms(c->st[ST_PREPARE].median, e, sizeof e), fmt_ms(c->st[ST_FIELD].median, f, sizeof f),
           fmt_ms(c->st[ST_EXTRACT].median, g, sizeof g), fmt_ms(c->st[ST_ATTR].median, h, sizeof h));
    if (o->write_format >= 0)
        printf(" %9s", fmt_ms(c->st[ST_WRITE].median, a, sizeof a));
    double sec = c->st[ST_TOTAL].median / 1e3;
    printf(" | %8s %8s | %9zu %9zu | %8s %8s | %6s %6s\n",
           fmt_rate(sec > 0 ? (double)c->last.particles / sec : 0, a, sizeof a),
           fmt_rate(sec > 0 ? (double)c->last.triangles / sec : 0, b, sizeof b), c->last.vertices,
           c->last.triangles, fmt_mib(c->lib_peak, d, sizeof d), fmt_mib(c->rss_peak, e, sizeof e),
           fmt_ratio(c->speedup_threads, f, sizeof f), fmt_ratio(c->speedup_templates, g, sizeof g));
    fflush(stdout);
}

void bench_table_footer(const bench_opts *o, const bench_case *cases, size_t ncases, int failed)
{
    printf("\ntimes in ms; total: median, min, p90 over the timed runs; stages: medians");
    if (o->write_format >= 0)
        printf(" (write: %s, not part of total)", o->write_ext);
    printf(".\n");
    int unreset = 0;
    for (size_t k = 0; k < ncases; k++)
        unreset |= cases[k].ok && !cases[k].rss_reset;
    if (unreset)
        printf("RSS peak: the kernel refused a reset, so it is the process's peak so far.\n");
    for (size_t k = 0; k < ncases; k++)
        if (cases[k].ok && cases[k].flicker_frames)
            printf("flicker, case %zu: %d frames moved 1/%d cube apart, moved back: vertices from the first "
                   "frame's surface p99 %.4f R, max %.4f R\n", k + 1, cases[k].flicker_frames,
                   cases[k].flicker_frames, cases[k].flicker_p99, cases[k].flicker_max);
    if (failed)
        printf("%d case%s failed.\n", failed, failed == 1 ? "" : "s");
}
