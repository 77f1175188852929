/* csv_read.c - reads the fields of CSV lines (RFC 4180: quoted fields with "" inside, CRLF or LF). */
#include "csv_read.h"

#include <stdlib.h>

/* One field at r->p (RFC 4180), malloc'd into *out; r->p left on the
 * separator (',', '\n' or the end). */
static int csv_field(text_cursor *r, char **out)
{
    size_t cap = 32, n = 0;
    char *b = malloc(cap);
    if (!b)
        return text_fail(r, "out of memory");
    const char *start = r->p;
    int quoted = r->p < r->end && *r->p == '"';
    if (quoted)
        r->p++;
    for (;;) {
        if (r->p >= r->end) {
            if (quoted) {
                free(b);
                r->p = start;
                return text_fail(r, "a quoted field does not end");
            }
            break;
        }
        char c = *r->p;
        if (quoted && c == '"') {
            if (r->p + 1 < r->end && r->p[1] == '"') {
                r->p += 2;
            } else {
                r->p++;
                quoted = 0;
                continue;
            }
        } else if (!quoted && (c == ',' || c == '\n')) {
            break;
        } else {
            r->p++;
        }
        if (!quoted && c == '\r' && r->p < r->end && *r->p == '\n')
            continue; /* CRLF */
        if (n + 2 > cap) {
            char *nb = realloc(b, cap *= 2);
            if (!nb) {
                free(b);
                return text_fail(r, "out of memory");
            }
            b = nb;
        }
        b[n++] = c;
    }
    b[n] = '\0';
    *out = b;
    return 0;
}

void csv_free_fields(char **f, size_t n)
{
    for (size_t i = 0; f && i < n; i++)
        free(f[i]);
    free(f);
}

int csv_read_line(text_cursor *r, char ***fields, size_t *n)
{
    size_t cap = 32;
    *n = 0;
    *fields = malloc(cap * sizeof **fields);
    if (!*fields)
        return text_fail(r, "out of memory");
    for (;;) {
        char *f = NULL;
        if (csv_field(r, &f) != 0) {
            csv_free_fields(*fields, *n);
            *fields = NULL;
            return -1;
        }
        if (*n == cap) {
            char **nf = realloc(*fields, (cap *= 2) * sizeof **fields);
            if (!nf) {
                free(f);
                csv_free_fields(*fields, *n);
                *fields = NULL;
                return text_fail(r, "out of memory");
            }
            *fields = nf;
        }
        (*fields)[(*n)++] = f;
        if (r->p >= r->end)
            return 0;
        if (*r->p++ == '\n')
            return 0;
    }
}
