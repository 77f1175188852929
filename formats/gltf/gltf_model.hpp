// gltf_model.hpp - the tinygltf model pieces gltf_wrap.cpp builds, shared with the animated-sequence writer (C++ only, not installed).
#ifndef JETMESH_FORMATS_GLTF_MODEL_HPP
#define JETMESH_FORMATS_GLTF_MODEL_HPP

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "gltf_wrap.h"

// Adds one triangle primitive of mesh (at least one triangle) to m: its
// bufferViews and accessors after those already in m, its bytes appended to
// buf (views' offsets are into buf), KHR_draco_mesh_compression when
// p->draco, and p's per-vertex attributes as "_NAME". prim.material is 0.
jmf_status jmf_gltf_fill_primitive(const jm_mesh *mesh, const jmf_gltf_params *p, tinygltf::Model &m,
                                   std::vector<unsigned char> &buf, tinygltf::Primitive &prim, char *err,
                                   size_t errlen);
// The same with the bytes as pieces of buf (gltf_bin.hpp), the mesh's arrays
// borrowed, not copied: what the one-mesh writer writes straight from them.
struct jmf_gltf_bin;
jmf_status jmf_gltf_fill_primitive(const jm_mesh *mesh, const jmf_gltf_params *p, tinygltf::Model &m,
                                   jmf_gltf_bin &buf, tinygltf::Primitive &prim, char *err, size_t errlen);

// The plain grey material every jetmesh primitive uses.
void jmf_gltf_add_material(tinygltf::Model &m);

// RFC 3986 percent-encoding of a buffer URI.
std::string jmf_gltf_uri_encode(const char *s);

// The GLB container's framing (glTF 2.0, section "Binary glTF Layout"):
// bin_padded(n) is n rounded up to 4; glb_total is the whole file's length
// for a JSON chunk of json_padded bytes and a BIN chunk of bin_size bytes
// (none when 0); glb_header fills the 12-byte header and the JSON chunk's
// 8-byte header (20 bytes); glb_bin_header the BIN chunk's 8 bytes.
inline size_t jmf_glb_pad4(size_t n) { return (n + 3) / 4 * 4; }
inline uint64_t jmf_glb_total(size_t json_padded, size_t bin_size)
{
    return 12 + 8 + (uint64_t)json_padded + (bin_size ? 8 + (uint64_t)jmf_glb_pad4(bin_size) : 0);
}
inline void jmf_glb_put32(unsigned char *q, uint64_t v)
{
    for (int k = 0; k < 4; k++) q[k] = static_cast<unsigned char>(v >> (8 * k));
}
inline void jmf_glb_header(unsigned char head[20], uint64_t total, size_t json_padded)
{
    std::memcpy(head, "glTF", 4);
    jmf_glb_put32(head + 4, 2);
    jmf_glb_put32(head + 8, total);
    jmf_glb_put32(head + 12, json_padded);
    std::memcpy(head + 16, "JSON", 4);
}
inline void jmf_glb_bin_header(unsigned char head[8], size_t bin_size)
{
    jmf_glb_put32(head, jmf_glb_pad4(bin_size));
    std::memcpy(head + 4, "BIN\0", 4);
}

#endif
