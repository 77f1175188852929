/* scenes_liquid.c - the smoothing's test scenes: a jittered ball of particles and a spray of droplets, pairs, clusters, lines and hanging drops. */
#include "scenes.h"

#include <math.h>
#include <stdlib.h>

/* A uniform double in [-1, 1) from (seed, i, k). */
static double hsigned(uint64_t seed, uint64_t i, unsigned k)
{
    uint64_t h = scene_hash(scene_hash(seed ^ 0x6c6971756964ull) + i * 64 + k);
    return (double)(h >> 11) * (1.0 / 9007199254740992.0) * 2.0 - 1.0;
}

typedef struct pts {
    float *xyz;
    size_t n, cap;
} pts;

static int add(pts *p, double x, double y, double z)
{
    if (p->n == p->cap) {
        size_t nc = p->cap ? 2 * p->cap : 1024;
        float *q = realloc(p->xyz, 3 * nc * sizeof *q);
        if (!q) return -1;
        p->xyz = q;
        p->cap = nc;
    }
    p->xyz[3 * p->n] = (float)x, p->xyz[3 * p->n + 1] = (float)y, p->xyz[3 * p->n + 2] = (float)z;
    p->n++;
    return 0;
}

static int finish(pts *p, int failed, scene_points *out)
{
    if (failed) {
        free(p->xyz);
        out->xyz = NULL;
        out->count = 0;
        return -1;
    }
    out->xyz = p->xyz ? p->xyz : malloc(sizeof(float));
    out->count = p->n;
    return out->xyz ? 0 : -1;
}

/* Whether no point of p within d of x (cells of edge d: head per cell, next per point). */
static int far_enough(const pts *p, const uint32_t *head, const uint32_t *next, int m, const double x[3], double d)
{
    int c[3];
    for (int a = 0; a < 3; a++) c[a] = (int)floor(x[a] / d) + m / 2;
    for (int z = c[2] - 1; z <= c[2] + 1; z++)
        for (int y = c[1] - 1; y <= c[1] + 1; y++)
            for (int w = c[0] - 1; w <= c[0] + 1; w++) {
                if (z < 0 || y < 0 || w < 0 || z >= m || y >= m || w >= m) continue;
                for (uint32_t i = head[((size_t)z * m + y) * m + w]; i != UINT32_MAX; i = next[i]) {
                    const float *q = &p->xyz[3 * (size_t)i];
                    double e = (q[0] - x[0]) * (q[0] - x[0]) + (q[1] - x[1]) * (q[1] - x[1]) + (q[2] - x[2]) * (q[2] - x[2]);
                    if (e < d * d) return 0;
                }
            }
    return 1;
}

int scene_ball(size_t n, double r, uint64_t seed, scene_points *out)
{
    /* random sequential packing: candidates uniform in the ball, kept when
     * at least 1.6 r from every point kept, until n (the density of a
     * lattice of spacing 2r fills the ball's radius) or 60 n candidates */
    const double d = 1.6 * r, rad = 2.0 * r * cbrt(3.0 * (double)n / (4.0 * SCENE_PI_L));
    const int m = 2 * (int)(rad / d) + 4;
    uint32_t *head = malloc((size_t)m * m * m * sizeof *head), *next = malloc((n + 1) * sizeof *next);
    pts p = {0};
    int bad = !head || !next;
    for (size_t c = 0; !bad && c < (size_t)m * m * m; c++) head[c] = UINT32_MAX;
    for (uint64_t i = 0; !bad && p.n < n && i < 60 * (uint64_t)n; i++) {
        double u[3] = {hsigned(seed, i, 0), hsigned(seed, i, 1), hsigned(seed, i, 2)};
        if (u[0] * u[0] + u[1] * u[1] + u[2] * u[2] > 1.0) continue;
        double x[3] = {rad * u[0], rad * u[1], rad * u[2]};
        if (!far_enough(&p, head, next, m, x, d)) continue;
        size_t c = 0;
        for (int a = 2; a >= 0; a--) c = c * (size_t)m + (size_t)((int)floor(x[a] / d) + m / 2);
        next[p.n] = head[c];
        head[c] = (uint32_t)p.n;
        bad = add(&p, x[0], x[1], x[2]);
    }
    free(head);
    free(next);
    return finish(&p, bad, out);
}

/* A point uniformly in the ball of radius rad about c (rejection, from hashes). */
static int in_ball(pts *p, uint64_t seed, uint64_t id, const double c[3], double rad)
{
    for (unsigned k = 0; k < 60; k += 3) {
        double u[3] = {hsigned(seed, id, k), hsigned(seed, id, k + 1), hsigned(seed, id, k + 2)};
        if (u[0] * u[0] + u[1] * u[1] + u[2] * u[2] <= 1.0)
            return add(p, c[0] + rad * u[0], c[1] + rad * u[1], c[2] + rad * u[2]);
    }
    return add(p, c[0], c[1], c[2]);
}

/* One group of the droplet scene about c: its kind is g % 5. */
static int droplet_group(pts *p, uint64_t seed, uint64_t g, const double c[3], double r)
{
    uint64_t id = g * 4096;
    double dir[3] = {hsigned(seed, id, 0), hsigned(seed, id, 1), hsigned(seed, id, 2)};
    double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    for (int a = 0; a < 3; a++) dir[a] = len > 0.1 ? dir[a] / len : (a == 0);
    int bad = 0;
    switch (g % 5) {
    case 0: /* a single particle */
        return add(p, c[0], c[1], c[2]);
    case 1: { /* a pair 1.4 r to 2.2 r apart */
        double d = r * (1.8 + 0.4 * hsigned(seed, id, 3));
        bad |= add(p, c[0] - 0.5 * d * dir[0], c[1] - 0.5 * d * dir[1], c[2] - 0.5 * d * dir[2]);
        return bad | add(p, c[0] + 0.5 * d * dir[0], c[1] + 0.5 * d * dir[1], c[2] + 0.5 * d * dir[2]);
    }
    case 2: { /* a dense cluster: 5 to 10 particles within 1.2 r of its centre */
        int k = 5 + (int)(scene_hash(seed ^ id) % 6);
        for (int i = 0; i < k && !bad; i++) bad = in_ball(p, seed, id + 1 + (uint64_t)i, c, 1.2 * r);
        return bad;
    }
    case 3: { /* a line of 3 to 6 particles 1.6 r to 2 r apart */
        int k = 3 + (int)(scene_hash(seed ^ id ^ 1) % 4);
        double s = r * (1.8 + 0.2 * hsigned(seed, id, 4));
        for (int i = 0; i < k && !bad; i++) {
            double t = s * ((double)i - 0.5 * (k - 1));
            bad = add(p, c[0] + t * dir[0] + 0.1 * r * hsigned(seed, id + 1 + i, 0),
                      c[1] + t * dir[1] + 0.1 * r * hsigned(seed, id + 1 + i, 1),
                      c[2] + t * dir[2] + 0.1 * r * hsigned(seed, id + 1 + i, 2));
        }
        return bad;
    }
    default: { /* a drop hanging from a sheet (two layers of 6 x 6 at 2 r) by a neck of two particles */
        for (int l = 0; l < 2; l++)
            for (int i = 0; i < 6; i++)
                for (int j = 0; j < 6 && !bad; j++)
                    bad = add(p, c[0] + 2.0 * r * (i - 2.5) + 0.1 * r * hsigned(seed, id + 100 + 36 * l + 6 * i + j, 0),
                              c[1] + 6.0 * r + 2.0 * r * l, c[2] + 2.0 * r * (j - 2.5));
        for (int i = 0; i < 2 && !bad; i++) bad = add(p, c[0], c[1] + 4.2 * r - 1.8 * r * i, c[2]);
        double d[3] = {c[0], c[1] - 1.2 * r, c[2]};
        for (int i = 0; i < 7 && !bad; i++) bad = in_ball(p, seed, id + 1 + (uint64_t)i, d, 1.2 * r);
        return bad;
    }
    }
}

int scene_droplets(size_t n, double r, uint64_t seed, scene_points *out)
{
    size_t m = 1;
    while (m * m * m < n) m++;
    const double cell = 24.0 * r, half = 0.5 * (double)(m - 1) * cell;
    pts p = {0};
    int bad = 0;
    for (size_t g = 0; g < n && !bad; g++) {
        double c[3] = {cell * (double)(g % m) - half, cell * (double)((g / m) % m) - half,
                       cell * (double)(g / (m * m)) - half};
        bad = droplet_group(&p, seed, g, c, r);
    }
    return finish(&p, bad, out);
}
