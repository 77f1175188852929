/* metavertex.c - metasphere vertices: every piece near a point, settling onto the exact surface. */
#include "field/meta/metavertex.h"
#include "core/cpu.h"
#include "core/lanes8.h"
#include <math.h>
#include <string.h>

/* normals blend no piece more than this below the maximum */
#define MV_GAP 0.4f

/* How far from its particle a piece can exceed `level`: a half-neck at s
 * along its axis reaches sqrt(s^2 + q^2) < s + r (cos(s/r) - level), which
 * grows with s (its slope is 1 - sin(s/r)), so the bound is its value at
 * the end S of the span where the cosine still exceeds the level (S <= L/2);
 * the ball, r (1 - level), is its value at 0. The same bounds the zero set
 * of a neck's continuation past its waist (a ball of radius
 * r (cos(D/2r) - level) about the waist's centre, D/2 from the particle),
 * which jm_prim_eval evaluates. */
static float reach_of(const jm_config *c, float level)
{
    const double r = c->r;
    double S = 0.5 * (double)c->link;
    if (level > -1.0f && S > acos((double)level) * r) S = acos((double)level) * r;
    double q = cos(S / r) - level;
    /* slack for the polynomial cosine of the splat */
    return (float)(S + (q > 0.0 ? q * r : 0.0) + 1e-4 * r);
}

void jm_metavertex_config(jm_config *c)
{
    /* a piece beating the vertex by more than a quarter of a hundredth of
     * r moves it (the vertex then lies within that of the exact surface) */
    c->mv_tol = 0.0025f;
    /* the probe settles again a vertex off the surface by more than this
     * (about 1.5 % of the jet's vertices; 0.8 % are off by more than 0.02) */
    c->mv_check = 0.0125f;
    c->mv_inv_r = 1.0f / c->r;
    /* normals blend the pieces within this of the threshold
     * (metanormal.h) */
    c->mv_tau = MV_GAP;
    float reach = reach_of(c, c->threshold - c->mv_tol);
    c->mv_reach2s = reach * reach;
    /* A surface point lies within reach_of(threshold) of its winning
     * piece's particle, a piece exceeding the threshold there within as
     * much of its own: when twice that is under the link distance, every
     * such piece belongs to the winner's particle or a linked neighbour. */
    c->mv_links = 2.0f * reach_of(c, c->threshold) <= c->link + 1e-3f * c->r;
}

/* pieces near a point, with their values (the NEAR best kept) */
#define NEAR 12
typedef struct near_set {
    int n;
    float vmax;
    uint32_t id[NEAR];
    float v[NEAR];
} near_set;

static void near_add(near_set *ns, uint32_t id, float v)
{
    if (v > ns->vmax) ns->vmax = v;
    if (ns->n < NEAR) {
        ns->id[ns->n] = id;
        ns->v[ns->n++] = v;
        return;
    }
    int lo = 0;
    for (int k = 1; k < NEAR; k++)
        if (ns->v[k] < ns->v[lo]) lo = k;
    if (v > ns->v[lo]) {
        ns->id[lo] = id;
        ns->v[lo] = v;
    }
}

/* adds particle k's pieces whose value at p exceeds `level`: its ball,
 * then its half-necks in link order, 8 links a step (lanes8.h: each lane
 * the float operations of one link's value, so the same bits as one at a
 * time) */
JM_L8 void near_particle(const jm_grid *g, const jm_config *c, uint32_t k, const float p[3], float level, float rl2,
                         float reach2, near_set *ns)
{
    const float *q = &g->pos[3 * (size_t)k];
    const float w[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    const float d2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    if (!(d2 < reach2)) return;
    const float inv_r = 1.0f / c->r;
    if (d2 < rl2) near_add(ns, k, 1.0f - sqrtf(d2) * inv_r);
    const uint32_t e0 = g->nb_start[k], e1 = g->nb_start[k + 1];
    for (uint32_t e = e0; e < e1; e += JM_LANES) {
        const int m = e1 - e < JM_LANES ? (int)(e1 - e) : JM_LANES;
        v8f u0, u1, u2, half;
        for (int l = 0; l < JM_LANES; l++) {
            const float *u = &g->nb_dir[4 * (size_t)(e + (uint32_t)(l < m ? l : m - 1))];
            u0[l] = u[0], u1[l] = u[1], u2[l] = u[2], half[l] = 0.5f * u[3];
        }
        const v8f s = w[0] * u0 + w[1] * u1 + w[2] * u2, q2 = d2 - s * s;
        const v8f v = vcos(s * inv_r) - vsqrt(sel(q2 > 0.0f, q2, bc(0.0f))) * inv_r;
        const v8i ok = (s >= 0.0f) & (s <= half) & (q2 < rl2) & (v > level);
        for (int l = 0; l < m; l++)
            if (ok[l]) near_add(ns, (uint32_t)g->n + e + (uint32_t)l, v[l]);
    }
}

/* Every piece whose value at p exceeds `level` (the NEAR best of them),
 * p being on the surface of piece win (or inside it). */
JM_L8 void near_scan(const jm_grid *g, const jm_config *c, const jm_hood *hood, uint32_t win, const float p[3],
                      float level, near_set *ns)
{
    ns->n = 0;
    ns->vmax = -INFINITY;
    /* q < r (cos(s/r) - level) <= r (1 - level) for any piece; and no
     * piece of a particle farther than its reach exceeds the level (the
     * settle's) */
    const float rl = c->r * (1.0f - level), rl2 = rl * rl;
    const float reach2 = c->mv_reach2s; /* level is the settle's */
    if (c->mv_links) {
        uint32_t i = win < g->n ? win : g->nb_owner[win - g->n];
        near_particle(g, c, i, p, level, rl2, reach2, ns);
        for (uint32_t e = g->nb_start[i]; e < g->nb_start[i + 1]; e++)
            near_particle(g, c, g->nb[e], p, level, rl2, reach2, ns);
        return;
    }
    const float reach = sqrtf(reach2);
    int lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        int64_t l = (int64_t)floorf((p[a] - reach) * g->inv_cell) - hood->c0[a];
        int64_t h = (int64_t)floorf((p[a] + reach) * g->inv_cell) - hood->c0[a];
        lo[a] = l < 0 ? 0 : (int)l;
        hi[a] = h >= hood->n[a] ? hood->n[a] - 1 : (int)h;
    }
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
            for (int x = lo[0]; x <= hi[0]; x++) {
                size_t cell = ((size_t)z * hood->n[1] + y) * hood->n[0] + x;
                for (uint32_t k = hood->range[2 * cell]; k < hood->range[2 * cell + 1]; k++)
                    if (!g->isolated[k]) near_particle(g, c, k, p, level, rl2, reach2, ns);
            }
}

/* the maximum over pieces set[0..n) at p: value, and the winner's index,
 * outward normal and gradient length */
static float set_eval(const jm_grid *g, const jm_config *c, const uint32_t *set, int n, const float p[3], int *wi,
                      float nrm[3], float *glen)
{
    float best = -INFINITY;
    for (int k = 0; k < n; k++) {
        float nk[3] = {0, 0, 0}, gk = 0.0f;
        float v = jm_prim_eval(g, c, set[k], p, nk, &gk);
        if (v > best) {
            best = v;
            *wi = k;
            memcpy(nrm, nk, sizeof nk);
            *glen = gk;
        }
    }
    return best;
}

/* Root of (max over set) - threshold on the edge within [ta, tb] (the
 * inside end first in sign: fin > 0 at t_in), by safeguarded Newton steps;
 * *win gets the piece winning at the root. */
static float set_root(const jm_grid *g, const jm_config *c, const uint32_t *set, int n, const float a[3],
                      const float ab[3], float t_in, float t_out, uint32_t *win)
{
    float ta = t_in, tb = t_out, t = t_in;
    const float tol = 1e-3f * c->h / c->r;
    for (int it = 0; it < 12; it++) {
        float p[3] = {a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]}, nk[3] = {0, 0, 0}, glen = 0.0f;
        int wi = 0;
        float f = set_eval(g, c, set, n, p, &wi, nk, &glen) - c->threshold;
        *win = set[wi];
        if (fabsf(f) < tol && it > 0) return t;
        if (f > 0.0f) ta = t; else tb = t;
        float df = -glen * (nk[0] * ab[0] + nk[1] * ab[1] + nk[2] * ab[2]);
        float tn = df != 0.0f ? t - f / df : 0.5f * (ta + tb);
        if (!((tn - ta) * (tn - tb) < 0.0f)) tn = 0.5f * (ta + tb);
        t = tn;
    }
    return t;
}

JM_BODY float settle_body(const jm_grid *g, const jm_config *c, const jm_hood *hood, const uint32_t cand[2], uint32_t win,
                          const float a[3], const float ab[3], float fa, float t)
{
    const float thr = c->threshold, tol = c->mv_tol, level = thr - tol;
    const float t_out = fa > 0.0f ? 1.0f : 0.0f, t_in = 1.0f - t_out;
    uint32_t set[8];
    int n = 0;
    for (int k = 0; k < 2; k++)
        if (cand[k] != UINT32_MAX && (k == 0 || cand[1] != cand[0])) set[n++] = cand[k];
    near_set ns;
    float p[3];
    for (int round = 0;; round++) {
        for (int q = 0; q < 3; q++) p[q] = a[q] + t * ab[q];
        near_scan(g, c, hood, win, p, level, &ns);
        if (round == 4 || (ns.vmax <= thr + tol && ns.vmax >= thr - tol)) break;
        if (ns.vmax > thr + tol) {
            /* pieces beating the surface here (a third piece winning
             * mid-edge): add them, best first, and find the edge's
             * crossing again between here and the outside end */
            for (;;) {
                int best = -1;
                for (int k = 0; k < ns.n; k++) {
                    if (!(ns.v[k] > thr + tol)) continue;
                    int dup = 0;
                    for (int j = 0; j < n; j++) dup |= set[j] == ns.id[k];
                    if (!dup && (best < 0 || ns.v[k] > ns.v[best])) best = k;
                }
                if (best < 0 || n == 8) break;
                set[n++] = ns.id[best];
            }
            t = set_root(g, c, set, n, a, ab, t, t_out, &win);
        } else {
            /* outside the surface: the refinement stopped short */
            t = set_root(g, c, set, n, a, ab, t_in, t, &win);
        }
    }
    return t;
}
JM_KERNEL_AVX2(, float, jm_meta_settle, settle_body,
               (const jm_grid *g, const jm_config *c, const jm_hood *hood, const uint32_t cand[2], uint32_t win,
                const float a[3], const float ab[3], float fa, float t),
               (g, c, hood, cand, win, a, ab, fa, t))
