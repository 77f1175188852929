/* files.c - test helper: reads a whole file into memory (0-terminated, for text). */
#include "files.h"

#include <stdio.h>
#include <stdlib.h>

unsigned char *test_read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    long n = -1;
    if (fseek(f, 0, SEEK_END) == 0)
        n = ftell(f);
    unsigned char *d = NULL;
    if (n >= 0 && fseek(f, 0, SEEK_SET) == 0)
        d = malloc((size_t)n + 1);
    if (d && fread(d, 1, (size_t)n, f) != (size_t)n) {
        free(d);
        d = NULL;
    }
    fclose(f);
    if (!d)
        return NULL;
    d[n] = 0;
    *size = (size_t)n;
    return d;
}
