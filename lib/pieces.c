/* pieces.c - the connected pieces of a triangle mesh, by union-find: each vertex's root is the smallest vertex of its piece. */
#include "pieces.h"

static uint32_t find(uint32_t *p, uint32_t x)
{
    /* a root or a root's child: what the loop would find, without its
     * stores (which would write what is there) */
    const uint32_t r = p[x];
    if (p[r] == r) return r;
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

void jm_mesh_pieces(uint32_t *parent, const uint32_t *idx, size_t n, size_t nt)
{
    for (size_t v = 0; v < n; v++) parent[v] = (uint32_t)v;
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *i = idx + 3 * t;
        uint32_t a = find(parent, i[0]), b = find(parent, i[1]), c = find(parent, i[2]);
        if (a == b && b == c) continue; /* one piece already */
        /* the smaller index as root */
        uint32_t m = a < b ? (a < c ? a : c) : (b < c ? b : c);
        parent[a] = parent[b] = parent[c] = m;
    }
    /* every vertex straight to its root: parent[v] <= v throughout, so in
     * index order a vertex's parent is already flattened when it is
     * reached */
    for (size_t v = 0; v < n; v++) parent[v] = parent[parent[v]];
}
