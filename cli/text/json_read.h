/* json_read.h - reads JSON as it goes: objects member by member, arrays element by element, strings decoded, scalars as text. */
#ifndef JETMESH_CLI_TEXT_JSON_READ_H
#define JETMESH_CLI_TEXT_JSON_READ_H

#include "cursor.h"

/* Every function returns 0, or -1 with the message in r->err (text_fail). */

/* Skips blanks (space, tab, CR, LF). */
void json_ws(text_cursor *r);

/* The next character, after blanks, must be c; it is passed. */
int json_expect(text_cursor *r, char c);

/* A string, decoded into a malloc'd UTF-8 string (lone surrogates become
 * U+FFFD). */
int json_string(text_cursor *r, char **out);

/* A scalar's text: a decoded string, a number's or literal's characters
 * (malloc'd), or NULL for null. At '{' or '[', *is_container is set and
 * nothing is read. */
int json_scalar(text_cursor *r, char **out, int *is_container);

/* Skips the value at r->p (at most 64 levels deep). */
int json_skip(text_cursor *r);

/* Skips the object or array at r->p (json_scalar found it). */
int json_skip_container(text_cursor *r);

/* Calls each(r, key, user) for every member of the object at r->p; each
 * reads the member's value. */
int json_members(text_cursor *r, int (*each)(text_cursor *, const char *, void *), void *user);

/* Calls each(r, user) for every element of the array at r->p; each reads
 * the element. */
int json_elements(text_cursor *r, int (*each)(text_cursor *, void *), void *user);

#endif
