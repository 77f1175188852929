/* signals.c - on SIGINT/SIGTERM/SIGHUP unlinks the atomic writers' temporaries and re-raises the signal. */
#include "signals.h"

#include <signal.h>
#include <string.h>
#include <unistd.h>

#include "../formats/atomic_file.h"

static void on_signal(int sig)
{
    jmf_atomic_remove_pending(); /* async-signal-safe */
    raise(sig);       /* SA_RESETHAND restored the default action; SA_NODEFER: not blocked */
    _exit(128 + sig); /* not reached */
}

void signals_install_cleanup(void)
{
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};
    for (size_t i = 0; i < sizeof sigs / sizeof *sigs; i++) {
        struct sigaction sa, old;
        if (sigaction(sigs[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN)
            continue; /* ignored by whoever started us (nohup, a background job): keep it so */
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sa.sa_flags = SA_RESETHAND | SA_NODEFER;
        sigemptyset(&sa.sa_mask);
        sigaction(sigs[i], &sa, NULL);
    }
}
