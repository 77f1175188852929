/* draco_bits.c - picks the fewest Draco position bits (from 16) at which no triangle of a mesh collapses. */
#include "draco_bits.h"
#include <math.h>
#include <stdint.h>

/* Draco quantises every position component on one grid: origin at the
 * per-axis minimum, range = the largest extent, q = floor((v - min) * m /
 * range + 0.5) with m = 2^bits - 1. */
static size_t collapsed_at(const jm_mesh *mesh, int bits, const float lo[3], float range)
{
    const double scale = range > 0.0f ? (double)((1u << bits) - 1u) / range : 0.0;
    size_t bad = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        int64_t q[3][3];
        for (int k = 0; k < 3; k++) {
            const float *p = mesh->positions + 3 * (size_t)mesh->indices[3 * t + k];
            for (int a = 0; a < 3; a++) q[k][a] = (int64_t)floor((p[a] - lo[a]) * scale + 0.5);
        }
        int64_t u[3], v[3];
        for (int a = 0; a < 3; a++) {
            u[a] = q[1][a] - q[0][a];
            v[a] = q[2][a] - q[0][a];
        }
        /* zero area (two corners on one grid point included) */
        if (u[1] * v[2] - u[2] * v[1] == 0 && u[2] * v[0] - u[0] * v[2] == 0 && u[0] * v[1] - u[1] * v[0] == 0) bad++;
    }
    return bad;
}

int jmf_draco_auto_position_bits(const jm_mesh *mesh, size_t *out_collapsed)
{
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    if (mesh->vertex_count) {
        for (int a = 0; a < 3; a++) lo[a] = hi[a] = mesh->positions[a];
        for (size_t v = 1; v < mesh->vertex_count; v++)
            for (int a = 0; a < 3; a++) {
                float x = mesh->positions[3 * v + a];
                lo[a] = x < lo[a] ? x : lo[a];
                hi[a] = x > hi[a] ? x : hi[a];
            }
    }
    float range = 0.0f;
    for (int a = 0; a < 3; a++) range = hi[a] - lo[a] > range ? hi[a] - lo[a] : range;
    /* triangles already flat in float stay flat at any number of bits */
    size_t floor_bad = collapsed_at(mesh, 30, lo, range);
    size_t bad = 0;
    int bits = JMF_DRACO_AUTO_MIN_BITS;
    for (; bits < JMF_DRACO_AUTO_MAX_BITS; bits++) {
        bad = collapsed_at(mesh, bits, lo, range);
        if (bad <= floor_bad) break;
    }
    if (bits == JMF_DRACO_AUTO_MAX_BITS) bad = collapsed_at(mesh, bits, lo, range);
    if (out_collapsed) *out_collapsed = bad;
    return bits;
}
