/* numbers.h - strict parsing of numbers in command-line arguments. */
#ifndef JETMESH_CLI_NUMBERS_H
#define JETMESH_CLI_NUMBERS_H

/* A whole, finite decimal number (strtod syntax, nothing after it); 0 or -1. */
int cli_parse_double(const char *s, double *out);
/* A whole decimal integer within [lo, hi]; 0 or -1. */
int cli_parse_long(const char *s, long lo, long hi, long *out);

#endif
