/* option_common.h - what every command's option parser shares: the usage error and the size parser. */
#ifndef JETMESH_OPTION_COMMON_H
#define JETMESH_OPTION_COMMON_H

#include <stddef.h>
#include <stdio.h>

#define OPTIONS_USAGE 2 /* a usage error was printed: exit 2 */

/** Parses a size: a number of bytes with an optional K, M, G or T suffix
 *  (powers of 1024; "B"/"iB" may follow): "2G", "500M", "1.5GiB".
 *  0 on success, -1 if malformed. */
int options_parse_size(const char *s, size_t *out);

/** Prints "jetmesh CMD: message" and the --help hint on stderr; returns OPTIONS_USAGE. */
#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
int options_usage_error(const char *cmd, const char *fmt, ...);

#endif
