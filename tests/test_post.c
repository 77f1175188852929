/* test_post.c - post-processing: smoothing reduces SPH orange peel and keeps volumes and droplets, simplification stays close and closed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../formats/reader.h"
#include "../lib/jetmesh.h"
#include "util/meshcheck.h"
#include "util/test_meshes.h"
#include "util/shared_data.h"

#define R 0.025f

/* ---- inputs */

/* A jittered ball: lattice points of spacing s (times r) within 15r of the
 * origin, each moved by up to s/8 per axis (the surface lies near 16r). */
static float *make_ball(float s, size_t *n)
{
    unsigned seed = 7;
    int m = (int)(15.0f / s) + 1;
    float *p = malloc(3 * (size_t)(2 * m + 1) * (2 * m + 1) * (2 * m + 1) * sizeof *p);
    assert_non_null(p);
    size_t k = 0;
    for (int z = -m; z <= m; z++)
        for (int y = -m; y <= m; y++)
            for (int x = -m; x <= m; x++) {
                float c[3] = {s * R * x, s * R * y, s * R * z};
                if (sqrtf(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) > 15 * R) continue;
                for (int a = 0; a < 3; a++) p[3 * k + a] = c[a] + (mc_randf(&seed) - 0.5f) * 0.25f * s * R;
                k++;
            }
    *n = k;
    return p;
}

/* Spray: single droplets, pairs, lines of 3 and clusters of 8 (a 2x2x2
 * cube) at spacing 2r, each group 12r from any other. */
static float *make_spray(size_t *n)
{
    unsigned seed = 11;
    float *p = malloc(3 * 4096 * sizeof *p);
    assert_non_null(p);
    size_t k = 0;
    for (int g = 0; g < 64; g++) {
        float o[3] = {12 * R * (g % 4), 12 * R * ((g / 4) % 4), 12 * R * (g / 16)};
        int kind = g % 4, count = kind == 0 ? 1 : kind == 1 ? 2 : kind == 2 ? 3 : 8;
        for (int i = 0; i < count; i++) {
            int ix = kind == 3 ? i & 1 : i, iy = kind == 3 ? (i >> 1) & 1 : 0, iz = kind == 3 ? i >> 2 : 0;
            p[3 * k] = o[0] + 2 * R * ix + (mc_randf(&seed) - 0.5f) * 0.2f * R;
            p[3 * k + 1] = o[1] + 2 * R * iy + (mc_randf(&seed) - 0.5f) * 0.2f * R;
            p[3 * k + 2] = o[2] + 2 * R * iz + (mc_randf(&seed) - 0.5f) * 0.2f * R;
            k++;
        }
    }
    *n = k;
    return p;
}

static void mesh_with(const float *xyz, size_t n, jm_params p, test_mesh *out)
{
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
    jm_particles in = {xyz, n, 0, NULL};
    jm_mesh m;
    jm_stats st;
    assert_int_equal(jm_mesh_particles(ctx, &in, &m, &st), JM_OK);
    if (p.smooth_iterations || p.smooth_normal_iterations || p.simplify_error > 0.0f)
        assert_true(st.ms_post > 0.0);
    else
        assert_true(st.ms_post == 0.0);
    assert_int_equal(test_mesh_copy(&m, out), 0);
    jm_context_free(ctx);
}

static int cmp_f(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

/* Radial standard deviation about the vertex centroid; the 95th percentile
 * of the normals' angle (degrees) from the radial direction. */
static void sphere_stats(const jm_mesh *m, const uint32_t *lab, uint32_t which, double *sd, double *p95)
{
    size_t all = m->vertex_count, nv = 0;
    double c[3] = {0, 0, 0};
    for (size_t v = 0; v < all; v++) {
        if (lab && lab[v] != which) continue;
        for (int a = 0; a < 3; a++) c[a] += m->positions[3 * v + a];
        nv++;
    }
    for (int a = 0; a < 3; a++) c[a] /= (double)nv;
    double s = 0, s2 = 0;
    float *ang = malloc(all * sizeof *ang);
    assert_non_null(ang);
    size_t na = 0;
    for (size_t v = 0; v < all; v++) {
        if (lab && lab[v] != which) continue;
        double d[3], l = 0, dot = 0;
        for (int a = 0; a < 3; a++) {
            d[a] = m->positions[3 * v + a] - c[a];
            l += d[a] * d[a];
        }
        l = sqrt(l);
        s += l;
        s2 += l * l;
        for (int a = 0; a < 3; a++) dot += d[a] / l * m->normals[3 * v + a];
        ang[na++] = (float)(acos(dot > 1 ? 1 : dot < -1 ? -1 : dot) * 180.0 / M_PI);
    }
    double mean = s / (double)nv;
    *sd = sqrt(s2 / (double)nv - mean * mean);
    qsort(ang, nv, sizeof *ang, cmp_f);
    *p95 = ang[(size_t)(0.95 * (double)nv)];
    free(ang);
}

/* ---- smoothing */

static uint32_t *components(const jm_mesh *m, size_t *count);
static void component_volumes(const jm_mesh *m, const uint32_t *lab, double *vol, size_t count);

static void test_ball_orange_peel(void **state)
{
    (void)state;
    size_t n;
    float *xyz = make_ball(2.0f, &n);
    jm_params p = {0};
    p.radius = R;
    p.field = JM_FIELD_SPH;
    p.method = JM_METHOD_MC;
    test_mesh raw, sm;
    mesh_with(xyz, n, p, &raw);
    p.smooth_iterations = 25;
    p.smooth_normal_iterations = 10;
    mesh_with(xyz, n, p, &sm);
    mc_report r0, r1;
    assert_true(mc_check(&raw.mesh, &r0));
    if (!mc_check(&sm.mesh, &r1)) fail_msg("smoothed ball: %s", r1.problem);
    assert_int_equal(r1.normals_away, 0);
    double sd0, a0, sd1, a1;
    sphere_stats(&raw.mesh, NULL, 0, &sd0, &a0);
    sphere_stats(&sm.mesh, NULL, 0, &sd1, &a1);
    double dv = (r1.volume - r0.volume) / r0.volume;
    printf("ball of %zu particles: radial sd %.3f r -> %.3f r, normals p95 %.1f -> %.1f deg, volume %+.2f %%\n", n,
           sd0 / R, sd1 / R, a0, a1, 100 * dv);
    /* 0.46: no vertex moves more than 0.46 r along its normal and 25
     * iterations diffuse as splashsurf's 25 do (issue 31; 0.44 with a band
     * of 0.5 r; the unbounded smoothing before reached a third by moving
     * the surface up to 1.1 r and shrinking dense droplets to nothing) */
    assert_true(sd1 <= 0.47 * sd0);
    assert_true(a1 <= 10.0);
    assert_true(fabs(dv) <= 0.02);
    /* the same triangles: smoothing moves vertices only */
    assert_int_equal(raw.mesh.triangle_count, sm.mesh.triangle_count);
    assert_memory_equal(raw.indices, sm.indices, 3 * raw.mesh.triangle_count * sizeof(uint32_t));
    test_mesh_free(&raw);
    test_mesh_free(&sm);

    /* the steady smoothing (--smooth-implicit) as much: 0.154 r of 0.328 r */
    p.smooth_implicit = 1;
    mesh_with(xyz, n, p, &sm);
    if (!mc_check(&sm.mesh, &r1)) fail_msg("ball smoothed by the implicit steps: %s", r1.problem);
    assert_int_equal(r1.normals_away, 0);
    sphere_stats(&sm.mesh, NULL, 0, &sd1, &a1);
    dv = (r1.volume - r0.volume) / r0.volume;
    printf("ball of %zu particles, --smooth-implicit: radial sd %.3f r -> %.3f r, normals p95 %.1f -> %.1f deg, "
           "volume %+.2f %%\n", n, sd0 / R, sd1 / R, a0, a1, 100 * dv);
    assert_true(sd1 <= 0.48 * sd0);
    assert_true(a1 <= 10.0);
    assert_true(fabs(dv) <= 0.02);
    test_mesh_free(&sm);
    p.smooth_implicit = 0;

    /* the metasphere (marching tetrahedra) smooths too; at spacing 2r its
     * balls only touch, a porous sponge, so a denser ball (spacing 1.2r; its
     * outer surface: small voids inside are pieces of their own) */
    free(xyz);
    xyz = make_ball(1.2f, &n);
    p.field = JM_FIELD_METASPHERE;
    p.method = JM_METHOD_MT;
    p.smooth_iterations = 0;
    p.smooth_normal_iterations = 0;
    mesh_with(xyz, n, p, &raw);
    p.smooth_iterations = 25;
    p.smooth_normal_iterations = 10;
    mesh_with(xyz, n, p, &sm);
    assert_true(mc_check(&raw.mesh, &r0));
    if (!mc_check(&sm.mesh, &r1)) fail_msg("smoothed metasphere ball: %s", r1.problem);
    size_t nc;
    uint32_t *lab = components(&raw.mesh, &nc);
    double *v0 = calloc(nc, sizeof *v0), *v1 = calloc(nc, sizeof *v1);
    assert_true(v0 && v1);
    component_volumes(&raw.mesh, lab, v0, nc);
    component_volumes(&sm.mesh, lab, v1, nc);
    uint32_t outer = 0;
    for (size_t k = 1; k < nc; k++)
        if (v0[k] > v0[outer]) outer = (uint32_t)k;
    sphere_stats(&raw.mesh, lab, outer, &sd0, &a0);
    sphere_stats(&sm.mesh, lab, outer, &sd1, &a1);
    dv = (v1[outer] - v0[outer]) / v0[outer];
    printf("metasphere ball (outer surface of %zu pieces): radial sd %.3f r -> %.3f r, normals p95 %.1f -> %.1f deg, "
           "volume %+.2f %%\n", nc, sd0 / R, sd1 / R, a0, a1, 100 * dv);
    /* 0.45 and 9.1 degrees (0.55 and 13.1 while the band clamped within
     * the super time stepping cycles) */
    assert_true(sd1 <= 0.5 * sd0);
    assert_true(a1 <= 10.0);
    assert_true(fabs(dv) <= 0.02);
    free(v0);
    free(v1);
    free(lab);
    test_mesh_free(&raw);
    test_mesh_free(&sm);
    free(xyz);
}

static uint32_t root(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

/* Per-vertex component labels (0..count-1) through shared vertices. */
static uint32_t *components(const jm_mesh *m, size_t *count)
{
    size_t nv = m->vertex_count;
    uint32_t *par = malloc(nv * sizeof *par), *lab = malloc(nv * sizeof *lab);
    assert_true(par && lab);
    for (size_t v = 0; v < nv; v++) par[v] = (uint32_t)v;
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int k = 1; k < 3; k++) {
            uint32_t a = root(par, m->indices[3 * t]), b = root(par, m->indices[3 * t + k]);
            if (a != b) par[a > b ? a : b] = a < b ? a : b;
        }
    size_t c = 0;
    for (size_t v = 0; v < nv; v++) {
        uint32_t r = root(par, (uint32_t)v);
        lab[v] = r == v ? (uint32_t)c++ : lab[r];
    }
    free(par);
    *count = c;
    return lab;
}

static void component_volumes(const jm_mesh *m, const uint32_t *lab, double *vol, size_t count)
{
    memset(vol, 0, count * sizeof *vol);
    for (size_t t = 0; t < m->triangle_count; t++) {
        const float *a = &m->positions[3 * m->indices[3 * t]], *b = &m->positions[3 * m->indices[3 * t + 1]],
                    *c = &m->positions[3 * m->indices[3 * t + 2]];
        vol[lab[m->indices[3 * t]]] += (a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) +
                                        a[1] * ((double)b[2] * c[0] - (double)b[0] * c[2]) +
                                        a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0])) / 6.0;
    }
}

/* Droplets, pairs and small clusters keep their number and their volume. */
static void test_spray_kept(void **state)
{
    (void)state;
    size_t n;
    float *xyz = make_spray(&n);
    for (int f = JM_FIELD_METASPHERE; f <= JM_FIELD_SPH; f++)
        for (int tpl = 0; tpl < 2; tpl++) {
            jm_params p = {0};
            p.radius = R;
            p.field = (jm_field)f;
            p.method = f == JM_FIELD_SPH ? JM_METHOD_MC : JM_METHOD_MT;
            p.no_templates = tpl;
            test_mesh raw, sm;
            mesh_with(xyz, n, p, &raw);
            p.smooth_iterations = 25;
            mesh_with(xyz, n, p, &sm);
            mc_report r0, r1;
            assert_true(mc_check(&raw.mesh, &r0));
            if (!mc_check(&sm.mesh, &r1)) fail_msg("smoothed spray: %s", r1.problem);
            assert_true(r0.components >= 64);
            assert_int_equal(r1.components, r0.components);
            size_t nc;
            uint32_t *lab = components(&raw.mesh, &nc);
            assert_int_equal(nc, r0.components);
            double v0[512], v1[512], worst = 1e9;
            assert_true(nc <= 512);
            component_volumes(&raw.mesh, lab, v0, nc);
            component_volumes(&sm.mesh, lab, v1, nc);
            for (size_t k = 0; k < nc; k++) {
                if (v0[k] <= 0) continue; /* a void inside a cluster */
                double q = v1[k] / v0[k];
                if (q < worst) worst = q;
                if (q < 0.85 || q > 1.15) fail_msg("field %d: droplet %zu keeps %.1f %% of its volume", f, k, 100 * q);
            }
            printf("spray (field %d, templates %s): %zu pieces, least volume kept %.1f %%\n", f, tpl ? "off" : "on",
                   nc, 100 * worst);
            free(lab);
            test_mesh_free(&raw);
            test_mesh_free(&sm);
        }
    free(xyz);
}

/* ---- simplification: distances between two meshes */

typedef struct tri_grid {
    const jm_mesh *m;
    float lo[3], cell;
    int n[3];
    uint32_t *start, *items;
} tri_grid;

static int gidx(const tri_grid *g, const int c[3]) { return (c[2] * g->n[1] + c[1]) * g->n[0] + c[0]; }

/* Buckets the triangles of m by the cells their boxes (grown by pad) touch. */
static void grid_build(tri_grid *g, const jm_mesh *m, float cell, float pad)
{
    g->m = m;
    g->cell = cell;
    for (int a = 0; a < 3; a++) {
        g->lo[a] = m->bounds_min[a] - 2 * pad;
        g->n[a] = (int)((m->bounds_max[a] + 2 * pad - g->lo[a]) / cell) + 1;
    }
    size_t cells = (size_t)g->n[0] * g->n[1] * g->n[2];
    g->items = NULL;
    g->start = calloc(cells + 1, sizeof *g->start);
    assert_non_null(g->start);
    for (int pass = 0; pass < 2; pass++) {
        for (size_t t = 0; t < m->triangle_count; t++) {
            int lo[3], hi[3];
            for (int a = 0; a < 3; a++) {
                float mn = 1e30f, mx = -1e30f;
                for (int k = 0; k < 3; k++) {
                    float x = m->positions[3 * m->indices[3 * t + k] + a];
                    mn = x < mn ? x : mn;
                    mx = x > mx ? x : mx;
                }
                lo[a] = (int)((mn - pad - g->lo[a]) / cell);
                hi[a] = (int)((mx + pad - g->lo[a]) / cell);
            }
            int c[3];
            for (c[2] = lo[2]; c[2] <= hi[2]; c[2]++)
                for (c[1] = lo[1]; c[1] <= hi[1]; c[1]++)
                    for (c[0] = lo[0]; c[0] <= hi[0]; c[0]++) {
                        int i = gidx(g, c);
                        if (pass == 0) g->start[i + 1]++;
                        else g->items[g->start[i]++] = (uint32_t)t;
                    }
        }
        if (pass == 0) {
            for (size_t i = 0; i < cells; i++) g->start[i + 1] += g->start[i];
            g->items = malloc((g->start[cells] + 1) * sizeof *g->items);
            assert_non_null(g->items);
        } else {
            memmove(g->start + 1, g->start, cells * sizeof *g->start);
            g->start[0] = 0;
        }
    }
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Squared distance from p to triangle abc (Ericson, Real-Time Collision
 * Detection, 5.1.5). */
static double point_tri2(const double p[3], const double a[3], const double b[3], const double c[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], q[3];
    for (int k = 0; k < 3; k++) ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k];
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) { memcpy(q, a, sizeof q); goto done; }
    for (int k = 0; k < 3; k++) bp[k] = p[k] - b[k];
    double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) { memcpy(q, b, sizeof q); goto done; }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++) q[k] = a[k] + v * ab[k];
        goto done;
    }
    for (int k = 0; k < 3; k++) cp[k] = p[k] - c[k];
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) { memcpy(q, c, sizeof q); goto done; }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double w = d2 / (d2 - d6);
        for (int k = 0; k < 3; k++) q[k] = a[k] + w * ac[k];
        goto done;
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++) q[k] = b[k] + w * (c[k] - b[k]);
        goto done;
    }
    {
        double den = 1.0 / (va + vb + vc), v = vb * den, w = vc * den;
        for (int k = 0; k < 3; k++) q[k] = a[k] + ab[k] * v + ac[k] * w;
    }
done:;
    double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    return dot3(d, d);
}

/* Distance from p to the surface of g's mesh, or pad if at least pad; or,
 * as soon as a triangle is found within `enough` of p, a distance of at
 * most `enough` (a caller after the largest distance need not know
 * which). */
static double distance_to(const tri_grid *g, const float pf[3], double pad, double enough)
{
    int c[3];
    for (int a = 0; a < 3; a++) {
        c[a] = (int)((pf[a] - g->lo[a]) / g->cell);
        if (c[a] < 0 || c[a] >= g->n[a]) return pad;
    }
    int i = gidx(g, c);
    double best = pad * pad, p[3] = {pf[0], pf[1], pf[2]};
    for (uint32_t k = g->start[i]; k < g->start[i + 1]; k++) {
        const uint32_t *t = &g->m->indices[3 * (size_t)g->items[k]];
        double v[3][3];
        for (int j = 0; j < 3; j++)
            for (int a = 0; a < 3; a++) v[j][a] = g->m->positions[3 * t[j] + a];
        double d = point_tri2(p, v[0], v[1], v[2]);
        if (d < best) best = d;
        if (best <= enough * enough) break;
    }
    return sqrt(best);
}

/* The larger of: the distance of every vertex, edge midpoint and centroid of
 * a to b's surface, and the other way round. */
static double hausdorff(const jm_mesh *a, const jm_mesh *b, double pad)
{
    double worst = 0;
    for (int dir = 0; dir < 2; dir++) {
        const jm_mesh *from = dir ? b : a, *to = dir ? a : b;
        tri_grid g;
        grid_build(&g, to, (float)pad, (float)pad);
        for (size_t t = 0; t < from->triangle_count; t++) {
            const float *v[3];
            for (int k = 0; k < 3; k++) v[k] = &from->positions[3 * from->indices[3 * t + k]];
            float pts[7][3];
            for (int a = 0; a < 3; a++) {
                for (int k = 0; k < 3; k++) {
                    pts[k][a] = v[k][a];
                    pts[3 + k][a] = 0.5f * (v[k][a] + v[(k + 1) % 3][a]);
                }
                pts[6][a] = (v[0][a] + v[1][a] + v[2][a]) / 3.0f;
            }
            for (int k = 0; k < 7; k++) {
                double d = distance_to(&g, pts[k], pad, worst);
                if (d > worst) worst = d;
            }
        }
        free(g.start);
        free(g.items);
    }
    return worst;
}

static int read_frame(const char *rel, jmf_frame *fr)
{
    char err[512];
    int got = test_read_shared(rel, NULL, fr, err, sizeof err);
    if (got < 0) fail_msg("%s", err);
    return got;
}

/* normals: also check that almost every normal faces the same side as its
 * faces (not for the metasphere, whose necks have creases) */
static void check_simplified(const char *what, const test_mesh *raw, const test_mesh *sim, double max_frac, int normals)
{
    mc_report r0, r1;
    assert_true(mc_check(&raw->mesh, &r0));
    if (!mc_check(&sim->mesh, &r1)) fail_msg("%s simplified: %s", what, r1.problem);
    double frac = (double)sim->mesh.triangle_count / (double)raw->mesh.triangle_count;
    /* distances measured up to 0.3 r (the bound below is 0.25 r): a point
     * farther reads 0.3 and fails it */
    double d = hausdorff(&raw->mesh, &sim->mesh, 0.3 * R);
    printf("%s: %zu -> %zu triangles (%.1f %%), max distance %.3f r, volume %+.2f %%, normals away from their "
           "faces %zu -> %zu\n",
           what, raw->mesh.triangle_count, sim->mesh.triangle_count, 100 * frac, d / R, 100 * (r1.volume / r0.volume - 1),
           r0.normals_away, r1.normals_away);
    if (normals) {
        assert_true(r0.normals_away * 1000 < raw->mesh.vertex_count);
        assert_true(r1.normals_away * 1000 < sim->mesh.vertex_count);
    }
    assert_true(frac <= max_frac);
    assert_true(d <= 0.25 * R);
    assert_int_equal(r1.components, r0.components);
}

static void test_bunny_simplified(void **state)
{
    (void)state;
    jmf_frame fr;
    if (!read_frame("splashsurf/bunny_frame_14_7705_particles.vtk", &fr)) {
        printf("skipping: ../shared/data not found\n");
        skip();
    }
    jm_params p = {0};
    p.radius = R;
    p.field = JM_FIELD_SPH;
    p.method = JM_METHOD_MC;
    test_mesh raw, sim;
    mesh_with(fr.xyz, fr.count, p, &raw);
    p.simplify_error = 0.1f;
    mesh_with(fr.xyz, fr.count, p, &sim);
    check_simplified("bunny --simplify 0.1", &raw, &sim, 0.30, 1);
    test_mesh_free(&sim);
    test_mesh_free(&raw);

    /* smoothed, then simplified: compared with the smoothed mesh */
    p.simplify_error = 0.0f;
    p.smooth_iterations = 25;
    p.smooth_normal_iterations = 10;
    mesh_with(fr.xyz, fr.count, p, &raw);
    p.simplify_error = 0.1f;
    mesh_with(fr.xyz, fr.count, p, &sim);
    check_simplified("bunny --smooth 25 --simplify 0.1", &raw, &sim, 0.30, 1);
    test_mesh_free(&sim);
    test_mesh_free(&raw);
    jmf_frame_free(&fr);
}

/* Templates of isolated particles, metasphere: simplified, still closed. */
static void test_spray_simplified(void **state)
{
    (void)state;
    size_t n;
    float *xyz = make_spray(&n);
    for (int f = JM_FIELD_METASPHERE; f <= JM_FIELD_SPH; f++) {
        jm_params p = {0};
        p.radius = R;
        p.field = (jm_field)f;
        test_mesh raw, sim;
        mesh_with(xyz, n, p, &raw);
        p.simplify_error = 0.1f;
        mesh_with(xyz, n, p, &sim);
        check_simplified(f == JM_FIELD_SPH ? "spray sph mt --simplify 0.1" : "spray metasphere --simplify 0.1", &raw,
                         &sim, 0.6, f == JM_FIELD_SPH);
        test_mesh_free(&sim);
        test_mesh_free(&raw);
    }
    free(xyz);
}

/* ---- determinism */

static void test_threads_same_bytes(void **state)
{
    (void)state;
    size_t n;
    float *xyz = make_ball(2.0f, &n);
    /* the explicit steps (marching cubes), the steady smoothing with both
     * methods (marching tetrahedra: fans of over 8 triangles) */
    for (int f = JM_FIELD_METASPHERE; f <= JM_FIELD_SPH; f++)
        for (int k = 0; k < 3; k++) {
            test_mesh one, many;
            jm_params p = {0};
            p.radius = R;
            p.field = (jm_field)f;
            p.method = k == 2 ? JM_METHOD_MT : JM_METHOD_MC;
            p.smooth_implicit = k > 0;
            p.smooth_iterations = 25;
            p.smooth_normal_iterations = 10;
            p.simplify_error = 0.1f;
            p.threads = 1;
            mesh_with(xyz, n, p, &one);
            p.threads = 3;
            mesh_with(xyz, n, p, &many);
            assert_int_equal(one.mesh.vertex_count, many.mesh.vertex_count);
            assert_int_equal(one.mesh.triangle_count, many.mesh.triangle_count);
            assert_memory_equal(one.positions, many.positions, 3 * one.mesh.vertex_count * sizeof(float));
            assert_memory_equal(one.normals, many.normals, 3 * one.mesh.vertex_count * sizeof(float));
            assert_memory_equal(one.uvs, many.uvs, 2 * one.mesh.vertex_count * sizeof(float));
            assert_memory_equal(one.indices, many.indices, 3 * one.mesh.triangle_count * sizeof(uint32_t));
            test_mesh_free(&one);
            test_mesh_free(&many);
        }
    free(xyz);
}

/* UVs follow the final positions and normals (box projection). */
static void test_uvs_follow(void **state)
{
    (void)state;
    size_t n;
    float *xyz = make_ball(2.0f, &n);
    jm_params p = {0};
    p.radius = R;
    p.field = JM_FIELD_SPH;
    p.smooth_iterations = 10;
    p.smooth_normal_iterations = 3;
    test_mesh c;
    mesh_with(xyz, n, p, &c);
    float s = 1.0f / (16 * R);
    for (size_t v = 0; v < c.mesh.vertex_count; v++) {
        const float *q = &c.positions[3 * v], *nn = &c.normals[3 * v];
        float ax = fabsf(nn[0]), ay = fabsf(nn[1]), az = fabsf(nn[2]);
        int axis = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
        int u = axis == 0 ? 1 : 0, w = axis == 2 ? 1 : 2;
        assert_true(c.uvs[2 * v] == q[u] * s && c.uvs[2 * v + 1] == q[w] * s);
        assert_true(fabsf(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2] - 1.0f) < 1e-4f);
    }
    test_mesh_free(&c);
    free(xyz);
}

static void test_params_checked(void **state)
{
    (void)state;
    jm_params p = {0};
    p.radius = R;
    jm_context *ctx = NULL;
    p.smooth_iterations = -1;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    p.smooth_iterations = 0;
    p.smooth_normal_iterations = -2;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    p.smooth_normal_iterations = 0;
    p.simplify_error = -0.1f;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    p.simplify_error = NAN;
    assert_int_equal(jm_context_create(&p, &ctx), JM_E_INVALID_ARGUMENT);
    assert_null(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ball_orange_peel),  cmocka_unit_test(test_spray_kept),
        cmocka_unit_test(test_bunny_simplified),  cmocka_unit_test(test_spray_simplified),
        cmocka_unit_test(test_threads_same_bytes), cmocka_unit_test(test_uvs_follow),
        cmocka_unit_test(test_params_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
