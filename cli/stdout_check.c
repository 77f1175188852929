/* stdout_check.c - a write error on standard output is reported once and fails the run. */
#include "stdout_check.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "convert.h"

static int g_told;

int stdout_check(void)
{
    errno = 0;
    if (fflush(stdout) == 0 && !ferror(stdout))
        return 0;
    if (!g_told) {
        int e = errno ? errno : EIO;
        g_told = 1;
        fprintf(stderr, "jetmesh: cannot write standard output: %s\n", strerror(e));
        fflush(stderr);
    }
    return -1;
}

int stdout_finish(int rc)
{
    if (stdout_check() != 0 && rc == EXIT_ALL_OK)
        return EXIT_SOME_FAILED;
    return rc;
}
