/* numbers.c - strict parsing of numbers in command-line arguments. */
#include "numbers.h"
#include <errno.h>
#include <math.h>
#include <stdlib.h>

int cli_parse_double(const char *s, double *out)
{
    if (!s || !*s) return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || errno || !isfinite(v)) return -1;
    *out = v;
    return 0;
}

int cli_parse_long(const char *s, long lo, long hi, long *out)
{
    if (!s || !*s) return -1;
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || *end || errno || v < lo || v > hi) return -1;
    *out = v;
    return 0;
}

int cli_optional_long(const char *arg, int argc, char **argv, int *next, long lo, long hi, long dflt, long *out,
                      const char **out_word)
{
    *out_word = arg;
    if (arg) return cli_parse_long(arg, lo, hi, out);
    /* "--opt N": getopt leaves N for the next word; take it when it is a
     * number, so that "--smooth -1" is refused with its range rather than
     * read as an unknown option */
    if (*next < argc) {
        const char *w = argv[*next];
        char *end = NULL;
        (void)strtod(w, &end);
        if (end != w && *end == '\0') {
            ++*next;
            *out_word = w;
            return cli_parse_long(w, lo, hi, out);
        }
    }
    *out = dflt;
    return 0;
}
