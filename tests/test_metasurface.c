/* test_metasurface.c - metasphere surface quality: vertices on the exact surface, normals facing their triangles and continuous across creases. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/jetmesh.h"
#include "util/meshcheck.h"

/* ---- the metasphere by brute force (as jm_field_eval, with the links
 * found once instead of per point): max over balls and half-necks, units of r */
typedef struct cloud {
    const float *xyz;
    size_t n;
    double r, link;
    size_t *nb_start, *nb;
} cloud;

static void cloud_links(cloud *c)
{
    c->nb_start = calloc(c->n + 1, sizeof *c->nb_start);
    size_t cap = 64 * c->n + 1, k = 0;
    c->nb = malloc(cap * sizeof *c->nb);
    for (size_t i = 0; i < c->n; i++) {
        c->nb_start[i] = k;
        for (size_t j = 0; j < c->n; j++) {
            double d2 = 0;
            for (int a = 0; a < 3; a++) {
                double d = (double)c->xyz[3 * j + a] - c->xyz[3 * i + a];
                d2 += d * d;
            }
            if (j != i && d2 > 0 && sqrt(d2) < c->link && k < cap) c->nb[k++] = j;
        }
    }
    c->nb_start[c->n] = k;
}

static double cloud_field(const cloud *c, const float *x)
{
    double best = -1.0, r = c->r;
    for (size_t i = 0; i < c->n; i++) {
        const float *ci = c->xyz + 3 * i;
        double w[3] = {x[0] - ci[0], x[1] - ci[1], x[2] - ci[2]};
        double d = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        if (d > 2.0 * r) continue; /* no piece of i reaches past pi r / 2 */
        if (1.0 - d / r > best) best = 1.0 - d / r;
        for (size_t k = c->nb_start[i]; k < c->nb_start[i + 1]; k++) {
            const float *cj = c->xyz + 3 * c->nb[k];
            double u[3] = {cj[0] - ci[0], cj[1] - ci[1], cj[2] - ci[2]};
            double D = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
            double s = (w[0] * u[0] + w[1] * u[1] + w[2] * u[2]) / D;
            if (s < 0 || s > 0.5 * D) continue;
            double q2 = d * d - s * s, v = cos(s / r) - sqrt(q2 > 0 ? q2 : 0) / r;
            if (v > best) best = v;
        }
    }
    return best;
}

/* ---- scenes */
static float *read_csv(const char *path, size_t *n)
{
    FILE *f = fopen(path, "r");
    if (!f) return NULL;
    size_t cap = 256;
    float *p = malloc(3 * cap * sizeof *p);
    char line[256];
    *n = 0;
    while (fgets(line, sizeof line, f)) {
        float x, y, z;
        if (sscanf(line, "%f,%f,%f", &x, &y, &z) != 3) continue;
        if (*n == cap) p = realloc(p, 3 * (cap *= 2) * sizeof *p);
        p[3 * *n] = x, p[3 * *n + 1] = y, p[3 * *n + 2] = z;
        (*n)++;
    }
    fclose(f);
    return p;
}

static float *jet(size_t *n)
{
    const char *root = getenv("JETMESH_ROOT");
    char path[1024];
    snprintf(path, sizeof path, "%s/samples/jet/jet_099.csv", root ? root : ".");
    float *p = read_csv(path, n);
    if (!p) fail_msg("cannot read %s", path);
    assert_int_equal(*n, 125);
    return p;
}

/* k^3 particles on a cubic lattice of the given spacing (units of r = 1),
 * each moved by up to 0.1 r per axis: a dense frame full of tunnels */
static float *block(int k, float spacing, unsigned seed, size_t *n)
{
    *n = (size_t)k * k * k;
    float *p = malloc(3 * *n * sizeof *p);
    size_t i = 0;
    for (int z = 0; z < k; z++)
        for (int y = 0; y < k; y++)
            for (int x = 0; x < k; x++, i++) {
                const int ijk[3] = {x, y, z};
                for (int a = 0; a < 3; a++) p[3 * i + a] = spacing * (float)ijk[a] + 0.2f * (mc_randf(&seed) - 0.5f);
            }
    return p;
}

/* n particles as `jetmesh generate block N -r R` places them (cli/scenes.c,
 * seed 1): spacing 2R, each moved by up to 0.1 R per axis by a hash */
static uint64_t scene_hash(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}
static float *generated_block(size_t n, double R)
{
    size_t m = 1;
    while (m * m * m < n) m++;
    float *p = malloc(3 * n * sizeof *p);
    const double half = (double)(m - 1) * R;
    for (size_t i = 0; i < n; i++) {
        const size_t ijk[3] = {i % m, (i / m) % m, i / (m * m)};
        for (unsigned a = 0; a < 3; a++) {
            uint64_t h = scene_hash(scene_hash(1 ^ 0x6a657473ull) + i * 4 + a);
            double u = (double)(h >> 11) * (1.0 / 9007199254740992.0) * 2.0 - 1.0;
            p[3 * i + a] = (float)(2.0 * R * (double)ijk[a] - half + 0.1 * R * u);
        }
    }
    return p;
}

static jm_mesh mesh_of(jm_context **ctx, const float *xyz, size_t n, float r, jm_method m, int exact, int comp)
{
    jm_params p = {0};
    p.radius = r;
    p.method = m;
    p.exact_surface = exact;
    p.no_compensation = !comp;
    assert_int_equal(jm_context_create(&p, ctx), JM_OK);
    jm_particles in = {xyz, n, 0, NULL};
    jm_mesh mesh;
    assert_int_equal(jm_mesh_particles(*ctx, &in, &mesh, NULL), JM_OK);
    mc_report rep;
    if (!mc_check(&mesh, &rep)) fail_msg("mesh not closed/manifold/oriented: %s", rep.problem);
    return mesh;
}

/* the largest |f| (units of r) over the vertices, and how many exceed tol */
static double worst_vertex(const float *xyz, size_t n, float r, const jm_mesh *m, double tol, size_t *over)
{
    cloud c = {xyz, n, r, M_PI * r, NULL, NULL};
    cloud_links(&c);
    double worst = 0;
    *over = 0;
    for (size_t v = 0; v < m->vertex_count; v++) {
        double f = fabs(cloud_field(&c, m->positions + 3 * v));
        if (f > worst) worst = f;
        *over += f > tol;
    }
    free(c.nb_start);
    free(c.nb);
    return worst;
}

/* share of triangle corners whose vertex normal faces the triangle */
static double corners_facing(const jm_mesh *m)
{
    size_t ok = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *v = m->indices + 3 * t;
        const float *a = m->positions + 3 * v[0], *b = m->positions + 3 * v[1], *c = m->positions + 3 * v[2];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double fn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; k++) {
            const float *n = m->normals + 3 * v[k];
            ok += n[0] * fn[0] + n[1] * fn[1] + n[2] * fn[2] > 0;
        }
    }
    return m->triangle_count ? (double)ok / (3.0 * (double)m->triangle_count) : 1.0;
}

/* ---- every vertex on the exact surface, by default: the two pieces won
 * at an edge's nodes miss a third one winning mid-edge (0.8 % of the jet's
 * vertices were up to 0.33 r inside, and 7-10 % on dense lattices), which
 * the probe of every piece at every vertex catches (exact_surface, which
 * asked for that, is now accepted and ignored) */
static void exact_case(const float *xyz, size_t n, float r, jm_method m, int exact)
{
    jm_context *ctx;
    jm_mesh mesh = mesh_of(&ctx, xyz, n, r, m, exact, 0);
    size_t over;
    double worst = worst_vertex(xyz, n, r, &mesh, 0.02, &over);
    if (over) fail_msg("method %d, r %g: %zu of %zu vertices more than 0.02 r off the surface (worst %.3f r)", m, r,
                       over, mesh.vertex_count, worst);
    jm_context_free(ctx);
}

static void test_exact_jet(void **s)
{
    (void)s;
    size_t n;
    float *xyz = jet(&n);
    exact_case(xyz, n, 0.025f, JM_METHOD_MT, 0);
    exact_case(xyz, n, 0.025f, JM_METHOD_MC, 0);
    exact_case(xyz, n, 0.025f, JM_METHOD_MT, 1);
    free(xyz);
}

static void test_exact_dense(void **s)
{
    (void)s;
    size_t n;
    float *xyz = block(6, 2.0f, 7, &n);
    exact_case(xyz, n, 1.0f, JM_METHOD_MT, 0);       /* spacing 2 r */
    exact_case(xyz, n, 2.0f / 1.5f, JM_METHOD_MT, 0); /* spacing 1.5 r */
    exact_case(xyz, n, 1.0f, JM_METHOD_MC, 0);
    free(xyz);
    /* the generated block of 1000 (2.1 % of its vertices were off at
     * spacing 1.5 r, up to 0.33 r) */
    xyz = generated_block(1000, 0.025);
    exact_case(xyz, 1000, 0.05f / 1.5f, JM_METHOD_MT, 0);
    free(xyz);
}

/* ---- normals face their triangles at 99.5 % of the corners by default,
 * also where dense lattices bend the surface more sharply than the cubes
 * follow (4.6 % of the corners faced away at spacing 2 r before), and with
 * the sag compensation: its offset folded triangles over at creases (0.55 %
 * of the corners of the generated 1000-particle block at spacing 1.5 r
 * faced away) until a fold halves (then zeroes) the offsets of its vertices */
static void facing_case(const float *xyz, size_t n, float r, jm_method m, int exact, int comp)
{
    jm_context *ctx;
    jm_mesh mesh = mesh_of(&ctx, xyz, n, r, m, exact, comp);
    double share = corners_facing(&mesh);
    if (share < 0.995)
        fail_msg("method %d, r %g, exact %d, compensation %d: %.3f %% of corners face away", m, r, exact, comp,
                 100 * (1 - share));
    jm_context_free(ctx);
}

static void test_facing_dense(void **s)
{
    (void)s;
    size_t n;
    float *xyz = block(8, 2.0f, 3, &n);
    for (int comp = 0; comp <= 1; comp++) {
        facing_case(xyz, n, 1.0f, JM_METHOD_MT, 0, comp);
        facing_case(xyz, n, 1.0f, JM_METHOD_MC, 0, comp);
        facing_case(xyz, n, 2.0f / 1.5f, JM_METHOD_MT, 0, comp);
        facing_case(xyz, n, 2.0f / 1.5f, JM_METHOD_MC, 0, comp);
    }
    facing_case(xyz, n, 1.0f, JM_METHOD_MT, 1, 1);
    free(xyz);
    xyz = generated_block(1000, 0.025);
    for (int comp = 0; comp <= 1; comp++) {
        facing_case(xyz, 1000, 0.05f / 1.5f, JM_METHOD_MT, 0, comp); /* spacing 1.5 r */
        facing_case(xyz, 1000, 0.025f, JM_METHOD_MT, 0, comp);       /* spacing 2 r */
    }
    free(xyz);
    xyz = jet(&n);
    facing_case(xyz, n, 0.025f, JM_METHOD_MT, 0, 1);
    facing_case(xyz, n, 0.025f, JM_METHOD_MC, 0, 1);
    free(xyz);
}

/* ---- normals continuous across creases: how fast the normal turns along
 * each mesh edge, |n_a - n_b| r / |p_a - p_b| (1 on a ball of radius r).
 * Blending only the pieces won at an edge's nodes left a vertex beside a
 * crease with a piece its neighbour never saw, so the shading stepped
 * along the grid (a staircase in a close render); on the jet the 99th
 * percentile of that rate was 7.8 (mt, cube r/2), 11.5 (mt, r/4) and 5.7
 * (mc, r/4). Blending every piece within the band (metanormal.c) turns the
 * normal smoothly across the fillet: about 3.5 in all four cases. */
static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}
static int cmp_edge(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}
static double turn_rate_p99(const jm_mesh *m, float r)
{
    size_t ne = 3 * m->triangle_count, k = 0;
    uint64_t *e = malloc(ne * sizeof *e);
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int j = 0; j < 3; j++) {
            uint64_t a = m->indices[3 * t + j], b = m->indices[3 * t + (j + 1) % 3];
            e[k++] = a < b ? a << 32 | b : b << 32 | a;
        }
    qsort(e, ne, sizeof *e, cmp_edge);
    double *rate = malloc(ne * sizeof *rate);
    size_t nr = 0;
    for (size_t i = 0; i < ne; i++) {
        if (i && e[i] == e[i - 1]) continue;
        const uint32_t a = (uint32_t)(e[i] >> 32), b = (uint32_t)e[i];
        double dn = 0, dp = 0;
        for (int q = 0; q < 3; q++) {
            double x = (double)m->normals[3 * a + q] - m->normals[3 * b + q];
            double y = (double)m->positions[3 * a + q] - m->positions[3 * b + q];
            dn += x * x;
            dp += y * y;
        }
        if (dp > 0) rate[nr++] = sqrt(dn / dp) * r;
    }
    qsort(rate, nr, sizeof *rate, cmp_double);
    double p99 = rate[(size_t)(0.99 * (double)(nr - 1))];
    free(e);
    free(rate);
    return p99;
}

static void test_crease_normals(void **s)
{
    (void)s;
    size_t n;
    float *xyz = jet(&n);
    const struct { jm_method m; float cube; } cases[] = {
        {JM_METHOD_MT, 0.5f}, {JM_METHOD_MT, 0.25f}, {JM_METHOD_MC, 0.5f}, {JM_METHOD_MC, 0.25f}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        jm_params p = {0};
        p.radius = 0.025f;
        p.method = cases[i].m;
        p.cube_size = cases[i].cube;
        jm_context *ctx;
        assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
        jm_particles in = {xyz, n, 0, NULL};
        jm_mesh mesh;
        assert_int_equal(jm_mesh_particles(ctx, &in, &mesh, NULL), JM_OK);
        double p99 = turn_rate_p99(&mesh, p.radius);
        printf("method %d, cube %.2f r: normals turn at %.2f / r along edges (99th percentile)\n", cases[i].m,
               cases[i].cube, p99);
        if (!(p99 <= 5.0))
            fail_msg("method %d, cube %g r: normals turn at %.2f / r at the 99th percentile of edges (> 5: a step "
                     "across a crease)", cases[i].m, cases[i].cube, p99);
        jm_context_free(ctx);
    }
    free(xyz);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exact_jet),
        cmocka_unit_test(test_exact_dense),
        cmocka_unit_test(test_facing_dense),
        cmocka_unit_test(test_crease_normals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
