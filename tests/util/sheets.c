/* sheets.c - thin sheets of particles (1 to a few layers) with droplets beside them, for the anisotropic tests. */
#include "sheets.h"
#include "meshcheck.h"

#include <math.h>
#include <stdlib.h>

const int test_sheet_drop_size[TEST_SHEET_DROPLETS] = {1, 2, 4, 7};

/* each droplet's particles relative to its centre, in units of r: a
 * single, a pair 2r apart, a tetrahedron of edge 1.8r and an octahedron of
 * radius 1.2r around a seventh (a splash's clusters are denser than the
 * rest spacing 2r) */
static const float drop_shape[TEST_SHEET_DROPLETS][7][3] = {
    {{0, 0, 0}},
    {{-1, 0, 0}, {1, 0, 0}},
    {{0.9f, 0, -0.318f}, {-0.9f, 0, -0.318f}, {0, 0.9f, 0.318f}, {0, -0.9f, 0.318f}},
    {{0, 0, 0}, {1.2f, 0, 0}, {-1.2f, 0, 0}, {0, 1.2f, 0}, {0, -1.2f, 0}, {0, 0, 1.2f}, {0, 0, -1.2f}},
};

size_t test_sheet(int layers, int side, float r, float jitter, unsigned seed, int droplets, float gap, float **out,
                  float *dc)
{
    size_t n = (size_t)layers * side * side, cap = n + (droplets ? 14 : 0);
    float *p = malloc(3 * cap * sizeof *p);
    *out = p;
    if (!p) return 0;
    /* tilted: about 5 degrees around x, then 3 around y */
    const double ax = 0.087, ay = 0.052;
    const double cx = cos(ax), sx = sin(ax), cy = cos(ay), sy = sin(ay);
    size_t m = 0;
    for (int l = 0; l < layers; l++)
        for (int j = 0; j < side; j++)
            for (int i = 0; i < side; i++) {
                double q[3] = {2.0 * i, 2.0 * j, 2.0 * l};
                if (jitter > 0)
                    for (int k = 0; k < 3; k++) q[k] += jitter * (2.0 * mc_randf(&seed) - 1.0);
                p[3 * m] = (float)q[0];
                p[3 * m + 1] = (float)q[1];
                p[3 * m + 2] = (float)q[2];
                m++;
            }
    /* droplets 8r apart, around the middle: over the top face, the lowest
     * particle of each gap r over the top layer (droplets 1), or beside the
     * rim at the last column, in the sheet's mid-plane, the nearest particle
     * gap r out from the column (droplets 2) */
    const int axis = droplets == 2 ? 0 : 2;
    for (int d = 0; droplets && d < TEST_SHEET_DROPLETS; d++) {
        float low = 0;
        for (int k = 0; k < test_sheet_drop_size[d]; k++)
            low = drop_shape[d][k][axis] < low ? drop_shape[d][k][axis] : low;
        const double along = side - 12.0 + 8.0 * d;
        double base[3] = {along, side - 1.0, 2.0 * (layers - 1) + gap - low}; /* over the top face */
        if (droplets == 2) /* beside the last column, in the mid-plane */
            base[0] = 2.0 * (side - 1) + gap - low, base[1] = along, base[2] = layers - 1.0;
        double c[3] = {0, 0, 0};
        for (int k = 0; k < test_sheet_drop_size[d]; k++) {
            for (int a = 0; a < 3; a++) {
                double v = base[a] + drop_shape[d][k][a];
                p[3 * m + a] = (float)v;
                c[a] += v / test_sheet_drop_size[d];
            }
            m++;
        }
        if (dc)
            for (int a = 0; a < 3; a++) dc[3 * d + a] = (float)c[a];
    }
    /* rotate and scale to r; the droplets' centres too */
    for (size_t i = 0; i < m + (dc && droplets ? TEST_SHEET_DROPLETS : 0); i++) {
        float *v = i < m ? p + 3 * i : dc + 3 * (i - m);
        double x = v[0], y = v[1] * cx - v[2] * sx, z = v[1] * sx + v[2] * cx;
        double x2 = x * cy + z * sy, z2 = -x * sy + z * cy;
        v[0] = (float)(x2 * r + 0.0131);
        v[1] = (float)(y * r - 0.0077);
        v[2] = (float)(z2 * r + 0.0042);
    }
    return m;
}
