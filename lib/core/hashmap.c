/* hashmap.c - open-addressing hash map from 64-bit keys to 32-bit values (cells, blocks). */
#include "core/internal.h"
#include <string.h>

jm_status jm_hashmap_init(jm_hashmap *m, jm_mem *mem, size_t expected)
{
    size_t cap = 16;
    unsigned bits = 4;
    while (cap < expected * 2 + 1) {
        if (cap > SIZE_MAX / 4) return JM_E_TOO_LARGE;
        cap <<= 1;
        bits++;
    }
    m->keys = jm_alloc(mem, cap * sizeof *m->keys);
    m->vals = jm_alloc(mem, cap * sizeof *m->vals);
    if (!m->keys || !m->vals) {
        jm_free(mem, m->keys, cap * sizeof *m->keys);
        jm_free(mem, m->vals, cap * sizeof *m->vals);
        m->keys = NULL;
        m->vals = NULL;
        return JM_E_OUT_OF_MEMORY;
    }
    memset(m->keys, 0xff, cap * sizeof *m->keys);
    m->cap = cap;
    m->count = 0;
    m->shift = 64u - bits;
    return JM_OK;
}

void jm_hashmap_free(jm_hashmap *m, jm_mem *mem)
{
    jm_free(mem, m->keys, m->cap * sizeof *m->keys);
    jm_free(mem, m->vals, m->cap * sizeof *m->vals);
    memset(m, 0, sizeof *m);
}

uint32_t *jm_hashmap_upsert(jm_hashmap *m, uint64_t key)
{
    size_t mask = m->cap - 1;
    size_t i = (size_t)((key * 0x9E3779B97F4A7C15ull) >> m->shift);
    for (;;) {
        uint64_t k = m->keys[i];
        if (k == key) return &m->vals[i];
        if (k == JM_HASH_EMPTY) {
            m->keys[i] = key;
            m->vals[i] = UINT32_MAX;
            m->count++;
            return &m->vals[i];
        }
        i = (i + 1) & mask;
    }
}
