/* readbuf.h - helpers shared by the particle readers: byte cursor, endian loads, errors, size math, point buffer. */
#ifndef JETMESH_FORMATS_READBUF_H
#define JETMESH_FORMATS_READBUF_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "../reader.h"

/*
 * Conventions of the readers (formats/read/read_*.c):
 *  - Input is a complete, already gunzipped buffer (data, size); it is never
 *    NUL-terminated and readers never read outside [data, data + size).
 *  - Errors go through jmr_fail(); the message is one line (control bytes are
 *    replaced by spaces), starts with the file name and names the line
 *    ("a.csv:12: ...") for text or the byte offset ("a.bgeo: byte 40: ...")
 *    for binary, followed by what was expected. For gzip inputs offsets are
 *    positions in the decompressed data and say so.
 *  - Points go into a jmr_points buffer. Non-finite coordinates (after the
 *    conversion to float) are an error unless drop_invalid is set; then they
 *    are kept as NaN while reading and removed (with their ids) by
 *    jmr_points_finish(), which counts them in dropped.
 *  - Ids are optional extras: a reader fills them when the file has an
 *    integer "id" attribute whose values all fit in uint32; otherwise the
 *    frame has ids = NULL (an unusable id array is dropped, not an error).
 */

/** Where a problem is: a text line, a byte offset, or nowhere in particular. */
typedef enum { JMR_AT_NONE = 0, JMR_AT_LINE, JMR_AT_BYTE } jmr_at_kind;
typedef struct jmr_at {
    jmr_at_kind kind;
    size_t n;
} jmr_at;

static inline jmr_at jmr_line(size_t line) { jmr_at a = { JMR_AT_LINE, line }; return a; }
static inline jmr_at jmr_byte(size_t off) { jmr_at a = { JMR_AT_BYTE, off }; return a; }
static inline jmr_at jmr_nowhere(void) { jmr_at a = { JMR_AT_NONE, 0 }; return a; }

/** What one read is about: the name for messages, the options, where errors go. */
typedef struct jmr_ctx {
    const char *name;             /* never NULL */
    const jmf_read_options *opt;  /* never NULL */
    char *err;
    size_t errlen;
    int gunzipped;                /* offsets are into decompressed data */
} jmr_ctx;

/** Formats "NAME:LINE: msg" / "NAME: byte N: msg" / "NAME: msg" into ctx->err; returns st. */
jmf_status jmr_fail(const jmr_ctx *ctx, jmf_status st, jmr_at at, const char *fmt, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* ---- overflow-checked size math: return 1 on success, 0 on overflow ---- */
static inline int jmr_mul(size_t a, size_t b, size_t *out)
{
    if (a != 0 && b > SIZE_MAX / a) return 0;
    *out = a * b;
    return 1;
}
static inline int jmr_add(size_t a, size_t b, size_t *out)
{
    if (b > SIZE_MAX - a) return 0;
    *out = a + b;
    return 1;
}

/* ---- endian loads from unaligned bytes ---- */
static inline uint16_t jmr_be16(const uint8_t *p) { return (uint16_t)((p[0] << 8) | p[1]); }
static inline uint16_t jmr_le16(const uint8_t *p) { return (uint16_t)((p[1] << 8) | p[0]); }
static inline uint32_t jmr_be32(const uint8_t *p)
{
    return ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | p[3];
}
static inline uint32_t jmr_le32(const uint8_t *p)
{
    return ((uint32_t)p[3] << 24) | ((uint32_t)p[2] << 16) | ((uint32_t)p[1] << 8) | p[0];
}
static inline uint64_t jmr_be64(const uint8_t *p)
{
    return ((uint64_t)jmr_be32(p) << 32) | jmr_be32(p + 4);
}
static inline uint64_t jmr_le64(const uint8_t *p)
{
    return ((uint64_t)jmr_le32(p + 4) << 32) | jmr_le32(p);
}
static inline float jmr_f32_bits(uint32_t u) { float f; memcpy(&f, &u, 4); return f; }
static inline double jmr_f64_bits(uint64_t u) { double d; memcpy(&d, &u, 8); return d; }

/** Numeric scalar types shared by VTK, VTU and PLY. */
typedef enum {
    JMR_T_NONE = 0, JMR_T_I8, JMR_T_U8, JMR_T_I16, JMR_T_U16, JMR_T_I32, JMR_T_U32,
    JMR_T_I64, JMR_T_U64, JMR_T_F32, JMR_T_F64
} jmr_type;
/** Size in bytes of one value of t (0 for JMR_T_NONE). */
size_t jmr_type_size(jmr_type t);
/** 1 for the integer types. */
int jmr_type_is_int(jmr_type t);
/** Loads one value of type t from p (big_endian or little) as a double. */
double jmr_load(const uint8_t *p, jmr_type t, int big_endian);
/** Loads one integer value; *ok = 0 if it is negative (64-bit values above INT64_MAX load fine). */
uint64_t jmr_load_u64(const uint8_t *p, jmr_type t, int big_endian, int *ok);

/* ---- text helpers (bounded; the buffers are not NUL-terminated) ---- */
static inline int jmr_isspace(int c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}
/** Case-insensitive compare of s[0..n) with the NUL-terminated word w. */
int jmr_ieq(const char *s, size_t n, const char *w);
/**
 * Parses s[0..n) entirely as a decimal (or strtod-style) floating point number;
 * returns 1 on success. Independent of the C locale's decimal point. "nan"
 * and "inf" parse (the NaN policy applies later); values beyond double range
 * become +-inf.
 */
int jmr_parse_double(const char *s, size_t n, double *out);
/** Parses s[0..n) entirely as an unsigned decimal integer; 0 if not one or it overflows. */
int jmr_parse_size(const char *s, size_t n, size_t *out);

/* ---- the points being read (read_points.c) ---- */
typedef struct jmr_points {
    float *xyz;
    uint32_t *ids;      /* NULL unless jmr_points_want_ids() was called */
    size_t count;
    size_t cap;
    size_t invalid;     /* non-finite points kept as NaN (drop_invalid) */
    int ids_bad;        /* an id did not fit: ids are dropped at the end */
    struct jmr_attr **attrs; /* the per-particle arrays asked for (read_attrs.c) */
    size_t nattrs;
    char *seen;         /* every per-particle array name met, ", "-separated */
    size_t seen_len;
} jmr_points;

/** Makes room for n more points; JMF_E_NOMEM/LIMIT with a message on failure. */
jmf_status jmr_points_reserve(jmr_points *pts, const jmr_ctx *ctx, size_t n);
/** Allocates the id array (zeroed) for the capacity reserved so far and later growth. */
jmf_status jmr_points_want_ids(jmr_points *pts, const jmr_ctx *ctx);
/**
 * Appends one point (grows as needed). A non-finite coordinate is an error at
 * `at` unless drop_invalid. id is stored when ids are wanted.
 */
jmf_status jmr_points_add(jmr_points *pts, const jmr_ctx *ctx, double x, double y, double z,
                          uint32_t id, jmr_at at);
/** Stores id for point i when ids are wanted; a value above UINT32_MAX marks ids bad. */
void jmr_points_set_id(jmr_points *pts, size_t i, uint64_t id, int ok);
/** Removes dropped points, drops bad ids, moves everything into out (zeroed first). */
void jmr_points_finish(jmr_points *pts, jmf_frame *out);
void jmr_points_free(jmr_points *pts);

/* ---- per-particle attributes (read_attrs.c; jmf_read_options.attributes) ---- */
typedef struct jmr_attr {
    char *name;
    int comps;      /* 1..4 */
    float *v;       /* comps per tuple */
    size_t count;   /* tuples held */
    size_t cap;
} jmr_attr;

/**
 * A per-particle array NAME (n bytes) of comps components and count tuples
 * (0 when they are pushed one at a time) met in the file: notes its name and,
 * when it was asked for, allocates it (zeroed) into *out; else *out = NULL.
 * The first array of a name wins. An array of over 4 components asked for
 * by name is an error; with "all" it is passed over. Kept arrays of over
 * JMF_MAX_ATTRIBUTE_COMPONENTS components in all are an error. The reader
 * checks count against the bytes left before the call: a count the file
 * cannot hold is a truncated file, not an allocation to try.
 */
jmf_status jmr_attr_begin(jmr_points *pts, const jmr_ctx *ctx, const char *name, size_t n, size_t comps,
                          size_t count, jmr_at at, jmr_attr **out);
/** Appends one tuple of a->comps values. */
jmf_status jmr_attr_push(jmr_attr *a, const jmr_ctx *ctx, const double *vals);
/** Sets component c of tuple i (ignored beyond count). */
void jmr_attr_set(jmr_attr *a, size_t i, size_t c, double v);
/** 1 when any attribute is asked for. */
int jmr_attrs_wanted(const jmr_ctx *ctx);
/**
 * After a successful read: every attribute asked for by name is present,
 * each has one tuple per particle, every value is finite (with drop_invalid
 * a particle with a non-finite value is dropped instead). Errors name the
 * file and the attribute.
 */
jmf_status jmr_attrs_check(jmr_points *pts, const jmr_ctx *ctx);
/** Moves tuple i to k (compaction by jmr_points_finish). */
void jmr_attrs_move(jmr_points *pts, size_t k, size_t i);
/** Moves the attributes and names into out (count tuples kept). */
void jmr_attrs_finish(jmr_points *pts, jmf_frame *out);
void jmr_attrs_free(jmr_points *pts);
/** Frees a frame's attributes (jmf_frame_free). */
void jmr_frame_attrs_free(jmf_frame *f);

/** A group of columns making one attribute (PLY properties, CSV columns). */
typedef struct jmr_colgroup {
    char name[64];
    int comps;
    size_t cols[3];
} jmr_colgroup;
/**
 * Groups columns into attributes: NAME_x/_y/_z (or .x, or NAMEx with a
 * NAME of 1+ letters when all three exist; vx vy vz give "velocity") make
 * one 3-component attribute, any other column a scalar. skip[i] marks the
 * columns already used (x, y, z, id). out has room for ncols groups;
 * returns how many.
 */
size_t jmr_group_columns(const char *const *names, const size_t *lens, const int *skip, size_t ncols,
                         jmr_colgroup *out);

/* ---- zlib helpers ---- */
/**
 * Inflates exactly one zlib stream src[0..n) into dst[0..want) and requires it
 * to produce exactly want bytes. Returns 0 on success, else a short reason.
 */
const char *jmr_zlib_block(const uint8_t *src, size_t n, uint8_t *dst, size_t want);

/* ---- the readers: data is gunzipped already; size > 0 ---- */
jmf_status jmr_read_csv(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts);
jmf_status jmr_read_xyz(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts);
jmf_status jmr_read_vtk(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts);
jmf_status jmr_read_vtu(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts);
jmf_status jmr_read_bgeo(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts);
jmf_status jmr_read_ply(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts);

/** The default cap on decompressed sizes when opt->max_bytes is 0 (bomb guard). */
#define JMR_DEFAULT_MAX_DECODED ((size_t)1 << (sizeof(size_t) >= 8 ? 32 : 30))
/** opt->max_bytes, or the default cap when it is 0. */
static inline size_t jmr_max_decoded(const jmr_ctx *ctx)
{
    return ctx->opt->max_bytes ? ctx->opt->max_bytes : JMR_DEFAULT_MAX_DECODED;
}

#endif
