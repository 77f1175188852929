/* write_vtk.c - writes a mesh as legacy VTK 3.0 POLYDATA, binary big-endian, with normals and texture coordinates. */
#include "write_formats.h"

#include <limits.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define VTK_CHUNK ((size_t)1 << 20) /* a multiple of 16 */

static void put_be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

/* Writes count floats from src as big-endian. */
static jmf_status put_floats(jmf_atomic_file *af, unsigned char *buf, const float *src,
                             size_t count, char *err, size_t errlen)
{
    size_t n = 0;
    for (size_t i = 0; i < count; i++) {
        uint32_t v;
        memcpy(&v, &src[i], 4);
        put_be32(buf + n, v);
        n += 4;
        if (n == VTK_CHUNK) {
            jmf_status st = jmf_atomic_write(af, buf, n, err, errlen);
            if (st) return st;
            n = 0;
        }
    }
    return jmf_atomic_write(af, buf, n, err, errlen);
}

/* One header line of any length (an attribute's name is not bounded). */
__attribute__((format(printf, 4, 5)))
static jmf_status put_text(jmf_atomic_file *af, char *err, size_t errlen, const char *fmt, ...)
{
    char line[512], *big = NULL;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (n < 0) {
        snprintf(err, errlen, "%s: cannot format a header line", af->final_path);
        return JMF_E_IO;
    }
    if ((size_t)n >= sizeof line) {
        big = malloc((size_t)n + 1);
        if (!big) {
            snprintf(err, errlen, "%s: out of memory", af->final_path);
            return JMF_E_NOMEM;
        }
        va_start(ap, fmt);
        vsnprintf(big, (size_t)n + 1, fmt, ap);
        va_end(ap);
    }
    jmf_status st = jmf_atomic_write(af, big ? big : line, (size_t)n, err, errlen);
    free(big);
    return st;
}

jmf_status jmf_write_vtk(jmf_atomic_file *af, const jm_mesh *mesh,
                         const char *generator, char *err, size_t errlen)
{
    return jmf_write_vtk_attrs(af, mesh, NULL, 0, generator, err, errlen);
}

jmf_status jmf_write_vtk_attrs(jmf_atomic_file *af, const jm_mesh *mesh, const jmf_attribute *attrs,
                               size_t nattrs, const char *generator, char *err, size_t errlen)
{
    /* Legacy readers hold counts, and the POLYGONS size 4 * triangles, in an int. */
    if (mesh->vertex_count > INT_MAX || mesh->triangle_count > INT_MAX / 4) {
        snprintf(err, errlen, "%s: too many vertices or triangles for legacy VTK", af->final_path);
        return JMF_E_LIMIT;
    }
    /* The title line is at most 255 characters and may not hold a newline. */
    char title[256];
    snprintf(title, sizeof title, "%s", generator ? generator : "jetmesh");
    for (char *c = title; *c; c++)
        if (*c == '\n' || *c == '\r') *c = ' ';

    unsigned char *buf = malloc(VTK_CHUNK);
    if (!buf) {
        snprintf(err, errlen, "%s: out of memory", af->final_path);
        return JMF_E_NOMEM;
    }
    const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
    jmf_status st = put_text(af, err, errlen,
                             "# vtk DataFile Version 3.0\n%s\nBINARY\nDATASET POLYDATA\n"
                             "POINTS %zu float\n", title, nv);
    if (!st) st = put_floats(af, buf, mesh->positions, 3 * nv, err, errlen);
    if (!st) st = put_text(af, err, errlen, "\nPOLYGONS %zu %zu\n", nt, 4 * nt);
    size_t n = 0;
    for (size_t t = 0; t < nt && !st; t++) {
        put_be32(buf + n, 3);
        for (int k = 0; k < 3; k++) put_be32(buf + n + 4 + 4 * (size_t)k, mesh->indices[3 * t + (size_t)k]);
        n += 16;
        if (n == VTK_CHUNK) {
            st = jmf_atomic_write(af, buf, n, err, errlen);
            n = 0;
        }
    }
    if (!st) st = jmf_atomic_write(af, buf, n, err, errlen);
    if (!st) st = put_text(af, err, errlen, "\n");
    if (!st && nv > 0 && (mesh->normals || mesh->uvs || nattrs)) {
        st = put_text(af, err, errlen, "POINT_DATA %zu\n", nv);
        if (!st && mesh->normals) {
            st = put_text(af, err, errlen, "NORMALS Normals float\n");
            if (!st) st = put_floats(af, buf, mesh->normals, 3 * nv, err, errlen);
            if (!st) st = put_text(af, err, errlen, "\n");
        }
        if (!st && mesh->uvs) {
            st = put_text(af, err, errlen, "TEXTURE_COORDINATES TCoords 2 float\n");
            if (!st) st = put_floats(af, buf, mesh->uvs, 2 * nv, err, errlen);
            if (!st) st = put_text(af, err, errlen, "\n");
        }
        if (!st && nattrs) st = put_text(af, err, errlen, "FIELD FieldData %zu\n", nattrs);
        for (size_t a = 0; a < nattrs && !st; a++) {
            st = put_text(af, err, errlen, "%s %d %zu float\n", attrs[a].name, attrs[a].components, nv);
            if (!st) st = put_floats(af, buf, attrs[a].values, (size_t)attrs[a].components * nv, err, errlen);
            if (!st) st = put_text(af, err, errlen, "\n");
        }
    }
    free(buf);
    return st;
}
