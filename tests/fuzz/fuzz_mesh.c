/* fuzz_mesh.c - libFuzzer target: CSV particles meshed with bounded parameters (dense cells, extreme scales), the mesh's invariants checked. */
#include "fuzz_mesh_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_mesh(data, size);
    return 0;
}
