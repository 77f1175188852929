/* cursor.h - a read position in a file's text, and its errors worded "path:line: what" (the CLI's JSON and CSV readers). */
#ifndef JETMESH_CLI_TEXT_CURSOR_H
#define JETMESH_CLI_TEXT_CURSOR_H

#include <stddef.h>

typedef struct text_cursor {
    const char *path;        /* for messages */
    const char *s, *end, *p; /* the text, its end, the position */
    char *err;               /* where a failure's message goes */
    size_t errlen;
} text_cursor;

/* Writes "path:line: what" (the line of r->p) into r->err; returns -1. */
int text_fail(text_cursor *r, const char *what);

/* The whole file at path, NUL-terminated (malloc'd; *len its length), at
 * most max bytes; NULL with "path: why" in err. */
char *text_slurp(const char *path, size_t max, size_t *len, char *err, size_t errlen);

#endif
