/* read_csv.c - reads particles from delimited text (CSV/TSV/space separated), header optional, x/y/z by name or position, other named columns as attributes. */
#include "readbuf.h"

#include <stdlib.h>

/*
 * Rules:
 *  - Lines end in LF or CRLF. Blank lines and lines whose first non-blank
 *    character is '#' are skipped. A UTF-8 byte order mark is skipped.
 *  - The separator is chosen from the first content line: the most frequent
 *    of ',' ';' TAB (ties in that order); with none of them, runs of spaces
 *    and tabs separate fields. Fields are trimmed of blanks and of one pair of
 *    enclosing double quotes (quoted separators are not supported). Decimal
 *    commas are not supported.
 *  - The first content line is a header when none of its fields is a number.
 *    Columns are found by name, case-insensitively:
 *      x/y/z exactly, or a prefix "p", "pos", "position", "point", "points",
 *      "coord", "coords" followed by an optional '_', '.', ':', '-' or ' '
 *      and x/y/z or 0/1/2: "px", "pos_x", "Position.X", "Points:0" (ParaView).
 *    Exact names win over prefixed ones. An "id" (or "particle_id") column
 *    fills the ids. When the header names none of x, y, z, the first three
 *    columns (other than id) that are numeric in the first data row are used;
 *    naming only some of them is an error. Without a header, the first three
 *    numeric columns of the first row are used.
 *  - Every row must have as many fields as the header (or the first row);
 *    the used columns must be numbers (nan/inf parse, then the NaN policy
 *    applies). Columns that are not used may hold anything.
 */

typedef struct field {
    const char *s;
    size_t n;
} field;

typedef struct splitter {
    const char *p, *end;
    char sep; /* 0: runs of blanks */
    int done;
} splitter;

static int is_blank(char c) { return c == ' ' || c == '\t'; }

static field trim(const char *s, size_t n, char sep)
{
    field f;
    while (n > 0 && (s[0] == ' ' || (sep != '\t' && s[0] == '\t'))) { s++; n--; }
    while (n > 0 && (s[n - 1] == ' ' || (sep != '\t' && s[n - 1] == '\t'))) n--;
    if (n >= 2 && s[0] == '"' && s[n - 1] == '"') { s++; n -= 2; }
    f.s = s;
    f.n = n;
    return f;
}

/* Next field of the line; returns 0 when there are no more. */
static int next_field(splitter *sp, field *f)
{
    const char *q;
    if (sp->done) return 0;
    if (sp->sep == 0) {
        while (sp->p < sp->end && is_blank(*sp->p)) sp->p++;
        if (sp->p == sp->end) { sp->done = 1; return 0; }
        q = sp->p;
        while (q < sp->end && !is_blank(*q)) q++;
        f->s = sp->p;
        f->n = (size_t)(q - sp->p);
        sp->p = q;
        return 1;
    }
    q = memchr(sp->p, sp->sep, (size_t)(sp->end - sp->p));
    if (!q) {
        *f = trim(sp->p, (size_t)(sp->end - sp->p), sp->sep);
        sp->done = 1;
        return 1;
    }
    *f = trim(sp->p, (size_t)(q - sp->p), sp->sep);
    sp->p = q + 1;
    return 1;
}

static void split_init(splitter *sp, const char *s, size_t n, char sep)
{
    sp->p = s;
    sp->end = s + n;
    sp->sep = sep;
    sp->done = 0;
}

/* Which axis a header name means: 0..2, or -1; *exact says whether it was a bare x/y/z. */
static int axis_of(field f, int *exact)
{
    static const char *const prefixes[] = { "position", "points", "point", "coords", "coord", "pos", "p" };
    size_t i;
    *exact = 0;
    if (f.n == 1) {
        char c = (char)(f.s[0] | 0x20);
        if (c >= 'x' && c <= 'z') { *exact = 1; return c - 'x'; }
        return -1;
    }
    for (i = 0; i < sizeof prefixes / sizeof prefixes[0]; i++) {
        size_t k = strlen(prefixes[i]), rest;
        const char *r;
        char c;
        if (f.n <= k || !jmr_ieq(f.s, k, prefixes[i])) continue;
        r = f.s + k;
        rest = f.n - k;
        if (rest == 2 && (r[0] == '_' || r[0] == '.' || r[0] == ':' || r[0] == '-' || r[0] == ' ')) {
            r++;
            rest--;
        }
        if (rest != 1) continue;
        c = (char)(r[0] | 0x20);
        if (c >= 'x' && c <= 'z') return c - 'x';
        if (r[0] >= '0' && r[0] <= '2') return r[0] - '0';
    }
    return -1;
}

static int is_number(field f)
{
    double d;
    return jmr_parse_double(f.s, f.n, &d);
}

/* Shows at most 40 bytes of a field in a message. */
#define SHOW(f) (int)((f).n > 40 ? 40 : (f).n), (f).s

static const char *sep_name(char sep)
{
    switch (sep) {
    case ',': return "comma";
    case ';': return "semicolon";
    case '\t': return "tab";
    default: return "blank";
    }
}

/* The header's columns other than x, y, z and id, as attributes (when asked for). */
typedef struct csv_attrs {
    const char **names; /* header fields (into the data) */
    size_t *lens;
    size_t ncols;
    jmr_attr **attr;    /* per column: the attribute it fills, or NULL */
    size_t *comp;
    jmr_attr **list;    /* the distinct attributes, in order */
    size_t nlist;
    double *row;        /* per column: this row's value */
} csv_attrs;

static void csv_attrs_free(csv_attrs *ca)
{
    free(ca->names);
    free(ca->lens);
    free(ca->attr);
    free(ca->comp);
    free(ca->list);
    free(ca->row);
}

/* Groups the header's other columns into attributes (col: x, y, z, id). */
static jmf_status csv_attrs_start(csv_attrs *ca, const long *col, size_t line, const jmr_ctx *ctx, jmr_points *pts)
{
    size_t n = ca->ncols, ng, k;
    int *skip = calloc(n ? n : 1, sizeof *skip);
    jmr_colgroup *g = calloc(n ? n : 1, sizeof *g);
    jmf_status st = JMF_OK;
    ca->attr = calloc(n ? n : 1, sizeof *ca->attr);
    ca->comp = calloc(n ? n : 1, sizeof *ca->comp);
    ca->list = calloc(n ? n : 1, sizeof *ca->list);
    ca->row = calloc(n ? n : 1, sizeof *ca->row);
    if (!skip || !g || !ca->attr || !ca->comp || !ca->list || !ca->row) {
        free(skip);
        free(g);
        return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for the header's columns");
    }
    for (k = 0; k < 4; k++)
        if (col[k] >= 0 && (size_t)col[k] < n) skip[col[k]] = 1;
    ng = jmr_group_columns(ca->names, ca->lens, skip, n, g);
    for (k = 0; k < ng && !st; k++) {
        jmr_attr *a = NULL;
        st = jmr_attr_begin(pts, ctx, g[k].name, strlen(g[k].name), (size_t)g[k].comps, 0, jmr_line(line), &a);
        if (!st && a) {
            ca->list[ca->nlist++] = a;
            for (int c = 0; c < g[k].comps; c++) {
                ca->attr[g[k].cols[c]] = a;
                ca->comp[g[k].cols[c]] = (size_t)c;
            }
        }
    }
    free(skip);
    free(g);
    return st;
}

static jmf_status read_csv(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts, csv_attrs *ca);

jmf_status jmr_read_csv(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts)
{
    csv_attrs ca;
    memset(&ca, 0, sizeof ca);
    jmf_status st = read_csv(data, size, ctx, pts, &ca);
    csv_attrs_free(&ca);
    return st;
}

/* Where the reading of a file stands. */
typedef struct csv_state {
    const jmr_ctx *ctx;
    jmr_points *pts;
    csv_attrs *ca;
    size_t line, ncols, header_line;
    long col[4]; /* x, y, z, id */
    int have_sep, have_cols, attrs_ready;
    char sep;
} csv_state;

/* 1 for a blank or comment line; JMF_E_FORMAT (failed) for a control byte;
 * else 0. */
static int skip_line(const csv_state *s, const char *q, size_t n, jmf_status *st)
{
    size_t i = 0;
    while (i < n && is_blank(q[i])) i++;
    if (i == n || q[i] == '#') return 1;
    for (i = 0; i < n; i++) {
        unsigned char c = (unsigned char)q[i];
        if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7f) {
            *st = jmr_fail(s->ctx, JMF_E_FORMAT, jmr_line(s->line),
                           "unexpected control byte 0x%02x in column %zu; expected text", c, i + 1);
            return 1;
        }
    }
    return 0;
}

/* The header's column names: x, y, z and id by name, attributes kept. */
static jmf_status read_header(csv_state *s, const char *q, size_t n, size_t nf)
{
    int best[3] = { 0, 0, 0 }, exact, named = 0;
    const jmr_ctx *ctx = s->ctx;
    long *col = s->col;
    splitter sp;
    field f;
    size_t k;
    jmf_status st;
    s->ncols = nf;
    s->header_line = s->line;
    split_init(&sp, q, n, s->sep);
    for (k = 0; next_field(&sp, &f); k++) {
        int a = axis_of(f, &exact);
        if (a >= 0 && (col[a] < 0 || (exact && !best[a]))) {
            col[a] = (long)k;
            best[a] = exact;
        }
        if (col[3] < 0 && (jmr_ieq(f.s, f.n, "id") || jmr_ieq(f.s, f.n, "particle_id")))
            col[3] = (long)k;
    }
    for (k = 0; k < 3; k++) named += col[k] >= 0;
    if (named == 0 && nf - (col[3] >= 0) < 3)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(s->line),
                        "header has %zu %s-separated column(s) and no x, y, z names; expected "
                        "at least 3 columns",
                        nf, sep_name(s->sep));
    if (named == 3) {
        s->have_cols = 1;
    } else if (named > 0) {
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(s->line),
                        "header names only some of the x, y, z columns (missing %s); expected "
                        "all three or none",
                        col[0] < 0 ? "x" : col[1] < 0 ? "y" : "z");
    }
    if (col[3] >= 0) {
        st = jmr_points_want_ids(s->pts, ctx);
        if (st) return st;
    }
    if (jmr_attrs_wanted(ctx)) {
        csv_attrs *ca = s->ca;
        ca->names = calloc(nf ? nf : 1, sizeof *ca->names);
        ca->lens = calloc(nf ? nf : 1, sizeof *ca->lens);
        if (!ca->names || !ca->lens)
            return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for the header");
        ca->ncols = nf;
        split_init(&sp, q, n, s->sep);
        for (k = 0; next_field(&sp, &f); k++) {
            ca->names[k] = f.s;
            ca->lens[k] = f.n;
        }
    }
    return JMF_OK;
}

/* The first content line: the separator, and the header if it is one
 * (*header set). */
static jmf_status first_line(csv_state *s, const char *q, size_t n, int *header)
{
    size_t cnt[3] = { 0, 0, 0 }, i, k, nf = 0;
    static const char seps[3] = { ',', ';', '\t' };
    splitter sp;
    field f;
    for (i = 0; i < n; i++)
        for (k = 0; k < 3; k++)
            if (q[i] == seps[k]) cnt[k]++;
    s->sep = 0;
    for (k = 0, i = 0; k < 3; k++)
        if (cnt[k] > i) { i = cnt[k]; s->sep = seps[k]; }
    s->have_sep = 1;

    /* header? none of the fields is a number */
    split_init(&sp, q, n, s->sep);
    *header = 1;
    while (next_field(&sp, &f)) {
        nf++;
        if (is_number(f)) *header = 0;
    }
    if (*header)
        return read_header(s, q, n, nf);
    s->ncols = nf;
    return JMF_OK;
}

/* The first data row without x, y, z names: its first three numeric
 * columns (not id). */
static jmf_status pick_columns(csv_state *s, const char *q, size_t n)
{
    int got = 0;
    splitter sp;
    field f;
    split_init(&sp, q, n, s->sep);
    for (size_t k = 0; got < 3 && next_field(&sp, &f); k++)
        if ((long)k != s->col[3] && is_number(f)) s->col[got++] = (long)k;
    if (got < 3)
        return jmr_fail(s->ctx, JMF_E_FORMAT, jmr_line(s->line),
                        "expected at least 3 numeric %s-separated columns for x, y, z, found %d",
                        sep_name(s->sep), got);
    s->have_cols = 1;
    return JMF_OK;
}

/* A row's x, y, z, id and attributes added to the points. */
static jmf_status add_row(csv_state *s, const field val[4])
{
    const jmr_ctx *ctx = s->ctx;
    csv_attrs *ca = s->ca;
    const long *col = s->col;
    double v[3];
    uint32_t id = 0;
    jmf_status st;
    for (size_t k = 0; k < 3; k++)
        if (!jmr_parse_double(val[k].s, val[k].n, &v[k]))
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(s->line),
                            "column %ld (%c): expected a number, found '%.*s'", col[k] + 1,
                            (char)('x' + k), SHOW(val[k]));
    if (col[3] >= 0) {
        double d;
        if (!jmr_parse_double(val[3].s, val[3].n, &d))
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(s->line),
                            "column %ld (id): expected an integer id, found '%.*s'", col[3] + 1,
                            SHOW(val[3]));
        if (d >= 0 && d <= 4294967295.0 && d == (double)(uint32_t)d)
            id = (uint32_t)d;
        else
            s->pts->ids_bad = 1;
    }
    st = jmr_points_add(s->pts, ctx, v[0], v[1], v[2], id, jmr_line(s->line));
    if (st) return st;
    for (size_t a = 0; a < ca->nlist; a++) {
        double t[4] = {0, 0, 0, 0};
        for (size_t c = 0; c < ca->ncols; c++)
            if (ca->attr[c] == ca->list[a]) t[ca->comp[c]] = ca->row[c];
        st = jmr_attr_push(ca->list[a], ctx, t);
        if (st) return st;
    }
    return JMF_OK;
}

/* A data row: its fields split, counted and added. */
static jmf_status data_row(csv_state *s, const char *q, size_t n)
{
    const jmr_ctx *ctx = s->ctx;
    csv_attrs *ca = s->ca;
    splitter sp;
    field f, val[4];
    size_t nf = 0;
    split_init(&sp, q, n, s->sep);
    memset(val, 0, sizeof val);
    while (next_field(&sp, &f)) {
        for (size_t k = 0; k < 4; k++)
            if (s->col[k] == (long)nf) val[k] = f;
        if (ca->attr && nf < ca->ncols && ca->attr[nf]) {
            double d;
            if (!jmr_parse_double(f.s, f.n, &d))
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(s->line),
                                "column %zu (%s): expected a number, found '%.*s'", nf + 1, ca->attr[nf]->name,
                                SHOW(f));
            ca->row[nf] = d;
        }
        nf++;
    }
    if (nf != s->ncols) {
        if (s->header_line)
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(s->line),
                            "expected %zu %s-separated fields as in the header on line %zu, found %zu",
                            s->ncols, sep_name(s->sep), s->header_line, nf);
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(s->line),
                        "expected %zu %s-separated fields as in the first row, found %zu", s->ncols,
                        sep_name(s->sep), nf);
    }
    return add_row(s, val);
}

static jmf_status read_csv(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts, csv_attrs *ca)
{
    const char *text = (const char *)data, *end = text + size, *p = text;
    csv_state s;
    jmf_status st = JMF_OK;
    memset(&s, 0, sizeof s);
    s.ctx = ctx;
    s.pts = pts;
    s.ca = ca;
    for (int k = 0; k < 4; k++) s.col[k] = -1;

    if (size >= 3 && memcmp(text, "\xef\xbb\xbf", 3) == 0) p += 3;
    while (p < end) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *le = nl ? nl : end, *q = p;
        size_t n = (size_t)(le - p);
        s.line++;
        if (n > 0 && p[n - 1] == '\r') n--;
        p = nl ? nl + 1 : end;
        if (skip_line(&s, q, n, &st)) {
            if (st) return st;
            continue;
        }
        if (!s.have_sep) {
            int header;
            st = first_line(&s, q, n, &header);
            if (st) return st;
            if (header) continue;
        }
        if (!s.have_cols) {
            st = pick_columns(&s, q, n);
            if (st) return st;
        }
        if (!s.attrs_ready) {
            s.attrs_ready = 1;
            if (ca->names) {
                st = csv_attrs_start(ca, s.col, s.header_line, ctx, pts);
                if (st) return st;
            }
        }
        st = data_row(&s, q, n);
        if (st) return st;
    }
    return JMF_OK;
}
