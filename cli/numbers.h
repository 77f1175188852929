/* numbers.h - strict parsing of numbers in command-line arguments. */
#ifndef JETMESH_CLI_NUMBERS_H
#define JETMESH_CLI_NUMBERS_H

/* A whole, finite decimal number (strtod syntax, nothing after it); 0 or -1. */
int cli_parse_double(const char *s, double *out);
/* A whole decimal integer within [lo, hi]; 0 or -1. */
int cli_parse_long(const char *s, long lo, long hi, long *out);

/* An option whose number may be left out (getopt_long's optional_argument):
 * arg (--opt=N) when given, else the next word argv[*next] when it is a
 * number (taken: *next advanced past it), else dflt. *out_word: the word
 * read (NULL for dflt). 0, or -1 when that word is not a whole number in
 * [lo, hi]. */
int cli_optional_long(const char *arg, int argc, char **argv, int *next, long lo, long hi, long dflt, long *out,
                      const char **out_word);

#endif
