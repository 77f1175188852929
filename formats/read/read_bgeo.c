/* read_bgeo.c - reads classic Houdini binary geometry (BgeoV 5, as partio / SPlisHSPlasH write it): positions, an "id" int attribute and the numeric point attributes asked for. */
#include "readbuf.h"

/*
 * Layout (all big-endian): "Bgeo" 'V' int32 version(5), int32 counts: points,
 * prims, point groups, prim groups, point attribs, vertex attribs, prim
 * attribs, detail attribs. Point attribute definitions (u16 name length,
 * name, u16 size, int32 type; type 0 float / 1 int / 5 vector are followed by
 * size 4-byte defaults, type 4 indexed string by an int32 string count and
 * u16-length strings), then per point float32 x y z w and the attribute words.
 * Then prim attribute definitions, the primitives (only the particle system
 * 0x8000 is understood: int32 n, n u16 point indices (int32 when there are
 * 65536 points or more), prim attribute words), detail attribute definitions
 * and their words, and the end marker 00 FF.
 *
 * Everything after the point block is validated where we understand it (so a
 * truncated file is rejected); after a primitive type we do not know, or when
 * groups are present, we only require the file to end with 00 FF.
 */

typedef struct bg {
    const uint8_t *d;
    size_t n, pos;
    const jmr_ctx *ctx;
} bg;

static jmf_status need(bg *b, size_t k, const char *what)
{
    if (k <= b->n - b->pos) return JMF_OK;
    return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(b->pos),
                    "truncated: expected %s (%zu bytes), only %zu bytes left", what, k, b->n - b->pos);
}

static jmf_status rd_i32(bg *b, const char *what, int32_t *v)
{
    jmf_status st = need(b, 4, what);
    if (st) return st;
    *v = (int32_t)jmr_be32(b->d + b->pos);
    b->pos += 4;
    return JMF_OK;
}

static jmf_status rd_count(bg *b, const char *what, size_t *v)
{
    size_t at = b->pos;
    int32_t x;
    jmf_status st = rd_i32(b, what, &x);
    if (st) return st;
    if (x < 0)
        return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(at), "negative %s (%ld); expected a count >= 0",
                        what, (long)x);
    *v = (size_t)x;
    return JMF_OK;
}

static jmf_status skip_str(bg *b, const char *what, const uint8_t **s, size_t *len)
{
    jmf_status st = need(b, 2, what);
    if (st) return st;
    *len = jmr_be16(b->d + b->pos);
    b->pos += 2;
    st = need(b, *len, what);
    if (st) return st;
    *s = b->d + b->pos;
    b->pos += *len;
    return JMF_OK;
}

/*
 * Reads nattr attribute definitions; adds their sizes to *words (32-bit words
 * per element) and, for points, reports the word offset of an int "id"
 * attribute in *id_word (left unchanged if none).
 */
/* A numeric point attribute: where its words are in a point's record. */
#define MAX_PATTRS 64
typedef struct pattr {
    const uint8_t *name;
    size_t namelen, size, word;
    int is_int;
} pattr;

static jmf_status attr_defs(bg *b, size_t nattr, const char *kind, size_t *words, size_t *id_word, pattr *pa,
                            size_t *npa)
{
    size_t i;
    for (i = 0; i < nattr; i++) {
        size_t at = b->pos, namelen, size, k;
        const uint8_t *name;
        int32_t type;
        jmf_status st = skip_str(b, "attribute name", &name, &namelen);
        if (st) return st;
        st = need(b, 6, "attribute size and type");
        if (st) return st;
        size = jmr_be16(b->d + b->pos);
        type = (int32_t)jmr_be32(b->d + b->pos + 2);
        b->pos += 6;
        switch (type) {
        case 0: case 1: case 5:
            st = need(b, size * 4, "attribute defaults");
            if (st) return st;
            b->pos += size * 4;
            if (id_word && type == 1 && size >= 1 && namelen == 2 && memcmp(name, "id", 2) == 0)
                *id_word = *words;
            if (pa && *npa < MAX_PATTRS) {
                pattr *q = &pa[(*npa)++];
                q->name = name;
                q->namelen = namelen;
                q->size = size;
                q->word = *words;
                q->is_int = type == 1;
            }
            break;
        case 4: {
            size_t nstr;
            st = rd_count(b, "indexed string count", &nstr);
            if (st) return st;
            for (k = 0; k < nstr; k++) {
                const uint8_t *s;
                size_t slen;
                st = skip_str(b, "indexed string", &s, &slen);
                if (st) return st;
            }
            break;
        }
        case 2:
            return jmr_fail(b->ctx, JMF_E_UNSUPPORTED, jmr_byte(at),
                            "%s attribute '%.*s' has type 2 (string), which is not supported; "
                            "expected float, int, vector or indexed string",
                            kind, (int)(namelen > 64 ? 64 : namelen), (const char *)name);
        default:
            return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(at + 4 + namelen),
                            "%s attribute '%.*s' has unknown type %ld; expected 0 (float), 1 (int), "
                            "4 (indexed string) or 5 (vector)",
                            kind, (int)(namelen > 64 ? 64 : namelen), (const char *)name, (long)type);
        }
        if (!jmr_add(*words, size, words))
            return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(at), "attribute sizes overflow");
    }
    return JMF_OK;
}

/* Validates what follows the point block (see the comment at the top). */
static jmf_status tail(bg *b, size_t npoints, size_t nprims, size_t ngroups, size_t nprimattr,
                       size_t ndetail)
{
    size_t primwords = 0, detailwords = 0, i, bytes;
    int lenient = ngroups > 0;
    jmf_status st = attr_defs(b, nprimattr, "primitive", &primwords, NULL, NULL, NULL);
    if (st) return st;
    if (!jmr_mul(primwords, 4, &bytes))
        return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(b->pos), "primitive attribute size overflows");
    for (i = 0; i < nprims && !lenient; i++) {
        size_t at = b->pos, nidx, ib;
        int32_t type;
        st = rd_i32(b, "primitive type", &type);
        if (st) return st;
        if (type != 0x8000) {
            (void)at;
            lenient = 1; /* a primitive we do not know: cannot walk further */
            break;
        }
        st = rd_count(b, "particle primitive size", &nidx);
        if (st) return st;
        if (!jmr_mul(nidx, npoints >= 65536 ? 4 : 2, &ib))
            return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(b->pos), "primitive size overflows");
        st = need(b, ib, "particle primitive point indices");
        if (st) return st;
        b->pos += ib;
        st = need(b, bytes, "primitive attribute values");
        if (st) return st;
        b->pos += bytes;
    }
    if (lenient) {
        if (b->n < 2 || b->d[b->n - 2] != 0x00 || b->d[b->n - 1] != 0xff)
            return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(b->n),
                            "truncated: expected the end marker 00 FF at the end of the file");
        return JMF_OK;
    }
    st = attr_defs(b, ndetail, "detail", &detailwords, NULL, NULL, NULL);
    if (st) return st;
    if (!jmr_mul(detailwords, 4, &bytes))
        return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(b->pos), "detail attribute size overflows");
    st = need(b, bytes, "detail attribute values");
    if (st) return st;
    b->pos += bytes;
    st = need(b, 2, "end marker 00 FF");
    if (st) return st;
    if (b->d[b->pos] != 0x00 || b->d[b->pos + 1] != 0xff)
        return jmr_fail(b->ctx, JMF_E_FORMAT, jmr_byte(b->pos), "expected the end marker 00 FF, found %02x %02x",
                        b->d[b->pos], b->d[b->pos + 1]);
    return JMF_OK; /* anything after the marker is ignored */
}

jmf_status jmr_read_bgeo(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts)
{
    static const char *const names[8] = { "point count", "primitive count", "point group count",
                                          "primitive group count", "point attribute count",
                                          "vertex attribute count", "primitive attribute count",
                                          "detail attribute count" };
    bg b = { data, size, 0, ctx };
    size_t c[8], i, words = 4, id_word = SIZE_MAX, rec, total, npa = 0;
    pattr pa[MAX_PATTRS];
    int32_t version;
    jmf_status st;

    if (size >= 4 && memcmp(data, "\x7fNSJ", 4) == 0)
        return jmr_fail(ctx, JMF_E_UNSUPPORTED, jmr_byte(0),
                        "new-style (JSON) Houdini bgeo is not supported; expected classic 'BgeoV' "
                        "(save as .bhclassic)");
    st = need(&b, 5, "magic 'BgeoV'");
    if (st) return st;
    if (memcmp(data, "Bgeo", 4) != 0)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(0), "wrong magic; expected 'Bgeo'");
    if (data[4] != 'V')
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(4), "expected 'V' after 'Bgeo', found byte 0x%02x", data[4]);
    b.pos = 5;
    st = rd_i32(&b, "version", &version);
    if (st) return st;
    if (version != 5)
        return jmr_fail(ctx, JMF_E_UNSUPPORTED, jmr_byte(5), "bgeo version %ld; expected 5", (long)version);
    for (i = 0; i < 8; i++) {
        st = rd_count(&b, names[i], &c[i]);
        if (st) return st;
    }
    if (c[5] != 0)
        return jmr_fail(ctx, JMF_E_UNSUPPORTED, jmr_byte(29), "%zu vertex attributes; expected none", c[5]);

    st = attr_defs(&b, c[4], "point", &words, &id_word, pa, &npa);
    if (st) return st;
    if (!jmr_mul(words, 4, &rec) || !jmr_mul(rec, c[0], &total))
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(9), "point count %zu times %zu words per point overflows",
                        c[0], words);
    if (total > size - b.pos)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(b.pos),
                        "truncated: %zu points of %zu bytes need %zu bytes, only %zu left", c[0], rec, total,
                        size - b.pos);
    st = jmr_points_reserve(pts, ctx, c[0]);
    if (st) return st;
    if (id_word != SIZE_MAX) {
        st = jmr_points_want_ids(pts, ctx);
        if (st) return st;
    }
    for (i = 0; i < c[0]; i++) {
        const uint8_t *p = data + b.pos + i * rec;
        uint32_t id = 0;
        if (id_word != SIZE_MAX) {
            int32_t v = (int32_t)jmr_be32(p + 4 * id_word);
            if (v < 0) pts->ids_bad = 1; else id = (uint32_t)v;
        }
        st = jmr_points_add(pts, ctx, jmr_f32_bits(jmr_be32(p)), jmr_f32_bits(jmr_be32(p + 4)),
                            jmr_f32_bits(jmr_be32(p + 8)), id, jmr_byte(b.pos + i * rec));
        if (st) return st;
    }
    for (size_t k = 0; k < npa; k++) {
        jmr_attr *a = NULL;
        st = jmr_attr_begin(pts, ctx, (const char *)pa[k].name, pa[k].namelen, pa[k].size, c[0],
                            jmr_byte((size_t)(pa[k].name - data)), &a);
        if (st) return st;
        for (i = 0; a && i < c[0]; i++) {
            const uint8_t *p = data + b.pos + i * rec + 4 * pa[k].word;
            for (size_t j = 0; j < pa[k].size; j++) {
                uint32_t u = jmr_be32(p + 4 * j);
                jmr_attr_set(a, i, j, pa[k].is_int ? (double)(int32_t)u : (double)jmr_f32_bits(u));
            }
        }
    }
    b.pos += total;
    return tail(&b, c[0], c[1], c[2] + c[3], c[6], c[7]);
}
