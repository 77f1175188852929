/* metaroot.c - a block's metasphere vertices on their lattice edges, 8 at a time: each piece's crossing in closed form (a ball) or by bracketed Newton steps (a half-neck). */
#include "field/meta/metaroot.h"
#include "core/lanes8.h"
#include "core/skew.h"
#include <math.h>
#include <string.h>

/* Every piece is evaluated as jm_prim_eval does (a half-neck continued past
 * its ends by its own ball and by the ball of its waist), without the
 * normal: only the value and its derivative along the edge, in 8 lanes
 * (lanes8.h: the same bits on every path); a vertex's root is one lane's,
 * whatever lanes its neighbours take (Newton steps and their latency, 8 at
 * once). */
#define W JM_LANES

/* W vertices' edges and the pieces to solve for (p: their particles'
 * centres; u, half: a half-neck's axis and half its link) */
typedef struct lanes {
    v8f ax, ay, az, bx, by, bz;
    v8f qx, qy, qz, ux, uy, uz, half;
} lanes;

/* lanes l of L from the vertices idx[0 .. m) (the last repeated past m)
 * and their pieces id[0 .. m): all balls, or all half-necks */
JM_L8 void load(const jm_grid *g, const jm_roots *r, const uint32_t *idx, const uint32_t *id, int m, int necks,
                lanes *L)
{
    for (int l = 0; l < W; l++) {
        const uint32_t v = idx[l < m ? l : m - 1], p = id[l < m ? l : m - 1];
        L->ax[l] = r->ax[v], L->ay[l] = r->ay[v], L->az[l] = r->az[v];
        L->bx[l] = r->bx[v], L->by[l] = r->by[v], L->bz[l] = r->bz[v];
        const uint32_t e = p - (uint32_t)g->n;
        const float *q = &g->pos[3 * (size_t)(necks ? g->nb_owner[e] : p)];
        L->qx[l] = q[0], L->qy[l] = q[1], L->qz[l] = q[2];
        if (necks) {
            const float *u = &g->nb_dir[4 * (size_t)e];
            L->ux[l] = u[0], L->uy[l] = u[1], L->uz[l] = u[2], L->half[l] = 0.5f * u[3];
        }
    }
}

/* the half-necks at a + t ab: values, and in *dv their derivatives along ab */
JM_L8 v8f neck_at(const lanes *L, v8f t, float inv_r, v8f *dv)
{
    const v8f wx = L->ax + t * L->bx - L->qx, wy = L->ay + t * L->by - L->qy, wz = L->az + t * L->bz - L->qz;
    v8f s = wx * L->ux + wy * L->uy + wz * L->uz;
    const v8i clamped = (s < 0.0f) | (s > L->half);
    s = sel(s < 0.0f, bc(0.0f), s);
    s = sel(s > L->half, L->half, s);
    const v8f rx = wx - s * L->ux, ry = wy - s * L->uy, rz = wz - s * L->uz;
    const v8f qq = vsqrt(rx * rx + ry * ry + rz * rz);
    /* d|rad|/dt = rad.ab / |rad| (rad is across the axis where s moves
     * along it); the cosine's: -sin(s/r) u.ab / r */
    const v8f along = sel(clamped, bc(0.0f), vsin(s * inv_r) * (L->ux * L->bx + L->uy * L->by + L->uz * L->bz));
    const v8f across = sel(qq > 0.0f, (rx * L->bx + ry * L->by + rz * L->bz) / qq, bc(0.0f));
    *dv = -(along + across) * inv_r;
    return vcos(s * inv_r) - qq * inv_r;
}

/* the balls at a + t ab */
JM_L8 v8f ball_at(const lanes *L, v8f t, float inv_r)
{
    const v8f wx = L->ax + t * L->bx - L->qx, wy = L->ay + t * L->by - L->qy, wz = L->az + t * L->bz - L->qz;
    return 1.0f - vsqrt(wx * wx + wy * wy + wz * wz) * inv_r;
}

/* Where each ball's surface leaves the edge between t_in (inside it) and
 * t_out: |a + t ab - q| = r (1 - threshold), the root on t_out's side
 * (t kept where the edge misses the ball) */
JM_L8 v8f ball_exit(const jm_config *c, const lanes *L, v8f ti, v8f to, v8f t)
{
    const float R = c->r * (1.0f - c->threshold);
    const v8f wx = L->ax - L->qx, wy = L->ay - L->qy, wz = L->az - L->qz;
    const v8f A = L->bx * L->bx + L->by * L->by + L->bz * L->bz;
    const v8f Bh = wx * L->bx + wy * L->by + wz * L->bz;
    const v8f C = wx * wx + wy * wy + wz * wz - R * R;
    const v8f disc = Bh * Bh - A * C;
    const v8i ok = disc >= 0.0f;
    const v8f sq = vsqrt(sel(ok, disc, bc(0.0f)));
    const v8f r = sel(to > ti, (-Bh + sq) / A, (-Bh - sq) / A);
    const v8f lo = sel(ti < to, ti, to), hi = sel(ti < to, to, ti);
    return sel(ok, sel(r < lo, lo, sel(r > hi, hi, r)), t);
}

/* Where each half-neck's surface leaves the edge between t_in and t_out,
 * by Newton steps on its value less the threshold from t, bisecting
 * whenever a step leaves the bracket; done where the value is within a
 * thousandth of a cube of it, or a step moves under a twentieth of the
 * edge (what is left is second order in it, about a thousandth) */
JM_L8 v8f neck_exit(const jm_config *c, const lanes *L, v8f ti, v8f to, v8f t)
{
    const float thr = c->threshold, inv_r = c->mv_inv_r, tol = 1e-3f * c->h / c->r;
    t = sel((t - ti) * (t - to) <= 0.0f, t, 0.5f * (ti + to));
    v8i done = (v8i){0};
    for (int it = 0; it < 12 && any(~done); it++) {
        v8f dv;
        const v8f f = neck_at(L, t, inv_r, &dv) - thr;
        const v8i conv = vabs(f) < tol, active = ~done & ~conv;
        ti = sel(active & (f > 0.0f), t, ti);
        to = sel(active & ~(f > 0.0f), t, to);
        v8f tn = sel(dv != 0.0f, t - f / dv, 0.5f * (ti + to));
        const v8i out = ~((tn - ti) * (tn - to) < 0.0f);
        tn = sel(out, 0.5f * (ti + to), tn);
        const v8i small = ~out & (vabs(tn - t) < 0.05f);
        t = sel(active, tn, t);
        done |= conv | (active & small);
    }
    return t;
}

/* The vertices idx[0 .. m) (m > 0), their pieces id[0 .. m) (balls, or
 * half-necks), exits between t_in (1 - t_out) and t_out (per vertex: 1
 * where its node a is inside) from their t: into t. */
JM_L8 void exits(const jm_grid *g, const jm_config *c, jm_roots *r, const uint32_t *idx, const uint32_t *id, size_t m,
                  int necks, int from_t)
{
    for (size_t k = 0; k < m; k += W) {
        const int w = m - k < W ? (int)(m - k) : W;
        lanes L;
        load(g, r, idx + k, id + k, w, necks, &L);
        float tl[W], tol[W];
        for (int l = 0; l < W; l++) {
            const uint32_t v = idx[k + (size_t)(l < w ? l : w - 1)];
            tl[l] = r->t[v];
            tol[l] = r->fa[v] > 0.0f ? 1.0f : 0.0f;
        }
        v8f t, to;
        memcpy(&t, tl, sizeof t);
        memcpy(&to, tol, sizeof to);
        const v8f ti = from_t ? t : 1.0f - to;
        t = necks ? neck_exit(c, &L, ti, to, t) : ball_exit(c, &L, ti, to, t);
        for (int l = 0; l < w; l++) r->t[idx[k + (size_t)l]] = t[l];
    }
}

/* The vertices idx[0 .. m) whose piece id beats the threshold at their t
 * (balls, or half-necks) moved to the front; their count. */
JM_L8 size_t beaten(const jm_grid *g, const jm_config *c, jm_roots *r, uint32_t *idx, uint32_t *id, size_t m,
                     int necks)
{
    size_t kept = 0;
    for (size_t k = 0; k < m; k += W) {
        const int w = m - k < W ? (int)(m - k) : W;
        lanes L;
        load(g, r, idx + k, id + k, w, necks, &L);
        float tl[W];
        for (int l = 0; l < W; l++) tl[l] = r->t[idx[k + (size_t)(l < w ? l : w - 1)]];
        v8f t, dv;
        memcpy(&t, tl, sizeof t);
        const v8f v = necks ? neck_at(&L, t, c->mv_inv_r, &dv) : ball_at(&L, t, c->mv_inv_r);
        for (int l = 0; l < w; l++)
            if (v[l] > c->threshold) {
                idx[kept] = idx[k + (size_t)l];
                id[kept++] = id[k + (size_t)l];
            }
    }
    return kept;
}

JM_BODY void jm_roots_solve_body(const jm_grid *g, const jm_config *c, jm_roots *r)
{
    const size_t n = r->n;
    if (!n) return;
    /* four lists of n: balls and half-necks (vertex, piece) from the
     * front and from the back of the first two */
    uint32_t *vi = r->list, *pi = r->list + n, *vj = r->list + 2 * n, *pj = r->list + 3 * n;
    for (int round = 0; round < 2; round++) {
        /* round 0: the inside node's piece from the inside end; round 1:
         * the other node's, from there on, where it holds the point */
        size_t nb = 0, nn = 0;
        for (size_t v = 0; v < n; v++) {
            const int a_in = r->fa[v] > 0.0f;
            const uint32_t k_in = a_in ? r->c0[v] : r->c1[v], k_out = a_in ? r->c1[v] : r->c0[v];
            const uint32_t p = round ? k_out : k_in;
            /* (an inside node always has its piece); each vertex to one
             * list or neither, without a branch */
            const int use = k_in != UINT32_MAX && p != UINT32_MAX && !(round && k_out == k_in), ball = p < g->n;
            vi[nb] = (uint32_t)v, pi[nb] = p, vj[nn] = (uint32_t)v, pj[nn] = p;
            nb += (size_t)(use & ball);
            nn += (size_t)(use & !ball);
        }
        if (round) {
            nb = beaten(g, c, r, vi, pi, nb, 0);
            nn = beaten(g, c, r, vj, pj, nn, 1);
        }
        exits(g, c, r, vi, pi, nb, 0, round);
        exits(g, c, r, vj, pj, nn, 1, round);
    }
}
JM_KERNEL_AVX2(, void, jm_roots_solve, jm_roots_solve_body, (const jm_grid *g, const jm_config *c, jm_roots *r), (g, c, r))

int jm_roots_grow(jm_roots *r)
{
    const size_t nc = r->cap ? 2 * r->cap : 1024;
    jm_roots o = *r;
    o.cap = nc;
    return jm_roots_match(r, &o);
}

/* 8 floats and 2 + 4 indices a vertex, in one block (ax its start) with
 * each array skewed (skew.h) */
static const size_t roots_esz[11] = {4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 16};

int jm_roots_match(jm_roots *r, const jm_roots *o)
{
    if (o->cap <= r->cap) return 1;
    const size_t nc = o->cap, oc = r->cap;
    char *b = jm_alloc_lasting(r->mem, jm_skew_bytes(roots_esz, 11, nc)), *old = (char *)r->ax;
    if (!b) return 0;
    void **a[11] = {(void **)&r->ax, (void **)&r->ay, (void **)&r->az, (void **)&r->bx, (void **)&r->by,
                    (void **)&r->bz, (void **)&r->fa, (void **)&r->t, (void **)&r->c0, (void **)&r->c1,
                    (void **)&r->list};
    for (int k = 0; k < 11; k++) {
        void *nw = jm_skew_at(b, roots_esz, k, nc);
        if (r->n && k < 10) memcpy(nw, *a[k], r->n * roots_esz[k]);
        *a[k] = nw;
    }
    if (old) jm_free(r->mem, old, jm_skew_bytes(roots_esz, 11, oc));
    r->cap = nc;
    return 1;
}

void jm_roots_free(jm_roots *r)
{
    jm_mem *m = r->mem;
    if (r->cap) jm_free(m, r->ax, jm_skew_bytes(roots_esz, 11, r->cap));
    memset(r, 0, sizeof *r);
    r->mem = m;
}
