/* temp_stem.c - prints the STEM of the atomic writer's temporaries for an output name (jmf_atomic_temp_stem), for the stale-temporary tests. */
#include <stdio.h>

#include "../../formats/atomic_file.h"

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: temp_stem NAME\n");
        return 2;
    }
    char stem[JMF_TEMP_STEM_MAX + 1];
    jmf_atomic_temp_stem(argv[1], stem);
    puts(stem);
    return 0;
}
