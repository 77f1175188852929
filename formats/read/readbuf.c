/* readbuf.c - helpers shared by the particle readers: messages, number parsing, scalar loads, point buffer, zlib blocks. */
#include "readbuf.h"

#include <errno.h>
#include <float.h>
#include <locale.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <zlib.h>

/* Copies src into dst[0..cap) replacing control bytes by spaces; returns the length written. */
static size_t put_clean(char *dst, size_t cap, const char *src)
{
    size_t n = 0;
    if (cap == 0) return 0;
    for (; *src && n + 1 < cap; src++) {
        unsigned char c = (unsigned char)*src;
        dst[n++] = (c < 0x20 || c == 0x7f) ? ' ' : (char)c;
    }
    dst[n] = '\0';
    return n;
}

jmf_status jmr_fail(const jmr_ctx *ctx, jmf_status st, jmr_at at, const char *fmt, ...)
{
    char msg[512], head[64];
    va_list ap;
    size_t n;
    if (!ctx->err || ctx->errlen == 0) return st;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (at.kind == JMR_AT_LINE)
        snprintf(head, sizeof head, ":%zu: ", at.n);
    else if (at.kind == JMR_AT_BYTE)
        snprintf(head, sizeof head, ": byte %zu%s: ", at.n, ctx->gunzipped ? " (decompressed)" : "");
    else
        snprintf(head, sizeof head, ": ");
    n = put_clean(ctx->err, ctx->errlen, ctx->name);
    n += put_clean(ctx->err + n, ctx->errlen - n, head);
    n += put_clean(ctx->err + n, ctx->errlen - n, msg);
    /* never end with a newline or blank */
    while (n > 0 && ctx->err[n - 1] == ' ') ctx->err[--n] = '\0';
    return st;
}

int jmr_ieq(const char *s, size_t n, const char *w)
{
    size_t i;
    for (i = 0; i < n; i++) {
        unsigned char a = (unsigned char)s[i], b = (unsigned char)w[i];
        if (b == 0) return 0;
        if (a >= 'A' && a <= 'Z') a = (unsigned char)(a - 'A' + 'a');
        if (b >= 'A' && b <= 'Z') b = (unsigned char)(b - 'A' + 'a');
        if (a != b) return 0;
    }
    return w[n] == 0;
}

int jmr_parse_double(const char *s, size_t n, double *out)
{
    char buf[128], *end;
    char dp = '.';
    const struct lconv *lc;
    size_t i;
    double v;
    if (n == 0 || n >= sizeof buf) return 0;
    lc = localeconv();
    if (lc && lc->decimal_point && lc->decimal_point[0] && !lc->decimal_point[1])
        dp = lc->decimal_point[0];
    for (i = 0; i < n; i++) {
        char c = s[i];
        /* only the characters a decimal number can have; keeps strtod from
         * surprises: no 'x', so no hexadecimal ("0x10" is not 16 in a CSV) */
        if (!((c >= '0' && c <= '9') || c == '.' || c == '+' || c == '-' ||
              (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '(' || c == ')' || c == '_') ||
            c == 'x' || c == 'X')
            return 0;
        buf[i] = (c == '.') ? dp : c;
    }
    buf[n] = '\0';
    if (dp != '.' && memchr(s, dp, n)) return 0; /* e.g. "1,5" under a ',' locale */
    errno = 0;
    v = strtod(buf, &end);
    if (end != buf + n) return 0;
    (void)errno; /* ERANGE: overflow gives +-HUGE_VAL (inf), underflow a tiny value: both fine */
    *out = v;
    return 1;
}

int jmr_parse_size(const char *s, size_t n, size_t *out)
{
    size_t v = 0, i;
    if (n == 0) return 0;
    for (i = 0; i < n; i++) {
        unsigned d;
        if (s[i] < '0' || s[i] > '9') return 0;
        d = (unsigned)(s[i] - '0');
        if (v > (SIZE_MAX - d) / 10) return 0;
        v = v * 10 + d;
    }
    *out = v;
    return 1;
}

size_t jmr_type_size(jmr_type t)
{
    switch (t) {
    case JMR_T_I8: case JMR_T_U8: return 1;
    case JMR_T_I16: case JMR_T_U16: return 2;
    case JMR_T_I32: case JMR_T_U32: case JMR_T_F32: return 4;
    case JMR_T_I64: case JMR_T_U64: case JMR_T_F64: return 8;
    default: return 0;
    }
}

int jmr_type_is_int(jmr_type t)
{
    return t != JMR_T_NONE && t != JMR_T_F32 && t != JMR_T_F64;
}

static uint64_t load_bits(const uint8_t *p, size_t sz, int be)
{
    switch (sz) {
    case 1: return p[0];
    case 2: return be ? jmr_be16(p) : jmr_le16(p);
    case 4: return be ? jmr_be32(p) : jmr_le32(p);
    default: return be ? jmr_be64(p) : jmr_le64(p);
    }
}

double jmr_load(const uint8_t *p, jmr_type t, int be)
{
    uint64_t u = load_bits(p, jmr_type_size(t), be);
    switch (t) {
    case JMR_T_I8: return (double)(int8_t)(uint8_t)u;
    case JMR_T_U8: return (double)(uint8_t)u;
    case JMR_T_I16: return (double)(int16_t)(uint16_t)u;
    case JMR_T_U16: return (double)(uint16_t)u;
    case JMR_T_I32: return (double)(int32_t)(uint32_t)u;
    case JMR_T_U32: return (double)(uint32_t)u;
    case JMR_T_I64: return (double)(int64_t)u;
    case JMR_T_U64: return (double)u;
    case JMR_T_F32: return (double)jmr_f32_bits((uint32_t)u);
    case JMR_T_F64: return jmr_f64_bits(u);
    default: return 0.0;
    }
}

uint64_t jmr_load_u64(const uint8_t *p, jmr_type t, int be, int *ok)
{
    uint64_t u = load_bits(p, jmr_type_size(t), be);
    int64_t s;
    *ok = 1;
    switch (t) {
    case JMR_T_I8: s = (int8_t)(uint8_t)u; break;
    case JMR_T_I16: s = (int16_t)(uint16_t)u; break;
    case JMR_T_I32: s = (int32_t)(uint32_t)u; break;
    case JMR_T_I64: s = (int64_t)u; break;
    case JMR_T_U8: case JMR_T_U16: case JMR_T_U32: case JMR_T_U64: return u;
    default: *ok = 0; return 0;
    }
    if (s < 0) { *ok = 0; return 0; }
    return (uint64_t)s;
}

/* ---- points ---- */

const char *jmr_zlib_block(const uint8_t *src, size_t n, uint8_t *dst, size_t want)
{
    z_stream zs;
    uint8_t dummy[1];
    int rc;
    const char *why = NULL;
    if (n > UINT_MAX || want > UINT_MAX) return "block larger than 4 GiB";
    memset(&zs, 0, sizeof zs);
    if (inflateInit(&zs) != Z_OK) return "zlib init failed";
    zs.next_in = (Bytef *)(uintptr_t)src;
    zs.avail_in = (uInt)n;
    zs.next_out = want ? dst : dummy;
    zs.avail_out = want ? (uInt)want : 0;
    rc = inflate(&zs, Z_FINISH);
    if (rc == Z_STREAM_END) {
        if (zs.total_out != want) why = "block is shorter than its stated size";
    } else if (rc == Z_DATA_ERROR) {
        why = zs.msg ? zs.msg : "corrupt zlib data";
    } else if (rc == Z_BUF_ERROR && zs.avail_out == 0 && want) {
        why = "block is longer than its stated size";
    } else if (rc == Z_BUF_ERROR || rc == Z_OK) {
        why = "truncated zlib block";
    } else if (rc == Z_MEM_ERROR) {
        why = "out of memory in zlib";
    } else {
        why = "corrupt zlib data";
    }
    inflateEnd(&zs);
    return why;
}
