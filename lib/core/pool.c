/* pool.c - a small pthread pool: parallel loops with dynamic chunking, the caller taking part. */
#include "core/internal.h"
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>

/* A frame runs a few dozen loops, some of tens of microseconds (issue 34:
 * the paper's jet meshes in a few milliseconds). Waking a sleeping thread
 * costs about as much as such a loop, so between loops the helpers, and the
 * caller waiting for them, first spin this long before they sleep. */
#define POOL_SPIN_MS 0.2

struct jm_pool {
    int n;                 /* workers including the caller */
    pthread_t *threads;
    pthread_mutex_t mu;
    pthread_cond_t wake, done;
    _Atomic unsigned long generation; /* written under mu; read by spinning helpers */
    _Atomic int quit;
    _Atomic int busy;      /* helpers still inside the current job */
    /* the current job */
    jm_task_fn fn;
    void *arg;
    size_t items, chunk;
    _Atomic size_t next;
};

static void work(jm_pool *p, int worker)
{
    for (;;) {
        size_t start = atomic_fetch_add(&p->next, p->chunk);
        if (start >= p->items) break;
        size_t end = start + p->chunk < p->items ? start + p->chunk : p->items;
        for (size_t i = start; i < end; i++) p->fn(p->arg, i, worker);
    }
}

typedef struct { jm_pool *pool; int worker; } helper_arg;

/* A spin's step: the CPU given to any other thread that can run (on a
 * busy machine the thread we wait for may need this core). */
static inline void relax(void) { sched_yield(); }

/* A helper's next job (or quit) has come: the generation moved past seen. */
static int job_came(const jm_pool *p, unsigned long seen)
{
    return atomic_load_explicit(&p->generation, memory_order_acquire) != seen ||
           atomic_load_explicit(&p->quit, memory_order_relaxed);
}
/* The caller's job is done: every helper out of it (seen unused). */
static int helpers_out(const jm_pool *p, unsigned long seen)
{
    (void)seen;
    return atomic_load_explicit(&p->busy, memory_order_acquire) == 0;
}

/* Spins up to POOL_SPIN_MS until ready(p, seen); whether it became so
 * (if not, the caller sleeps on the condition variable instead). */
static int spin_until(const jm_pool *p, int (*ready)(const jm_pool *, unsigned long), unsigned long seen)
{
    const double t0 = jm_now_ms();
    for (unsigned k = 1;; k++) {
        if (ready(p, seen)) return 1;
        relax();
        if ((k & 15) == 0 && jm_now_ms() - t0 > POOL_SPIN_MS) return 0;
    }
}

static void *helper_main(void *varg)
{
    helper_arg *ha = varg;
    jm_pool *p = ha->pool;
    int worker = ha->worker;
    free(ha);
    unsigned long seen = 0;
    for (;;) {
        if (!spin_until(p, job_came, seen)) {
            pthread_mutex_lock(&p->mu);
            while (!p->quit && p->generation == seen) pthread_cond_wait(&p->wake, &p->mu);
            pthread_mutex_unlock(&p->mu);
        }
        if (p->quit) break;
        seen = p->generation;
        work(p, worker);
        /* the last helper out tells a caller that may sleep (under mu: the
         * caller checks busy under mu before it waits) */
        if (atomic_fetch_sub(&p->busy, 1) == 1) {
            pthread_mutex_lock(&p->mu);
            pthread_cond_signal(&p->done);
            pthread_mutex_unlock(&p->mu);
        }
    }
    return NULL;
}

jm_status jm_pool_create(int nthreads, jm_pool **out)
{
    *out = NULL;
    if (nthreads < 1) nthreads = 1;
    jm_pool *p = calloc(1, sizeof *p);
    if (!p) return JM_E_OUT_OF_MEMORY;
    p->n = nthreads;
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->wake, NULL);
    pthread_cond_init(&p->done, NULL);
    atomic_init(&p->next, 0);
    atomic_init(&p->generation, 0);
    atomic_init(&p->quit, 0);
    atomic_init(&p->busy, 0);
    if (nthreads > 1) {
        p->threads = calloc((size_t)nthreads - 1, sizeof *p->threads);
        if (!p->threads) { jm_pool_free(p); return JM_E_OUT_OF_MEMORY; }
        for (int i = 1; i < nthreads; i++) {
            helper_arg *ha = malloc(sizeof *ha);
            if (ha) { ha->pool = p; ha->worker = i; }
            if (!ha || pthread_create(&p->threads[i - 1], NULL, helper_main, ha) != 0) {
                free(ha);
                p->n = i; /* threads [1, i) exist */
                jm_pool_free(p);
                return JM_E_THREAD;
            }
        }
    }
    *out = p;
    return JM_OK;
}

void jm_pool_free(jm_pool *p)
{
    if (!p) return;
    pthread_mutex_lock(&p->mu);
    p->quit = 1;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->mu);
    for (int i = 1; i < p->n; i++) pthread_join(p->threads[i - 1], NULL);
    free(p->threads);
    pthread_mutex_destroy(&p->mu);
    pthread_cond_destroy(&p->wake);
    pthread_cond_destroy(&p->done);
    free(p);
}

int jm_pool_threads(const jm_pool *p) { return p ? p->n : 1; }

void jm_pool_run(jm_pool *p, size_t n, size_t chunk, jm_task_fn fn, void *arg)
{
    if (n == 0) return;
    if (chunk == 0) chunk = 1;
    if (!p || p->n == 1 || n <= chunk) {
        for (size_t i = 0; i < n; i++) fn(arg, i, 0);
        return;
    }
    pthread_mutex_lock(&p->mu);
    p->fn = fn;
    p->arg = arg;
    p->items = n;
    p->chunk = chunk;
    atomic_store(&p->next, 0);
    p->busy = p->n - 1;
    atomic_fetch_add_explicit(&p->generation, 1, memory_order_release);
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->mu);
    work(p, 0);
    /* the helpers out of this job: spun for a while, then asleep */
    if (!spin_until(p, helpers_out, 0)) {
        pthread_mutex_lock(&p->mu);
        while (p->busy > 0) pthread_cond_wait(&p->done, &p->mu);
        pthread_mutex_unlock(&p->mu);
    }
}

double jm_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}
