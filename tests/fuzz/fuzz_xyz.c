/* fuzz_xyz.c - libFuzzer target: the XYZ reader (format forced) through jmf_read_particles_mem. */
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_read(data, size, JMF_IN_XYZ, "particles.xyz");
    return 0;
}
