/* test_pool.c - the thread pool runs every item of every loop exactly once, whether its helpers are spinning or asleep between loops. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../lib/core/internal.h"

#define MAXN 5000

typedef struct {
    _Atomic int hits[MAXN];
    _Atomic int bad_worker;
    int threads;
} job;

static void task(void *arg, size_t i, int worker)
{
    job *j = arg;
    atomic_fetch_add(&j->hits[i], 1);
    if (worker < 0 || worker >= j->threads) atomic_store(&j->bad_worker, 1);
}

/* one loop of n items in chunks of chunk: every item once, workers in range */
static void run_and_check(jm_pool *p, job *j, size_t n, size_t chunk)
{
    for (size_t i = 0; i < n; i++) atomic_store(&j->hits[i], 0);
    jm_pool_run(p, n, chunk, task, j);
    for (size_t i = 0; i < n; i++)
        if (atomic_load(&j->hits[i]) != 1) fail_msg("%d threads, %zu items of %zu: item %zu ran %d times", j->threads, n, chunk, i, atomic_load(&j->hits[i]));
    assert_int_equal(atomic_load(&j->bad_worker), 0);
}

static void pause_ms(long ms)
{
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    while (nanosleep(&ts, &ts) != 0) {
    }
}

/* Loops back to back (the helpers still spinning from the last one) and
 * loops after a pause longer than the spin (the helpers asleep, woken by
 * the condition variable), for 1 to 4 threads and sizes around the chunk. */
static void test_every_item_once(void **state)
{
    (void)state;
    static job j;
    for (int t = 1; t <= 4; t++) {
        jm_pool *p = NULL;
        assert_int_equal(jm_pool_create(t, &p), JM_OK);
        assert_int_equal(jm_pool_threads(p), t);
        j.threads = t;
        for (int k = 0; k < 1000; k++) run_and_check(p, &j, (size_t)(k % 37), 1 + (size_t)(k % 3));
        for (int k = 0; k < 20; k++) {
            pause_ms(2);
            run_and_check(p, &j, MAXN, 64);
            run_and_check(p, &j, 3, 1);
        }
        jm_pool_free(p);
    }
}

/* Freed right after a loop (helpers spinning) and after a pause (helpers
 * asleep): both return. */
static void test_free_spinning_or_asleep(void **state)
{
    (void)state;
    static job j;
    j.threads = 2;
    for (int k = 0; k < 200; k++) {
        jm_pool *p = NULL;
        assert_int_equal(jm_pool_create(2, &p), JM_OK);
        run_and_check(p, &j, 16, 1);
        if (k % 2) pause_ms(1);
        jm_pool_free(p);
    }
    jm_pool_free(NULL);
}

int main(void)
{
    alarm(300); /* a lost wake-up hangs: fail instead (a loaded machine takes seconds) */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_item_once),
        cmocka_unit_test(test_free_spinning_or_asleep),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
