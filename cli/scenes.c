/* scenes.c - generates the synthetic jet, block and spray particle scenes from integer hashes only. */
#include "scenes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SCENE_PI 3.14159265358979323846

uint64_t scene_hash(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/* A uniform double in [-1, 1) from (seed, i, axis). */
static double unit_signed(uint64_t seed, uint64_t i, unsigned axis)
{
    uint64_t h = scene_hash(scene_hash(seed ^ 0x6a657473ull) + i * 4 + axis);
    return (double)(h >> 11) * (1.0 / 9007199254740992.0) * 2.0 - 1.0;
}

static int alloc_points(scene_points *out, size_t n)
{
    out->count = 0;
    out->xyz = NULL;
    if (n > ((size_t)-1) / (3 * sizeof(float)))
        return -1;
    out->xyz = malloc(n ? n * 3 * sizeof(float) : sizeof(float));
    if (!out->xyz)
        return -1;
    out->count = n;
    return 0;
}

void scene_points_free(scene_points *p)
{
    if (!p)
        return;
    free(p->xyz);
    p->xyz = NULL;
    p->count = 0;
}

int scene_jet(int frame, double r, scene_points *out)
{
    const double emit_dt = 0.0025;           /* s between two particles */
    const double spacing = 1.5 * r;          /* at the nozzle */
    const double v0 = spacing / emit_dt;     /* along +x */
    const double g = 9.81 * (r / 0.025);     /* along -y */
    const double eps = 0.02;                 /* speed perturbation */
    const double wavelength = 6.0;           /* particles */
    const double min_gap = 0.7 * r;          /* along the track */
    const double max_side = 0.6 * r;         /* sideways spread of caught-up particles */
    const double golden = 2.39996322972865332; /* rad */

    if (frame < 0 || !(r > 0)) {
        out->xyz = NULL;
        out->count = 0;
        return -1;
    }
    /* time since the first particle left, in emission intervals */
    double t = 1.25 * ((double)frame + 0.5);
    long newest = (long)floor(t);
    long oldest = newest - (SCENE_JET_PARTICLES - 1);
    if (oldest < 0)
        oldest = 0;
    size_t n = (size_t)(newest - oldest + 1);
    if (alloc_points(out, n) != 0)
        return -1;

    double prev_s = 0;
    for (size_t i = 0; i < n; i++) { /* oldest (furthest) first */
        long k = oldest + (long)i;
        double age = (t - (double)k) * emit_dt;
        double speed = v0 * (1.0 + eps * sin(2.0 * SCENE_PI * (double)k / wavelength));
        double s = speed * age; /* distance along the track */
        double caught = 0;
        if (i > 0 && s > prev_s - min_gap) {
            caught = s - (prev_s - min_gap);
            s = prev_s - min_gap;
        }
        if (s < 0)
            s = 0;
        prev_s = s;
        double tau = s / v0; /* time along the common ballistic track */
        double x = v0 * tau, y = -0.5 * g * tau * tau;
        /* unit normal of the track in the xy plane, and +z */
        double vx = v0, vy = -g * tau, vl = sqrt(vx * vx + vy * vy);
        double nx = -vy / vl, ny = vx / vl;
        double side = caught * 0.5;
        if (side > max_side)
            side = max_side;
        double a = golden * (double)k;
        double c = cos(a) * side, z = sin(a) * side;
        out->xyz[3 * i + 0] = (float)(x + c * nx);
        out->xyz[3 * i + 1] = (float)(y + c * ny);
        out->xyz[3 * i + 2] = (float)z;
    }
    return 0;
}

int scene_block(size_t n, double r, uint64_t seed, scene_points *out)
{
    if (alloc_points(out, n) != 0)
        return -1;
    size_t m = (size_t)ceil(cbrt((double)n));
    while (m > 1 && (m - 1) * (m - 1) * (m - 1) >= n)
        m--;
    while (m * m * m < n)
        m++;
    double half = (double)(m > 0 ? m - 1 : 0) * r; /* centre on the origin */
    for (size_t i = 0; i < n; i++) {
        size_t ijk[3] = {i % m, (i / m) % m, i / (m * m)};
        for (unsigned a = 0; a < 3; a++)
            out->xyz[3 * i + a] =
                (float)(2.0 * r * (double)ijk[a] - half + 0.1 * r * unit_signed(seed, i, a));
    }
    return 0;
}

int scene_spray(size_t n, double r, uint64_t seed, scene_points *out)
{
    if (alloc_points(out, n) != 0)
        return -1;
    size_t m = 1;
    while (m * m * m < 2 * n)
        m++;
    size_t cells = m * m * m;
    uint32_t *order = malloc(cells * sizeof *order);
    if (!order) {
        scene_points_free(out);
        return -1;
    }
    for (size_t c = 0; c < cells; c++)
        order[c] = (uint32_t)c;
    /* partial Fisher-Yates: the first n entries are a seeded random choice */
    for (size_t i = 0; i < n; i++) {
        uint64_t h = scene_hash(scene_hash(seed ^ 0x7370726179ull) + i);
        size_t j = i + (size_t)(h % (uint64_t)(cells - i));
        uint32_t tmp = order[i];
        order[i] = order[j];
        order[j] = tmp;
    }
    const double cell = 12.0 * r, jitter = 2.0 * r;
    double half = 0.5 * (double)(m - 1) * cell;
    for (size_t i = 0; i < n; i++) {
        size_t c = order[i];
        size_t ijk[3] = {c % m, (c / m) % m, c / (m * m)};
        for (unsigned a = 0; a < 3; a++)
            out->xyz[3 * i + a] =
                (float)(cell * (double)ijk[a] - half + jitter * unit_signed(seed, i, a));
    }
    free(order);
    return 0;
}
