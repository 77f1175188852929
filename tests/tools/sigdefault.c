/* sigdefault.c - runs a command with SIGINT/SIGQUIT/SIGTERM/SIGHUP/SIGPIPE at their default action, for the kill tests. */
#include <signal.h>
#include <stdio.h>
#include <unistd.h>

/* A non-interactive shell starts its background jobs with SIGINT and
 * SIGQUIT ignored, and jetmesh keeps an ignored signal ignored: to test
 * SIGINT on a background conversion, this resets them before the exec. */
int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: sigdefault COMMAND [ARG...]\n");
        return 2;
    }
    static const int sigs[] = {SIGINT, SIGQUIT, SIGTERM, SIGHUP, SIGPIPE};
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, NULL);
    for (size_t i = 0; i < sizeof sigs / sizeof *sigs; i++)
        signal(sigs[i], SIG_DFL);
    execvp(argv[1], argv + 1);
    perror(argv[1]);
    return 127;
}
