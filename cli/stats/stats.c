/* stats.c - collects per-frame records, summarises them and writes them as CSV or JSON. */
#include "stats.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../formats/atomic_file.h"
#include "../../lib/jetmesh.h"

static char *dup_or_null(const char *s)
{
    if (!s)
        return NULL;
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

stats_record *stats_add(stats_log *log, long index, const char *input, const char *output)
{
    if (log->count == log->cap) {
        size_t cap = log->cap ? log->cap * 2 : 64;
        stats_record *n = realloc(log->items, cap * sizeof *n);
        if (!n)
            return NULL;
        log->items = n;
        log->cap = cap;
    }
    stats_record *r = &log->items[log->count];
    memset(r, 0, sizeof *r);
    r->index = index;
    r->input = dup_or_null(input ? input : "");
    r->output = dup_or_null(output ? output : "");
    if (!r->input || !r->output) {
        free(r->input);
        free(r->output);
        return NULL;
    }
    log->count++;
    return r;
}

void stats_fail(stats_record *r, const char *msg)
{
    r->status = STATS_FAILED;
    free(r->error);
    r->error = dup_or_null(msg ? msg : "failed");
}

void stats_free(stats_log *log)
{
    if (!log)
        return;
    for (size_t i = 0; i < log->count; i++) {
        free(log->items[i].input);
        free(log->items[i].output);
        free(log->items[i].error);
    }
    free(log->items);
    memset(log, 0, sizeof *log);
}

const char *stats_status_name(stats_status s)
{
    switch (s) {
    case STATS_OK: return "ok";
    case STATS_FAILED: return "failed";
    case STATS_SKIPPED: return "skipped";
    }
    return "?";
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void stats_summarize(const stats_log *log, double wall_ms, stats_summary *out)
{
    memset(out, 0, sizeof *out);
    out->frames = log->count;
    out->wall_seconds = wall_ms / 1000.0;
    double *t = malloc((log->count ? log->count : 1) * sizeof *t);
    size_t n = 0;
    for (size_t i = 0; i < log->count; i++) {
        const stats_record *r = &log->items[i];
        if (r->status == STATS_OK) {
            out->ok++;
            if (t)
                t[n++] = r->ms_total;
        } else if (r->status == STATS_FAILED)
            out->failed++;
        else
            out->skipped++;
    }
    if (t && n > 0) {
        qsort(t, n, sizeof *t, cmp_double);
        out->ms_min = t[0];
        out->ms_max = t[n - 1];
        out->ms_median = n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
        size_t rank = (size_t)ceil(0.95 * (double)n);
        if (rank < 1)
            rank = 1;
        out->ms_p95 = t[rank - 1];
    }
    free(t);
    if (out->wall_seconds > 0)
        out->frames_per_second = (double)out->ok / out->wall_seconds;
}

int stats_path_ok(const char *path)
{
    size_t n = strlen(path);
    return (n > 4 && strcmp(path + n - 4, ".csv") == 0) ||
           (n > 5 && strcmp(path + n - 5, ".json") == 0);
}

/* A CSV field, quoted (RFC 4180) when it holds a comma, quote, CR, LF or
 * leading/trailing space. */
static void csv_string(FILE *f, const char *s)
{
    if (!s)
        s = "";
    size_t n = strlen(s);
    int quote = n > 0 && (s[0] == ' ' || s[n - 1] == ' ');
    for (const char *p = s; *p && !quote; p++)
        quote = *p == ',' || *p == '"' || *p == '\n' || *p == '\r';
    if (!quote) {
        fputs(s, f);
        return;
    }
    fputc('"', f);
    for (const char *p = s; *p; p++) {
        if (*p == '"')
            fputc('"', f);
        fputc(*p, f);
    }
    fputc('"', f);
}

/* Length of the valid UTF-8 sequence at s, or 0. */
static size_t utf8_len(const unsigned char *s)
{
    unsigned c = s[0];
    size_t n;
    unsigned min;
    if (c < 0x80)
        return 1;
    if (c >= 0xc2 && c <= 0xdf)
        n = 2, min = 0x80;
    else if (c >= 0xe0 && c <= 0xef)
        n = 3, min = 0x800;
    else if (c >= 0xf0 && c <= 0xf4)
        n = 4, min = 0x10000;
    else
        return 0;
    unsigned v = c & (0x3f >> (n - 1));
    for (size_t i = 1; i < n; i++) {
        if ((s[i] & 0xc0) != 0x80)
            return 0;
        v = (v << 6) | (s[i] & 0x3f);
    }
    if (v < min || v > 0x10ffff || (v >= 0xd800 && v <= 0xdfff))
        return 0;
    return n;
}

/* A JSON string; bytes that are not UTF-8 become U+FFFD. */
static void json_string(FILE *f, const char *s)
{
    if (!s) {
        fputs("null", f);
        return;
    }
    fputc('"', f);
    const unsigned char *p = (const unsigned char *)s;
    while (*p) {
        unsigned c = *p;
        if (c == '"' || c == '\\') {
            fputc('\\', f);
            fputc((int)c, f);
            p++;
        } else if (c < 0x20) {
            switch (c) {
            case '\n': fputs("\\n", f); break;
            case '\r': fputs("\\r", f); break;
            case '\t': fputs("\\t", f); break;
            case '\b': fputs("\\b", f); break;
            case '\f': fputs("\\f", f); break;
            default: fprintf(f, "\\u%04x", c); break;
            }
            p++;
        } else if (c < 0x80) {
            fputc((int)c, f);
            p++;
        } else {
            size_t n = utf8_len(p);
            if (n == 0) {
                fputs("\\ufffd", f);
                p++;
            } else {
                fwrite(p, 1, n, f);
                p += n;
            }
        }
    }
    fputc('"', f);
}

static void write_csv(FILE *f, const stats_log *log, const stats_summary *s)
{
    fputs("index,input,output,particles,dropped,vertices,triangles,bytes,ms_read,ms_field,"
          "ms_extract,ms_attributes,ms_post,ms_write,ms_total,peak_rss_bytes,lib_peak_bytes,status,error\n",
          f);
    for (size_t i = 0; i < log->count; i++) {
        const stats_record *r = &log->items[i];
        fprintf(f, "%ld,", r->index);
        csv_string(f, r->input);
        fputc(',', f);
        csv_string(f, r->output);
        fprintf(f, ",%zu,%zu,%zu,%zu,%zu,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%zu,%zu,%s,", r->particles,
                r->dropped, r->vertices, r->triangles, r->bytes, r->ms_read, r->ms_field,
                r->ms_extract, r->ms_attributes, r->ms_post, r->ms_write, r->ms_total, r->peak_rss_bytes,
                r->lib_peak_bytes, stats_status_name(r->status));
        csv_string(f, r->error);
        fputc('\n', f);
    }
    fprintf(f, "# summary frames=%zu\n# summary ok=%zu\n# summary failed=%zu\n# summary skipped=%zu\n",
            s->frames, s->ok, s->failed, s->skipped);
    if (s->ok)
        fprintf(f,
                "# summary ms_total_min=%.3f\n# summary ms_total_median=%.3f\n"
                "# summary ms_total_p95=%.3f\n# summary ms_total_max=%.3f\n",
                s->ms_min, s->ms_median, s->ms_p95, s->ms_max);
    else /* no frame converted: no times */
        fputs("# summary ms_total_min=\n# summary ms_total_median=\n"
              "# summary ms_total_p95=\n# summary ms_total_max=\n",
              f);
    fprintf(f, "# summary wall_seconds=%.3f\n# summary frames_per_second=%.3f\n", s->wall_seconds,
            s->frames_per_second);
    if (s->field) {
        fprintf(f, "# summary field=%s\n# summary method=%s\n# summary field_choice=%s\n", s->field,
                s->method, s->field_choice);
        if (s->neighbours >= 0)
            fprintf(f, "# summary neighbours=%.2f\n", s->neighbours);
    }
    if (s->shards) /* stats merge */
        fprintf(f, "# summary shards=%zu\n# summary shards_wall_seconds=%.3f\n", s->shards,
                s->shards_wall_seconds);
}

static void write_json(FILE *f, const stats_log *log, const stats_summary *s)
{
    fprintf(f, "{\n  \"generator\": \"jetmesh %s\",\n  \"frames\": [", JM_VERSION_STRING);
    for (size_t i = 0; i < log->count; i++) {
        const stats_record *r = &log->items[i];
        fprintf(f, "%s\n    {\"index\": %ld, \"input\": ", i ? "," : "", r->index);
        json_string(f, r->input);
        fputs(", \"output\": ", f);
        json_string(f, r->output);
        fprintf(f,
                ", \"particles\": %zu, \"dropped\": %zu, \"vertices\": %zu, \"triangles\": %zu, "
                "\"bytes\": %zu, \"ms_read\": %.3f, \"ms_field\": %.3f, \"ms_extract\": %.3f, "
                "\"ms_attributes\": %.3f, \"ms_post\": %.3f, \"ms_write\": %.3f, \"ms_total\": %.3f, "
                "\"peak_rss_bytes\": %zu, \"lib_peak_bytes\": %zu, \"status\": \"%s\", \"error\": ",
                r->particles, r->dropped, r->vertices, r->triangles, r->bytes, r->ms_read,
                r->ms_field, r->ms_extract, r->ms_attributes, r->ms_post, r->ms_write, r->ms_total,
                r->peak_rss_bytes, r->lib_peak_bytes, stats_status_name(r->status));
        json_string(f, r->error);
        fputc('}', f);
    }
    fprintf(f, "%s],\n  \"summary\": {\"frames\": %zu, \"ok\": %zu, \"failed\": %zu, "
               "\"skipped\": %zu, ",
            log->count ? "\n  " : "", s->frames, s->ok, s->failed, s->skipped);
    if (s->ok)
        fprintf(f,
                "\"ms_total_min\": %.3f, \"ms_total_median\": %.3f, \"ms_total_p95\": %.3f, "
                "\"ms_total_max\": %.3f, ",
                s->ms_min, s->ms_median, s->ms_p95, s->ms_max);
    else
        fputs("\"ms_total_min\": null, \"ms_total_median\": null, \"ms_total_p95\": null, "
              "\"ms_total_max\": null, ",
              f);
    fprintf(f, "\"wall_seconds\": %.3f, \"frames_per_second\": %.3f", s->wall_seconds,
            s->frames_per_second);
    if (s->field) {
        fprintf(f, ", \"field\": \"%s\", \"method\": \"%s\", \"field_choice\": \"%s\"", s->field,
                s->method, s->field_choice);
        if (s->neighbours >= 0)
            fprintf(f, ", \"neighbours\": %.2f", s->neighbours);
    }
    if (s->shards) /* stats merge */
        fprintf(f, ", \"shards\": %zu, \"shards_wall_seconds\": %.3f", s->shards, s->shards_wall_seconds);
    fputs("}\n}\n", f);
}

int stats_write(const char *path, const stats_log *log, const stats_summary *sum,
                char *err, size_t errlen)
{
    size_t n = strlen(path);
    int json = n > 5 && strcmp(path + n - 5, ".json") == 0;
    if (!json && !(n > 4 && strcmp(path + n - 4, ".csv") == 0)) {
        snprintf(err, errlen, "%s: statistics files end in .csv or .json", path);
        return -1;
    }
    jmf_atomic_file af;
    if (jmf_atomic_open(&af, path, err, errlen) != JMF_OK)
        return -1;
    if (json)
        write_json(af.fp, log, sum);
    else
        write_csv(af.fp, log, sum);
    return jmf_atomic_commit(&af, err, errlen) == JMF_OK ? 0 : -1;
}
