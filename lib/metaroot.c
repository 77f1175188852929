/* metaroot.c - a metasphere vertex on its lattice edge: each piece's crossing in closed form (a ball) or by bracketed Newton steps (a half-neck). */
#include "metaroot.h"
#include <math.h>

/* Every piece is evaluated as jm_prim_eval does (a half-neck continued past
 * its ends by its own ball and by the ball of its waist), without the
 * normal: only the value and its derivative along the edge. */

/* half-neck e at p: its value, and in *dv its derivative along ab */
static inline float neck_at(const jm_grid *g, const jm_config *c, uint32_t e, const float p[3], const float ab[3],
                            float *dv)
{
    const float inv_r = c->mv_inv_r;
    const float *q = &g->pos[3 * (size_t)g->nb_owner[e]], *u = &g->nb_dir[4 * (size_t)e];
    const float w[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    float s = w[0] * u[0] + w[1] * u[1] + w[2] * u[2];
    const float half = 0.5f * u[3];
    const int clamped = s < 0.0f || s > half;
    s = s < 0.0f ? 0.0f : (s > half ? half : s);
    const float rad[3] = {w[0] - s * u[0], w[1] - s * u[1], w[2] - s * u[2]};
    const float qq = sqrtf(rad[0] * rad[0] + rad[1] * rad[1] + rad[2] * rad[2]);
    /* d|rad|/dt = rad.ab / |rad| (rad is across the axis where s moves
     * along it); the cosine's: -sin(s/r) u.ab / r */
    const float along = clamped ? 0.0f : jm_sin_quarter(s * inv_r) * (u[0] * ab[0] + u[1] * ab[1] + u[2] * ab[2]);
    const float across = qq > 0.0f ? (rad[0] * ab[0] + rad[1] * ab[1] + rad[2] * ab[2]) / qq : 0.0f;
    *dv = -(along + across) * inv_r;
    return jm_cos_quarter(s * inv_r) - qq * inv_r;
}

/* piece id's value at p */
static inline float value_at(const jm_grid *g, const jm_config *c, uint32_t id, const float p[3])
{
    if (id < g->n) {
        const float *q = &g->pos[3 * (size_t)id];
        const float w[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
        return 1.0f - sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) * c->mv_inv_r;
    }
    float dv;
    return neck_at(g, c, id - (uint32_t)g->n, p, p, &dv);
}

/* Where piece id's surface leaves the edge between t_in (inside the piece)
 * and t_out (outside it, or at most on it), starting from t. */
static float exit_of(const jm_grid *g, const jm_config *c, uint32_t id, const float a[3], const float ab[3],
                     float t_in, float t_out, float t)
{
    const float thr = c->threshold;
    if (id < g->n) {
        /* |a + t ab - q| = r (1 - threshold): the root on t_out's side */
        const float *q = &g->pos[3 * (size_t)id];
        const float R = c->r * (1.0f - thr);
        const float w[3] = {a[0] - q[0], a[1] - q[1], a[2] - q[2]};
        const float A = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
        const float Bh = w[0] * ab[0] + w[1] * ab[1] + w[2] * ab[2];
        const float C = w[0] * w[0] + w[1] * w[1] + w[2] * w[2] - R * R;
        const float disc = Bh * Bh - A * C;
        if (!(disc >= 0.0f)) return t;
        const float sq = sqrtf(disc), r = t_out > t_in ? (-Bh + sq) / A : (-Bh - sq) / A;
        const float lo = t_in < t_out ? t_in : t_out, hi = t_in < t_out ? t_out : t_in;
        return r < lo ? lo : (r > hi ? hi : r);
    }
    /* a half-neck: Newton steps on its value less the threshold, bisecting
     * whenever a step leaves the bracket [t_in, t_out] */
    const uint32_t e = id - (uint32_t)g->n;
    const float tol = 1e-3f * c->h / c->r; /* a thousandth of a cube, in units of r */
    float ti = t_in, to = t_out;
    if (!((t - ti) * (t - to) <= 0.0f)) t = 0.5f * (ti + to);
    for (int it = 0; it < 12; it++) {
        const float p[3] = {a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]};
        float dv;
        const float f = neck_at(g, c, e, p, ab, &dv) - thr;
        if (fabsf(f) < tol) return t;
        if (f > 0.0f) ti = t; else to = t;
        float tn = dv != 0.0f ? t - f / dv : 0.5f * (ti + to);
        if (!((tn - ti) * (tn - to) < 0.0f)) tn = 0.5f * (ti + to);
        /* a Newton step of under a twentieth of the edge: done (what is
         * left is second order in it, about a thousandth of the edge) */
        else if (fabsf(tn - t) < 0.05f) return tn;
        t = tn;
    }
    return t;
}

float jm_meta_root(const jm_grid *g, const jm_config *c, const uint32_t cand[2], const float a[3], const float ab[3],
                   float fa, float t0)
{
    const int a_in = fa > 0.0f;
    const uint32_t k_in = a_in ? cand[0] : cand[1], k_out = a_in ? cand[1] : cand[0];
    if (k_in == UINT32_MAX) return t0; /* (an inside node always has its piece) */
    const float t_in = a_in ? 0.0f : 1.0f, t_out = 1.0f - t_in;
    float t = exit_of(g, c, k_in, a, ab, t_in, t_out, t0);
    if (k_out != UINT32_MAX && k_out != k_in) {
        const float p[3] = {a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]};
        if (value_at(g, c, k_out, p) > c->threshold) t = exit_of(g, c, k_out, a, ab, t, t_out, t);
    }
    return t;
}
