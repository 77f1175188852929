/* stats_read.c - reads a --stats report (CSV or JSON) back into per-frame records, with the CLI's text readers (cli/text/). */
#include "stats_read.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../text/csv_read.h"
#include "../text/json_read.h"

#define READ_MAX ((size_t)1 << 30) /* a report of 1 GiB is millions of frames */

static int parse_size(const char *t, size_t *out)
{
    char *e;
    errno = 0;
    if (!*t || *t == '-')
        return -1;
    unsigned long long v = strtoull(t, &e, 10);
    if (*e || errno)
        return -1;
    *out = (size_t)v;
    return 0;
}

static int parse_ms(const char *t, double *out)
{
    char *e;
    errno = 0;
    double v = strtod(t, &e);
    if (!*t || *e || errno || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

static int set_string(char **dst, const char *text)
{
    free(*dst);
    *dst = NULL;
    if (!text)
        return 0;
    *dst = strdup(text);
    return *dst ? 0 : -1;
}

/* Sets the member named name from text (NULL: a JSON null). 0, 1 for a
 * name not known (ignored), -1 for a bad value. */
static int set_field(stats_record *rec, const char *name, const char *text)
{
    static const struct {
        const char *name;
        size_t off;
    } sizes[] = {
        {"particles", offsetof(stats_record, particles)},
        {"dropped", offsetof(stats_record, dropped)},
        {"vertices", offsetof(stats_record, vertices)},
        {"triangles", offsetof(stats_record, triangles)},
        {"bytes", offsetof(stats_record, bytes)},
        {"peak_rss_bytes", offsetof(stats_record, peak_rss_bytes)},
        {"lib_peak_bytes", offsetof(stats_record, lib_peak_bytes)},
    }, times[] = {
        {"ms_read", offsetof(stats_record, ms_read)},
        {"ms_field", offsetof(stats_record, ms_field)},
        {"ms_extract", offsetof(stats_record, ms_extract)},
        {"ms_attributes", offsetof(stats_record, ms_attributes)},
        {"ms_post", offsetof(stats_record, ms_post)}, /* 0 when absent: files before issue 32 */
        {"ms_write", offsetof(stats_record, ms_write)},
        {"ms_total", offsetof(stats_record, ms_total)},
    };
    if (strcmp(name, "index") == 0) {
        char *e;
        errno = 0;
        long v = text ? strtol(text, &e, 10) : 0;
        if (!text || !*text || *e || errno)
            return -1;
        rec->index = v;
        return 0;
    }
    if (strcmp(name, "status") == 0) {
        if (text && strcmp(text, "ok") == 0)
            rec->status = STATS_OK;
        else if (text && strcmp(text, "failed") == 0)
            rec->status = STATS_FAILED;
        else if (text && strcmp(text, "skipped") == 0)
            rec->status = STATS_SKIPPED;
        else
            return -1;
        return 0;
    }
    if (strcmp(name, "input") == 0)
        return set_string(&rec->input, text ? text : "");
    if (strcmp(name, "output") == 0)
        return set_string(&rec->output, text ? text : "");
    if (strcmp(name, "error") == 0)
        return set_string(&rec->error, text && *text ? text : NULL);
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        if (strcmp(name, sizes[i].name) == 0)
            return text && parse_size(text, (size_t *)((char *)rec + sizes[i].off)) == 0 ? 0 : -1;
    for (size_t i = 0; i < sizeof times / sizeof times[0]; i++)
        if (strcmp(name, times[i].name) == 0)
            return text && parse_ms(text, (double *)((char *)rec + times[i].off)) == 0 ? 0 : -1;
    return 1;
}

/* A new zeroed record at the end of log, its strings "" until set. */
static stats_record *new_record(stats_log *log)
{
    return stats_add(log, 0, "", "");
}

/* ---- CSV ---------------------------------------------------------------- */

/* a summary value into its place in sum; unknown keys are ignored */
static void summary_value(stats_read_summary *sum, const char *key, size_t klen, const char *v, size_t vlen)
{
    static const struct {
        const char *key;
        size_t off, cap;
    } strs[] = {
        {"field", offsetof(stats_read_summary, field), sizeof ((stats_read_summary *)0)->field},
        {"method", offsetof(stats_read_summary, method), sizeof ((stats_read_summary *)0)->method},
        {"field_choice", offsetof(stats_read_summary, field_choice), sizeof ((stats_read_summary *)0)->field_choice},
    };
    if (klen == 12 && strncmp(key, "wall_seconds", 12) == 0) {
        char b[64];
        size_t n = vlen < sizeof b - 1 ? vlen : sizeof b - 1;
        memcpy(b, v, n);
        b[n] = '\0';
        double w = strtod(b, NULL);
        /* only a usable time reaches the merged report (no inf, no NaN) */
        sum->wall_seconds = isfinite(w) && w >= 0 ? w : 0;
        return;
    }
    for (size_t i = 0; i < sizeof strs / sizeof *strs; i++)
        if (strlen(strs[i].key) == klen && strncmp(key, strs[i].key, klen) == 0 && vlen < strs[i].cap) {
            char *d = (char *)sum + strs[i].off;
            memcpy(d, v, vlen);
            d[vlen] = '\0';
        }
}

static int read_csv(text_cursor *r, stats_log *log, stats_read_summary *sum)
{
    char **head = NULL, **row = NULL;
    size_t nh = 0, nr = 0;
    int rc = 0;
    while (rc == 0 && r->p < r->end) {
        if (*r->p == '#') { /* "# summary key=value" */
            const char *eol = memchr(r->p, '\n', (size_t)(r->end - r->p));
            const char *stop = eol ? eol : r->end;
            static const char key[] = "# summary ";
            size_t len = (size_t)(stop - r->p);
            if (len > 0 && r->p[len - 1] == '\r')
                len--;
            if (len > sizeof key - 1 && strncmp(r->p, key, sizeof key - 1) == 0) {
                const char *k = r->p + sizeof key - 1, *eq = memchr(k, '=', len - (sizeof key - 1));
                if (eq)
                    summary_value(sum, k, (size_t)(eq - k), eq + 1, (size_t)(r->p + len - eq - 1));
            }
            r->p = eol ? eol + 1 : r->end;
            continue;
        }
        if (*r->p == '\n' || (*r->p == '\r' && r->p + 1 < r->end && r->p[1] == '\n')) {
            r->p += *r->p == '\n' ? 1 : 2;
            continue;
        }
        if (!head) {
            const char *hstart = r->p;
            if (csv_read_line(r, &head, &nh) != 0) {
                rc = -1;
                break;
            }
            int has_index = 0, has_status = 0;
            for (size_t i = 0; i < nh; i++) {
                has_index |= strcmp(head[i], "index") == 0;
                has_status |= strcmp(head[i], "status") == 0;
            }
            if (!has_index || !has_status)
                rc = (r->p = hstart, text_fail(r, "not a jetmesh statistics CSV (no index and status columns in its header)"));
            continue;
        }
        const char *start = r->p;
        if (csv_read_line(r, &row, &nr) != 0) {
            rc = -1;
            break;
        }
        if (nr != nh) {
            r->p = start;
            rc = text_fail(r, "a row with another number of fields than the header");
        } else {
            stats_record *rec = new_record(log);
            if (!rec)
                rc = text_fail(r, "out of memory");
            for (size_t i = 0; rc == 0 && i < nr; i++) {
                int s = set_field(rec, head[i], row[i]);
                if (s < 0) {
                    char msg[300];
                    snprintf(msg, sizeof msg, "bad %s '%.200s'", head[i], row[i]);
                    r->p = start;
                    rc = text_fail(r, msg);
                }
            }
        }
        csv_free_fields(row, nr);
        row = NULL;
    }
    if (rc == 0 && !head)
        rc = text_fail(r, "empty: no header line");
    csv_free_fields(head, nh);
    return rc;
}

/* ---- JSON --------------------------------------------------------------- */

static int frame_member(text_cursor *r, const char *key, void *user)
{
    stats_record *rec = user;
    char *t;
    int cont;
    if (json_scalar(r, &t, &cont) != 0)
        return -1;
    if (cont)
        return json_skip_container(r);
    int s = set_field(rec, key, t);
    free(t);
    if (s < 0) {
        char msg[200];
        snprintf(msg, sizeof msg, "bad \"%.100s\" of a frame", key);
        return text_fail(r, msg);
    }
    return 0;
}

static int summary_member(text_cursor *r, const char *key, void *user)
{
    char *t;
    int cont;
    if (json_scalar(r, &t, &cont) != 0)
        return -1;
    if (cont)
        return json_skip_container(r);
    if (t)
        summary_value(user, key, strlen(key), t, strlen(t));
    free(t);
    return 0;
}

/* One element of "frames": a record with its index and status. */
static int frame(text_cursor *r, void *user)
{
    stats_record *rec = new_record(user);
    if (!rec)
        return text_fail(r, "out of memory");
    rec->index = -1;
    rec->status = (stats_status)-1;
    if (json_members(r, frame_member, rec) != 0)
        return -1;
    if (rec->index < 0 || (int)rec->status < 0)
        return text_fail(r, "a frame without index or status");
    return 0;
}

typedef struct top {
    stats_log *log;
    stats_read_summary *sum;
    int frames_seen;
} top;

static int top_member(text_cursor *r, const char *key, void *user)
{
    top *t = user;
    if (strcmp(key, "summary") == 0)
        return json_members(r, summary_member, t->sum);
    if (strcmp(key, "frames") != 0)
        return json_skip(r);
    t->frames_seen = 1;
    return json_elements(r, frame, t->log);
}

static int read_json(text_cursor *r, stats_log *log, stats_read_summary *sum)
{
    top t = {log, sum, 0};
    if (json_members(r, top_member, &t) != 0)
        return -1;
    if (!t.frames_seen)
        return text_fail(r, "not a jetmesh statistics JSON (no \"frames\")");
    return 0;
}

int stats_read(const char *path, stats_log *log, stats_read_summary *sum, char *err, size_t errlen)
{
    size_t len = 0;
    char *text = text_slurp(path, READ_MAX, &len, err, errlen);
    if (!text)
        return -1;
    text_cursor r = {path, text, text + len, text, err, errlen};
    memset(sum, 0, sizeof *sum);
    json_ws(&r);
    size_t before = log->count;
    int rc = r.p < r.end && *r.p == '{' ? read_json(&r, log, sum) : (r.p = text, read_csv(&r, log, sum));
    if (rc != 0) { /* drop this file's records */
        stats_log tail = {log->items + before, log->count - before, 0};
        for (size_t i = 0; i < tail.count; i++) {
            free(tail.items[i].input);
            free(tail.items[i].output);
            free(tail.items[i].error);
        }
        log->count = before;
    }
    free(text);
    return rc;
}
