/* read_attrs.c - the per-particle arrays (velocity, density, ...) the readers keep besides the positions. */
#include "readbuf.h"

#include <ctype.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>

int jmr_attrs_wanted(const jmr_ctx *ctx)
{
    return ctx->opt->attributes && *ctx->opt->attributes;
}

/* The next name of a comma-separated list from *p: [s, s+n); 0 at the end. */
static int next_name(const char **p, const char **s, size_t *n)
{
    const char *q = *p;
    while (*q == ',' || *q == ' ') q++;
    if (!*q) return 0;
    *s = q;
    while (*q && *q != ',') q++;
    *n = (size_t)(q - *s);
    while (*n > 0 && (*s)[*n - 1] == ' ') (*n)--;
    *p = q;
    return 1;
}

static int is_all(const jmr_ctx *ctx)
{
    const char *l = ctx->opt->attributes;
    return l && jmr_ieq(l, strlen(l), "all");
}

static int same_name(const char *a, size_t an, const char *b, size_t bn)
{
    if (an != bn) return 0;
    for (size_t i = 0; i < an; i++)
        if (tolower((unsigned char)a[i]) != tolower((unsigned char)b[i])) return 0;
    return 1;
}

/* 1 if the list names it. */
static int named(const jmr_ctx *ctx, const char *name, size_t n)
{
    const char *p = ctx->opt->attributes, *s;
    size_t k;
    if (!p) return 0;
    while (next_name(&p, &s, &k))
        if (same_name(s, k, name, n)) return 1;
    return 0;
}

static void note_name(jmr_points *pts, const char *name, size_t n)
{
    size_t need = pts->seen_len + (pts->seen_len ? 2 : 0) + n + 1;
    char *s;
    /* once per name */
    if (pts->seen) {
        const char *p = pts->seen, *w;
        size_t k;
        while (next_name(&p, &w, &k))
            if (same_name(w, k, name, n)) return;
    }
    if (n > 200 || need > 8192) return; /* for messages only */
    s = realloc(pts->seen, need);
    if (!s) return;
    if (pts->seen_len) {
        memcpy(s + pts->seen_len, ", ", 2);
        pts->seen_len += 2;
    }
    memcpy(s + pts->seen_len, name, n);
    pts->seen_len += n;
    s[pts->seen_len] = '\0';
    pts->seen = s;
}

jmf_status jmr_attr_begin(jmr_points *pts, const jmr_ctx *ctx, const char *name, size_t n, size_t comps,
                          size_t count, jmr_at at, jmr_attr **out)
{
    jmr_attr *a, **na;
    size_t bytes;
    *out = NULL;
    if (!jmr_attrs_wanted(ctx) || n == 0) return JMF_OK;
    /* positions and ids are not attributes */
    if (jmr_ieq(name, n, "id") || jmr_ieq(name, n, "position") || jmr_ieq(name, n, "points") ||
        jmr_ieq(name, n, "p"))
        return JMF_OK;
    note_name(pts, name, n);
    if (!is_all(ctx) && !named(ctx, name, n)) return JMF_OK;
    for (size_t i = 0; i < pts->nattrs; i++)
        if (same_name(pts->attrs[i]->name, strlen(pts->attrs[i]->name), name, n)) return JMF_OK;
    if (comps < 1 || comps > 4) {
        if (is_all(ctx)) return JMF_OK;
        return jmr_fail(ctx, JMF_E_UNSUPPORTED, at, "attribute '%.*s' has %zu components; expected 1 to 4",
                        (int)(n > 60 ? 60 : n), name, comps);
    }
    size_t kept = comps;
    for (size_t i = 0; i < pts->nattrs; i++) kept += (size_t)pts->attrs[i]->comps;
    if (kept > JMF_MAX_ATTRIBUTE_COMPONENTS)
        return jmr_fail(ctx, JMF_E_UNSUPPORTED, at,
                        "attribute '%.*s' makes %zu components in all, over the limit of %d a frame carries; "
                        "ask for fewer arrays by name",
                        (int)(n > 60 ? 60 : n), name, kept, JMF_MAX_ATTRIBUTE_COMPONENTS);
    if (!jmr_mul(count, comps * sizeof(float), &bytes))
        return jmr_fail(ctx, JMF_E_NOMEM, at, "attribute '%.*s': size overflows", (int)(n > 60 ? 60 : n), name);
    na = realloc(pts->attrs, (pts->nattrs + 1) * sizeof *na);
    if (!na) return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for attributes");
    pts->attrs = na;
    a = calloc(1, sizeof *a);
    if (a) {
        a->name = malloc(n + 1);
        a->v = calloc(count ? count * comps : 1, sizeof(float));
    }
    if (!a || !a->name || !a->v) {
        if (a) {
            free(a->name);
            free(a->v);
        }
        free(a);
        return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for attribute '%.*s'",
                        (int)(n > 60 ? 60 : n), name);
    }
    memcpy(a->name, name, n);
    a->name[n] = '\0';
    a->comps = (int)comps;
    a->count = a->cap = count;
    na[pts->nattrs++] = a;
    *out = a;
    return JMF_OK;
}

jmf_status jmr_attr_push(jmr_attr *a, const jmr_ctx *ctx, const double *vals)
{
    if (a->count == a->cap) {
        size_t cap = a->cap < 1024 ? 1024 : a->cap * 2, bytes;
        float *nv;
        if (!jmr_mul(cap, (size_t)a->comps * sizeof(float), &bytes) || !(nv = realloc(a->v, bytes)))
            return jmr_fail(ctx, JMF_E_NOMEM, jmr_nowhere(), "out of memory for attribute '%s'", a->name);
        a->v = nv;
        a->cap = cap;
    }
    for (int c = 0; c < a->comps; c++) {
        double v = vals[c];
        a->v[a->count * (size_t)a->comps + (size_t)c] =
            isnan(v) ? NAN : v > FLT_MAX ? INFINITY : v < -FLT_MAX ? -INFINITY : (float)v;
    }
    a->count++;
    return JMF_OK;
}

void jmr_attr_set(jmr_attr *a, size_t i, size_t c, double v)
{
    if (!a || i >= a->count || c >= (size_t)a->comps) return;
    a->v[i * (size_t)a->comps + c] = isnan(v) ? NAN : v > FLT_MAX ? INFINITY : v < -FLT_MAX ? -INFINITY : (float)v;
}

jmf_status jmr_attrs_check(jmr_points *pts, const jmr_ctx *ctx)
{
    const char *p = ctx->opt->attributes, *s;
    size_t n;
    if (!jmr_attrs_wanted(ctx)) return JMF_OK;
    if (!is_all(ctx)) {
        while (next_name(&p, &s, &n)) {
            size_t i;
            for (i = 0; i < pts->nattrs; i++)
                if (same_name(pts->attrs[i]->name, strlen(pts->attrs[i]->name), s, n)) break;
            if (i == pts->nattrs)
                return jmr_fail(ctx, JMF_E_FORMAT, jmr_nowhere(),
                                "no per-particle attribute '%.*s' in this file (it has: %s)", (int)(n > 60 ? 60 : n), s,
                                pts->seen ? pts->seen : "none");
        }
    }
    for (size_t k = 0; k < pts->nattrs; k++) {
        jmr_attr *a = pts->attrs[k];
        if (a->count != pts->count)
            return jmr_fail(ctx, JMF_E_FORMAT, jmr_nowhere(),
                            "attribute '%s' has %zu values for %zu particles; expected one per particle", a->name,
                            a->count, pts->count);
        for (size_t i = 0; i < a->count; i++)
            for (int c = 0; c < a->comps; c++) {
                float v = a->v[i * (size_t)a->comps + (size_t)c];
                if (isfinite(v)) continue;
                if (!ctx->opt->drop_invalid)
                    return jmr_fail(ctx, JMF_E_FORMAT, jmr_nowhere(),
                                    "attribute '%s' of particle %zu is %s; expected finite numbers "
                                    "(--drop-invalid drops such particles)",
                                    a->name, i, isnan(v) ? "NaN" : "infinite");
                if (!isnan(pts->xyz[3 * i])) {
                    pts->xyz[3 * i] = pts->xyz[3 * i + 1] = pts->xyz[3 * i + 2] = NAN;
                    pts->invalid++;
                }
            }
    }
    return JMF_OK;
}

void jmr_attrs_move(jmr_points *pts, size_t k, size_t i)
{
    for (size_t j = 0; j < pts->nattrs; j++) {
        jmr_attr *a = pts->attrs[j];
        memmove(a->v + k * (size_t)a->comps, a->v + i * (size_t)a->comps, (size_t)a->comps * sizeof(float));
    }
}

void jmr_attrs_finish(jmr_points *pts, jmf_frame *out)
{
    jmf_attribute *fa = pts->nattrs ? calloc(pts->nattrs, sizeof *fa) : NULL;
    if (fa) {
        for (size_t j = 0; j < pts->nattrs; j++) {
            fa[j].name = pts->attrs[j]->name;
            fa[j].components = pts->attrs[j]->comps;
            fa[j].values = pts->attrs[j]->v;
            free(pts->attrs[j]);
        }
        out->attributes = fa;
        out->attribute_count = pts->nattrs;
        free(pts->attrs);
    } else {
        jmr_attrs_free(pts); /* none, or no memory for the list */
    }
    out->array_names = pts->seen;
    pts->attrs = NULL;
    pts->nattrs = 0;
    pts->seen = NULL;
    pts->seen_len = 0;
}

void jmr_attrs_free(jmr_points *pts)
{
    for (size_t j = 0; j < pts->nattrs; j++) {
        free(pts->attrs[j]->name);
        free(pts->attrs[j]->v);
        free(pts->attrs[j]);
    }
    free(pts->attrs);
    free(pts->seen);
    pts->attrs = NULL;
    pts->nattrs = 0;
    pts->seen = NULL;
    pts->seen_len = 0;
}

void jmr_frame_attrs_free(jmf_frame *f)
{
    for (size_t j = 0; j < f->attribute_count; j++) {
        free(f->attributes[j].name);
        free(f->attributes[j].values);
    }
    free(f->attributes);
    free(f->array_names);
}

/* Splits a column name into a base and an axis 0..2: "velocity_x",
 * "velocity.y", "vz"; -1 if it has none. */
static int axis_suffix(const char *s, size_t n, size_t *base)
{
    int c;
    if (n < 2) return -1;
    c = tolower((unsigned char)s[n - 1]);
    if (c < 'x' || c > 'z') return -1;
    *base = n - 1;
    if (s[n - 2] == '_' || s[n - 2] == '.' || s[n - 2] == ':') (*base)--;
    return *base > 0 ? c - 'x' : -1;
}

size_t jmr_group_columns(const char *const *names, const size_t *lens, const int *skip, size_t ncols,
                         jmr_colgroup *out)
{
    size_t ng = 0;
    char *used = calloc(ncols ? ncols : 1, 1);
    if (!used) return 0;
    for (size_t i = 0; i < ncols; i++) {
        size_t base, cols[3] = {0, 0, 0};
        int have = 0;
        if (skip[i] || used[i]) continue;
        if (axis_suffix(names[i], lens[i], &base) == 0) {
            /* look for the y and z of the same base */
            for (size_t j = 0; j < ncols; j++) {
                size_t b2;
                int ax;
                if (skip[j] || used[j]) continue;
                ax = axis_suffix(names[j], lens[j], &b2);
                if (ax >= 0 && b2 == base && lens[j] == lens[i] && same_name(names[j], b2, names[i], base) &&
                    !(have & (1 << ax))) {
                    cols[ax] = j;
                    have |= 1 << ax;
                }
            }
        }
        jmr_colgroup *g = &out[ng++];
        if (have == 7) {
            const char *nm = names[i];
            size_t nl = base;
            if (base == 1 && (nm[0] == 'v' || nm[0] == 'V')) {
                nm = "velocity";
                nl = 8;
            }
            if (nl > sizeof g->name - 1) nl = sizeof g->name - 1;
            memcpy(g->name, nm, nl);
            g->name[nl] = '\0';
            g->comps = 3;
            for (int k = 0; k < 3; k++) {
                g->cols[k] = cols[k];
                used[cols[k]] = 1;
            }
        } else {
            size_t nl = lens[i] > sizeof g->name - 1 ? sizeof g->name - 1 : lens[i];
            memcpy(g->name, names[i], nl);
            g->name[nl] = '\0';
            g->comps = 1;
            g->cols[0] = i;
            used[i] = 1;
        }
    }
    free(used);
    return ng;
}
