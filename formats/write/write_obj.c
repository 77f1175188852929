/* write_obj.c - writes a mesh as Wavefront OBJ (v, vt, vn, f a/a/a) with a fast %.7g float printer. */
#include "write_formats.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double k_pow10[] = {
    1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11, 1e12,
    1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22, 1e23, 1e24, 1e25,
    1e26, 1e27, 1e28, 1e29, 1e30, 1e31, 1e32, 1e33, 1e34, 1e35, 1e36, 1e37, 1e38,
    1e39, 1e40, 1e41, 1e42, 1e43, 1e44, 1e45, 1e46, 1e47, 1e48, 1e49, 1e50, 1e51};

/* round(v * 10^k) to nearest, ties to even. 10^k is exact up to k = 22;
 * a negative k divides by an exact power, so that exact ties (which only
 * occur there) round the way printf rounds them. */
static uint64_t scaled(double v, int k)
{
    double s = k >= 0 ? v * k_pow10[k] : v / k_pow10[-k];
    return (uint64_t)llrint(s);
}

size_t jmf_format_float(char *out, float fv)
{
    char *p = out;
    double v = fv;
    if (isnan(v)) {
        memcpy(out, signbit(v) ? "-nan" : "nan", signbit(v) ? 5 : 4);
        return strlen(out);
    }
    if (signbit(v)) {
        *p++ = '-';
        v = -v;
    }
    if (isinf(v)) {
        memcpy(p, "inf", 4);
        return (size_t)(p - out) + 3;
    }
    if (v == 0) {
        *p++ = '0';
        *p = '\0';
        return (size_t)(p - out);
    }
    /* Decimal exponent e with 10^e <= v < 10^(e+1), and the 7 significant
     * digits m (10^6 <= m < 10^7), after rounding. */
    int e2;
    (void)frexp(v, &e2);
    int e = (int)floor((e2 - 1) * 0.30102999566398120);
    uint64_t m = scaled(v, 6 - e);
    for (int guard = 0; guard < 4 && (m >= 10000000u || m < 1000000u); guard++) {
        e += m >= 10000000u ? 1 : -1;
        m = scaled(v, 6 - e);
    }
    char d[7];
    for (int i = 6; i >= 0; i--) {
        d[i] = (char)('0' + m % 10);
        m /= 10;
    }
    int nd = 7; /* significant digits left once trailing zeros are dropped */
    while (nd > 1 && d[nd - 1] == '0') nd--;

    if (e < -4 || e >= 7) { /* d.dddddde+XX */
        *p++ = d[0];
        if (nd > 1) {
            *p++ = '.';
            memcpy(p, d + 1, (size_t)nd - 1);
            p += nd - 1;
        }
        *p++ = 'e';
        *p++ = e < 0 ? '-' : '+';
        int ae = e < 0 ? -e : e;
        if (ae >= 100) *p++ = (char)('0' + ae / 100);
        *p++ = (char)('0' + ae / 10 % 10);
        *p++ = (char)('0' + ae % 10);
    } else if (e >= 0) { /* ddd.dddd */
        int ip = e + 1;
        for (int i = 0; i < ip; i++) *p++ = d[i];
        if (nd > ip) {
            *p++ = '.';
            memcpy(p, d + ip, (size_t)(nd - ip));
            p += nd - ip;
        }
    } else { /* 0.000ddd */
        *p++ = '0';
        *p++ = '.';
        for (int i = 0; i < -e - 1; i++) *p++ = '0';
        memcpy(p, d, (size_t)nd);
        p += nd;
    }
    *p = '\0';
    return (size_t)(p - out);
}

static char *put_u64(char *p, uint64_t v)
{
    char tmp[24];
    int n = 0;
    do {
        tmp[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    while (n) *p++ = tmp[--n];
    return p;
}

static char *put_floats(char *p, const char *tag, const float *f, int n)
{
    while (*tag) *p++ = *tag++;
    for (int i = 0; i < n; i++) {
        *p++ = ' ';
        p += jmf_format_float(p, f[i]);
    }
    *p++ = '\n';
    return p;
}

#define OBJ_CHUNK ((size_t)1 << 20)
#define OBJ_LINE_MAX 256 /* longest line: "f" + 3 * (3 * 20 digits + 2 '/') */

jmf_status jmf_write_obj(jmf_atomic_file *af, const jm_mesh *mesh,
                         const char *generator, char *err, size_t errlen)
{
    char *buf = malloc(OBJ_CHUNK);
    if (!buf) {
        snprintf(err, errlen, "%s: out of memory", af->final_path);
        return JMF_E_NOMEM;
    }
    char *p = buf;
    jmf_status st = JMF_OK;
#define OBJ_FLUSH_IF_FULL()                                                         \
    do {                                                                            \
        if ((size_t)(p - buf) > OBJ_CHUNK - OBJ_LINE_MAX) {                         \
            if ((st = jmf_atomic_write(af, buf, (size_t)(p - buf), err, errlen)))   \
                goto done;                                                          \
            p = buf;                                                                \
        }                                                                           \
    } while (0)

    int hn = snprintf(p, OBJ_LINE_MAX, "# %.150s\n# %zu vertices, %zu triangles\n",
                      generator ? generator : "jetmesh", mesh->vertex_count,
                      mesh->triangle_count);
    p += hn > 0 && hn < OBJ_LINE_MAX ? hn : 0;
    for (size_t i = 0; i < mesh->vertex_count; i++) {
        OBJ_FLUSH_IF_FULL();
        p = put_floats(p, "v", mesh->positions + 3 * i, 3);
    }
    if (mesh->uvs)
        for (size_t i = 0; i < mesh->vertex_count; i++) {
            OBJ_FLUSH_IF_FULL();
            p = put_floats(p, "vt", mesh->uvs + 2 * i, 2);
        }
    if (mesh->normals)
        for (size_t i = 0; i < mesh->vertex_count; i++) {
            OBJ_FLUSH_IF_FULL();
            p = put_floats(p, "vn", mesh->normals + 3 * i, 3);
        }
    /* The same index for v, vt and vn: "a/a/a", "a//a", "a/a" or "a". */
    const int has_uv = mesh->uvs != NULL, has_n = mesh->normals != NULL;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        OBJ_FLUSH_IF_FULL();
        *p++ = 'f';
        for (int c = 0; c < 3; c++) {
            uint64_t a = (uint64_t)mesh->indices[3 * t + (size_t)c] + 1;
            *p++ = ' ';
            p = put_u64(p, a);
            if (has_uv || has_n) {
                *p++ = '/';
                if (has_uv) p = put_u64(p, a);
                if (has_n) {
                    *p++ = '/';
                    p = put_u64(p, a);
                }
            }
        }
        *p++ = '\n';
    }
    st = jmf_atomic_write(af, buf, (size_t)(p - buf), err, errlen);
done:
    free(buf);
    return st;
#undef OBJ_FLUSH_IF_FULL
}
