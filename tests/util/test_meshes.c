/* test_meshes.c - builds the octahedron, icosphere, torus and empty test meshes used by the writer tests. */
#include "test_meshes.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TM_PI 3.14159265358979323846

static int alloc_mesh(test_mesh *tm, size_t nv, size_t nt)
{
    memset(tm, 0, sizeof *tm);
    tm->positions = malloc(3 * nv * sizeof(float) + 1);
    tm->normals = malloc(3 * nv * sizeof(float) + 1);
    tm->uvs = malloc(2 * nv * sizeof(float) + 1);
    tm->indices = malloc(3 * nt * sizeof(uint32_t) + 1);
    if (!tm->positions || !tm->normals || !tm->uvs || !tm->indices) {
        test_mesh_free(tm);
        return -1;
    }
    tm->mesh.positions = tm->positions;
    tm->mesh.normals = tm->normals;
    tm->mesh.uvs = tm->uvs;
    tm->mesh.indices = tm->indices;
    tm->mesh.vertex_count = nv;
    tm->mesh.triangle_count = nt;
    return 0;
}

static void finish_bounds(test_mesh *tm)
{
    jm_mesh *m = &tm->mesh;
    for (int k = 0; k < 3; k++) m->bounds_min[k] = m->bounds_max[k] = 0;
    for (size_t i = 0; i < m->vertex_count; i++)
        for (int k = 0; k < 3; k++) {
            float x = tm->positions[3 * i + (size_t)k];
            if (i == 0 || x < m->bounds_min[k]) m->bounds_min[k] = x;
            if (i == 0 || x > m->bounds_max[k]) m->bounds_max[k] = x;
        }
}

/* Unit-sphere vertices: the normal is the position; uvs from the direction. */
static void sphere_attributes(test_mesh *tm)
{
    for (size_t i = 0; i < tm->mesh.vertex_count; i++) {
        float *p = tm->positions + 3 * i;
        double l = sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
        for (int k = 0; k < 3; k++) {
            p[k] = (float)(p[k] / l);
            tm->normals[3 * i + (size_t)k] = p[k];
        }
        tm->uvs[2 * i] = (float)(atan2(p[1], p[0]) / (2 * TM_PI) + 0.5);
        tm->uvs[2 * i + 1] = (float)(acos(p[2] < -1 ? -1 : p[2] > 1 ? 1 : p[2]) / TM_PI);
    }
}

static int make_octahedron(test_mesh *tm)
{
    static const float v[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    static const uint32_t f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                     {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    if (alloc_mesh(tm, 6, 8)) return -1;
    memcpy(tm->positions, v, sizeof v);
    memcpy(tm->indices, f, sizeof f);
    sphere_attributes(tm);
    return 0;
}

/* Midpoint of edge (a, b), created once: an open-addressing map of edges. */
typedef struct edge_map {
    uint64_t *keys;
    uint32_t *vals;
    size_t cap;
} edge_map;

static uint32_t midpoint(edge_map *em, float *pos, uint32_t *nv, uint32_t a, uint32_t b)
{
    uint64_t key = a < b ? ((uint64_t)a << 32 | b) : ((uint64_t)b << 32 | a);
    size_t h = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & (em->cap - 1);
    while (em->keys[h] != UINT64_MAX) {
        if (em->keys[h] == key) return em->vals[h];
        h = (h + 1) & (em->cap - 1);
    }
    uint32_t m = (*nv)++;
    for (int k = 0; k < 3; k++) pos[3 * m + (uint32_t)k] = 0.5f * (pos[3 * a + (uint32_t)k] + pos[3 * b + (uint32_t)k]);
    em->keys[h] = key;
    em->vals[h] = m;
    return m;
}

static int make_icosphere(test_mesh *tm, int levels)
{
    const float t = (float)((1.0 + sqrt(5.0)) / 2.0);
    const float v[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    static const uint32_t f[20][3] = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
        {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    size_t nt = 20, nv_final = 12;
    for (int l = 0; l < levels; l++) {
        nv_final += nt * 3 / 2; /* one new vertex per edge */
        nt *= 4;
    }
    if (alloc_mesh(tm, nv_final, nt)) return -1;
    memcpy(tm->positions, v, sizeof v);
    memcpy(tm->indices, f, sizeof f);
    uint32_t nv = 12;
    size_t cur = 20;
    uint32_t *tmp = malloc(3 * nt * sizeof(uint32_t));
    edge_map em = {0};
    em.cap = 1;
    while (em.cap < 4 * nt) em.cap <<= 1;
    em.keys = malloc(em.cap * sizeof *em.keys);
    em.vals = malloc(em.cap * sizeof *em.vals);
    if (!tmp || !em.keys || !em.vals) {
        free(tmp), free(em.keys), free(em.vals);
        test_mesh_free(tm);
        return -1;
    }
    for (int l = 0; l < levels; l++) {
        memset(em.keys, 0xff, em.cap * sizeof *em.keys);
        for (size_t i = 0; i < cur; i++) {
            uint32_t a = tm->indices[3 * i], b = tm->indices[3 * i + 1], c = tm->indices[3 * i + 2];
            uint32_t ab = midpoint(&em, tm->positions, &nv, a, b);
            uint32_t bc = midpoint(&em, tm->positions, &nv, b, c);
            uint32_t ca = midpoint(&em, tm->positions, &nv, c, a);
            uint32_t q[12] = {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca};
            memcpy(tmp + 12 * i, q, sizeof q);
        }
        cur *= 4;
        memcpy(tm->indices, tmp, 3 * cur * sizeof(uint32_t));
    }
    free(tmp), free(em.keys), free(em.vals);
    sphere_attributes(tm);
    return 0;
}

/* A torus around the z axis: nu steps around the axis, nv around the tube. */
static int make_torus(test_mesh *tm, unsigned nu, unsigned nv)
{
    if (nu < 3 || nv < 3) return -1;
    if (alloc_mesh(tm, (size_t)nu * nv, 2 * (size_t)nu * nv)) return -1;
    const double R = 2.0, r = 0.75, cx = 10, cy = -5, cz = 3;
    for (unsigned i = 0; i < nu; i++)
        for (unsigned j = 0; j < nv; j++) {
            double u = 2 * TM_PI * i / nu, w = 2 * TM_PI * j / nv;
            size_t k = (size_t)i * nv + j;
            double nx = cos(w) * cos(u), ny = cos(w) * sin(u), nz = sin(w);
            tm->positions[3 * k] = (float)(cx + (R + r * cos(w)) * cos(u));
            tm->positions[3 * k + 1] = (float)(cy + (R + r * cos(w)) * sin(u));
            tm->positions[3 * k + 2] = (float)(cz + r * sin(w));
            tm->normals[3 * k] = (float)nx;
            tm->normals[3 * k + 1] = (float)ny;
            tm->normals[3 * k + 2] = (float)nz;
            tm->uvs[2 * k] = (float)i / (float)nu;
            tm->uvs[2 * k + 1] = (float)j / (float)nv;
        }
    size_t t = 0;
    for (unsigned i = 0; i < nu; i++)
        for (unsigned j = 0; j < nv; j++) {
            uint32_t a = i * nv + j, b = ((i + 1) % nu) * nv + j;
            uint32_t c = ((i + 1) % nu) * nv + (j + 1) % nv, d = i * nv + (j + 1) % nv;
            uint32_t q[6] = {a, b, c, a, c, d};
            memcpy(tm->indices + 6 * t++, q, sizeof q);
        }
    return 0;
}

int test_mesh_make(const char *name, test_mesh *out)
{
    int rc = -1;
    unsigned a = 0, b = 0;
    int l = 2;
    memset(out, 0, sizeof *out);
    if (strcmp(name, "octahedron") == 0) rc = make_octahedron(out);
    else if (strcmp(name, "icosphere") == 0) rc = make_icosphere(out, l);
    else if (sscanf(name, "icosphere:%d", &l) == 1 && l >= 0 && l <= 8) rc = make_icosphere(out, l);
    else if (strcmp(name, "grid") == 0) rc = make_torus(out, 280, 250);
    else if (sscanf(name, "torus:%ux%u", &a, &b) == 2 && (size_t)a * b <= 50000000u) rc = make_torus(out, a, b);
    else if (strcmp(name, "empty") == 0) {
        rc = 0;
        out->mesh.normals = out->mesh.uvs = NULL;
    }
    if (rc == 0) finish_bounds(out);
    return rc;
}

void test_mesh_free(test_mesh *tm)
{
    if (!tm) return;
    free(tm->positions);
    free(tm->normals);
    free(tm->uvs);
    free(tm->indices);
    memset(tm, 0, sizeof *tm);
}

int test_mesh_copy(const jm_mesh *m, test_mesh *out)
{
    const size_t nv = m->vertex_count, ni = 3 * m->triangle_count;
    memset(out, 0, sizeof *out);
    out->positions = malloc(3 * nv * sizeof(float) + 1);
    out->normals = m->normals ? malloc(3 * nv * sizeof(float) + 1) : NULL;
    out->uvs = m->uvs ? malloc(2 * nv * sizeof(float) + 1) : NULL;
    out->indices = malloc(ni * sizeof(uint32_t) + 1);
    if (!out->positions || !out->indices || (m->normals && !out->normals) || (m->uvs && !out->uvs)) {
        test_mesh_free(out);
        return -1;
    }
    memcpy(out->positions, m->positions, 3 * nv * sizeof(float));
    if (m->normals) memcpy(out->normals, m->normals, 3 * nv * sizeof(float));
    if (m->uvs) memcpy(out->uvs, m->uvs, 2 * nv * sizeof(float));
    memcpy(out->indices, m->indices, ni * sizeof(uint32_t));
    out->mesh = *m;
    out->mesh.positions = out->positions;
    out->mesh.normals = out->normals;
    out->mesh.uvs = out->uvs;
    out->mesh.indices = out->indices;
    return 0;
}
