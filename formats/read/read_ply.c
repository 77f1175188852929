/* read_ply.c - reads the x, y, z (and optional id and asked-for) properties of the "vertex" element of a PLY file: ascii, binary LE or BE. */
#include "readbuf.h"

/*
 * The header declares elements and their properties (scalar or list, any of
 * the PLY numeric types, old or new names). Every element is read in order,
 * so elements before and after "vertex" (faces with list properties, ...) are
 * skipped exactly and a truncated body is noticed. Data after the last
 * element other than blanks is an error, as in VTK: rows beyond the count
 * the header declares (issue 30). Errors name the line in the header and in
 * ascii bodies, the byte offset in binary bodies.
 */

#define MAX_PROPS 256
#define MAX_ELEMS 64

typedef struct prop {
    jmr_type type;      /* value type */
    jmr_type count_type; /* list count type, JMR_T_NONE for scalars */
    int role;           /* 0..2 x y z, 3 id, -1 other */
    const char *name;
    size_t namelen;
    jmr_attr *attr;     /* the attribute it fills (asked for), or NULL */
    size_t comp;
} prop;

typedef struct elem {
    const char *name;
    size_t namelen;
    size_t count;
    size_t first, nprops; /* into the property table */
    int is_vertex;
    size_t line;
} elem;

typedef struct hdr_line {
    const char *s;
    size_t n;
} hdr_line;

static jmr_type ply_type(const char *s, size_t n)
{
    static const struct { const char *name; jmr_type t; } types[] = {
        { "char", JMR_T_I8 }, { "int8", JMR_T_I8 }, { "uchar", JMR_T_U8 }, { "uint8", JMR_T_U8 },
        { "short", JMR_T_I16 }, { "int16", JMR_T_I16 }, { "ushort", JMR_T_U16 }, { "uint16", JMR_T_U16 },
        { "int", JMR_T_I32 }, { "int32", JMR_T_I32 }, { "uint", JMR_T_U32 }, { "uint32", JMR_T_U32 },
        { "float", JMR_T_F32 }, { "float32", JMR_T_F32 }, { "double", JMR_T_F64 }, { "float64", JMR_T_F64 },
        { "int64", JMR_T_I64 }, { "uint64", JMR_T_U64 },
    };
    size_t i;
    for (i = 0; i < sizeof types / sizeof types[0]; i++)
        if (n == strlen(types[i].name) && memcmp(s, types[i].name, n) == 0) return types[i].t;
    return JMR_T_NONE;
}

/* Splits a header line into up to max words; returns the number found (max+1 if more). */
static size_t words(const char *s, size_t n, hdr_line *w, size_t max)
{
    size_t k = 0, i = 0;
    while (i < n) {
        size_t st;
        while (i < n && jmr_isspace(s[i])) i++;
        if (i >= n) break;
        st = i;
        while (i < n && !jmr_isspace(s[i])) i++;
        if (k == max) return max + 1;
        w[k].s = s + st;
        w[k].n = i - st;
        k++;
    }
    return k;
}

#define SHOW(w) (int)((w).n > 40 ? 40 : (w).n), (w).s

typedef struct body {
    const uint8_t *d;
    size_t n, pos, line;
    const jmr_ctx *ctx;
    int format; /* 0 ascii, 1 LE, 2 BE */
} body;

static jmr_at body_at(const body *b, size_t pos, size_t line)
{
    return b->format == 0 ? jmr_line(line) : jmr_byte(pos);
}

/* One ascii token as a number. */
static jmf_status ascii_num(body *b, double *out, const char *what)
{
    size_t s;
    while (b->pos < b->n && jmr_isspace(b->d[b->pos])) {
        if (b->d[b->pos] == '\n') b->line++;
        b->pos++;
    }
    if (b->pos >= b->n)
        return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_line(b->line), "truncated: expected %s, found end of file", what);
    s = b->pos;
    while (b->pos < b->n && !jmr_isspace(b->d[b->pos])) b->pos++;
    if (!jmr_parse_double((const char *)b->d + s, b->pos - s, out))
        return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_line(b->line), "expected %s (a number), found '%.*s'", what,
                        (int)(b->pos - s > 40 ? 40 : b->pos - s), (const char *)b->d + s);
    return JMF_OK;
}

/* One value of type t (binary) or one token (ascii). */
static jmf_status value(body *b, jmr_type t, double *out, const char *what)
{
    size_t sz;
    if (b->format == 0) return ascii_num(b, out, what);
    sz = jmr_type_size(t);
    if (sz > b->n - b->pos)
        return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(b->pos), "truncated: expected %s (%zu bytes), %zu bytes left",
                        what, sz, b->n - b->pos);
    *out = jmr_load(b->d + b->pos, t, b->format == 2);
    b->pos += sz;
    return JMF_OK;
}

/*
 * The element's claimed rows checked against the bytes left, before
 * anything is allocated for them (issue 30): binary rows take at least the
 * sizes of their scalars and list counts; ascii rows a character and a
 * separator per property.
 */
static jmf_status elem_fits(const body *b, const elem *e, const prop *props)
{
    size_t k, minrow = 0, need, left = b->n - b->pos;
    for (k = 0; k < e->nprops; k++) {
        const prop *p = &props[e->first + k];
        minrow += b->format == 0 ? 2 : jmr_type_size(p->count_type != JMR_T_NONE ? p->count_type : p->type);
    }
    if (b->format == 0) left++; /* no separator after the last value */
    if (!jmr_mul(e->count, minrow, &need) || need > left) {
        if (b->format != 0)
            return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(b->pos),
                            "truncated: element of %zu rows needs at least %zu bytes each, only %zu bytes left",
                            e->count, minrow, b->n - b->pos);
        return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_line(e->line),
                        "truncated: element of %zu rows of %zu values cannot fit in the %zu bytes after the "
                        "header",
                        e->count, e->nprops, b->n - b->pos);
    }
    return JMF_OK;
}

static jmf_status read_elem(body *b, const elem *e, const prop *props, jmr_points *pts)
{
    size_t r, k;
    jmf_status st;
    if (e->nprops == 0) return JMF_OK; /* rows without properties take no bytes */
    if (b->format != 0) {
        st = elem_fits(b, e, props);
        if (st) return st;
    }
    if (e->is_vertex) {
        size_t guess = b->format == 0 ? (b->n - b->pos) / 2 + 1 : e->count;
        st = jmr_points_reserve(pts, b->ctx, e->count < guess ? e->count : guess);
        if (st) return st;
    }
    for (r = 0; r < e->count; r++) {
        double xyz[3] = { 0, 0, 0 };
        uint64_t id = 0;
        int id_ok = 1;
        size_t at_pos, at_line;
        if (b->format == 0)
            while (b->pos < b->n && jmr_isspace(b->d[b->pos])) {
                if (b->d[b->pos] == '\n') b->line++;
                b->pos++;
            }
        at_pos = b->pos;
        at_line = b->line;
        for (k = 0; k < e->nprops; k++) {
            const prop *p = &props[e->first + k];
            double d;
            if (p->count_type != JMR_T_NONE) {
                size_t len, i;
                st = value(b, p->count_type, &d, "a list length");
                if (st) return st;
                if (!(d >= 0 && d <= 1e15 && d == (double)(size_t)d))
                    return jmr_fail(b->ctx, JMF_E_FORMAT, body_at(b, b->pos, b->line),
                                    "list length %g; expected a non-negative integer", d);
                len = (size_t)d;
                if (b->format != 0) {
                    size_t bytes;
                    if (!jmr_mul(len, jmr_type_size(p->type), &bytes) || bytes > b->n - b->pos)
                        return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(b->pos),
                                        "truncated: list of %zu values does not fit in the %zu bytes left", len,
                                        b->n - b->pos);
                    b->pos += bytes;
                } else {
                    for (i = 0; i < len; i++) {
                        st = ascii_num(b, &d, "a list value");
                        if (st) return st;
                    }
                }
                continue;
            }
            st = value(b, p->type, &d, "a property value");
            if (st) return st;
            if (p->attr) jmr_attr_set(p->attr, pts->count, p->comp, d);
            if (p->role >= 0 && p->role < 3) xyz[p->role] = d;
            else if (p->role == 3) {
                id_ok = d >= 0 && d <= 4294967295.0 && d == (double)(uint32_t)d;
                id = id_ok ? (uint64_t)d : 0;
            }
        }
        if (e->is_vertex) {
            st = jmr_points_add(pts, b->ctx, xyz[0], xyz[1], xyz[2], 0, body_at(b, at_pos, at_line));
            if (st) return st;
            jmr_points_set_id(pts, pts->count - 1, id, id_ok);
        }
    }
    return JMF_OK;
}

/* The vertex element's other scalar properties asked for as attributes
 * (grouped NAME_x/_y/_z), kept once the rows claimed can be in the file
 * at all (elem_fits). */
static jmf_status begin_attrs(const body *b, const elem *e, prop *props, jmr_points *pts)
{
    const char *nm[MAX_PROPS];
    size_t nl[MAX_PROPS], ng, k;
    int skip[MAX_PROPS];
    jmr_colgroup g[MAX_PROPS];
    jmf_status st = elem_fits(b, e, props);
    if (st) return st;
    for (k = 0; k < e->nprops; k++) {
        const prop *p = &props[e->first + k];
        nm[k] = p->name;
        nl[k] = p->namelen;
        skip[k] = p->role != -1 || p->count_type != JMR_T_NONE || (p->namelen == 2 && memcmp(p->name, "id", 2) == 0);
    }
    ng = jmr_group_columns(nm, nl, skip, e->nprops, g);
    for (k = 0; k < ng; k++) {
        jmr_attr *a = NULL;
        st = jmr_attr_begin(pts, b->ctx, g[k].name, strlen(g[k].name), (size_t)g[k].comps, e->count,
                            jmr_line(e->line), &a);
        if (st) return st;
        for (int c = 0; a && c < g[k].comps; c++) {
            props[e->first + g[k].cols[c]].attr = a;
            props[e->first + g[k].cols[c]].comp = (size_t)c;
        }
    }
    return JMF_OK;
}

/* The header as read so far. */
typedef struct ply_header {
    prop props[MAX_PROPS];
    elem elems[MAX_ELEMS];
    size_t nprops, nelems, pos, line;
    int format, vertex_seen;
    const jmr_ctx *ctx;
} ply_header;

static jmf_status header_format(ply_header *h, const hdr_line *w, size_t nw)
{
    if (nw != 3)
        return jmr_fail(h->ctx, JMF_E_FORMAT, jmr_line(h->line), "expected 'format TYPE 1.0'");
    if (jmr_ieq(w[1].s, w[1].n, "ascii")) h->format = 0;
    else if (jmr_ieq(w[1].s, w[1].n, "binary_little_endian")) h->format = 1;
    else if (jmr_ieq(w[1].s, w[1].n, "binary_big_endian")) h->format = 2;
    else
        return jmr_fail(h->ctx, JMF_E_FORMAT, jmr_line(h->line),
                        "unknown format '%.*s'; expected ascii, binary_little_endian or binary_big_endian",
                        SHOW(w[1]));
    return JMF_OK;
}

static jmf_status header_element(ply_header *h, const hdr_line *w, size_t nw)
{
    elem *e;
    if (nw != 3)
        return jmr_fail(h->ctx, JMF_E_FORMAT, jmr_line(h->line), "expected 'element NAME COUNT'");
    if (h->nelems == MAX_ELEMS)
        return jmr_fail(h->ctx, JMF_E_UNSUPPORTED, jmr_line(h->line), "more than %d elements", MAX_ELEMS);
    e = &h->elems[h->nelems];
    if (!jmr_parse_size(w[2].s, w[2].n, &e->count))
        return jmr_fail(h->ctx, JMF_E_FORMAT, jmr_line(h->line), "expected an element count, found '%.*s'",
                        SHOW(w[2]));
    e->name = w[1].s;
    e->namelen = w[1].n;
    e->first = h->nprops;
    e->nprops = 0;
    e->line = h->line;
    e->is_vertex = !h->vertex_seen && w[1].n == 6 && memcmp(w[1].s, "vertex", 6) == 0;
    if (e->is_vertex) h->vertex_seen = 1;
    h->nelems++;
    return JMF_OK;
}

static jmf_status header_property(ply_header *h, const hdr_line *w, size_t nw)
{
    const jmr_ctx *ctx = h->ctx;
    prop *p;
    hdr_line name;
    if (h->nelems == 0)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(h->line), "property before any element");
    if (h->nprops == MAX_PROPS)
        return jmr_fail(ctx, JMF_E_UNSUPPORTED, jmr_line(h->line), "more than %d properties", MAX_PROPS);
    p = &h->props[h->nprops];
    if (nw >= 2 && w[1].n == 4 && memcmp(w[1].s, "list", 4) == 0) {
        if (nw != 5)
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(h->line), "expected 'property list COUNTTYPE TYPE NAME'");
        p->count_type = ply_type(w[2].s, w[2].n);
        p->type = ply_type(w[3].s, w[3].n);
        if (p->count_type == JMR_T_NONE || p->type == JMR_T_NONE || !jmr_type_is_int(p->count_type))
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(h->line),
                            "unknown list types '%.*s %.*s'; expected an integer count type and a PLY type",
                            SHOW(w[2]), SHOW(w[3]));
        name = w[4];
        p->role = -1;
    } else {
        if (nw != 3)
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(h->line), "expected 'property TYPE NAME'");
        p->count_type = JMR_T_NONE;
        p->type = ply_type(w[1].s, w[1].n);
        if (p->type == JMR_T_NONE)
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(h->line),
                            "unknown property type '%.*s'; expected char, uchar, short, ushort, int, "
                            "uint, float, double (or int8..float64)",
                            SHOW(w[1]));
        name = w[2];
        p->role = -1;
        if (name.n == 1 && name.s[0] >= 'x' && name.s[0] <= 'z') p->role = name.s[0] - 'x';
        else if (name.n == 2 && memcmp(name.s, "id", 2) == 0) p->role = 3;
    }
    p->name = name.s;
    p->namelen = name.n;
    p->attr = NULL;
    p->comp = 0;
    h->elems[h->nelems - 1].nprops++;
    h->nprops++;
    return JMF_OK;
}

/* The header, one line at a time, up to end_header. */
static jmf_status read_header(ply_header *h, const uint8_t *data, size_t size)
{
    const jmr_ctx *ctx = h->ctx;
    int have_end = 0;
    jmf_status st;
    while (h->pos < size) {
        const char *s = (const char *)data + h->pos;
        const uint8_t *nl = memchr(data + h->pos, '\n', size - h->pos);
        size_t n = nl ? (size_t)(nl - (data + h->pos)) : size - h->pos, nw;
        hdr_line w[6];
        h->line++;
        h->pos = nl ? (size_t)(nl - data) + 1 : size;
        if (!nl)
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(h->line), "truncated header: expected end_header");
        if (n > 0 && s[n - 1] == '\r') n--;
        nw = words(s, n, w, 5);
        if (h->line == 1) {
            if (nw != 1 || w[0].n != 3 || memcmp(w[0].s, "ply", 3) != 0)
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(1), "wrong magic; expected 'ply'");
            continue;
        }
        if (nw == 0) continue;
        if ((w[0].n == 7 && memcmp(w[0].s, "comment", 7) == 0) ||
            (w[0].n == 8 && memcmp(w[0].s, "obj_info", 8) == 0))
            continue;
        if (w[0].n == 10 && memcmp(w[0].s, "end_header", 10) == 0) {
            have_end = 1;
            break;
        }
        if (w[0].n == 6 && memcmp(w[0].s, "format", 6) == 0) st = header_format(h, w, nw);
        else if (w[0].n == 7 && memcmp(w[0].s, "element", 7) == 0) st = header_element(h, w, nw);
        else if (w[0].n == 8 && memcmp(w[0].s, "property", 8) == 0) st = header_property(h, w, nw);
        else
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(h->line),
                            "unknown header line '%.*s'; expected format, element, property, comment or end_header",
                            SHOW(w[0]));
        if (st) return st;
    }
    if (!have_end)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(h->line), "truncated header: expected end_header");
    if (h->format < 0)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(h->line), "no 'format' line in the header");
    return JMF_OK;
}

/* The vertex element's x, y, z and id (the first of each name), and the
 * attributes asked for; b set up at the start of the body. */
static jmf_status vertex_roles(ply_header *h, const uint8_t *data, size_t size, jmr_points *pts, body *b)
{
    const jmr_ctx *ctx = h->ctx;
    size_t i;
    jmf_status st;
    for (i = 0; i < h->nelems && !h->elems[i].is_vertex; i++) {}
    if (i == h->nelems)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(h->line), "no 'element vertex' in the header");
    const elem *e = &h->elems[i];
    int have[4] = { 0, 0, 0, 0 };
    for (size_t k = 0; k < e->nprops; k++) {
        prop *p = &h->props[e->first + k];
        if (p->role >= 0) {
            if (have[p->role]) {
                p->role = -1; /* a duplicate name: use the first */
                continue;
            }
            have[p->role] = 1;
        }
    }
    if (!have[0] || !have[1] || !have[2])
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_line(e->line),
                        "element vertex has no '%s' property; expected scalar x, y and z",
                        !have[0] ? "x" : !have[1] ? "y" : "z");
    if (have[3]) {
        st = jmr_points_want_ids(pts, ctx);
        if (st) return st;
    }
    b->d = data;
    b->n = size;
    b->pos = h->pos;
    b->line = h->line + 1;
    b->ctx = ctx;
    b->format = h->format;
    if (jmr_attrs_wanted(ctx) && e->nprops) {
        st = begin_attrs(b, e, h->props, pts);
        if (st) return st;
    }
    return JMF_OK;
}

jmf_status jmr_read_ply(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts)
{
    ply_header h; /* 16 KiB: the tables are bounded (MAX_PROPS, MAX_ELEMS) */
    body b;
    jmf_status st;
    h.nprops = h.nelems = h.pos = h.line = 0;
    h.format = -1;
    h.vertex_seen = 0;
    h.ctx = ctx;
    st = read_header(&h, data, size);
    if (!st) st = vertex_roles(&h, data, size, pts, &b);
    if (st) return st;

    for (size_t i = 0; i < h.nelems; i++) {
        st = read_elem(&b, &h.elems[i], h.props, pts);
        if (st) return st;
    }
    while (b.pos < size && jmr_isspace(data[b.pos])) {
        if (data[b.pos] == '\n') b.line++;
        b.pos++;
    }
    if (b.pos < size) {
        const elem *e = &h.elems[h.nelems - 1];
        return jmr_fail(ctx, JMF_E_FORMAT, body_at(&b, b.pos, b.line),
                        "data after the last element ('%.*s', %zu rows as the header declares); expected the "
                        "end of the file: the header's count is lower than the rows",
                        (int)(e->namelen > 40 ? 40 : e->namelen), e->name, e->count);
    }
    return JMF_OK;
}
