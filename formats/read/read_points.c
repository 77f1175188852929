/* read_points.c - the points a reader collects: growth, ids, non-finite points dropped, the frame handed over. */
#include "readbuf.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static jmf_status grow_to(jmr_points *pts, const jmr_ctx *ctx, size_t cap)
{
    size_t bytes;
    float *nx;
    if (cap <= pts->cap) return JMF_OK;
    if (!jmr_mul(cap, 3 * sizeof(float), &bytes))
        return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "particle count %zu overflows memory size", cap);
    nx = realloc(pts->xyz, bytes);
    if (!nx)
        return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for %zu particles", cap);
    pts->xyz = nx;
    if (pts->ids) {
        uint32_t *ni = realloc(pts->ids, cap * sizeof(uint32_t));
        if (!ni)
            return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for %zu particle ids", cap);
        memset(ni + pts->cap, 0, (cap - pts->cap) * sizeof(uint32_t));
        pts->ids = ni;
    }
    pts->cap = cap;
    return JMF_OK;
}

jmf_status jmr_points_reserve(jmr_points *pts, const jmr_ctx *ctx, size_t n)
{
    size_t want;
    if (!jmr_add(pts->count, n, &want))
        return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "particle count overflows");
    return grow_to(pts, ctx, want);
}

jmf_status jmr_points_want_ids(jmr_points *pts, const jmr_ctx *ctx)
{
    if (pts->ids) return JMF_OK;
    pts->ids = calloc(pts->cap ? pts->cap : 1, sizeof(uint32_t));
    if (!pts->ids)
        return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for particle ids");
    return JMF_OK;
}

/* double -> float without relying on out-of-range conversions: too big becomes +-inf. */
static float to_float(double v)
{
    if (isnan(v)) return NAN;
    if (v > FLT_MAX) return INFINITY;
    if (v < -FLT_MAX) return -INFINITY;
    return (float)v;
}

jmf_status jmr_points_add(jmr_points *pts, const jmr_ctx *ctx, double x, double y, double z,
                          uint32_t id, jmr_at at)
{
    float fx = to_float(x), fy = to_float(y), fz = to_float(z);
    float *p;
    if (!isfinite(fx) || !isfinite(fy) || !isfinite(fz)) {
        if (!ctx->opt->drop_invalid)
            return jmr_fail(ctx, JMF_E_FORMAT, at,
                            "particle %zu has a non-finite coordinate (%g, %g, %g); expected finite "
                            "numbers (drop_invalid skips such particles)",
                            pts->count, x, y, z);
        fx = fy = fz = NAN;
        pts->invalid++;
    }
    if (pts->count == pts->cap) {
        size_t cap = pts->cap < 1024 ? 1024 : pts->cap;
        jmf_status st;
        if (cap > SIZE_MAX / 2) cap = SIZE_MAX; else cap *= 2;
        st = grow_to(pts, ctx, cap);
        if (st) return st;
    }
    p = pts->xyz + 3 * pts->count;
    p[0] = fx; p[1] = fy; p[2] = fz;
    if (pts->ids) pts->ids[pts->count] = id;
    pts->count++;
    return JMF_OK;
}

void jmr_points_set_id(jmr_points *pts, size_t i, uint64_t id, int ok)
{
    if (!pts->ids || i >= pts->cap) return;
    if (!ok || id > UINT32_MAX) { pts->ids_bad = 1; return; }
    pts->ids[i] = (uint32_t)id;
}

void jmr_points_finish(jmr_points *pts, jmf_frame *out)
{
    size_t i, k = 0;
    memset(out, 0, sizeof *out);
    if (pts->ids && pts->ids_bad) { free(pts->ids); pts->ids = NULL; }
    if (pts->invalid) {
        for (i = 0; i < pts->count; i++) {
            if (isnan(pts->xyz[3 * i])) continue;
            if (k != i) {
                memmove(pts->xyz + 3 * k, pts->xyz + 3 * i, 3 * sizeof(float));
                if (pts->ids) pts->ids[k] = pts->ids[i];
                jmr_attrs_move(pts, k, i);
            }
            k++;
        }
        out->dropped = pts->count - k;
        pts->count = k;
    }
    out->count = pts->count;
    jmr_attrs_finish(pts, out);
    if (pts->count == 0) {
        free(pts->xyz);
        free(pts->ids);
    } else {
        out->xyz = pts->xyz;
        out->ids = pts->ids;
    }
    memset(pts, 0, sizeof *pts);
}

void jmr_points_free(jmr_points *pts)
{
    jmr_attrs_free(pts);
    free(pts->xyz);
    free(pts->ids);
    memset(pts, 0, sizeof *pts);
}
