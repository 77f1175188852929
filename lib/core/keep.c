/* keep.c - a context's freed working memory, kept in size classes for its next frames: after the first, a frame as large allocates nothing. */
#include "core/keep.h"
#include "core/internal.h"
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>

/* classes: 16 to 64 bytes in steps of 16, then 4 an octave (2^k times
 * 1.25, 1.5, 1.75 and 2) up to JM_KEEP_MAX */
#define CLASSES (4 + 4 * 16)

/* a kept block's first bytes link it to the next of its class */
typedef struct node {
    struct node *next;
} node;

struct jm_keep {
    pthread_mutex_t mu; /* the workers free and allocate too */
    node *head[CLASSES];
    size_t bytes;       /* kept, in all */
};

static int class_of(size_t b, size_t *size)
{
    if (b <= 64) {
        const size_t q = b ? (b + 15) / 16 : 1;
        *size = 16 * q;
        return (int)q - 1;
    }
    const int k = 63 - __builtin_clzll((unsigned long long)(b - 1)); /* 2^k < b <= 2^(k+1) */
    const size_t step = (size_t)1 << (k - 2), j = (b - ((size_t)1 << k) + step - 1) / step; /* 1 .. 4 */
    *size = ((size_t)1 << k) + j * step;
    return 4 + 4 * (k - 6) + (int)j - 1;
}

size_t jm_keep_class_bytes(size_t bytes)
{
    size_t s;
    class_of(bytes, &s);
    return s;
}

jm_keep *jm_keep_create(void)
{
    jm_keep *k = calloc(1, sizeof *k);
    if (k && pthread_mutex_init(&k->mu, NULL) != 0) {
        free(k);
        return NULL;
    }
    return k;
}

void jm_keep_destroy(jm_keep *k)
{
    if (!k) return;
    for (int c = 0; c < CLASSES; c++)
        for (node *n = k->head[c], *next; n; n = next) {
            next = n->next;
            free(n);
        }
    pthread_mutex_destroy(&k->mu);
    free(k);
}

void *jm_keep_take(jm_keep *k, size_t bytes)
{
    size_t size;
    const int c = class_of(bytes, &size);
    pthread_mutex_lock(&k->mu);
    node *n = k->head[c];
    if (n) {
        k->head[c] = n->next;
        k->bytes -= size;
    }
    pthread_mutex_unlock(&k->mu);
    if (n) return n;
    jm_heap_note();
    return malloc(size);
}

void jm_keep_give(jm_keep *k, void *p, size_t bytes)
{
    size_t size;
    const int c = class_of(bytes, &size);
    pthread_mutex_lock(&k->mu);
    const int kept = k->bytes + size <= JM_KEEP_BUDGET;
    if (kept) {
        node *n = p;
        n->next = k->head[c];
        k->head[c] = n;
        k->bytes += size;
    }
    pthread_mutex_unlock(&k->mu);
    if (!kept) {
        jm_heap_note();
        free(p);
    }
}
