/* fuzz_auto.c - libFuzzer target: format detection (magic, gzip unwrapping, extension) through jmf_read_particles_mem. */
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* detection by magic (with an extension nothing matches), then by each extension */
    static const char *const names[] = { "frame.unknown", "frame.csv.gz", "frame.xyz" };
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; i++) fuzz_read(data, size, JMF_IN_AUTO, names[i]);
    return 0;
}
