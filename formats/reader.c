/* reader.c - jmf_read_particles(_mem): reads the file, unwraps gzip, detects the format and runs its reader. */
#include "read/readbuf.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

static const char *const format_names[] = { "auto", "csv", "xyz", "vtk", "vtu", "bgeo", "ply" };

const char *jmf_input_format_name(jmf_input_format f)
{
    if ((unsigned)f < sizeof format_names / sizeof format_names[0]) return format_names[f];
    return "unknown";
}

int jmf_input_format_parse(const char *name)
{
    size_t i;
    if (!name) return -1;
    for (i = 0; i < sizeof format_names / sizeof format_names[0]; i++)
        if (jmr_ieq(name, strlen(name), format_names[i])) return (int)i;
    return -1;
}

void jmf_frame_free(jmf_frame *frame)
{
    if (!frame) return;
    free(frame->xyz);
    free(frame->ids);
    jmr_frame_attrs_free(frame);
    memset(frame, 0, sizeof *frame);
}

/* ---- gzip ---- */

static int is_gzip(const uint8_t *d, size_t n)
{
    return n >= 2 && d[0] == 0x1f && d[1] == 0x8b;
}

/*
 * Inflates a gzip file (one or more members) into *out. The output grows as
 * data actually decompresses, up to opt->max_bytes (JMF_E_LIMIT beyond it) or
 * the default cap JMR_DEFAULT_MAX_DECODED, so a small bomb cannot allocate
 * more than the limit.
 */
static jmf_status gunzip(const uint8_t *src, size_t n, const jmr_ctx *ctx, uint8_t **out,
                         size_t *outlen)
{
    const size_t limit = jmr_max_decoded(ctx);
    z_stream zs;
    uint8_t *buf = NULL;
    size_t cap = 0, len = 0, in_off = 0;
    jmf_status st = JMF_OK;
    int rc;

    memset(&zs, 0, sizeof zs);
    if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK)
        return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "cannot initialise zlib");
    /* first guess: 4x the compressed size, at least 64 KiB, at most the limit */
    cap = n > SIZE_MAX / 4 ? SIZE_MAX : n * 4;
    if (cap < 65536) cap = 65536;
    if (cap > limit) cap = limit;
    if (cap == 0) cap = 1;
    buf = malloc(cap);
    if (!buf) {
        inflateEnd(&zs);
        return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for %zu bytes of gunzipped data", cap);
    }
    for (;;) {
        size_t chunk_in = n - in_off, chunk_out;
        if (chunk_in > (1u << 30)) chunk_in = 1u << 30;
        if (len == cap) {
            size_t ncap;
            uint8_t *nb;
            if (len >= limit) {
                st = jmr_fail(ctx, JMF_E_LIMIT, jmr_nowhere(),
                              "decompressed size exceeds the limit of %zu bytes%s", limit,
                              ctx->opt->max_bytes ? " (max_bytes)" : " (built-in cap when max_bytes is 0)");
                break;
            }
            ncap = cap > limit / 2 ? limit : cap * 2;
            nb = realloc(buf, ncap);
            if (!nb) {
                st = jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for %zu bytes of gunzipped data", ncap);
                break;
            }
            buf = nb;
            cap = ncap;
        }
        chunk_out = cap - len;
        if (chunk_out > (1u << 30)) chunk_out = 1u << 30;
        zs.next_in = (Bytef *)(uintptr_t)(src + in_off);
        zs.avail_in = (uInt)chunk_in;
        zs.next_out = buf + len;
        zs.avail_out = (uInt)chunk_out;
        rc = inflate(&zs, Z_NO_FLUSH);
        in_off += chunk_in - zs.avail_in;
        len += chunk_out - zs.avail_out;
        if (rc == Z_STREAM_END) {
            /* another gzip member may follow (as `cat a.gz b.gz` makes) */
            if (in_off == n) break;
            if (!is_gzip(src + in_off, n - in_off)) {
                st = jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(in_off),
                              "unexpected data after the end of the gzip stream; expected end of file or another gzip member");
                break;
            }
            if (inflateReset(&zs) != Z_OK) {
                st = jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(in_off), "cannot restart zlib");
                break;
            }
            continue;
        }
        if (rc == Z_DATA_ERROR || rc == Z_NEED_DICT) {
            st = jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(in_off), "corrupt gzip stream (%s)",
                          zs.msg ? zs.msg : "invalid data");
            break;
        }
        if (rc == Z_MEM_ERROR) {
            st = jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory in zlib");
            break;
        }
        if (rc == Z_BUF_ERROR || rc == Z_OK) {
            if (rc == Z_BUF_ERROR && zs.avail_in != 0 && zs.avail_out != 0) {
                st = jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(in_off), "corrupt gzip stream (no progress)");
                break;
            }
            if (in_off == n && zs.avail_out != 0) {
                st = jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(n),
                              "truncated gzip stream: the file ends before the end of the compressed data");
                break;
            }
            continue; /* more output space or more input chunks needed */
        }
        st = jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(in_off), "corrupt gzip stream (zlib error %d)", rc);
        break;
    }
    inflateEnd(&zs);
    if (st) {
        free(buf);
        return st;
    }
    *out = buf;
    *outlen = len;
    return JMF_OK;
}

/* ---- detection ---- */

static int starts(const uint8_t *d, size_t n, const char *s)
{
    size_t k = strlen(s);
    return n >= k && memcmp(d, s, k) == 0;
}

static jmf_input_format by_magic(const uint8_t *d, size_t n)
{
    size_t i = 0;
    if (starts(d, n, "Bgeo") || starts(d, n, "\x7fNSJ")) return JMF_IN_BGEO;
    if (starts(d, n, "# vtk DataFile")) return JMF_IN_VTK;
    if (starts(d, n, "ply\n") || starts(d, n, "ply\r\n")) return JMF_IN_PLY;
    if (starts(d, n, "\xef\xbb\xbf")) i = 3; /* UTF-8 byte order mark */
    while (i < n && jmr_isspace(d[i])) i++;
    if (starts(d + i, n - i, "<?xml") || starts(d + i, n - i, "<VTKFile")) return JMF_IN_VTU;
    return JMF_IN_AUTO;
}

/* The extension of name, ignoring a trailing ".gz"; "" if none. */
static jmf_input_format by_extension(const char *name)
{
    static const struct { const char *ext; jmf_input_format f; } exts[] = {
        { "csv", JMF_IN_CSV }, { "txt", JMF_IN_CSV }, { "tsv", JMF_IN_CSV },
        { "xyz", JMF_IN_XYZ }, { "vtk", JMF_IN_VTK }, { "vtu", JMF_IN_VTU },
        { "bgeo", JMF_IN_BGEO }, { "geo", JMF_IN_BGEO }, { "ply", JMF_IN_PLY },
    };
    const char *base = strrchr(name, '/');
    const char *end, *dot;
    size_t i, len;
    base = base ? base + 1 : name;
    end = base + strlen(base);
    if (end - base > 3 && jmr_ieq(end - 3, 3, ".gz")) end -= 3;
    dot = NULL;
    for (const char *p = base; p < end; p++)
        if (*p == '.') dot = p;
    if (!dot) return JMF_IN_AUTO;
    len = (size_t)(end - dot - 1);
    for (i = 0; i < sizeof exts / sizeof exts[0]; i++)
        if (jmr_ieq(dot + 1, len, exts[i].ext)) return exts[i].f;
    return JMF_IN_AUTO;
}

jmf_status jmf_read_particles_mem(const void *data, size_t size, const char *name,
                                  const jmf_read_options *opt, jmf_frame *out, char *err,
                                  size_t errlen)
{
    static const jmf_read_options defaults = { JMF_IN_AUTO, 0, 0, NULL };
    jmr_ctx ctx;
    jmr_points pts;
    const uint8_t *d = data;
    uint8_t *plain = NULL;
    size_t n = size;
    jmf_input_format f;
    jmf_status st;
    int compressed = 0;

    if (err && errlen) err[0] = '\0';
    if (!out) return JMF_E_FORMAT;
    memset(out, 0, sizeof *out);
    memset(&pts, 0, sizeof pts);
    ctx.name = name ? name : "<memory>";
    ctx.opt = opt ? opt : &defaults;
    ctx.err = err;
    ctx.errlen = errlen;
    ctx.gunzipped = 0;

    if ((unsigned)ctx.opt->format > JMF_IN_PLY)
        return jmr_fail(&ctx, JMF_E_UNSUPPORTED, jmr_nowhere(), "unknown input format %d", (int)ctx.opt->format);
    if (!d && size) return jmr_fail(&ctx, JMF_E_IO, jmr_nowhere(), "no data");
    if (size == 0) return jmr_fail(&ctx, JMF_E_FORMAT, jmr_nowhere(), "empty file (0 bytes)");
    if (ctx.opt->max_bytes && size > ctx.opt->max_bytes)
        return jmr_fail(&ctx, JMF_E_LIMIT, jmr_nowhere(), "input of %zu bytes exceeds max_bytes (%zu)",
                        size, ctx.opt->max_bytes);

    if (is_gzip(d, n)) {
        st = gunzip(d, n, &ctx, &plain, &n);
        if (st) return st;
        d = plain;
        compressed = 1;
        ctx.gunzipped = 1;
        if (n == 0) {
            free(plain);
            return jmr_fail(&ctx, JMF_E_FORMAT, jmr_nowhere(), "empty file (0 bytes after gunzip)");
        }
    }

    f = ctx.opt->format;
    if (f == JMF_IN_AUTO) f = by_magic(d, n);
    if (f == JMF_IN_AUTO) f = by_extension(ctx.name);
    switch (f) {
    case JMF_IN_CSV: st = jmr_read_csv(d, n, &ctx, &pts); break;
    case JMF_IN_XYZ: st = jmr_read_xyz(d, n, &ctx, &pts); break;
    case JMF_IN_VTK: st = jmr_read_vtk(d, n, &ctx, &pts); break;
    case JMF_IN_VTU: st = jmr_read_vtu(d, n, &ctx, &pts); break;
    case JMF_IN_BGEO: st = jmr_read_bgeo(d, n, &ctx, &pts); break;
    case JMF_IN_PLY: st = jmr_read_ply(d, n, &ctx, &pts); break;
    default:
        st = jmr_fail(&ctx, JMF_E_UNSUPPORTED, jmr_byte(0),
                      "unknown particle format: no known magic and no known extension "
                      "(expected .csv .txt .xyz .vtk .vtu .bgeo .ply, optionally .gz)");
        break;
    }
    free(plain);
    if (!st) st = jmr_attrs_check(&pts, &ctx);
    if (st) {
        jmr_points_free(&pts);
        memset(out, 0, sizeof *out);
        return st;
    }
    jmr_points_finish(&pts, out);
    out->format = f;
    out->compressed = compressed;
    if (err && errlen) err[0] = '\0';
    return JMF_OK;
}

/* ---- files ---- */

const char *jmf_input_name(const char *path)
{
    return path && strcmp(path, "-") == 0 ? JMF_STDIN_NAME : path;
}

jmf_status jmf_read_input(const char *path, const jmf_read_options *opt, void **out, size_t *out_size, char *err,
                          size_t errlen)
{
    static const jmf_read_options defaults = { JMF_IN_AUTO, 0, 0, NULL };
    jmr_ctx ctx;
    struct stat sb;
    FILE *fp;
    uint8_t *buf = NULL;
    size_t cap = 0, len = 0, limit;
    int is_stdin = path && strcmp(path, "-") == 0;

    if (err && errlen) err[0] = '\0';
    if (out) *out = NULL;
    if (out_size) *out_size = 0;
    ctx.name = path ? jmf_input_name(path) : "<null>";
    ctx.opt = opt ? opt : &defaults;
    ctx.err = err;
    ctx.errlen = errlen;
    ctx.gunzipped = 0;
    if (!out || !out_size) return JMF_E_IO;
    if (!path || !*path) return jmr_fail(&ctx, JMF_E_IO, jmr_nowhere(), "no file name given");
    /* also bounds endless non-regular files (/dev/zero) when max_bytes is 0 */
    limit = jmr_max_decoded(&ctx);

    if (is_stdin) {
        int fd = dup(0);
        fp = fd >= 0 ? fdopen(fd, "rb") : NULL;
        if (!fp && fd >= 0) close(fd);
    } else {
        fp = fopen(path, "rb");
    }
    if (!fp) return jmr_fail(&ctx, JMF_E_IO, jmr_nowhere(), "cannot open: %s", strerror(errno));
    if (fstat(fileno(fp), &sb) != 0) {
        int e = errno;
        fclose(fp);
        return jmr_fail(&ctx, JMF_E_IO, jmr_nowhere(), "cannot stat: %s", strerror(e));
    }
    if (S_ISDIR(sb.st_mode)) {
        fclose(fp);
        return jmr_fail(&ctx, JMF_E_IO, jmr_nowhere(), "is a directory, expected a particle file");
    }
    if (S_ISREG(sb.st_mode) && sb.st_size > 0 && !is_stdin) {
        if ((uint64_t)sb.st_size > limit) {
            fclose(fp);
            return jmr_fail(&ctx, JMF_E_LIMIT, jmr_nowhere(), "file of %lld bytes exceeds the limit of %zu bytes%s",
                            (long long)sb.st_size, limit, ctx.opt->max_bytes ? " (max_bytes)" : " (built-in cap when max_bytes is 0)");
        }
        if ((uint64_t)sb.st_size >= SIZE_MAX) {
            fclose(fp);
            return jmr_fail(&ctx, JMF_E_NOMEM, jmr_nowhere(), "file too large for memory");
        }
        cap = (size_t)sb.st_size + 1; /* +1 to see EOF without growing */
    } else {
        cap = 65536;
    }
    buf = malloc(cap);
    if (!buf) {
        fclose(fp);
        return jmr_fail(&ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for %zu bytes", cap);
    }
    for (;;) {
        size_t got;
        if (len == cap) {
            size_t ncap = cap > SIZE_MAX / 2 ? SIZE_MAX : cap * 2;
            uint8_t *nb;
            if (len > limit) break; /* reported below */
            if (ncap > limit + 1) ncap = limit + 1;
            nb = (ncap > cap) ? realloc(buf, ncap) : NULL;
            if (!nb) {
                free(buf);
                fclose(fp);
                return jmr_fail(&ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory reading the file");
            }
            buf = nb;
            cap = ncap;
        }
        got = fread(buf + len, 1, cap - len, fp);
        len += got;
        if (got == 0) {
            if (ferror(fp)) {
                int e = errno;
                free(buf);
                fclose(fp);
                return jmr_fail(&ctx, JMF_E_IO, jmr_nowhere(), "read error: %s",
                                e ? strerror(e) : "I/O error");
            }
            break;
        }
    }
    fclose(fp);
    if (len > limit) {
        free(buf);
        return jmr_fail(&ctx, JMF_E_LIMIT, jmr_nowhere(), "file exceeds the limit of %zu bytes%s", limit,
                        ctx.opt->max_bytes ? " (max_bytes)" : " (built-in cap when max_bytes is 0)");
    }
    *out = buf;
    *out_size = len;
    return JMF_OK;
}

jmf_status jmf_read_particles(const char *path, const jmf_read_options *opt, jmf_frame *out,
                              char *err, size_t errlen)
{
    void *buf = NULL;
    size_t len = 0;
    jmf_status st;
    if (out) memset(out, 0, sizeof *out);
    if (!out) {
        if (err && errlen) err[0] = '\0';
        return JMF_E_IO;
    }
    st = jmf_read_input(path, opt, &buf, &len, err, errlen);
    if (st) return st;
    st = jmf_read_particles_mem(buf, len, jmf_input_name(path), opt, out, err, errlen);
    free(buf);
    return st;
}
