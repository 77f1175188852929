/* stats_read.c - reads a --stats report (CSV or JSON) back into per-frame records. */
#include "stats_read.h"

#include <stddef.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define READ_MAX ((size_t)1 << 30) /* a report of 1 GiB is millions of frames */

typedef struct reader {
    const char *path;
    const char *s, *end, *p;
    char *err;
    size_t errlen;
} reader;

static int line_of(const reader *r)
{
    int line = 1;
    for (const char *q = r->s; q < r->p && q < r->end; q++)
        line += *q == '\n';
    return line;
}

static int fail(reader *r, const char *what)
{
    snprintf(r->err, r->errlen, "%s:%d: %s", r->path, line_of(r), what);
    return -1;
}

static char *slurp(const char *path, size_t *len, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        return NULL;
    }
    size_t cap = 65536, n = 0;
    char *buf = malloc(cap + 1);
    while (buf) {
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (n < cap)
            break;
        if (cap >= READ_MAX) {
            snprintf(err, errlen, "%s: larger than %zu bytes", path, READ_MAX);
            free(buf);
            fclose(f);
            return NULL;
        }
        char *nb = realloc(buf, cap * 2 + 1);
        if (!nb) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = nb;
        cap *= 2;
    }
    if (!buf || ferror(f)) {
        snprintf(err, errlen, "%s: %s", path, buf ? "read error" : "out of memory");
        free(buf);
        fclose(f);
        return NULL;
    }
    fclose(f);
    buf[n] = '\0';
    *len = n;
    return buf;
}

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

/* One field at r->p (RFC 4180), malloc'd into *out; r->p left on the
 * separator (',', '\n' or the end). */
static int csv_field(reader *r, char **out)
{
    size_t cap = 32, n = 0;
    char *b = malloc(cap);
    if (!b)
        return fail(r, "out of memory");
    const char *start = r->p;
    int quoted = r->p < r->end && *r->p == '"';
    if (quoted)
        r->p++;
    for (;;) {
        if (r->p >= r->end) {
            if (quoted) {
                free(b);
                r->p = start;
                return fail(r, "a quoted field does not end");
            }
            break;
        }
        char c = *r->p;
        if (quoted && c == '"') {
            if (r->p + 1 < r->end && r->p[1] == '"') {
                r->p += 2;
            } else {
                r->p++;
                quoted = 0;
                continue;
            }
        } else if (!quoted && (c == ',' || c == '\n')) {
            break;
        } else {
            r->p++;
        }
        if (!quoted && c == '\r' && r->p < r->end && *r->p == '\n')
            continue; /* CRLF */
        if (n + 2 > cap) {
            char *nb = realloc(b, cap *= 2);
            if (!nb) {
                free(b);
                return fail(r, "out of memory");
            }
            b = nb;
        }
        b[n++] = c;
    }
    b[n] = '\0';
    *out = b;
    return 0;
}

static void free_fields(char **f, size_t n)
{
    for (size_t i = 0; f && i < n; i++)
        free(f[i]);
    free(f);
}

/* The fields of one CSV line; *n set. Leaves r->p after the newline. */
static int csv_line(reader *r, char ***fields, size_t *n)
{
    size_t cap = 32;
    *n = 0;
    *fields = malloc(cap * sizeof **fields);
    if (!*fields)
        return fail(r, "out of memory");
    for (;;) {
        char *f = NULL;
        if (csv_field(r, &f) != 0) {
            free_fields(*fields, *n);
            *fields = NULL;
            return -1;
        }
        if (*n == cap) {
            char **nf = realloc(*fields, (cap *= 2) * sizeof **fields);
            if (!nf) {
                free(f);
                free_fields(*fields, *n);
                *fields = NULL;
                return fail(r, "out of memory");
            }
            *fields = nf;
        }
        (*fields)[(*n)++] = f;
        if (r->p >= r->end)
            return 0;
        if (*r->p++ == '\n')
            return 0;
    }
}

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

static int read_csv(reader *r, stats_log *log, stats_read_summary *sum)
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
            if (csv_line(r, &head, &nh) != 0) {
                rc = -1;
                break;
            }
            int has_index = 0, has_status = 0;
            for (size_t i = 0; i < nh; i++) {
                has_index |= strcmp(head[i], "index") == 0;
                has_status |= strcmp(head[i], "status") == 0;
            }
            if (!has_index || !has_status)
                rc = (r->p = hstart, fail(r, "not a jetmesh statistics CSV (no index and status columns in its header)"));
            continue;
        }
        const char *start = r->p;
        if (csv_line(r, &row, &nr) != 0) {
            rc = -1;
            break;
        }
        if (nr != nh) {
            r->p = start;
            rc = fail(r, "a row with another number of fields than the header");
        } else {
            stats_record *rec = new_record(log);
            if (!rec)
                rc = fail(r, "out of memory");
            for (size_t i = 0; rc == 0 && i < nr; i++) {
                int s = set_field(rec, head[i], row[i]);
                if (s < 0) {
                    char msg[300];
                    snprintf(msg, sizeof msg, "bad %s '%.200s'", head[i], row[i]);
                    r->p = start;
                    rc = fail(r, msg);
                }
            }
        }
        free_fields(row, nr);
        row = NULL;
    }
    if (rc == 0 && !head)
        rc = fail(r, "empty: no header line");
    free_fields(head, nh);
    return rc;
}

/* ---- JSON --------------------------------------------------------------- */

static void ws(reader *r)
{
    while (r->p < r->end && (*r->p == ' ' || *r->p == '\t' || *r->p == '\n' || *r->p == '\r'))
        r->p++;
}

static int expect(reader *r, char c)
{
    ws(r);
    if (r->p >= r->end || *r->p != c) {
        char msg[64];
        snprintf(msg, sizeof msg, "expected '%c' in the JSON", c);
        return fail(r, msg);
    }
    r->p++;
    return 0;
}

static void put_utf8(char *b, size_t *n, unsigned v)
{
    if (v < 0x80) {
        b[(*n)++] = (char)v;
    } else if (v < 0x800) {
        b[(*n)++] = (char)(0xc0 | (v >> 6));
        b[(*n)++] = (char)(0x80 | (v & 0x3f));
    } else if (v < 0x10000) {
        b[(*n)++] = (char)(0xe0 | (v >> 12));
        b[(*n)++] = (char)(0x80 | ((v >> 6) & 0x3f));
        b[(*n)++] = (char)(0x80 | (v & 0x3f));
    } else {
        b[(*n)++] = (char)(0xf0 | (v >> 18));
        b[(*n)++] = (char)(0x80 | ((v >> 12) & 0x3f));
        b[(*n)++] = (char)(0x80 | ((v >> 6) & 0x3f));
        b[(*n)++] = (char)(0x80 | (v & 0x3f));
    }
}

static int hex4(reader *r, unsigned *v)
{
    *v = 0;
    for (int i = 0; i < 4; i++) {
        if (r->p >= r->end)
            return -1;
        char c = *r->p++;
        unsigned d = c >= '0' && c <= '9' ? (unsigned)(c - '0')
                     : c >= 'a' && c <= 'f' ? (unsigned)(c - 'a' + 10)
                     : c >= 'A' && c <= 'F' ? (unsigned)(c - 'A' + 10) : 16u;
        if (d > 15)
            return -1;
        *v = *v * 16 + d;
    }
    return 0;
}

/* A JSON string, decoded into a malloc'd UTF-8 string. */
static int json_str(reader *r, char **out)
{
    if (expect(r, '"') != 0)
        return -1;
    size_t cap = 64, n = 0;
    char *b = malloc(cap + 8);
    if (!b)
        return fail(r, "out of memory");
    for (;;) {
        if (r->p >= r->end) {
            free(b);
            return fail(r, "a JSON string does not end");
        }
        if (n + 8 > cap) {
            char *nb = realloc(b, (cap *= 2) + 8);
            if (!nb) {
                free(b);
                return fail(r, "out of memory");
            }
            b = nb;
        }
        char c = *r->p++;
        if (c == '"')
            break;
        if (c != '\\') {
            b[n++] = c;
            continue;
        }
        if (r->p >= r->end)
            continue;
        c = *r->p++;
        unsigned v;
        switch (c) {
        case 'n': b[n++] = '\n'; break;
        case 'r': b[n++] = '\r'; break;
        case 't': b[n++] = '\t'; break;
        case 'b': b[n++] = '\b'; break;
        case 'f': b[n++] = '\f'; break;
        case 'u':
            if (hex4(r, &v) != 0) {
                free(b);
                return fail(r, "a bad \\u escape in a JSON string");
            }
            if (v >= 0xd800 && v <= 0xdbff && r->end - r->p >= 6 && r->p[0] == '\\' && r->p[1] == 'u') {
                unsigned lo;
                r->p += 2;
                if (hex4(r, &lo) == 0 && lo >= 0xdc00 && lo <= 0xdfff)
                    v = 0x10000 + ((v - 0xd800) << 10) + (lo - 0xdc00);
                else
                    v = 0xfffd;
            } else if (v >= 0xd800 && v <= 0xdfff)
                v = 0xfffd;
            put_utf8(b, &n, v);
            break;
        default: b[n++] = c; break; /* \" \\ \/ */
        }
    }
    b[n] = '\0';
    *out = b;
    return 0;
}

/* A scalar's text: a decoded string, a number's or literal's characters,
 * or NULL for null. *is_container set for '{' or '['. */
static int json_scalar(reader *r, char **out, int *is_container)
{
    ws(r);
    *out = NULL;
    *is_container = 0;
    if (r->p >= r->end)
        return fail(r, "the JSON ends early");
    if (*r->p == '"')
        return json_str(r, out);
    if (*r->p == '{' || *r->p == '[') {
        *is_container = 1;
        return 0;
    }
    const char *s = r->p;
    while (r->p < r->end && !strchr(",}] \t\r\n", *r->p))
        r->p++;
    size_t len = (size_t)(r->p - s);
    if (len == 0)
        return fail(r, "a JSON value expected");
    if (len == 4 && strncmp(s, "null", 4) == 0)
        return 0;
    *out = malloc(len + 1);
    if (!*out)
        return fail(r, "out of memory");
    memcpy(*out, s, len);
    (*out)[len] = '\0';
    return 0;
}

static int json_skip(reader *r, int depth);

/* Skips the object or array at r->p. */
static int json_skip_container(reader *r, int depth)
{
    if (depth > 64)
        return fail(r, "JSON nested too deeply");
    ws(r);
    char close = *r->p == '{' ? '}' : ']';
    int object = close == '}';
    r->p++;
    ws(r);
    if (r->p < r->end && *r->p == close) {
        r->p++;
        return 0;
    }
    for (;;) {
        if (object) {
            char *k;
            if (json_str(r, &k) != 0)
                return -1;
            free(k);
            if (expect(r, ':') != 0)
                return -1;
        }
        if (json_skip(r, depth + 1) != 0)
            return -1;
        ws(r);
        if (r->p < r->end && *r->p == ',') {
            r->p++;
            continue;
        }
        return expect(r, close);
    }
}

static int json_skip(reader *r, int depth)
{
    char *t;
    int cont;
    if (json_scalar(r, &t, &cont) != 0)
        return -1;
    free(t);
    return cont ? json_skip_container(r, depth) : 0;
}

/* Calls each(r, key, user) for every member of the object at r->p; each
 * consumes the value. */
static int json_members(reader *r, int (*each)(reader *, const char *, void *), void *user)
{
    if (expect(r, '{') != 0)
        return -1;
    ws(r);
    if (r->p < r->end && *r->p == '}') {
        r->p++;
        return 0;
    }
    for (;;) {
        char *k;
        if (json_str(r, &k) != 0)
            return -1;
        int rc = expect(r, ':') == 0 ? each(r, k, user) : -1;
        free(k);
        if (rc != 0)
            return -1;
        ws(r);
        if (r->p < r->end && *r->p == ',') {
            r->p++;
            continue;
        }
        return expect(r, '}');
    }
}

static int frame_member(reader *r, const char *key, void *user)
{
    stats_record *rec = user;
    char *t;
    int cont;
    if (json_scalar(r, &t, &cont) != 0)
        return -1;
    if (cont)
        return json_skip_container(r, 1);
    int s = set_field(rec, key, t);
    free(t);
    if (s < 0) {
        char msg[200];
        snprintf(msg, sizeof msg, "bad \"%.100s\" of a frame", key);
        return fail(r, msg);
    }
    return 0;
}

static int summary_member(reader *r, const char *key, void *user)
{
    char *t;
    int cont;
    if (json_scalar(r, &t, &cont) != 0)
        return -1;
    if (cont)
        return json_skip_container(r, 1);
    if (t)
        summary_value(user, key, strlen(key), t, strlen(t));
    free(t);
    return 0;
}

typedef struct top {
    stats_log *log;
    stats_read_summary *sum;
    int frames_seen;
} top;

static int top_member(reader *r, const char *key, void *user)
{
    top *t = user;
    if (strcmp(key, "summary") == 0)
        return json_members(r, summary_member, t->sum);
    if (strcmp(key, "frames") != 0)
        return json_skip(r, 1);
    t->frames_seen = 1;
    if (expect(r, '[') != 0)
        return -1;
    ws(r);
    if (r->p < r->end && *r->p == ']') {
        r->p++;
        return 0;
    }
    for (;;) {
        stats_record *rec = new_record(t->log);
        if (!rec)
            return fail(r, "out of memory");
        rec->index = -1;
        rec->status = (stats_status)-1;
        if (json_members(r, frame_member, rec) != 0)
            return -1;
        if (rec->index < 0 || (int)rec->status < 0)
            return fail(r, "a frame without index or status");
        ws(r);
        if (r->p < r->end && *r->p == ',') {
            r->p++;
            continue;
        }
        return expect(r, ']');
    }
}

static int read_json(reader *r, stats_log *log, stats_read_summary *sum)
{
    top t = {log, sum, 0};
    if (json_members(r, top_member, &t) != 0)
        return -1;
    if (!t.frames_seen)
        return fail(r, "not a jetmesh statistics JSON (no \"frames\")");
    return 0;
}

int stats_read(const char *path, stats_log *log, stats_read_summary *sum, char *err, size_t errlen)
{
    size_t len = 0;
    char *text = slurp(path, &len, err, errlen);
    if (!text)
        return -1;
    reader r = {path, text, text + len, text, err, errlen};
    memset(sum, 0, sizeof *sum);
    ws(&r);
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
