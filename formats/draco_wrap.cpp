// draco_wrap.cpp - encodes a jm_mesh with libdraco (Edgebreaker, quantized attributes) into a malloc'd buffer.
#include "draco_wrap.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <vector>

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>
#include <memory>

namespace {

int pick(int v, int def) { return v > 0 ? v : def; }

// Adds an attribute with one value per point, copied from src.
int add_attribute(draco::Mesh &m, draco::GeometryAttribute::Type type, int comps,
                  const float *src, size_t n)
{
    draco::GeometryAttribute ga;
    ga.Init(type, nullptr, static_cast<uint8_t>(comps), draco::DT_FLOAT32, false,
            sizeof(float) * static_cast<size_t>(comps), 0);
    const int id = m.AddAttribute(ga, true, static_cast<uint32_t>(n));
    if (id < 0) return -1;
    m.attribute(id)->buffer()->Write(0, src, sizeof(float) * static_cast<size_t>(comps) * n);
    return id;
}

jmf_status encode(const jm_mesh *mesh, const jmf_attribute *attrs, size_t nattrs, const jmf_draco_params *p,
                  const char *name, jmf_draco_blob *out, char *err, size_t errlen)
{
    jmf_draco_params d;
    jmf_draco_params_default(&d);
    const int pos_bits = pick(p ? p->position_bits : 0, d.position_bits);
    const int nrm_bits = pick(p ? p->normal_bits : 0, d.normal_bits);
    const int uv_bits = pick(p ? p->uv_bits : 0, d.uv_bits);
    const int speed = p && p->speed >= 0 ? p->speed : d.speed;
    const int att_bits = pick(p ? p->attribute_bits : 0, d.attribute_bits);
    if (pos_bits > 30 || nrm_bits > 30 || uv_bits > 30 || att_bits > 30 || speed > 10) {
        std::snprintf(err, errlen,
                      "%s: Draco quantization bits must be 1-30 and speed 0-10 "
                      "(got %d/%d/%d bits, speed %d)", name, pos_bits, nrm_bits, uv_bits, speed);
        return JMF_E_UNSUPPORTED;
    }
    if (mesh->triangle_count == 0 || mesh->vertex_count == 0) {
        std::snprintf(err, errlen, "%s: cannot write an empty mesh (0 triangles) with Draco", name);
        return JMF_E_UNSUPPORTED;
    }
    if (mesh->vertex_count > 0x7fffffffu || mesh->triangle_count > 0x7fffffffu) {
        std::snprintf(err, errlen, "%s: mesh too large for Draco", name);
        return JMF_E_LIMIT;
    }
    const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;

    draco::Mesh m;
    m.set_num_points(static_cast<uint32_t>(nv));
    m.SetNumFaces(nt);
    for (size_t t = 0; t < nt; t++) {
        draco::Mesh::Face f;
        for (int c = 0; c < 3; c++) {
            const uint32_t v = mesh->indices[3 * t + static_cast<size_t>(c)];
            if (v >= nv) {
                std::snprintf(err, errlen, "%s: triangle %zu uses vertex %u of %zu", name, t,
                              static_cast<unsigned>(v), nv);
                return JMF_E_FORMAT;
            }
            f[c] = draco::PointIndex(v);
        }
        m.SetFace(draco::FaceIndex(static_cast<uint32_t>(t)), f);
    }
    const int pos_att = add_attribute(m, draco::GeometryAttribute::POSITION, 3, mesh->positions, nv);
    const int nrm_att = mesh->normals
        ? add_attribute(m, draco::GeometryAttribute::NORMAL, 3, mesh->normals, nv) : -2;
    const int uv_att = mesh->uvs
        ? add_attribute(m, draco::GeometryAttribute::TEX_COORD, 2, mesh->uvs, nv) : -2;
    if (pos_att < 0 || nrm_att == -1 || uv_att == -1) {
        std::snprintf(err, errlen, "%s: Draco could not create the mesh attributes", name);
        return JMF_E_NOMEM;
    }
    // per-vertex attributes: GENERIC, named by metadata
    std::vector<int> gen(nattrs, -1);
    for (size_t a = 0; a < nattrs; a++) {
        const jmf_attribute *at = &attrs[a];
        if (at->components < 1 || at->components > 4 || !at->values || !at->name) {
            std::snprintf(err, errlen, "%s: attribute %zu has no name, values or 1-4 components", name, a);
            return JMF_E_FORMAT;
        }
        gen[a] = add_attribute(m, draco::GeometryAttribute::GENERIC, at->components, at->values, nv);
        if (gen[a] < 0) {
            std::snprintf(err, errlen, "%s: Draco could not create the attribute '%s'", name, at->name);
            return JMF_E_NOMEM;
        }
        std::unique_ptr<draco::AttributeMetadata> md(new draco::AttributeMetadata());
        md->AddEntryString("name", at->name);
        m.AddAttributeMetadata(gen[a], std::move(md));
    }

    draco::Encoder enc;
    enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, pos_bits);
    enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, nrm_bits);
    enc.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, uv_bits);
    enc.SetAttributeQuantization(draco::GeometryAttribute::GENERIC, att_bits);
    enc.SetSpeedOptions(speed, speed);
    enc.SetEncodingMethod(draco::MESH_EDGEBREAKER_ENCODING);
    enc.SetTrackEncodedProperties(true);
    draco::EncoderBuffer buf;
    const draco::Status s = enc.EncodeMeshToBuffer(m, &buf);
    if (!s.ok()) {
        std::snprintf(err, errlen, "%s: Draco encoding failed: %s", name, s.error_msg());
        return JMF_E_FORMAT;
    }
    out->data = static_cast<unsigned char *>(std::malloc(buf.size() ? buf.size() : 1));
    if (!out->data) {
        std::snprintf(err, errlen, "%s: out of memory", name);
        return JMF_E_NOMEM;
    }
    std::memcpy(out->data, buf.data(), buf.size());
    out->size = buf.size();
    out->num_points = enc.num_encoded_points();
    out->num_faces = enc.num_encoded_faces();
    out->position_id = static_cast<int>(m.attribute(pos_att)->unique_id());
    out->normal_id = nrm_att >= 0 ? static_cast<int>(m.attribute(nrm_att)->unique_id()) : -1;
    out->uv_id = uv_att >= 0 ? static_cast<int>(m.attribute(uv_att)->unique_id()) : -1;
    if (nattrs) {
        out->attribute_ids = static_cast<int *>(std::malloc(nattrs * sizeof(int)));
        if (!out->attribute_ids) {
            std::snprintf(err, errlen, "%s: out of memory", name);
            return JMF_E_NOMEM;
        }
        for (size_t a = 0; a < nattrs; a++)
            out->attribute_ids[a] = static_cast<int>(m.attribute(gen[a])->unique_id());
        out->attribute_count = nattrs;
    }
    return JMF_OK;
}

} // namespace

extern "C" void jmf_draco_params_default(jmf_draco_params *p)
{
    p->position_bits = JMF_DRACO_POSITION_BITS;
    p->normal_bits = JMF_DRACO_NORMAL_BITS;
    p->uv_bits = JMF_DRACO_UV_BITS;
    p->speed = JMF_DRACO_SPEED;
    p->attribute_bits = JMF_DRACO_ATTRIBUTE_BITS;
}

extern "C" jmf_status jmf_draco_encode(const jm_mesh *mesh, const jmf_draco_params *p,
                                       const char *name, jmf_draco_blob *out,
                                       char *err, size_t errlen)
{
    return jmf_draco_encode_attributes(mesh, nullptr, 0, p, name, out, err, errlen);
}

extern "C" jmf_status jmf_draco_encode_attributes(const jm_mesh *mesh, const jmf_attribute *attrs, size_t nattrs,
                                                  const jmf_draco_params *p, const char *name, jmf_draco_blob *out,
                                                  char *err, size_t errlen)
{
    if (!out) return JMF_E_NOMEM;
    std::memset(out, 0, sizeof *out);
    out->normal_id = out->uv_id = -1;
    if (!name) name = "draco";
    if (!mesh) {
        std::snprintf(err, errlen, "%s: no mesh", name);
        return JMF_E_FORMAT;
    }
    try {
        const jmf_status st = encode(mesh, attrs, nattrs, p, name, out, err, errlen);
        if (st) jmf_draco_blob_free(out);
        return st;
    } catch (const std::bad_alloc &) {
        std::snprintf(err, errlen, "%s: out of memory in the Draco encoder", name);
    } catch (const std::exception &e) {
        std::snprintf(err, errlen, "%s: Draco encoder: %s", name, e.what());
    }
    jmf_draco_blob_free(out);
    return JMF_E_NOMEM;
}

extern "C" void jmf_draco_blob_free(jmf_draco_blob *blob)
{
    if (!blob) return;
    std::free(blob->data);
    std::free(blob->attribute_ids);
    std::memset(blob, 0, sizeof *blob);
    blob->normal_id = blob->uv_id = -1;
}
