/* csv_read.h - reads the fields of CSV lines (RFC 4180: quoted fields with "" inside, CRLF or LF). */
#ifndef JETMESH_CLI_TEXT_CSV_READ_H
#define JETMESH_CLI_TEXT_CSV_READ_H

#include <stddef.h>

#include "cursor.h"

/* The fields of the line at r->p, each malloc'd, into *fields (*n of
 * them); r->p left after the line's newline. 0, or -1 (text_fail). */
int csv_read_line(text_cursor *r, char ***fields, size_t *n);

/* Frees what csv_read_line returned (NULL accepted). */
void csv_free_fields(char **fields, size_t n);

#endif
