/* read_vtk.c - reads the POINTS of a legacy VTK file (versions 1.0-5.x, ASCII or big-endian BINARY), an optional "id" array and the point-data arrays asked for. */
#include "readbuf.h"

/*
 * Every section is walked (so truncation anywhere is noticed), but only
 * POINTS is kept, plus a point-data array named "id" (SCALARS with one
 * component or a FIELD array) of an integer type. Handled sections: DATASET,
 * POINTS, CELLS/VERTICES/LINES/POLYGONS/TRIANGLE_STRIPS (legacy and 5.x
 * OFFSETS/CONNECTIVITY), CELL_TYPES, POINT_DATA/CELL_DATA with SCALARS (+
 * LOOKUP_TABLE line), LOOKUP_TABLE, COLOR_SCALARS, VECTORS, NORMALS,
 * TENSORS(6), TEXTURE_COORDINATES, GLOBAL_IDS, PEDIGREE_IDS, FIELD arrays
 * (incl. NULL_ARRAY), METADATA blocks, DIMENSIONS/ORIGIN/SPACING/
 * ASPECT_RATIO and X/Y/Z_COORDINATES. Errors name the line in ASCII files and
 * the byte offset in BINARY ones.
 */

typedef struct vt {
    const uint8_t *d;
    size_t n, pos, line;
    int binary;
    const jmr_ctx *ctx;
    jmr_attr *attr; /* SINK_ATTR's target */
} vt;

typedef struct tok {
    const char *s;
    size_t n;
    size_t pos; /* where it starts */
    size_t line;
} tok;

static jmr_at here_at(const vt *v, size_t pos, size_t line)
{
    return v->binary ? jmr_byte(pos) : jmr_line(line);
}
static jmr_at at_tok(const vt *v, const tok *t) { return here_at(v, t->pos, t->line); }
static jmr_at at_now(const vt *v)
{
    /* at the end of a file that ends with a newline, name its last line */
    size_t line = v->line;
    if (v->pos >= v->n && v->n > 0 && v->d[v->n - 1] == '\n' && line > 1) line--;
    return here_at(v, v->pos, line);
}

#define SHOW(t) (int)((t).n > 40 ? 40 : (t).n), (t).s

/* Next whitespace-separated token across lines; 0 at end of file. */
static int next_tok(vt *v, tok *t)
{
    while (v->pos < v->n && jmr_isspace(v->d[v->pos])) {
        if (v->d[v->pos] == '\n') v->line++;
        v->pos++;
    }
    t->pos = v->pos;
    t->line = v->line;
    t->s = (const char *)v->d + v->pos;
    while (v->pos < v->n && !jmr_isspace(v->d[v->pos])) v->pos++;
    t->n = v->pos - t->pos;
    return t->n > 0;
}

/* Next token on the current line only; 0 at end of line or file. */
static int line_tok(vt *v, tok *t)
{
    while (v->pos < v->n && v->d[v->pos] != '\n' && jmr_isspace(v->d[v->pos])) v->pos++;
    if (v->pos >= v->n || v->d[v->pos] == '\n') {
        t->pos = v->pos;
        t->line = v->line;
        t->s = (const char *)v->d + v->pos;
        t->n = 0;
        return 0;
    }
    return next_tok(v, t);
}

/* Requires the rest of the line to be blank and moves past its newline. */
static jmf_status end_line(vt *v, const char *after)
{
    tok t;
    if (line_tok(v, &t))
        return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, &t), "unexpected '%.*s' after %s; expected end of line",
                        SHOW(t), after);
    if (v->pos < v->n) { v->pos++; v->line++; }
    return JMF_OK;
}

static jmf_status need_line_tok(vt *v, tok *t, const char *what)
{
    if (line_tok(v, t)) return JMF_OK;
    return jmr_fail(v->ctx, JMF_E_FORMAT, at_now(v), "expected %s, found %s", what,
                    v->pos >= v->n ? "end of file" : "end of line");
}

static jmf_status line_size(vt *v, const char *what, size_t *out)
{
    tok t;
    jmf_status st = need_line_tok(v, &t, what);
    if (st) return st;
    if (!jmr_parse_size(t.s, t.n, out))
        return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, &t), "expected %s (a non-negative integer), found '%.*s'",
                        what, SHOW(t));
    return JMF_OK;
}

static jmr_type type_of(const tok *t, int *is_bit)
{
    static const struct { const char *name; jmr_type t; } types[] = {
        { "unsigned_char", JMR_T_U8 }, { "char", JMR_T_I8 }, { "unsigned_short", JMR_T_U16 },
        { "short", JMR_T_I16 }, { "unsigned_int", JMR_T_U32 }, { "int", JMR_T_I32 },
        { "unsigned_long", JMR_T_U64 }, { "long", JMR_T_I64 }, { "float", JMR_T_F32 },
        { "double", JMR_T_F64 }, { "vtktypeint8", JMR_T_I8 }, { "vtktypeuint8", JMR_T_U8 },
        { "vtktypeint16", JMR_T_I16 }, { "vtktypeuint16", JMR_T_U16 }, { "vtktypeint32", JMR_T_I32 },
        { "vtktypeuint32", JMR_T_U32 }, { "vtktypeint64", JMR_T_I64 }, { "vtktypeuint64", JMR_T_U64 },
        { "vtktypefloat32", JMR_T_F32 }, { "vtktypefloat64", JMR_T_F64 }, { "vtkidtype", JMR_T_I32 },
        { "signed_char", JMR_T_I8 },
    };
    size_t i;
    *is_bit = 0;
    if (jmr_ieq(t->s, t->n, "bit")) { *is_bit = 1; return JMR_T_U8; }
    for (i = 0; i < sizeof types / sizeof types[0]; i++)
        if (jmr_ieq(t->s, t->n, types[i].name)) return types[i].t;
    return JMR_T_NONE;
}

static jmf_status line_type(vt *v, jmr_type *ty, int *is_bit)
{
    tok t;
    jmf_status st = need_line_tok(v, &t, "a data type");
    if (st) return st;
    *ty = type_of(&t, is_bit);
    if (*ty == JMR_T_NONE) {
        if (jmr_ieq(t.s, t.n, "string") || jmr_ieq(t.s, t.n, "utf8_string") ||
            jmr_ieq(t.s, t.n, "variant"))
            return jmr_fail(v->ctx, JMF_E_UNSUPPORTED, at_tok(v, &t), "data type '%.*s' is not supported", SHOW(t));
        return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, &t),
                        "unknown data type '%.*s'; expected float, double, int, unsigned_int, ...", SHOW(t));
    }
    return JMF_OK;
}

enum sink { SINK_NONE, SINK_POINTS, SINK_IDS, SINK_ATTR };

/*
 * A claim of count values of type ty checked against the bytes left, before
 * anything is allocated for them (issue 30: a file that cannot hold what it
 * claims is a bad frame, not a memory error): binary, count values of their
 * size; ASCII, at least a character and a separator each.
 */
static jmf_status fits(vt *v, size_t count, jmr_type ty, int is_bit, const char *what)
{
    size_t left = v->n - v->pos, bytes;
    if (!v->binary) {
        if (count > left / 2 + 1)
            return jmr_fail(v->ctx, JMF_E_FORMAT, at_now(v),
                            "truncated %s: expected %zu values, but the %zu bytes left hold at most %zu", what,
                            count, left, left / 2 + 1);
        return JMF_OK;
    }
    if (is_bit) bytes = count / 8 + (count % 8 != 0);
    else if (!jmr_mul(count, jmr_type_size(ty), &bytes))
        return jmr_fail(v->ctx, JMF_E_FORMAT, at_now(v), "%s: %zu values overflow", what, count);
    if (bytes > left)
        return jmr_fail(v->ctx, JMF_E_FORMAT, at_now(v),
                        "truncated %s: expected %zu values (%zu bytes), only %zu bytes left", what, count, bytes,
                        left);
    return JMF_OK;
}

/*
 * Reads count values of type ty (after the header line). Binary: big-endian
 * raw values; ASCII: count numeric tokens. SINK_POINTS adds triples to pts,
 * SINK_IDS stores integer ids.
 */
static jmf_status values(vt *v, size_t count, jmr_type ty, int is_bit, enum sink sink, jmr_points *pts,
                         const char *what)
{
    size_t i;
    double xyz[3];
    jmf_status st;
    if (v->binary) {
        size_t sz = jmr_type_size(ty), bytes = is_bit ? count / 8 + (count % 8 != 0) : count * sz;
        st = fits(v, count, ty, is_bit, what);
        if (st) return st;
        if (sink == SINK_POINTS) {
            st = jmr_points_reserve(pts, v->ctx, count / 3);
            if (st) return st;
            for (i = 0; i + 3 <= count; i += 3) {
                const uint8_t *p = v->d + v->pos + i * sz;
                st = jmr_points_add(pts, v->ctx, jmr_load(p, ty, 1), jmr_load(p + sz, ty, 1),
                                    jmr_load(p + 2 * sz, ty, 1), 0, jmr_byte(v->pos + i * sz));
                if (st) return st;
            }
        } else if (sink == SINK_IDS && !is_bit) {
            for (i = 0; i < count; i++) {
                int ok;
                uint64_t u = jmr_load_u64(v->d + v->pos + i * sz, ty, 1, &ok);
                jmr_points_set_id(pts, i, u, ok);
            }
        } else if (sink == SINK_ATTR && !is_bit) {
            const size_t nc = (size_t)v->attr->comps;
            for (i = 0; i < count; i++)
                jmr_attr_set(v->attr, i / nc, i % nc, jmr_load(v->d + v->pos + i * sz, ty, 1));
        }
        v->pos += bytes;
        return JMF_OK;
    }
    if (sink == SINK_POINTS) {
        size_t guess = (v->n - v->pos) / 6 + 1;
        st = jmr_points_reserve(pts, v->ctx, count / 3 < guess ? count / 3 : guess);
        if (st) return st;
    }
    for (i = 0; i < count; i++) {
        tok t;
        double d;
        if (!next_tok(v, &t))
            return jmr_fail(v->ctx, JMF_E_FORMAT, at_now(v), "truncated %s: expected %zu values, found %zu", what,
                            count, i);
        if (!jmr_parse_double(t.s, t.n, &d))
            return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, &t), "%s: expected a number, found '%.*s'", what,
                            SHOW(t));
        if (sink == SINK_POINTS) {
            xyz[i % 3] = d;
            if (i % 3 == 2) {
                st = jmr_points_add(pts, v->ctx, xyz[0], xyz[1], xyz[2], 0, at_tok(v, &t));
                if (st) return st;
            }
        } else if (sink == SINK_IDS) {
            int ok = d >= 0 && d <= 18446744073709549568.0 && d == (double)(uint64_t)d;
            jmr_points_set_id(pts, i, ok ? (uint64_t)d : 0, ok);
        } else if (sink == SINK_ATTR) {
            jmr_attr_set(v->attr, i / (size_t)v->attr->comps, i % (size_t)v->attr->comps, d);
        }
    }
    return JMF_OK;
}

/* A point-data array to keep (jmr_attr_begin) once its values are known to fit. */
typedef struct claim {
    const tok *name;
    size_t comps, tuples;
} claim;

/* Reads "count values" of a section whose header line has ended with the
 * type token; with attr, the array asked for is kept (SINK_ATTR). */
static jmf_status typed_values(vt *v, size_t count, enum sink sink, jmr_points *pts, const char *what,
                               const claim *attr)
{
    jmr_type ty;
    int is_bit;
    jmf_status st = line_type(v, &ty, &is_bit);
    if (st) return st;
    st = end_line(v, what);
    if (st) return st;
    if (sink == SINK_IDS && (!jmr_type_is_int(ty) || is_bit)) sink = SINK_NONE;
    if (attr && !is_bit) {
        st = fits(v, count, ty, is_bit, what);
        if (st) return st;
        st = jmr_attr_begin(pts, v->ctx, attr->name->s, attr->name->n, attr->comps, attr->tuples,
                            at_tok(v, attr->name), &v->attr);
        if (st) return st;
        if (v->attr) sink = SINK_ATTR;
    }
    return values(v, count, ty, is_bit, sink, pts, what);
}

/* Peeks whether the next token is kw; consumes it if so. */
static int peek_kw(vt *v, const char *kw, tok *t)
{
    size_t pos = v->pos, line = v->line;
    if (next_tok(v, t) && jmr_ieq(t->s, t->n, kw)) return 1;
    v->pos = pos;
    v->line = line;
    return 0;
}

/* CELLS-like section "KW a b": legacy b int32 values, or 5.x OFFSETS (a) + CONNECTIVITY (b). */
static jmf_status cells(vt *v, const char *kw, size_t *ncells)
{
    size_t a, b;
    tok t;
    jmf_status st = line_size(v, "a cell count", &a);
    if (st) return st;
    st = line_size(v, "a cell data size", &b);
    if (st) return st;
    st = end_line(v, kw);
    if (st) return st;
    *ncells = a;
    if (peek_kw(v, "OFFSETS", &t)) {
        *ncells = a ? a - 1 : 0; /* 5.x: a offsets for a - 1 cells */
        st = typed_values(v, a, SINK_NONE, NULL, "OFFSETS", NULL);
        if (st) return st;
        if (!peek_kw(v, "CONNECTIVITY", &t))
            return jmr_fail(v->ctx, JMF_E_FORMAT, at_now(v), "expected CONNECTIVITY after the OFFSETS of %s", kw);
        return typed_values(v, b, SINK_NONE, NULL, "CONNECTIVITY", NULL);
    }
    return values(v, b, JMR_T_I32, 0, SINK_NONE, NULL, kw);
}

static jmf_status metadata(vt *v)
{
    /* METADATA blocks end with a blank line (or the end of the file) */
    jmf_status st = end_line(v, "METADATA");
    if (st) return st;
    while (v->pos < v->n) {
        size_t s = v->pos;
        int blank = 1;
        while (v->pos < v->n && v->d[v->pos] != '\n') {
            if (!jmr_isspace(v->d[v->pos])) blank = 0;
            v->pos++;
        }
        if (v->pos < v->n) { v->pos++; v->line++; }
        if (blank) break;
        (void)s;
    }
    return JMF_OK;
}

/* FIELD name k, then k arrays "name ncomp ntuples type" + values. */
static jmf_status field(vt *v, size_t ntuples_expected, int point_data, jmr_points *pts)
{
    size_t k, i;
    tok t;
    jmf_status st = need_line_tok(v, &t, "a FIELD name");
    if (st) return st;
    st = line_size(v, "a FIELD array count", &k);
    if (st) return st;
    st = end_line(v, "FIELD");
    if (st) return st;
    for (i = 0; i < k; i++) {
        tok name;
        size_t ncomp, ntup, total;
        enum sink sink = SINK_NONE;
        claim keep = { &name, 0, 0 };
        if (!next_tok(v, &name))
            return jmr_fail(v->ctx, JMF_E_FORMAT, at_now(v), "truncated FIELD: expected %zu arrays, found %zu", k, i);
        if (jmr_ieq(name.s, name.n, "METADATA")) { /* belongs to the previous array */
            st = metadata(v);
            if (st) return st;
            i--;
            continue;
        }
        if (jmr_ieq(name.s, name.n, "NULL_ARRAY")) {
            st = end_line(v, "NULL_ARRAY");
            if (st) return st;
            continue;
        }
        st = line_size(v, "a FIELD array component count", &ncomp);
        if (st) return st;
        st = line_size(v, "a FIELD array tuple count", &ntup);
        if (st) return st;
        if (!jmr_mul(ncomp, ntup, &total))
            return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, &name), "FIELD array size overflows");
        if (point_data && ncomp == 1 && ntup == ntuples_expected && pts->count == ntup &&
            name.n == 2 && memcmp(name.s, "id", 2) == 0) {
            st = jmr_points_want_ids(pts, v->ctx);
            if (st) return st;
            sink = SINK_IDS;
        } else if (point_data && ntup > 0) {
            keep.comps = ncomp;
            keep.tuples = ntup;
        }
        st = typed_values(v, total, sink, pts, "FIELD array", keep.comps ? &keep : NULL);
        if (st) return st;
    }
    return JMF_OK;
}

/* The sections read so far. */
typedef struct vtk_doc {
    vt v;
    tok dataset;
    size_t npoints, attr_count, ncells;
    int have_points, have_cells, have_dataset, mode; /* mode: 1 point data, 2 cell data */
    jmr_points *pts;
} vtk_doc;

/* Lines 1 to 3: magic and version, title, ASCII or BINARY. */
static jmf_status preamble(vt *v)
{
    static const char magic[] = "# vtk DataFile Version";
    const jmr_ctx *ctx = v->ctx;
    tok t;
    size_t major;
    jmf_status st;
    /* line 1: magic and version */
    if (v->n < sizeof magic - 1 || memcmp(v->d, magic, sizeof magic - 1) != 0)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(1), "expected '%s X.Y'", magic);
    v->pos = sizeof magic - 1;
    st = need_line_tok(v, &t, "a version number");
    if (st) return st;
    if (t.n < 1 || t.s[0] < '0' || t.s[0] > '9' || (t.n > 1 && t.s[1] != '.') ||
        !jmr_parse_size(t.s, 1, &major))
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(1), "expected a version number X.Y, found '%.*s'", SHOW(t));
    if (major < 1 || major > 5)
        return jmr_fail(ctx, JMF_E_UNSUPPORTED, jmr_line(1), "VTK file version %.*s; expected 1.0 to 5.x",
                        SHOW(t));
    st = end_line(v, "the version");
    if (st) return st;
    /* line 2: title (anything) */
    while (v->pos < v->n && v->d[v->pos] != '\n') v->pos++;
    if (v->pos >= v->n)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(v->line), "truncated header: expected a title line and ASCII or BINARY");
    v->pos++;
    v->line++;
    /* line 3: ASCII | BINARY (blank lines before it tolerated) */
    if (!next_tok(v, &t))
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(v->line), "truncated header: expected ASCII or BINARY");
    if (jmr_ieq(t.s, t.n, "BINARY")) v->binary = 1;
    else if (!jmr_ieq(t.s, t.n, "ASCII"))
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(t.line), "expected ASCII or BINARY, found '%.*s'", SHOW(t));
    return end_line(v, t.s[0] == 'B' || t.s[0] == 'b' ? "BINARY" : "ASCII");
}

/* DATASET, POINTS, the cell sections, POINT_DATA/CELL_DATA: 1 if t was
 * one of them (*st set), else 0. */
static int structure_section(vtk_doc *doc, const tok *t, jmf_status *st)
{
    vt *v = &doc->v;
    const jmr_ctx *ctx = v->ctx;
    if (jmr_ieq(t->s, t->n, "POINTS")) {
        size_t nvals;
        if (doc->have_points)
            return *st = jmr_fail(ctx, JMF_E_FORMAT, at_tok(v, t), "second POINTS section; expected one"), 1;
        *st = line_size(v, "a point count", &doc->npoints);
        if (*st) return 1;
        if (!jmr_mul(doc->npoints, 3, &nvals))
            return *st = jmr_fail(ctx, JMF_E_FORMAT, at_tok(v, t), "point count %zu overflows", doc->npoints), 1;
        doc->have_points = 1;
        *st = typed_values(v, nvals, SINK_POINTS, doc->pts, "POINTS", NULL);
    } else if (jmr_ieq(t->s, t->n, "CELLS") || jmr_ieq(t->s, t->n, "VERTICES") || jmr_ieq(t->s, t->n, "LINES") ||
               jmr_ieq(t->s, t->n, "POLYGONS") || jmr_ieq(t->s, t->n, "TRIANGLE_STRIPS")) {
        size_t nc = 0;
        *st = cells(v, jmr_ieq(t->s, t->n, "CELLS") ? "CELLS" : "the cell section", &nc);
        if (!jmr_add(doc->ncells, nc, &doc->ncells))
            return *st = jmr_fail(ctx, JMF_E_FORMAT, at_tok(v, t), "cell count overflows"), 1;
        doc->have_cells = 1;
    } else if (jmr_ieq(t->s, t->n, "CELL_TYPES")) {
        size_t n;
        *st = line_size(v, "a cell count", &n);
        if (!*st) *st = end_line(v, "CELL_TYPES");
        if (!*st) *st = values(v, n, JMR_T_I32, 0, SINK_NONE, NULL, "CELL_TYPES");
    } else if (jmr_ieq(t->s, t->n, "POINT_DATA") || jmr_ieq(t->s, t->n, "CELL_DATA")) {
        int mode = doc->mode = (t->s[0] == 'P' || t->s[0] == 'p') ? 1 : 2;
        *st = line_size(v, "an attribute count", &doc->attr_count);
        if (*st) return 1;
        if (mode == 1 && doc->have_points && doc->attr_count != doc->npoints)
            return *st = jmr_fail(ctx, JMF_E_FORMAT, at_tok(v, t), "POINT_DATA %zu; expected %zu as in POINTS",
                                  doc->attr_count, doc->npoints), 1;
        if (mode == 2 && doc->have_cells && doc->attr_count != doc->ncells)
            return *st = jmr_fail(ctx, JMF_E_FORMAT, at_tok(v, t), "CELL_DATA %zu; expected %zu as in the cells",
                                  doc->attr_count, doc->ncells), 1;
        *st = end_line(v, mode == 1 ? "POINT_DATA" : "CELL_DATA");
    } else
        return 0;
    return 1;
}

/* Sections of structured grids: walked, nothing kept. 1 if t was one. */
static int grid_section(vtk_doc *doc, const tok *t, jmf_status *st)
{
    vt *v = &doc->v;
    if (jmr_ieq(t->s, t->n, "DIMENSIONS") || jmr_ieq(t->s, t->n, "ORIGIN") || jmr_ieq(t->s, t->n, "SPACING") ||
        jmr_ieq(t->s, t->n, "ASPECT_RATIO")) {
        tok num;
        double d;
        for (int i = 0; i < 3 && !*st; i++) {
            *st = need_line_tok(v, &num, "a number");
            if (!*st && !jmr_parse_double(num.s, num.n, &d))
                *st = jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, &num), "expected a number, found '%.*s'", SHOW(num));
        }
        if (!*st) *st = end_line(v, "the three numbers");
        return 1;
    }
    if (jmr_ieq(t->s, t->n, "X_COORDINATES") || jmr_ieq(t->s, t->n, "Y_COORDINATES") ||
        jmr_ieq(t->s, t->n, "Z_COORDINATES")) {
        size_t n;
        *st = line_size(v, "a coordinate count", &n);
        if (!*st) *st = typed_values(v, n, SINK_NONE, NULL, "coordinates", NULL);
        return 1;
    }
    return 0;
}

/* SCALARS: the point ids ("id"), an attribute asked for, or skipped. */
static jmf_status scalars(vtk_doc *doc)
{
    vt *v = &doc->v;
    const jmr_ctx *ctx = v->ctx;
    jmr_points *pts = doc->pts;
    tok name, t;
    jmr_type ty;
    int is_bit;
    size_t ncomp = 1, total;
    enum sink sink = SINK_NONE;
    jmf_status st = need_line_tok(v, &name, "a SCALARS name");
    if (st) return st;
    st = line_type(v, &ty, &is_bit);
    if (st) return st;
    {
        tok c;
        if (line_tok(v, &c) && !jmr_parse_size(c.s, c.n, &ncomp))
            return jmr_fail(ctx, JMF_E_FORMAT, at_tok(v, &c), "expected a component count, found '%.*s'", SHOW(c));
        if (ncomp < 1 || ncomp > 4)
            return jmr_fail(ctx, JMF_E_FORMAT, at_tok(v, &c), "SCALARS with %zu components; expected 1 to 4", ncomp);
    }
    st = end_line(v, "SCALARS");
    if (st) return st;
    if (peek_kw(v, "LOOKUP_TABLE", &t)) {
        tok tn;
        st = need_line_tok(v, &tn, "a lookup table name");
        if (!st) st = end_line(v, "LOOKUP_TABLE");
        if (st) return st;
    }
    if (doc->attr_count > SIZE_MAX / 4)
        return jmr_fail(ctx, JMF_E_FORMAT, at_tok(v, &name), "attribute count %zu overflows", doc->attr_count);
    total = doc->attr_count * ncomp; /* ncomp <= 4 */
    if (doc->mode == 1 && ncomp == 1 && doc->have_points && !is_bit && jmr_type_is_int(ty) && name.n == 2 &&
        memcmp(name.s, "id", 2) == 0 && pts->count == doc->npoints) {
        st = jmr_points_want_ids(pts, ctx);
        if (st) return st;
        sink = SINK_IDS;
    } else if (doc->mode == 1 && !is_bit) {
        st = fits(v, total, ty, is_bit, "SCALARS");
        if (!st) st = jmr_attr_begin(pts, ctx, name.s, name.n, ncomp, doc->attr_count, at_tok(v, &name), &v->attr);
        if (st) return st;
        if (v->attr) sink = SINK_ATTR;
    }
    return values(v, total, ty, is_bit, sink, pts, "SCALARS");
}

/* LOOKUP_TABLE and COLOR_SCALARS: skipped. */
static jmf_status colours(vtk_doc *doc, const tok *t)
{
    vt *v = &doc->v;
    const int lookup = jmr_ieq(t->s, t->n, "LOOKUP_TABLE");
    tok name;
    size_t n, total;
    jmf_status st = need_line_tok(v, &name, lookup ? "a lookup table name" : "a COLOR_SCALARS name");
    if (!st) st = line_size(v, lookup ? "a lookup table size" : "a component count", &n);
    if (!st) st = end_line(v, lookup ? "LOOKUP_TABLE" : "COLOR_SCALARS");
    if (st) return st;
    if (lookup && !jmr_mul(n, 4, &total))
        return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, &name), "lookup table size %zu overflows", n);
    if (!lookup && !jmr_mul(doc->attr_count, n, &total))
        return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, &name), "COLOR_SCALARS size overflows");
    return values(v, total, v->binary ? JMR_T_U8 : JMR_T_F32, 0, SINK_NONE, NULL,
                  lookup ? "LOOKUP_TABLE" : "COLOR_SCALARS");
}

/* VECTORS, NORMALS, TENSORS(6), TEXTURE_COORDINATES, GLOBAL_IDS,
 * PEDIGREE_IDS: point VECTORS and NORMALS kept when asked for. */
static jmf_status tuples(vtk_doc *doc, const tok *t)
{
    vt *v = &doc->v;
    tok name;
    size_t per = 3, total;
    jmf_status st;
    if (jmr_ieq(t->s, t->n, "TENSORS")) per = 9;
    else if (jmr_ieq(t->s, t->n, "TENSORS6")) per = 6;
    else if (jmr_ieq(t->s, t->n, "GLOBAL_IDS") || jmr_ieq(t->s, t->n, "PEDIGREE_IDS")) per = 1;
    st = need_line_tok(v, &name, "an attribute name");
    if (st) return st;
    if (jmr_ieq(t->s, t->n, "TEXTURE_COORDINATES")) {
        st = line_size(v, "a texture dimension", &per);
        if (st) return st;
        if (per < 1 || per > 3)
            return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, &name), "texture dimension %zu; expected 1 to 3", per);
    }
    if (!jmr_mul(doc->attr_count, per, &total))
        return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, &name), "attribute size overflows");
    claim keep = { &name, per, doc->attr_count };
    int kept = doc->mode == 1 && (jmr_ieq(t->s, t->n, "VECTORS") || jmr_ieq(t->s, t->n, "NORMALS"));
    return typed_values(v, total, SINK_NONE, doc->pts, "attribute", kept ? &keep : NULL);
}

/* One section, by its keyword t. */
static jmf_status section(vtk_doc *doc, const tok *t)
{
    vt *v = &doc->v;
    jmf_status st = JMF_OK;
    if (jmr_ieq(t->s, t->n, "DATASET")) {
        if (doc->have_dataset)
            return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, t), "second DATASET; expected one");
        st = need_line_tok(v, &doc->dataset, "a dataset type");
        if (st) return st;
        doc->have_dataset = 1;
        return end_line(v, "DATASET");
    }
    if (!doc->have_dataset && !jmr_ieq(t->s, t->n, "FIELD"))
        return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, t), "expected DATASET, found '%.*s'", SHOW(*t));
    if (structure_section(doc, t, &st) || grid_section(doc, t, &st))
        return st;
    if (jmr_ieq(t->s, t->n, "FIELD")) /* dataset-level FIELD arrays have their own tuple counts */
        return field(v, doc->mode ? doc->attr_count : 0, doc->mode == 1, doc->pts);
    if (jmr_ieq(t->s, t->n, "METADATA"))
        return metadata(v);
    if (doc->mode && jmr_ieq(t->s, t->n, "SCALARS"))
        return scalars(doc);
    if (doc->mode && (jmr_ieq(t->s, t->n, "LOOKUP_TABLE") || jmr_ieq(t->s, t->n, "COLOR_SCALARS")))
        return colours(doc, t);
    if (doc->mode && (jmr_ieq(t->s, t->n, "VECTORS") || jmr_ieq(t->s, t->n, "NORMALS") ||
                      jmr_ieq(t->s, t->n, "TENSORS") || jmr_ieq(t->s, t->n, "TENSORS6") ||
                      jmr_ieq(t->s, t->n, "TEXTURE_COORDINATES") || jmr_ieq(t->s, t->n, "GLOBAL_IDS") ||
                      jmr_ieq(t->s, t->n, "PEDIGREE_IDS")))
        return tuples(doc, t);
    return jmr_fail(v->ctx, JMF_E_FORMAT, at_tok(v, t),
                    "unknown keyword '%.*s'; expected a section such as POINTS, CELLS, CELL_TYPES, "
                    "POINT_DATA, SCALARS or FIELD",
                    SHOW(*t));
}

jmf_status jmr_read_vtk(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts)
{
    vtk_doc doc;
    tok t;
    jmf_status st;
    memset(&doc, 0, sizeof doc);
    doc.v = (vt){ data, size, 0, 1, 0, ctx, NULL };
    doc.dataset = (tok){ "", 0, 0, 0 };
    doc.pts = pts;
    st = preamble(&doc.v);
    if (st) return st;
    while (next_tok(&doc.v, &t)) {
        st = section(&doc, &t);
        if (st) return st;
    }
    if (!doc.have_dataset)
        return jmr_fail(ctx, JMF_E_FORMAT, at_now(&doc.v), "truncated: expected DATASET and POINTS, found end of file");
    if (!doc.have_points) {
        const tok *ds = &doc.dataset;
        if (jmr_ieq(ds->s, ds->n, "STRUCTURED_POINTS") || jmr_ieq(ds->s, ds->n, "RECTILINEAR_GRID"))
            return jmr_fail(ctx, JMF_E_UNSUPPORTED, at_now(&doc.v), "dataset %.*s has no POINTS; expected point data",
                            SHOW(*ds));
        return jmr_fail(ctx, JMF_E_FORMAT, at_now(&doc.v), "no POINTS section; expected POINTS n type");
    }
    return JMF_OK;
}
