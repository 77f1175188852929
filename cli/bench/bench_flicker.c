/* bench_flicker.c - the flicker figure of `jetmesh bench --flicker K`: how far the meshes of a translated input differ from translated copies. */
#include "bench_flicker.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_distance.h"

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Frame k's distances (vertices moved back by off) from frame 0's surface, appended to d. */
static void frame_distances(const md_grid *g, const jm_mesh *m, const double off[3], double limit, double *d, size_t *n)
{
    for (size_t v = 0; v < m->vertex_count; v++) {
        double p[3];
        for (int a = 0; a < 3; a++) p[a] = (double)m->positions[3 * v + a] - off[a];
        d[(*n)++] = md_distance(g, p, limit);
    }
}

int bench_flicker(const bench_opts *o, const bench_input *in, jm_context *ctx, bench_case *c)
{
    const int K = o->flicker;
    const double r = o->radius, h = (double)c->params.cube_size * r, dir[3] = {1.0, 0.6180339887, 0.3819660113};
    const double limit = 4.0 * r; /* a vertex farther is counted at 4 r: a lost piece, not shimmer */
    float *moved = malloc(3 * in->count * sizeof *moved + 1), *pos0 = NULL;
    uint32_t *idx0 = NULL;
    double *d = NULL;
    md_grid *g = NULL;
    size_t nd = 0, cap = 0;
    int rc = -1;
    if (!moved) goto oom;
    for (int k = 0; k < K; k++) {
        double off[3];
        for (int a = 0; a < 3; a++) off[a] = (double)k / K * h * dir[a];
        for (size_t i = 0; i < in->count; i++)
            for (int a = 0; a < 3; a++) moved[3 * i + a] = (float)((double)in->xyz[3 * i + a] + off[a]);
        jm_particles parts = {moved, in->count, 0, in->ids};
        jm_mesh m;
        jm_stats st;
        jm_status js = jm_mesh_particles(ctx, &parts, &m, &st);
        if (js != JM_OK) {
            snprintf(c->err, sizeof c->err, "flicker: jm_mesh_particles: %s", jm_status_message(js));
            goto out;
        }
        if (k == 0) { /* the reference: its arrays are the context's, copied */
            pos0 = malloc(3 * m.vertex_count * sizeof *pos0 + 1);
            idx0 = malloc(3 * m.triangle_count * sizeof *idx0 + 1);
            if (!pos0 || !idx0) goto oom;
            memcpy(pos0, m.positions, 3 * m.vertex_count * sizeof *pos0);
            memcpy(idx0, m.indices, 3 * m.triangle_count * sizeof *idx0);
            g = md_build(pos0, idx0, m.triangle_count, 0);
            if (!g && m.triangle_count) goto oom;
            continue;
        }
        if (nd + m.vertex_count > cap) {
            cap = 2 * (nd + m.vertex_count);
            double *nd2 = realloc(d, cap * sizeof *d);
            if (!nd2) goto oom;
            d = nd2;
        }
        if (g) frame_distances(g, &m, off, limit, d, &nd);
    }
    c->flicker_p99 = c->flicker_max = 0.0;
    if (nd) {
        qsort(d, nd, sizeof *d, cmp_d);
        c->flicker_p99 = d[(size_t)(0.99 * (double)(nd - 1) + 0.5)] / r;
        c->flicker_max = d[nd - 1] / r;
    }
    c->flicker_frames = K;
    rc = 0;
    goto out;
oom:
    snprintf(c->err, sizeof c->err, "flicker: out of memory");
out:
    md_free(g);
    free(moved), free(pos0), free(idx0), free(d);
    return rc;
}
