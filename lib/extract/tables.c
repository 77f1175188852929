/* tables.c - generates the marching cubes and marching tetrahedra tables (no copied tables). */
#include "extract/tables.h"
#include <pthread.h>
#include <stdatomic.h>
#include <string.h>

const int jm_dir[7][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};

/* Edges 0-11 are the axis edges (so marching cubes uses 0-11 only). */
const uint8_t jm_cube_edge_corner[19] = {
    0, 2, 4, 6,    /* x edges at (y,z) = 00 10 01 11 */
    0, 1, 4, 5,    /* y edges at (x,z) = 00 10 01 11 */
    0, 1, 2, 3,    /* z edges at (x,y) = 00 10 01 11 */
    0, 4,          /* xy diagonals on z = 0, 1 */
    0, 2,          /* xz diagonals on y = 0, 1 */
    0, 1,          /* yz diagonals on x = 0, 1 */
    0              /* body diagonal */
};
const uint8_t jm_cube_edge_dir[19] = {0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 4, 4, 5, 5, 6};

static jm_case_table mc_table, mt_table;
static pthread_once_t once = PTHREAD_ONCE_INIT;

static void corner_pos(int c, double p[3])
{
    p[0] = c & 1;
    p[1] = (c >> 1) & 1;
    p[2] = (c >> 2) & 1;
}

static int edge_between(int a, int b)
{
    if (a > b) { int t = a; a = b; b = t; }
    int d[3] = {(b & 1) - (a & 1), ((b >> 1) & 1) - ((a >> 1) & 1), ((b >> 2) & 1) - ((a >> 2) & 1)};
    for (int e = 0; e < 19; e++) {
        if (jm_cube_edge_corner[e] != a) continue;
        const int *v = jm_dir[jm_cube_edge_dir[e]];
        if (v[0] == d[0] && v[1] == d[1] && v[2] == d[2]) return e;
    }
    return -1;
}

static void edge_mid(int e, double m[3])
{
    double p[3];
    corner_pos(jm_cube_edge_corner[e], p);
    const int *v = jm_dir[jm_cube_edge_dir[e]];
    for (int i = 0; i < 3; i++) m[i] = p[i] + 0.5 * v[i];
}

static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* Appends triangle (e0,e1,e2), flipped if needed so its normal points along out. */
static void add_tri(jm_case_table *t, int cfg, int e0, int e1, int e2, const double out[3])
{
    double a[3], b[3], c[3], u[3], v[3], n[3];
    edge_mid(e0, a);
    edge_mid(e1, b);
    edge_mid(e2, c);
    for (int i = 0; i < 3; i++) { u[i] = b[i] - a[i]; v[i] = c[i] - a[i]; }
    cross(u, v, n);
    if (n[0] * out[0] + n[1] * out[1] + n[2] * out[2] < 0) { int s = e1; e1 = e2; e2 = s; }
    uint8_t *dst = &t->edges[cfg][3 * t->ntri[cfg]];
    dst[0] = (uint8_t)e0;
    dst[1] = (uint8_t)e1;
    dst[2] = (uint8_t)e2;
    t->ntri[cfg]++;
}

/* ---- marching tetrahedra: 6 tetrahedra around the 0-7 diagonal */
static const int tets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

static void build_mt(void)
{
    for (int cfg = 0; cfg < 256; cfg++) {
        for (int t = 0; t < 6; t++) {
            int in[4], out[4], ni = 0, no = 0;
            for (int k = 0; k < 4; k++) {
                int c = tets[t][k];
                if (cfg >> c & 1) in[ni++] = c; else out[no++] = c;
            }
            if (ni == 0 || no == 0) continue;
            /* outward direction: from the inside corners' centroid to the outside ones' */
            double ci[3] = {0, 0, 0}, co[3] = {0, 0, 0}, p[3], dir[3];
            for (int k = 0; k < ni; k++) { corner_pos(in[k], p); for (int i = 0; i < 3; i++) ci[i] += p[i] / ni; }
            for (int k = 0; k < no; k++) { corner_pos(out[k], p); for (int i = 0; i < 3; i++) co[i] += p[i] / no; }
            for (int i = 0; i < 3; i++) dir[i] = co[i] - ci[i];
            if (ni == 1 || no == 1) {
                int lone = ni == 1 ? in[0] : out[0];
                int *others = ni == 1 ? out : in;
                add_tri(&mt_table, cfg, edge_between(lone, others[0]), edge_between(lone, others[1]),
                        edge_between(lone, others[2]), dir);
            } else {
                int a = in[0], b = in[1], c = out[0], d = out[1];
                int ac = edge_between(a, c), ad = edge_between(a, d), bd = edge_between(b, d), bc = edge_between(b, c);
                add_tri(&mt_table, cfg, ac, ad, bd, dir);
                add_tri(&mt_table, cfg, ac, bd, bc, dir);
            }
        }
    }
}

/* ---- marching cubes: polygons traced face by face. On every face each
 * segment is directed with the inside corners on its right seen from
 * outside the cube; an ambiguous face (diagonal corners alike) cuts off each
 * inside corner on its own, which the neighbouring cube decides the same
 * way. The directed segments close into cycles, fanned into triangles. */
static const int faces[6][4] = {
    /* corners counter-clockwise seen from outside */
    {0, 4, 6, 2}, /* x = 0, normal -x */
    {1, 3, 7, 5}, /* x = 1, normal +x */
    {0, 1, 5, 4}, /* y = 0, normal -y */
    {2, 6, 7, 3}, /* y = 1, normal +y */
    {0, 2, 3, 1}, /* z = 0, normal -z */
    {4, 5, 7, 6}, /* z = 1, normal +z */
};

/* bit f set: cube edge e lies on face f (0 x=0, 1 x=1, 2 y=0, 3 y=1, 4 z=0, 5 z=1) */
static int face_mask(int e)
{
    int a = jm_cube_edge_corner[e];
    const int *d = jm_dir[jm_cube_edge_dir[e]];
    int m = 0;
    for (int ax = 0; ax < 3; ax++)
        if (!d[ax]) m |= 1 << (2 * ax + ((a >> ax) & 1));
    return m;
}

/* 0 if some polygon had no fan free of in-face diagonals (checked by tests) */
static int table_ok = 1;
int jm_tables_consistent(void)
{
    jm_table_mc();
    return table_ok;
}

static void build_mc(void)
{
    for (int cfg = 0; cfg < 256; cfg++) {
        int next[12];
        for (int e = 0; e < 12; e++) next[e] = -1;
        for (int f = 0; f < 6; f++) {
            const int *c = faces[f];
            int ins[4];
            for (int k = 0; k < 4; k++) ins[k] = cfg >> c[k] & 1;
            /* edge k joins corners c[k] and c[k+1] */
            int ek[4];
            for (int k = 0; k < 4; k++) ek[k] = edge_between(c[k], c[(k + 1) & 3]);
            /* Each run of consecutive inside corners (counter-clockwise seen
             * from outside) is cut off by one segment from the edge where the
             * run begins to the edge where it ends, which leaves the run on
             * the segment's right seen from outside. */
            for (int k = 0; k < 4; k++) {
                /* edge k goes from corner k to corner k+1 (ccw). If corner k is
                 * outside and k+1 inside, an inside run starts: find where it ends */
                if (!(!ins[k] && ins[(k + 1) & 3])) continue;
                int m = (k + 1) & 3;
                while (ins[(m + 1) & 3]) m = (m + 1) & 3;
                /* run is corners k+1..m, exits via edge m (m inside, m+1 outside) */
                int e_in = ek[k], e_out = ek[m];
                next[e_in] = e_out;
            }
        }
        int used[12] = {0};
        for (int s = 0; s < 12; s++) {
            if (next[s] < 0 || used[s]) continue;
            int cyc[12], n = 0, e = s;
            while (!used[e]) { used[e] = 1; cyc[n++] = e; e = next[e]; }
            /* Fan from a corner whose diagonals all cross the cube's inside:
             * a diagonal between two vertices on one face would lie in that
             * face, where the neighbouring cube may build the same triangle
             * facing the other way (a doubled, non-manifold sheet). */
            int start = 0;
            for (int k = 0; k < n; k++) {
                int good = 1;
                for (int d = 2; d + 1 < n && good; d++) good = !(face_mask(cyc[k]) & face_mask(cyc[(k + d) % n]));
                if (good) { start = k; break; }
                if (k == n - 1) table_ok = 0;
            }
            for (int k = 1; k + 1 < n; k++) {
                uint8_t *dst = &mc_table.edges[cfg][3 * mc_table.ntri[cfg]];
                dst[0] = (uint8_t)cyc[start];
                dst[1] = (uint8_t)cyc[(start + k) % n];
                dst[2] = (uint8_t)cyc[(start + k + 1) % n];
                mc_table.ntri[cfg]++;
            }
        }
    }
}

/* the distinct edges of each configuration, in order of first use */
static void index_edges(jm_case_table *t)
{
    for (int cfg = 0; cfg < 256; cfg++) {
        int slot[19];
        for (int e = 0; e < 19; e++) slot[e] = -1;
        for (int k = 0; k < 3 * t->ntri[cfg]; k++) {
            int e = t->edges[cfg][k];
            if (slot[e] < 0) {
                slot[e] = t->nedge[cfg]++;
                t->uedge[cfg][slot[e]] = (uint8_t)e;
            }
            t->local[cfg][k] = (uint8_t)slot[e];
        }
    }
}

static void build(void)
{
    memset(&mc_table, 0, sizeof mc_table);
    memset(&mt_table, 0, sizeof mt_table);
    build_mt();
    build_mc();
    index_edges(&mt_table);
    index_edges(&mc_table);
}

/* built once (the flag spares the blocks pthread_once's call) */
static atomic_int built;
static void ensure(void)
{
    if (atomic_load_explicit(&built, memory_order_acquire)) return;
    pthread_once(&once, build);
    atomic_store_explicit(&built, 1, memory_order_release);
}
const jm_case_table *jm_table_mc(void) { ensure(); return &mc_table; }
const jm_case_table *jm_table_mt(void) { ensure(); return &mt_table; }
