/* read_vtu.c - reads the Points (and PointData arrays asked for) of a VTK XML UnstructuredGrid (.vtu): ascii, base64 binary, appended raw/base64, zlib blocks. */
#include "readbuf.h"

#include <stdlib.h>

/*
 * A small bounds-checked XML scan (no entities, no namespaces): it finds
 * <VTKFile> (type UnstructuredGrid or PolyData, byte_order, header_type
 * UInt32/UInt64, compressor none or vtkZLibDataCompressor), every <Piece>
 * with NumberOfPoints, the first DataArray inside its <Points> (3
 * components, any numeric type) and a PointData DataArray Name="id" of an
 * integer type (optional ids). Scanning stops at <AppendedData> (raw data
 * may hold any byte); the file must end with </VTKFile>, so a truncated file
 * is noticed. Data blocks are a header (one size, or with compression:
 * nblocks, blocksize, lastblocksize, compressed sizes) then the data;
 * base64 data may be encoded in one piece or header and data separately.
 * Pieces are concatenated.
 */

#define MAX_ATTRS 32
#define MAX_PIECES 4096

typedef struct xattr {
    const char *name, *val;
    size_t nlen, vlen;
} xattr;

typedef struct xtag {
    const char *name;
    size_t nlen, pos;
    int end, selfclose;
    xattr a[MAX_ATTRS];
    size_t na;
} xtag;

typedef struct xs {
    const uint8_t *d;
    size_t n, pos;
    const jmr_ctx *ctx;
} xs;

enum { FMT_ASCII, FMT_BINARY, FMT_APPENDED };

typedef struct darr {
    int present;
    jmr_type type;
    size_t ncomp;
    int fmt;
    size_t offset;      /* appended */
    size_t seg, seglen; /* inline content (one text run) */
    size_t tagpos;
} darr;

#define MAX_POINT_ARRAYS 32

typedef struct piece {
    size_t npoints;
    size_t tagpos;
    darr pts, ids;
    darr arrs[MAX_POINT_ARRAYS]; /* PointData arrays other than id */
    const char *names[MAX_POINT_ARRAYS];
    size_t namelens[MAX_POINT_ARRAYS];
    size_t narrs;
} piece;

typedef struct vtu {
    xs x;
    int big_endian, hsize, zlib;
    int appended_b64;
    size_t appended; /* first byte after '_' */
    int have_appended;
    size_t decoded, decoded_max; /* bytes decoded so far, and the cap for all arrays together */
} vtu;

static int tag_is(const xtag *t, const char *name)
{
    return t->nlen == strlen(name) && memcmp(t->name, name, t->nlen) == 0;
}

static const xattr *attr(const xtag *t, const char *name)
{
    size_t i;
    for (i = 0; i < t->na; i++)
        if (t->a[i].nlen == strlen(name) && memcmp(t->a[i].name, name, t->a[i].nlen) == 0) return &t->a[i];
    return NULL;
}

static int val_is(const xattr *a, const char *v)
{
    return a && a->vlen == strlen(v) && memcmp(a->val, v, a->vlen) == 0;
}

#define SHOWA(a) (int)((a)->vlen > 40 ? 40 : (a)->vlen), (a)->val

static int is_name_char(uint8_t c)
{
    return !(jmr_isspace(c) || c == '/' || c == '>' || c == '=' || c == '<' || c == '"' || c == '\'');
}

/* Finds s in d[from..n); returns its position or n. */
static size_t find(const uint8_t *d, size_t n, size_t from, const char *s)
{
    size_t k = strlen(s);
    while (from < n && k <= n - from) {
        const uint8_t *p = memchr(d + from, s[0], n - from);
        if (!p) return n;
        from = (size_t)(p - d);
        if (k <= n - from && memcmp(p, s, k) == 0) return from;
        from++;
    }
    return n;
}

/*
 * Parses the markup at x->pos (which is '<'). Comments, processing
 * instructions, CDATA and declarations are skipped (returns 0 with *skipped).
 */
static jmf_status parse_tag(xs *x, xtag *t, int *skipped)
{
    const uint8_t *d = x->d;
    size_t n = x->n, p = x->pos + 1, e;
    *skipped = 0;
    if (p < n && (d[p] == '?' || d[p] == '!')) {
        const char *close = "?>";
        if (n - p >= 3 && memcmp(d + p, "!--", 3) == 0) close = "-->";
        else if (n - p >= 8 && memcmp(d + p, "![CDATA[", 8) == 0) close = "]]>";
        else if (d[p] == '!') close = ">";
        e = find(d, n, p, close);
        if (e == n)
            return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(x->pos), "truncated XML: expected '%s'", close);
        x->pos = e + strlen(close);
        *skipped = 1;
        return JMF_OK;
    }
    memset(t, 0, sizeof *t);
    t->pos = x->pos;
    if (p < n && d[p] == '/') { t->end = 1; p++; }
    t->name = (const char *)d + p;
    while (p < n && is_name_char(d[p])) p++;
    t->nlen = (size_t)((const char *)d + p - t->name);
    if (t->nlen == 0)
        return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(x->pos), "expected an XML tag name after '<'");
    for (;;) {
        size_t ns;
        while (p < n && jmr_isspace(d[p])) p++;
        if (p >= n) return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(t->pos), "truncated XML tag: expected '>'");
        if (d[p] == '>') { p++; break; }
        if (d[p] == '/' && p + 1 < n && d[p + 1] == '>') { t->selfclose = 1; p += 2; break; }
        if (t->end)
            return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(p), "expected '>' to close the end tag");
        ns = p;
        while (p < n && is_name_char(d[p])) p++;
        if (p == ns)
            return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(p), "unexpected character '%c' in XML tag; expected an attribute",
                            d[p] >= 0x20 && d[p] < 0x7f ? d[p] : '?');
        {
            size_t nlen = p - ns, vs;
            uint8_t q;
            while (p < n && jmr_isspace(d[p])) p++;
            if (p >= n || d[p] != '=')
                return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(p), "expected '=' after an XML attribute name");
            p++;
            while (p < n && jmr_isspace(d[p])) p++;
            if (p >= n || (d[p] != '"' && d[p] != '\''))
                return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(p), "expected a quoted XML attribute value");
            q = d[p++];
            vs = p;
            while (p < n && d[p] != q) p++;
            if (p >= n)
                return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(vs), "truncated XML attribute value: expected a closing quote");
            if (t->na < MAX_ATTRS) {
                xattr *a = &t->a[t->na++];
                a->name = (const char *)d + ns;
                a->nlen = nlen;
                a->val = (const char *)d + vs;
                a->vlen = p - vs;
            }
            p++;
        }
    }
    x->pos = p;
    return JMF_OK;
}

/* Next tag (skipping text, comments, declarations); 0 in *got at end of input. */
static jmf_status next_tag(xs *x, xtag *t, int *got)
{
    for (;;) {
        const uint8_t *lt;
        int skipped;
        jmf_status st;
        *got = 0;
        if (x->pos >= x->n) return JMF_OK;
        lt = memchr(x->d + x->pos, '<', x->n - x->pos);
        if (!lt) { x->pos = x->n; return JMF_OK; }
        x->pos = (size_t)(lt - x->d);
        st = parse_tag(x, t, &skipped);
        if (st) return st;
        if (!skipped) { *got = 1; return JMF_OK; }
    }
}

/* Skips to the end of the element whose start tag (not self-closing) was just read. */
static jmf_status skip_element(xs *x, const xtag *start)
{
    size_t depth = 1;
    while (depth) {
        xtag t;
        int got;
        jmf_status st = next_tag(x, &t, &got);
        if (st) return st;
        if (!got)
            return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(x->n), "truncated XML: expected </%.*s>",
                            (int)(start->nlen > 40 ? 40 : start->nlen), start->name);
        if (t.end) depth--;
        else if (!t.selfclose) depth++;
    }
    return JMF_OK;
}

static jmr_type vtu_type(const xattr *a)
{
    static const struct { const char *name; jmr_type t; } types[] = {
        { "Int8", JMR_T_I8 }, { "UInt8", JMR_T_U8 }, { "Int16", JMR_T_I16 }, { "UInt16", JMR_T_U16 },
        { "Int32", JMR_T_I32 }, { "UInt32", JMR_T_U32 }, { "Int64", JMR_T_I64 }, { "UInt64", JMR_T_U64 },
        { "Float32", JMR_T_F32 }, { "Float64", JMR_T_F64 },
    };
    size_t i;
    for (i = 0; a && i < sizeof types / sizeof types[0]; i++)
        if (val_is(a, types[i].name)) return types[i].t;
    return JMR_T_NONE;
}

static int attr_size(const xattr *a, size_t *out)
{
    size_t s = 0, e;
    if (!a) return 0;
    e = a->vlen;
    while (s < e && jmr_isspace((unsigned char)a->val[s])) s++;
    while (e > s && jmr_isspace((unsigned char)a->val[e - 1])) e--;
    return jmr_parse_size(a->val + s, e - s, out);
}

/* Reads a DataArray start tag into *da, and its inline content unless self-closing. */
static jmf_status data_array(vtu *v, const xtag *t, darr *da)
{
    const xattr *ty = attr(t, "type"), *nc = attr(t, "NumberOfComponents"), *fm = attr(t, "format");
    xs *x = &v->x;
    memset(da, 0, sizeof *da);
    da->present = 1;
    da->tagpos = t->pos;
    da->type = vtu_type(ty);
    if (da->type == JMR_T_NONE)
        return jmr_fail(x->ctx, ty ? JMF_E_UNSUPPORTED : JMF_E_FORMAT, jmr_byte(t->pos),
                        "DataArray type '%.*s'; expected Float32, Float64 or an integer type",
                        ty ? (int)(ty->vlen > 40 ? 40 : ty->vlen) : 0, ty ? ty->val : "");
    da->ncomp = 1;
    if (nc && !attr_size(nc, &da->ncomp))
        return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(t->pos), "DataArray NumberOfComponents '%.*s'; expected a count",
                        SHOWA(nc));
    if (!fm || val_is(fm, "ascii")) da->fmt = FMT_ASCII;
    else if (val_is(fm, "binary")) da->fmt = FMT_BINARY;
    else if (val_is(fm, "appended")) da->fmt = FMT_APPENDED;
    else
        return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(t->pos), "DataArray format '%.*s'; expected ascii, binary or appended",
                        SHOWA(fm));
    if (da->fmt == FMT_APPENDED && !attr_size(attr(t, "offset"), &da->offset))
        return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(t->pos), "appended DataArray without a valid offset attribute");
    /* where its (empty) content is, for messages */
    da->seg = t->selfclose ? t->pos : x->pos;
    if (t->selfclose) return JMF_OK;
    /* content: one non-blank text run (a CDATA section is text too),
     * nested elements (InformationKey) skipped */
    for (;;) {
        size_t s = x->pos, e, i;
        const uint8_t *lt = memchr(x->d + s, '<', x->n - s);
        xtag in;
        int skipped, cdata;
        jmf_status st;
        e = lt ? (size_t)(lt - x->d) : x->n;
        cdata = x->n - s >= 9 && memcmp(x->d + s, "<![CDATA[", 9) == 0;
        if (cdata) {
            s += 9;
            e = find(x->d, x->n, s, "]]>");
            if (e == x->n)
                return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(s - 9), "truncated XML: expected ']]>'");
        }
        for (i = s; i < e && jmr_isspace(x->d[i]); i++) {}
        if (i < e) {
            if (da->seglen)
                return jmr_fail(x->ctx, JMF_E_UNSUPPORTED, jmr_byte(i), "DataArray data split by elements");
            da->seg = s;
            da->seglen = e - s;
        }
        x->pos = cdata ? e + 3 : e;
        if (cdata) continue;
        if (!lt)
            return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(x->n), "truncated XML: expected </DataArray>");
        if (x->n - e >= 9 && memcmp(x->d + e, "<![CDATA[", 9) == 0) continue; /* the next run */
        st = parse_tag(x, &in, &skipped);
        if (st) return st;
        if (skipped) continue;
        if (in.end) {
            if (!tag_is(&in, "DataArray"))
                return jmr_fail(x->ctx, JMF_E_FORMAT, jmr_byte(in.pos), "expected </DataArray>, found </%.*s>",
                                (int)(in.nlen > 40 ? 40 : in.nlen), in.name);
            return JMF_OK;
        }
        if (!in.selfclose) {
            st = skip_element(x, &in);
            if (st) return st;
        }
    }
}

/* ---- byte sources: raw memory or base64 text ---- */

typedef struct src {
    const uint8_t *d;
    size_t n, pos;
    int b64;
    uint8_t carry[3];
    size_t ncarry, cpos;
} src;

static int b64val(uint8_t c)
{
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
}

/* Decodes one group of 4 (padding allowed at the end of any group); returns bytes (0 at the end). */
static size_t b64_group(src *s, uint8_t out[3])
{
    int v[4], k = 0, pad = 0;
    while (k < 4 && s->pos < s->n) {
        uint8_t c = s->d[s->pos];
        if (jmr_isspace(c)) { s->pos++; continue; }
        if (c == '=') {
            if (k < 2) break;
            pad++;
            v[k++] = 0;
            s->pos++;
            continue;
        }
        if (pad) break;
        v[k] = b64val(c);
        if (v[k] < 0) break;
        k++;
        s->pos++;
    }
    if (k < 2) return 0;
    while (k < 4) { v[k++] = 0; pad++; } /* unpadded tail */
    out[0] = (uint8_t)((v[0] << 2) | (v[1] >> 4));
    out[1] = (uint8_t)((v[1] << 4) | (v[2] >> 2));
    out[2] = (uint8_t)((v[2] << 6) | v[3]);
    return pad >= 2 ? 1 : pad == 1 ? 2 : 3;
}

/* Reads k bytes into dst; returns the number read (less at the end of the data). */
static size_t src_read(src *s, uint8_t *dst, size_t k)
{
    size_t got = 0;
    if (!s->b64) {
        size_t m = s->n - s->pos < k ? s->n - s->pos : k;
        if (m) memcpy(dst, s->d + s->pos, m);
        s->pos += m;
        return m;
    }
    while (got < k) {
        if (s->cpos < s->ncarry) {
            dst[got++] = s->carry[s->cpos++];
            continue;
        }
        s->ncarry = b64_group(s, s->carry);
        s->cpos = 0;
        if (s->ncarry == 0) break;
    }
    return got;
}

/* Upper bound of the bytes still available (to refuse absurd sizes before allocating). */
static size_t src_avail(const src *s)
{
    size_t left = s->n - s->pos;
    return (s->b64 ? left / 4 * 3 + 3 : left) + (s->ncarry - s->cpos);
}

/* Where the source is, as a byte offset in the file. */
static size_t src_at(const src *s) { return s->pos; }

static jmf_status read_header_word(vtu *v, src *s, uint64_t *out, const char *what, size_t file_base)
{
    uint8_t b[8];
    size_t h = (size_t)v->hsize;
    if (src_read(s, b, h) != h)
        return jmr_fail(v->x.ctx, JMF_E_FORMAT, jmr_byte(file_base + src_at(s)),
                        "truncated data block: expected the %s (%zu-byte header word)", what, h);
    if (h == 4) *out = v->big_endian ? jmr_be32(b) : jmr_le32(b);
    else *out = v->big_endian ? jmr_be64(b) : jmr_le64(b);
    return JMF_OK;
}

/* deflate's largest expansion, about 1032:1 (a block of repeated bytes) */
#define ZLIB_MAX_RATIO 1032

/* Counts bytes more decoded bytes against the cap for all arrays together:
 * the reader's limit (JMF_E_LIMIT), or what the file's size can decode to
 * at zlib's largest ratio, which only arrays sharing their data can pass
 * (a bad frame). */
static jmf_status decoded_room(vtu *v, size_t bytes, size_t at, const char *what)
{
    if (bytes > v->decoded_max - v->decoded) {
        if (v->decoded_max < jmr_max_decoded(v->x.ctx))
            return jmr_fail(v->x.ctx, JMF_E_FORMAT, jmr_byte(at),
                            "%s: the arrays claim over %zu decoded bytes, more than the file's %zu bytes can "
                            "hold (zlib expands at most %d:1)",
                            what, v->decoded_max, v->x.n, ZLIB_MAX_RATIO);
        return jmr_fail(v->x.ctx, JMF_E_LIMIT, jmr_byte(at), "%s: %zu more decoded bytes exceed the limit of %zu",
                        what, bytes, v->decoded_max);
    }
    v->decoded += bytes;
    return JMF_OK;
}

/*
 * Decodes one data block stream from s into a new buffer of exactly `bytes`
 * bytes. file_base + s->pos is the byte offset for messages.
 */
static jmf_status block_stream(vtu *v, src *s, size_t bytes, size_t file_base, uint8_t **out, const char *what)
{
    const jmr_ctx *ctx = v->x.ctx;
    uint8_t *buf;
    uint64_t w;
    jmf_status st;
    size_t at = file_base + src_at(s);
    *out = NULL;
    /* what the block claims is checked against the bytes there before the
     * limit (issue 30): a file that cannot hold it is a bad frame */
    if (!v->zlib) {
        st = read_header_word(v, s, &w, "byte count", file_base);
        if (st) return st;
        if (w != bytes)
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(at), "%s: block header says %llu bytes; expected %zu",
                            what, (unsigned long long)w, bytes);
        if (bytes > src_avail(s))
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(file_base + src_at(s)),
                            "truncated %s: expected %zu bytes of data, at most %zu left", what, bytes, src_avail(s));
        st = decoded_room(v, bytes, at, what);
        if (st) return st;
        buf = malloc(bytes ? bytes : 1);
        if (!buf) return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for %zu bytes", bytes);
        if (src_read(s, buf, bytes) != bytes) {
            free(buf);
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(file_base + src_at(s)),
                            "truncated %s: expected %zu bytes of data", what, bytes);
        }
        *out = buf;
        return JMF_OK;
    } else {
        uint64_t nblocks, bsize, last, total = 0, i;
        uint64_t *csize;
        size_t off = 0, maxc = 0;
        uint8_t *cbuf;
        st = read_header_word(v, s, &nblocks, "block count", file_base);
        if (!st) st = read_header_word(v, s, &bsize, "block size", file_base);
        if (!st) st = read_header_word(v, s, &last, "last block size", file_base);
        if (st) return st;
        if (nblocks > src_avail(s) / (size_t)v->hsize)
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(at),
                            "%s: %llu compressed blocks cannot fit in the %zu bytes left", what,
                            (unsigned long long)nblocks, src_avail(s));
        if (last > bsize || (nblocks > 0 && bsize == 0))
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(at), "%s: last block size %llu, block size %llu; expected "
                            "0 < last <= block size", what, (unsigned long long)last, (unsigned long long)bsize);
        if (nblocks > 0) {
            if (bsize > bytes ||
                nblocks - 1 > (uint64_t)bytes / bsize)
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(at), "%s: %llu blocks of %llu bytes; expected %zu bytes",
                                what, (unsigned long long)nblocks, (unsigned long long)bsize, bytes);
            total = (nblocks - 1) * bsize + (last ? last : bsize);
        }
        if (total != bytes)
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(at), "%s: compressed blocks hold %llu bytes; expected %zu",
                            what, (unsigned long long)total, bytes);
        csize = malloc((size_t)(nblocks ? nblocks : 1) * sizeof *csize);
        if (!csize) return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for the block table");
        for (i = 0; i < nblocks; i++) {
            st = read_header_word(v, s, &csize[i], "compressed block size", file_base);
            if (st) { free(csize); return st; }
            if (csize[i] > src_avail(s)) {
                unsigned long long c = (unsigned long long)csize[i];
                free(csize);
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(file_base + src_at(s)),
                                "truncated %s: block %llu of %llu compressed bytes does not fit in the %zu bytes left",
                                what, (unsigned long long)i, c, src_avail(s));
            }
            if (csize[i] > maxc) maxc = (size_t)csize[i];
            if ((i + 1 == nblocks && last ? last : bsize) > csize[i] * ZLIB_MAX_RATIO + 64) {
                unsigned long long c = (unsigned long long)csize[i];
                free(csize);
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(at),
                                "%s: compressed block %llu of %llu bytes cannot hold the %llu bytes its header "
                                "claims (zlib expands at most %d:1)",
                                what, (unsigned long long)i, c,
                                (unsigned long long)(i + 1 == nblocks && last ? last : bsize), ZLIB_MAX_RATIO);
            }
        }
        st = decoded_room(v, bytes, at, what);
        if (st) {
            free(csize);
            return st;
        }
        buf = malloc(bytes ? bytes : 1);
        cbuf = malloc(maxc ? maxc : 1);
        if (!buf || !cbuf) {
            free(buf); free(cbuf); free(csize);
            return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for %zu bytes", bytes);
        }
        for (i = 0; i < nblocks; i++) {
            size_t want = (size_t)(i + 1 == nblocks && last ? last : bsize), bat = file_base + src_at(s);
            const char *why;
            if (src_read(s, cbuf, (size_t)csize[i]) != csize[i]) {
                free(buf); free(cbuf); free(csize);
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(file_base + src_at(s)),
                                "truncated %s: compressed block %llu ends early", what, (unsigned long long)i);
            }
            why = jmr_zlib_block(cbuf, (size_t)csize[i], buf + off, want);
            if (why) {
                free(buf); free(cbuf); free(csize);
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(bat), "%s: compressed block %llu: %s", what,
                                (unsigned long long)i, why);
            }
            off += want;
        }
        free(cbuf);
        free(csize);
        *out = buf;
        return JMF_OK;
    }
}

/*
 * Decodes the values of da (count values) into a new buffer of count values
 * of da->type in the file's byte order; for ascii, into doubles (native).
 */
static jmf_status decode(vtu *v, const darr *da, size_t count, uint8_t **out, int *as_double, const char *what)
{
    const jmr_ctx *ctx = v->x.ctx;
    size_t bytes;
    src s;
    memset(&s, 0, sizeof s);
    *as_double = 0;
    *out = NULL;
    if (da->fmt == FMT_ASCII) {
        double *vals;
        size_t i = 0, p = da->seg, e = da->seg + da->seglen;
        if (!jmr_mul(count, sizeof(double), &bytes) || count > da->seglen / 2 + 1)
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(da->seg), "truncated %s: expected %zu ascii values in %zu bytes",
                            what, count, da->seglen);
        vals = malloc(bytes ? bytes : 1);
        if (!vals) return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for %zu values", count);
        for (;;) {
            size_t ts;
            while (p < e && jmr_isspace(v->x.d[p])) p++;
            if (p >= e) break;
            ts = p;
            while (p < e && !jmr_isspace(v->x.d[p])) p++;
            if (i == count) {
                free(vals);
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(ts), "%s: more than the expected %zu values", what, count);
            }
            if (!jmr_parse_double((const char *)v->x.d + ts, p - ts, &vals[i])) {
                free(vals);
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(ts), "%s: expected a number, found '%.*s'", what,
                                (int)(p - ts > 40 ? 40 : p - ts), (const char *)v->x.d + ts);
            }
            i++;
        }
        if (i != count) {
            free(vals);
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(e), "truncated %s: expected %zu values, found %zu", what, count, i);
        }
        *out = (uint8_t *)vals;
        *as_double = 1;
        return JMF_OK;
    }
    if (!jmr_mul(count, jmr_type_size(da->type), &bytes))
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(da->tagpos), "%s: %zu values overflow", what, count);
    if (da->fmt == FMT_BINARY) {
        s.d = v->x.d + da->seg;
        s.n = da->seglen;
        s.b64 = 1;
        return block_stream(v, &s, bytes, da->seg, out, what);
    }
    if (!v->have_appended)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(da->tagpos), "%s: appended DataArray but no <AppendedData>", what);
    if (da->offset > v->x.n - v->appended)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(da->tagpos), "%s: appended offset %zu is beyond the end of the file",
                        what, da->offset);
    s.d = v->x.d + v->appended + da->offset;
    s.n = v->x.n - v->appended - da->offset;
    s.b64 = v->appended_b64;
    return block_stream(v, &s, bytes, v->appended + da->offset, out, what);
}

static jmf_status read_piece(vtu *v, const piece *pc, jmr_points *pts)
{
    const jmr_ctx *ctx = v->x.ctx;
    size_t nvals, i, base = pts->count, sz;
    uint8_t *buf;
    int dbl;
    jmf_status st;
    if (pc->npoints == 0) return JMF_OK;
    if (!pc->pts.present)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(pc->tagpos), "Piece with %zu points has no <Points> DataArray",
                        pc->npoints);
    if (pc->pts.ncomp != 3)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(pc->pts.tagpos), "Points DataArray has %zu components; expected 3",
                        pc->pts.ncomp);
    if (!jmr_mul(pc->npoints, 3, &nvals))
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(pc->tagpos), "NumberOfPoints %zu overflows", pc->npoints);
    st = decode(v, &pc->pts, nvals, &buf, &dbl, "Points");
    if (st) return st;
    st = jmr_points_reserve(pts, ctx, pc->npoints);
    sz = jmr_type_size(pc->pts.type);
    for (i = 0; !st && i < pc->npoints; i++) {
        double c[3];
        int k;
        for (k = 0; k < 3; k++)
            c[k] = dbl ? ((double *)(void *)buf)[3 * i + k]
                       : jmr_load(buf + (3 * i + k) * sz, pc->pts.type, v->big_endian);
        st = jmr_points_add(pts, ctx, c[0], c[1], c[2], 0, jmr_byte(pc->pts.tagpos));
    }
    free(buf);
    if (st) return st;
    if (pc->ids.present && pc->ids.ncomp == 1 && jmr_type_is_int(pc->ids.type) && pts->ids) {
        st = decode(v, &pc->ids, pc->npoints, &buf, &dbl, "id");
        if (st) return st;
        sz = jmr_type_size(pc->ids.type);
        for (i = 0; i < pc->npoints; i++) {
            if (dbl) {
                double d = ((double *)(void *)buf)[i];
                int ok = d >= 0 && d <= 4294967295.0 && d == (double)(uint32_t)d;
                jmr_points_set_id(pts, base + i, ok ? (uint64_t)d : 0, ok);
            } else {
                int ok;
                uint64_t u = jmr_load_u64(buf + i * sz, pc->ids.type, v->big_endian, &ok);
                jmr_points_set_id(pts, base + i, u, ok);
            }
        }
        free(buf);
    } else if (pts->ids) {
        pts->ids_bad = 1; /* some piece without ids */
    }
    return JMF_OK;
}

/* The PointData arrays asked for (jmf_read_options.attributes), named as in
 * the first piece, concatenated over the pieces. */
static jmf_status read_arrays(vtu *v, const piece *pieces, size_t npieces, jmr_points *pts)
{
    const jmr_ctx *ctx = v->x.ctx;
    const piece *p0 = &pieces[0];
    for (size_t k = 0; k < p0->narrs; k++) {
        const darr *d0 = &p0->arrs[k];
        jmr_attr *a = NULL;
        size_t base = 0;
        jmf_status st = jmr_attr_begin(pts, ctx, p0->names[k], p0->namelens[k], d0->ncomp, pts->count,
                                       jmr_byte(d0->tagpos), &a);
        if (st) return st;
        for (size_t i = 0; a && i < npieces; i++) {
            const piece *pc = &pieces[i];
            const darr *da = NULL;
            size_t j, nvals, sz;
            uint8_t *buf;
            int dbl;
            for (j = 0; j < pc->narrs; j++)
                if (pc->namelens[j] == p0->namelens[k] && memcmp(pc->names[j], p0->names[k], p0->namelens[k]) == 0)
                    da = &pc->arrs[j];
            if (!da || da->ncomp != d0->ncomp)
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(pc->tagpos),
                                "attribute '%s': piece %zu has %s; expected %zu components per point", a->name, i,
                                da ? "another component count" : "no such PointData array", d0->ncomp);
            if (!jmr_mul(pc->npoints, da->ncomp, &nvals))
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(da->tagpos), "attribute '%s': size overflows", a->name);
            st = decode(v, da, nvals, &buf, &dbl, a->name);
            if (st) return st;
            sz = jmr_type_size(da->type);
            for (j = 0; j < nvals; j++)
                jmr_attr_set(a, base + j / da->ncomp, j % da->ncomp,
                             dbl ? ((double *)(void *)buf)[j] : jmr_load(buf + j * sz, da->type, v->big_endian));
            free(buf);
            base += pc->npoints;
        }
    }
    return JMF_OK;
}

/* Where the walk through the tags stands. */
typedef struct vtu_doc {
    vtu v;
    piece *pieces;
    size_t npieces, cap;
    int in_points, in_pointdata, in_piece, have_file, closed, any_ids;
} vtu_doc;

/* <VTKFile>: its type, byte order, header type and compressor. */
static jmf_status file_tag(vtu_doc *doc, const xtag *t)
{
    const jmr_ctx *ctx = doc->v.x.ctx;
    const xattr *a;
    if (!tag_is(t, "VTKFile") || t->end)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(t->pos), "expected <VTKFile>, found <%s%.*s>", t->end ? "/" : "",
                        (int)(t->nlen > 40 ? 40 : t->nlen), t->name);
    doc->have_file = 1;
    a = attr(t, "type");
    if (!val_is(a, "UnstructuredGrid") && !val_is(a, "PolyData"))
        return jmr_fail(ctx, JMF_E_UNSUPPORTED, jmr_byte(t->pos),
                        "VTKFile type '%.*s'; expected UnstructuredGrid (or PolyData)",
                        a ? (int)(a->vlen > 40 ? 40 : a->vlen) : 0, a ? a->val : "");
    a = attr(t, "byte_order");
    if (val_is(a, "BigEndian")) doc->v.big_endian = 1;
    else if (a && !val_is(a, "LittleEndian"))
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(t->pos), "byte_order '%.*s'; expected LittleEndian or BigEndian",
                        SHOWA(a));
    a = attr(t, "header_type");
    if (val_is(a, "UInt64")) doc->v.hsize = 8;
    else if (a && !val_is(a, "UInt32"))
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(t->pos), "header_type '%.*s'; expected UInt32 or UInt64", SHOWA(a));
    a = attr(t, "compressor");
    if (val_is(a, "vtkZLibDataCompressor")) doc->v.zlib = 1;
    else if (a && a->vlen)
        return jmr_fail(ctx, JMF_E_UNSUPPORTED, jmr_byte(t->pos),
                        "compressor '%.*s' is not supported; expected vtkZLibDataCompressor or none", SHOWA(a));
    if (t->selfclose) doc->closed = 1;
    return JMF_OK;
}

/* <Piece>: a new piece and its point count. */
static jmf_status piece_tag(vtu_doc *doc, const xtag *t)
{
    const jmr_ctx *ctx = doc->v.x.ctx;
    piece *pc;
    if (doc->npieces == MAX_PIECES)
        return jmr_fail(ctx, JMF_E_UNSUPPORTED, jmr_byte(t->pos), "more than %d pieces", MAX_PIECES);
    if (doc->npieces == doc->cap) {
        piece *np;
        doc->cap = doc->cap ? 2 * doc->cap : 4;
        np = realloc(doc->pieces, doc->cap * sizeof *doc->pieces);
        if (!np)
            return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for %zu pieces", doc->cap);
        doc->pieces = np;
    }
    pc = &doc->pieces[doc->npieces++];
    memset(pc, 0, sizeof *pc);
    pc->tagpos = t->pos;
    if (!attr_size(attr(t, "NumberOfPoints"), &pc->npoints))
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(t->pos), "Piece without a valid NumberOfPoints");
    doc->in_piece = !t->selfclose;
    doc->in_points = doc->in_pointdata = 0;
    return JMF_OK;
}

/* <DataArray>: the points, the ids or an attribute asked for, of the
 * piece it is in. */
static jmf_status data_array_tag(vtu_doc *doc, const xtag *t)
{
    piece *pc = doc->npieces ? &doc->pieces[doc->npieces - 1] : NULL;
    darr da;
    jmf_status st = data_array(&doc->v, t, &da);
    if (st) return st;
    if (!pc || !doc->in_piece)
        return JMF_OK;
    if (doc->in_points && !pc->pts.present) {
        pc->pts = da;
    } else if (doc->in_pointdata && !pc->ids.present && val_is(attr(t, "Name"), "id")) {
        pc->ids = da;
        doc->any_ids = 1;
    } else if (doc->in_pointdata && pc->narrs < MAX_POINT_ARRAYS && jmr_attrs_wanted(doc->v.x.ctx)) {
        const xattr *nm = attr(t, "Name");
        if (nm && nm->vlen) {
            pc->arrs[pc->narrs] = da;
            pc->names[pc->narrs] = nm->val;
            pc->namelens[pc->narrs] = nm->vlen;
            pc->narrs++;
        }
    }
    return JMF_OK;
}

/* <AppendedData>: where it starts; the file must end with </VTKFile>
 * (raw data cannot be scanned). */
static jmf_status appended_tag(vtu_doc *doc, const xtag *t)
{
    vtu *v = &doc->v;
    const jmr_ctx *ctx = v->x.ctx;
    const uint8_t *data = v->x.d;
    const size_t size = v->x.n;
    const xattr *enc = attr(t, "encoding");
    size_t p = v->x.pos, e = size;
    static const char endtag[] = "</VTKFile>";
    if (val_is(enc, "base64")) v->appended_b64 = 1;
    else if (enc && !val_is(enc, "raw"))
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(t->pos), "AppendedData encoding '%.*s'; expected raw or base64",
                        SHOWA(enc));
    while (p < size && jmr_isspace(data[p])) p++;
    if (p >= size || data[p] != '_')
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(p), "expected '_' at the start of the appended data");
    v->appended = p + 1;
    v->have_appended = 1;
    while (e > v->appended && (jmr_isspace(data[e - 1]) || data[e - 1] == 0)) e--;
    if (e - v->appended < sizeof endtag - 1 ||
        memcmp(data + e - (sizeof endtag - 1), endtag, sizeof endtag - 1) != 0)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(size), "truncated: expected the file to end with </VTKFile>");
    doc->closed = 1;
    return JMF_OK;
}

/* One tag inside <VTKFile>. */
static jmf_status inner_tag(vtu_doc *doc, const xtag *t)
{
    if (t->end) {
        if (tag_is(t, "Points")) doc->in_points = 0;
        else if (tag_is(t, "PointData")) doc->in_pointdata = 0;
        else if (tag_is(t, "Piece")) doc->in_piece = 0;
        else if (tag_is(t, "VTKFile")) doc->closed = 1;
        return JMF_OK;
    }
    if (tag_is(t, "Piece"))
        return piece_tag(doc, t);
    if (tag_is(t, "Points") && doc->in_piece)
        doc->in_points = !t->selfclose;
    else if (tag_is(t, "PointData") && doc->in_piece)
        doc->in_pointdata = !t->selfclose;
    else if (tag_is(t, "DataArray"))
        return data_array_tag(doc, t);
    else if (tag_is(t, "AppendedData"))
        return appended_tag(doc, t);
    else if (!t->selfclose && (tag_is(t, "FieldData") || tag_is(t, "CellData") || tag_is(t, "Cells") ||
                               tag_is(t, "Verts") || tag_is(t, "Lines") || tag_is(t, "Strips") ||
                               tag_is(t, "Polys")))
        /* contents are not needed; inline data in them is skipped */
        return skip_element(&doc->v.x, t);
    return JMF_OK;
}

jmf_status jmr_read_vtu(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts)
{
    vtu_doc doc;
    xtag t;
    int got;
    jmf_status st = JMF_OK;

    memset(&doc, 0, sizeof doc);
    vtu *v = &doc.v;
    v->x.d = data;
    v->x.n = size;
    v->x.ctx = ctx;
    v->hsize = 4;
    /* zlib cannot expand more than ~1032:1, so no real file decodes to more than this */
    v->decoded_max = jmr_max_decoded(ctx);
    if (size < (v->decoded_max - (1u << 20)) / 1100) v->decoded_max = size * 1100 + (1u << 20);

    while (!st && !doc.closed) {
        st = next_tag(&v->x, &t, &got);
        if (st || !got) break;
        st = doc.have_file ? inner_tag(&doc, &t) : file_tag(&doc, &t);
    }
    if (!st && !doc.have_file)
        st = jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(0), "expected an XML <VTKFile> element");
    if (!st && !doc.closed)
        st = jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(size), "truncated XML: expected </VTKFile>");
    if (!st && doc.any_ids) st = jmr_points_want_ids(pts, ctx);
    for (size_t i = 0; !st && i < doc.npieces; i++) st = read_piece(v, &doc.pieces[i], pts);
    if (!st && doc.npieces) st = read_arrays(v, doc.pieces, doc.npieces, pts);
    free(doc.pieces);
    return st;
}
