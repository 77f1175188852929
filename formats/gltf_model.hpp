// gltf_model.hpp - the tinygltf model pieces gltf_wrap.cpp builds, shared with the animated-sequence writer (C++ only, not installed).
#ifndef JETMESH_FORMATS_GLTF_MODEL_HPP
#define JETMESH_FORMATS_GLTF_MODEL_HPP

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

// The plain grey material every jetmesh primitive uses.
void jmf_gltf_add_material(tinygltf::Model &m);

// RFC 3986 percent-encoding of a buffer URI.
std::string jmf_gltf_uri_encode(const char *s);

#endif
