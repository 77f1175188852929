/* particle_groups.c - particles grouped by connectivity: two closer than a distance are of one group (union-find over cells of that edge, on the pool's threads). */
#include "grid/particle_groups.h"
#include "grid/cellbins.h"
#include "post/pieces.h"

#define GROUP_CELLS 64 /* cells a task */

typedef struct {
    const jm_cellbins *b;
    const float *pos;
    float d2;
    uint32_t *parent;
} group_job;

/* The pairs of the particles of cell c with those of c itself (later in
 * the cell) and of the 13 neighbours after it (so each pair once). */
static void cell_pairs(const group_job *j, size_t c)
{
    static const int nb[13][3] = {{1, 0, 0},  {-1, 1, 0}, {0, 1, 0},  {1, 1, 0},  {-1, -1, 1}, {0, -1, 1}, {1, -1, 1},
                                  {-1, 0, 1}, {0, 0, 1},  {1, 0, 1},  {-1, 1, 1}, {0, 1, 1},   {1, 1, 1}};
    const jm_cellbins *b = j->b;
    const uint32_t a0 = b->start[c], a1 = b->start[c + 1];
    const int32_t *cc = b->coord + 3 * c;
    for (int k = -1; k < 13; k++) {
        uint32_t o = (uint32_t)c;
        if (k >= 0) {
            o = jm_cellbins_find(b, cc[0] + nb[k][0], cc[1] + nb[k][1], cc[2] + nb[k][2]);
            if (o == UINT32_MAX) continue;
        }
        for (uint32_t s = a0; s < a1; s++) {
            const uint32_t p = b->items[s];
            const float *x = j->pos + 3 * (size_t)p;
            for (uint32_t t = k < 0 ? s + 1 : b->start[o]; t < b->start[o + 1]; t++) {
                const uint32_t q = b->items[t];
                const float *y = j->pos + 3 * (size_t)q;
                const float dx = x[0] - y[0], dy = x[1] - y[1], dz = x[2] - y[2];
                if (dx * dx + dy * dy + dz * dz < j->d2) jm_pieces_unite(j->parent, p, q);
            }
        }
    }
}

static void group_task(void *arg, size_t chunk, int worker)
{
    (void)worker;
    const group_job *j = arg;
    const size_t a = chunk * GROUP_CELLS, e = a + GROUP_CELLS < j->b->ncells ? a + GROUP_CELLS : j->b->ncells;
    for (size_t c = a; c < e; c++) cell_pairs(j, c);
}

jm_status jm_particle_groups(jm_mem *mem, jm_pool *pool, const float *pos, size_t n, float d, uint32_t *parent)
{
    jm_cellbins b;
    jm_status s = jm_cellbins_build(&b, mem, pos, n, d);
    if (s == JM_OK) {
        for (size_t i = 0; i < n; i++) parent[i] = (uint32_t)i;
        group_job j = {&b, pos, d * d, parent};
        jm_pool_run(pool, (b.ncells + GROUP_CELLS - 1) / GROUP_CELLS, 1, group_task, &j);
        for (size_t i = 0; i < n; i++) parent[i] = jm_pieces_find(parent, (uint32_t)i);
    }
    jm_cellbins_free(&b, mem);
    return s;
}
