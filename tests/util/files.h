/* files.h - test helper: a whole file read into memory. */
#ifndef JETMESH_TESTS_FILES_H
#define JETMESH_TESTS_FILES_H

#include <stddef.h>

/* Reads the file at path into a malloc'd buffer with a 0 byte after its
 * *size bytes (so text can be searched as a string); NULL if the file cannot
 * be opened or read (*size then unset). */
unsigned char *test_read_file(const char *path, size_t *size);

#endif
