/* domain_advice.c - explains particles too far from the origin or spread too wide for the lattice: what is wrong and what would help. */
#include "domain_advice.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* the largest --cube-size (jm_params_check) and the default */
#define CUBE_MAX 100.0
#define CUBE_DEFAULT 0.5

typedef struct box {
    double lo[3], hi[3];
    double far;    /* the largest |coordinate| */
    double half;   /* half the widest extent: the farthest once centred */
} box;

static void bounds(const jm_particles *parts, box *b)
{
    size_t stride = parts->stride ? parts->stride : 3 * sizeof(float);
    memset(b, 0, sizeof *b);
    for (size_t i = 0; i < parts->count; i++) {
        float x[3];
        memcpy(x, (const char *)parts->xyz + i * stride, sizeof x);
        for (int a = 0; a < 3; a++) {
            if (i == 0 || x[a] < b->lo[a]) b->lo[a] = x[a];
            if (i == 0 || x[a] > b->hi[a]) b->hi[a] = x[a];
        }
    }
    for (int a = 0; a < 3; a++) {
        b->far = fmax(b->far, fmax(fabs(b->lo[a]), fabs(b->hi[a])));
        b->half = fmax(b->half, (b->hi[a] - b->lo[a]) / 2);
    }
}

/* v rounded up to three significant digits, so that the size said reaches */
static double up3(double v)
{
    if (!(v > 0))
        return v;
    double m = pow(10.0, floor(log10(v)) - 2);
    return ceil(v / m) * m;
}

static double cube_of(const jm_params *p)
{
    return p->cube_size > 0 ? (double)p->cube_size : CUBE_DEFAULT;
}

int domain_outside(const jm_params *p, const jm_particles *parts)
{
    box b;
    if (!parts->count || !(p->radius > 0))
        return 0;
    bounds(parts, &b);
    return b.far > JM_MAX_CUBES_FROM_ORIGIN * cube_of(p) * (double)p->radius;
}

void domain_advice(char *msg, size_t len, const char *path, const jm_params *p, const jm_particles *parts)
{
    box b;
    bounds(parts, &b);
    const double r = p->radius, cube = cube_of(p), reach = JM_MAX_CUBES_FROM_ORIGIN * cube * r,
                 widest = JM_MAX_CUBES_FROM_ORIGIN * CUBE_MAX * r, need = b.far / (JM_MAX_CUBES_FROM_ORIGIN * r),
                 centred = b.half / (JM_MAX_CUBES_FROM_ORIGIN * r);
    char centre[96], help[400];
    snprintf(centre, sizeof centre, "(%g, %g, %g)", (b.lo[0] + b.hi[0]) / 2, (b.lo[1] + b.hi[1]) / 2,
             (b.lo[2] + b.hi[2]) / 2);
    if (need <= CUBE_MAX && b.half <= reach)
        snprintf(help, sizeof help, "--cube-size %g or more reaches them (a coarser mesh), or move them nearer "
                 "the origin: subtract their centre %s", up3(need), centre);
    else if (need <= CUBE_MAX)
        snprintf(help, sizeof help, "--cube-size %g or more reaches them (a coarser mesh)", up3(need));
    else if (b.half <= reach)
        snprintf(help, sizeof help, "no --cube-size reaches them (the largest, %g, reaches %g): move them nearer "
                 "the origin: subtract their centre %s", CUBE_MAX, widest, centre);
    else if (b.half <= widest)
        snprintf(help, sizeof help, "no --cube-size reaches them (the largest, %g, reaches %g): subtract their "
                 "centre %s and use --cube-size %g or more", CUBE_MAX, widest, centre, up3(centred));
    else
        snprintf(help, sizeof help, "they span %g, wider than one frame can be at any --cube-size (%g at the "
                 "largest, %g, around the origin): split the frame into parts at most that wide and move "
                 "each near the origin, or leave out the particles far from the rest",
                 2 * b.half, 2 * widest, CUBE_MAX);
    snprintf(msg, len,
             "%s: outside the numeric domain: the particles lie from (%g, %g, %g) to (%g, %g, %g); at "
             "--cube-size %g the lattice reaches %g from the origin (65536 cube edges of %g, what float "
             "precision allows): %s (see jetmesh(1), LIMITS)",
             path, b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2], cube, reach, cube * r, help);
}
