/* signals.c - SIGINT/SIGTERM/SIGHUP/SIGPIPE taken by one thread with sigwait: temporaries removed, then death by the signal. */
#include "signals.h"

#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../formats/atomic_file.h"

/*
 * Design. A handler that unlinks temporaries races with the threads that
 * create them: with several frames converted at once, a worker could create
 * a temporary after the handler's sweep and before the process died, and
 * that file was left behind. So no handler does the work here:
 *
 *  1. signals_install_cleanup() blocks SIGINT, SIGTERM, SIGHUP and SIGPIPE
 *     in the calling thread before any other thread exists; every thread
 *     started later (the frame workers, the library's pool) inherits the
 *     mask, so no thread is ever interrupted by them.
 *  2. One thread waits for them with sigwait(). When one arrives it calls
 *     jmf_atomic_shutdown(): under the lock that makes "create a temporary
 *     and register it" one step (formats/atomic_file.c), and "rename a
 *     finished output into place" another, it closes the writer for good
 *     and unlinks every registered temporary. A worker still meshing or
 *     writing cannot create or rename anything afterwards (its open or
 *     publish fails), so whatever the workers were doing, nothing is left.
 *  3. It then restores the default action, unblocks the signal in its own
 *     thread and raises it: the process dies by that signal (status 128+N
 *     in the shell), all threads with it.
 *  4. Between 2 and 3 the other threads run on: a frame whose write the
 *     shutdown refused fails ("stopping on a signal"), and without --keep-
 *     going the main thread then ends the run with status 1, before the
 *     waiter (descheduled on a loaded machine) has raised the signal. So
 *     exit() waits once a signal has been taken (an atexit handler): the
 *     process always dies by the signal, whatever the threads were doing.
 *
 * SIGPIPE is thread-directed: it goes to the thread whose write failed,
 * where a sigwait in another thread would never see it. So it is unblocked
 * again in the threads that write (every thread but the waiter) and its
 * handler forwards it to the waiter with pthread_kill (async-signal-safe).
 *
 * A signal that was ignored when jetmesh started (nohup, a background job
 * of a non-interactive shell) stays ignored.
 */

static const int g_sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};
static sigset_t g_set;
static pthread_t g_waiter;
static atomic_int g_taken; /* a signal was taken: the process dies by it */

/* atexit: after a signal, leave the exit to the waiter's raise (step 4) */
static void await_signal_death(void)
{
    if (atomic_load(&g_taken))
        for (;;)
            pause();
}

static void *waiter(void *arg)
{
    (void)arg;
    for (;;) {
        int sig = 0;
        if (sigwait(&g_set, &sig) != 0)
            continue;
        atomic_store(&g_taken, 1);
        jmf_atomic_shutdown();
        signal(sig, SIG_DFL);
        sigset_t one;
        sigemptyset(&one);
        sigaddset(&one, sig);
        pthread_sigmask(SIG_UNBLOCK, &one, NULL);
        raise(sig);
        _exit(128 + sig); /* not reached */
    }
    return NULL;
}

static void forward_pipe(int sig)
{
    pthread_kill(g_waiter, sig);
}

void signals_install_cleanup(void)
{
    static int done;
    if (done)
        return;
    done = 1;
    sigemptyset(&g_set);
    for (size_t i = 0; i < sizeof g_sigs / sizeof *g_sigs; i++) {
        struct sigaction old;
        if (sigaction(g_sigs[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN)
            continue; /* ignored by whoever started us: keep it so */
        sigaddset(&g_set, g_sigs[i]);
    }
    sigset_t before;
    pthread_sigmask(SIG_BLOCK, &g_set, &before);
    pthread_attr_t at;
    int ok = pthread_attr_init(&at) == 0;
    if (ok) {
        pthread_attr_setdetachstate(&at, PTHREAD_CREATE_DETACHED);
        pthread_attr_setstacksize(&at, 64 * 1024);
        ok = pthread_create(&g_waiter, &at, waiter, NULL) == 0;
        pthread_attr_destroy(&at);
    }
    if (!ok) { /* no waiter: the default actions, as if none were installed */
        pthread_sigmask(SIG_SETMASK, &before, NULL);
        return;
    }
    atexit(await_signal_death);
    if (sigismember(&g_set, SIGPIPE)) {
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = forward_pipe;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGPIPE, &sa, NULL);
        sigset_t pipe_only;
        sigemptyset(&pipe_only);
        sigaddset(&pipe_only, SIGPIPE);
        pthread_sigmask(SIG_UNBLOCK, &pipe_only, NULL); /* the waiter keeps it blocked */
    }
}
