/* pieces.c - the connected pieces of a triangle mesh, by union-find: each vertex's root is the smallest vertex of its piece. */
#include "post/pieces.h"

/* Triangles or vertices a task; below two chunks of triangles, or on one
 * thread, the plain union-find. */
#define PIECE_CHUNK ((size_t)1 << 13)

/* x's and y's sets joined by Rem's algorithm with splicing (Patwary,
 * Blair and Manne 2010): both climb together, the one with the larger
 * parent hooked onto the other's parent on the way, until they share a
 * parent or one is a root. Every parent stays smaller than its child, so a
 * set's root is its smallest element. Two neighbouring corners mostly share
 * a parent already: one load each, where finding both roots takes two. */
static inline void rem_unite(uint32_t *p, uint32_t x, uint32_t y)
{
    while (p[x] != p[y]) {
        if (p[x] < p[y]) {
            const uint32_t t = x;
            x = y;
            y = t;
        }
        /* p[x] > p[y] */
        const uint32_t z = p[x];
        p[x] = p[y];
        if (z == x) return; /* x was a root: hooked */
        x = z;
    }
}

static void pieces_serial(uint32_t *parent, const uint32_t *idx, size_t n, size_t nt)
{
    for (size_t v = 0; v < n; v++) parent[v] = (uint32_t)v;
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *i = idx + 3 * t;
        rem_unite(parent, i[0], i[1]);
        rem_unite(parent, i[0], i[2]);
    }
    /* every vertex straight to its root: parent[v] <= v throughout, so in
     * index order a vertex's parent is already flattened when it is
     * reached */
    for (size_t v = 0; v < n; v++) parent[v] = parent[parent[v]];
}

/*
 * The threads' union-find. A root is linked below a smaller root only, by
 * a compare-and-swap that fails (and the union starts again) if the root
 * was linked meanwhile; finds halve their paths by compare-and-swap. Every
 * parent is an ancestor, smaller than its vertex, and stays an ancestor as
 * trees merge, so a stale read only walks further; each piece ends as one
 * tree whose root is its smallest vertex, whatever the order of the
 * unions: the serial pass's result.
 */
static inline uint32_t ld(const uint32_t *p) { return __atomic_load_n(p, __ATOMIC_RELAXED); }

static uint32_t find_shared(uint32_t *p, uint32_t x)
{
    for (;;) {
        uint32_t q = ld(&p[x]);
        if (q == x) return x;
        const uint32_t r = ld(&p[q]);
        if (r == q) return q;
        __atomic_compare_exchange_n(&p[x], &q, r, 0, __ATOMIC_RELAXED, __ATOMIC_RELAXED); /* may fail: no matter */
        x = r;
    }
}

static void unite(uint32_t *p, uint32_t a, uint32_t b)
{
    for (;;) {
        a = find_shared(p, a);
        b = find_shared(p, b);
        if (a == b) return;
        if (a < b) {
            const uint32_t t = a;
            a = b;
            b = t;
        }
        uint32_t expect = a; /* a still a root: below b */
        if (__atomic_compare_exchange_n(&p[a], &expect, b, 0, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) return;
    }
}

typedef struct {
    uint32_t *parent;
    const uint32_t *idx;
    size_t n, nt;
} pieces_job;

static void init_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    pieces_job *j = arg;
    const size_t a = chunk * PIECE_CHUNK, b = a + PIECE_CHUNK < j->n ? a + PIECE_CHUNK : j->n;
    for (size_t v = a; v < b; v++) j->parent[v] = (uint32_t)v;
}

static void unite_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    pieces_job *j = arg;
    const size_t a = chunk * PIECE_CHUNK, b = a + PIECE_CHUNK < j->nt ? a + PIECE_CHUNK : j->nt;
    for (size_t t = a; t < b; t++) {
        const uint32_t *i = j->idx + 3 * t;
        unite(j->parent, i[0], i[1]);
        unite(j->parent, i[0], i[2]);
    }
}

static void flatten_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    pieces_job *j = arg;
    const size_t a = chunk * PIECE_CHUNK, b = a + PIECE_CHUNK < j->n ? a + PIECE_CHUNK : j->n;
    for (size_t v = a; v < b; v++) __atomic_store_n(&j->parent[v], find_shared(j->parent, (uint32_t)v), __ATOMIC_RELAXED);
}

void jm_mesh_pieces(jm_pool *pool, uint32_t *parent, const uint32_t *idx, size_t n, size_t nt)
{
    if (jm_pool_threads(pool) < 2 || nt < 2 * PIECE_CHUNK) {
        pieces_serial(parent, idx, n, nt);
        return;
    }
    pieces_job j = {parent, idx, n, nt};
    const size_t cv = (n + PIECE_CHUNK - 1) / PIECE_CHUNK, ct = (nt + PIECE_CHUNK - 1) / PIECE_CHUNK;
    jm_pool_run(pool, cv, 1, init_task, &j);
    jm_pool_run(pool, ct, 1, unite_task, &j);
    jm_pool_run(pool, cv, 1, flatten_task, &j);
}

void jm_pieces_unite(uint32_t *parent, uint32_t a, uint32_t b)
{
    unite(parent, a, b);
}

uint32_t jm_pieces_find(uint32_t *parent, uint32_t x)
{
    return find_shared(parent, x);
}
