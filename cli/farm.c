/* farm.c - runs frame jobs on worker threads ahead of their turn, for a caller that takes the results in order. */
#include "farm.h"

#include <pthread.h>
#include <stdlib.h>

enum { JOB_WAITING = 0, JOB_RUNNING, JOB_DONE };

typedef struct worker_arg {
    struct farm *f;
    int w;
} worker_arg;

struct farm {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    size_t n, next, limit, window; /* next job to start; jobs below limit may start */
    int stop;
    unsigned char *state;
    farm_fn fn;
    void *user;
    pthread_t *threads;
    worker_arg *args;
    int started;
};

static void *worker(void *arg)
{
    worker_arg *a = arg;
    farm *f = a->f;
    pthread_mutex_lock(&f->mu);
    for (;;) {
        while (!f->stop && f->next < f->n && f->next >= f->limit) pthread_cond_wait(&f->cv, &f->mu);
        if (f->stop || f->next >= f->n) break;
        size_t i = f->next++;
        f->state[i] = JOB_RUNNING;
        pthread_mutex_unlock(&f->mu);
        int halt = f->fn(f->user, a->w, i);
        pthread_mutex_lock(&f->mu);
        f->state[i] = JOB_DONE;
        if (halt) f->stop = 1;
        pthread_cond_broadcast(&f->cv);
    }
    pthread_mutex_unlock(&f->mu);
    return NULL;
}

static void farm_free(farm *f)
{
    pthread_cond_destroy(&f->cv);
    pthread_mutex_destroy(&f->mu);
    free(f->state);
    free(f->threads);
    free(f->args);
    free(f);
}

farm *farm_start(size_t n, int workers, size_t window, farm_fn fn, void *user)
{
    if (workers < 1 || n == 0) return NULL;
    farm *f = calloc(1, sizeof *f);
    if (!f) return NULL;
    if (pthread_mutex_init(&f->mu, NULL) != 0) {
        free(f);
        return NULL;
    }
    if (pthread_cond_init(&f->cv, NULL) != 0) {
        pthread_mutex_destroy(&f->mu);
        free(f);
        return NULL;
    }
    f->state = calloc(n, 1);
    f->threads = calloc((size_t)workers, sizeof *f->threads);
    f->args = calloc((size_t)workers, sizeof *f->args);
    if (!f->state || !f->threads || !f->args) {
        farm_free(f);
        return NULL;
    }
    f->n = n;
    f->window = window ? window : 1;
    f->limit = f->window;
    f->fn = fn;
    f->user = user;
    for (int w = 0; w < workers; w++) {
        f->args[f->started].f = f;
        f->args[f->started].w = f->started;
        if (pthread_create(&f->threads[f->started], NULL, worker, &f->args[f->started]) == 0) f->started++;
    }
    if (f->started == 0) {
        farm_free(f);
        return NULL;
    }
    return f;
}

int farm_wait(farm *f, size_t i)
{
    pthread_mutex_lock(&f->mu);
    while (f->state[i] != JOB_DONE && !(f->stop && f->state[i] == JOB_WAITING))
        pthread_cond_wait(&f->cv, &f->mu);
    int done = f->state[i] == JOB_DONE;
    pthread_mutex_unlock(&f->mu);
    return done;
}

void farm_taken(farm *f, size_t i)
{
    pthread_mutex_lock(&f->mu);
    if (i + 1 + f->window > f->limit) {
        f->limit = i + 1 + f->window;
        pthread_cond_broadcast(&f->cv);
    }
    pthread_mutex_unlock(&f->mu);
}

void farm_stop(farm *f)
{
    if (!f) return;
    pthread_mutex_lock(&f->mu);
    f->stop = 1;
    pthread_cond_broadcast(&f->cv);
    pthread_mutex_unlock(&f->mu);
    for (int w = 0; w < f->started; w++) pthread_join(f->threads[w], NULL);
    farm_free(f);
}
