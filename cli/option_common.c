/* option_common.c - what every command's option parser shares: the usage error and the size parser. */
#include "option_common.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>

int options_usage_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "jetmesh %s: ", cmd);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\nTry 'jetmesh %s --help' for more information.\n", cmd);
    return OPTIONS_USAGE;
}

int options_parse_size(const char *s, size_t *out)
{
    if (!s || !*s)
        return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || !isfinite(v) || v < 0 || end == s)
        return -1;
    double mul = 1;
    switch (*end) {
    case 'k': case 'K': mul = 1024.0; end++; break;
    case 'm': case 'M': mul = 1024.0 * 1024; end++; break;
    case 'g': case 'G': mul = 1024.0 * 1024 * 1024; end++; break;
    case 't': case 'T': mul = 1024.0 * 1024 * 1024 * 1024; end++; break;
    default: break;
    }
    if (mul > 1 && *end == 'i')
        end++;
    if (*end == 'B' || *end == 'b')
        end++;
    if (*end)
        return -1;
    double bytes = v * mul;
    if (bytes >= 18446744073709551615.0 || bytes > (double)(size_t)-1)
        return -1;
    *out = (size_t)bytes;
    return 0;
}
