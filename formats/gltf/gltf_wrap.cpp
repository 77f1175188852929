// gltf_wrap.cpp - builds a glTF 2.0 model of a jm_mesh with tinygltf (optionally Draco-compressed) and serializes it to memory.
#include "gltf_wrap.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <ostream>
#include <streambuf>
#include <string>
#include <vector>

// The implementation comes from the shared libtinygltf (-ltinygltf): do not
// define TINYGLTF_IMPLEMENTATION here.
#include <tiny_gltf.h>

#include "gltf_bin.hpp"
#include "gltf_model.hpp"

namespace {

const char *const kDraco = "KHR_draco_mesh_compression";

// An output stream buffer appending to one malloc'd block, handed to C as is.
class MallocBuf : public std::streambuf {
public:
    ~MallocBuf() override { std::free(data_); }
    bool reserve(size_t need)
    {
        if (need <= cap_) return true;
        size_t cap = cap_ ? cap_ : 4096;
        while (cap < need) cap = cap > std::numeric_limits<size_t>::max() / 2 ? need : cap * 2;
        void *d = std::realloc(data_, cap);
        if (!d) {
            failed_ = true;
            return false;
        }
        data_ = static_cast<unsigned char *>(d);
        cap_ = cap;
        return true;
    }
    unsigned char *release(size_t *size)
    {
        unsigned char *d = data_;
        *size = size_;
        data_ = nullptr;
        size_ = cap_ = 0;
        return d;
    }
    bool failed() const { return failed_; }

protected:
    int_type overflow(int_type c) override
    {
        if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
        if (!reserve(size_ + 1)) return traits_type::eof();
        data_[size_++] = static_cast<unsigned char>(c);
        return c;
    }
    std::streamsize xsputn(const char *s, std::streamsize n) override
    {
        if (n <= 0) return 0;
        if (!reserve(size_ + static_cast<size_t>(n))) return 0;
        std::memcpy(data_ + size_, s, static_cast<size_t>(n));
        size_ += static_cast<size_t>(n);
        return n;
    }

private:
    unsigned char *data_ = nullptr;
    size_t size_ = 0, cap_ = 0;
    bool failed_ = false;
};

int add_view(tinygltf::Model &m, size_t off, size_t len, int target)
{
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = off;
    v.byteLength = len;
    v.target = target;
    m.bufferViews.push_back(v);
    return static_cast<int>(m.bufferViews.size() - 1);
}

int add_accessor(tinygltf::Model &m, int view, int component, int type, size_t count)
{
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component;
    a.type = type;
    a.count = count;
    m.accessors.push_back(a);
    return static_cast<int>(m.accessors.size() - 1);
}

// RFC 3986: everything but the unreserved characters is percent-encoded.
std::string uri_encode(const char *s)
{
    static const char hex[] = "0123456789ABCDEF";
    std::string out;
    for (const unsigned char *p = reinterpret_cast<const unsigned char *>(s); *p; p++) {
        const unsigned char c = *p;
        if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
            c == '-' || c == '.' || c == '_' || c == '~') {
            out += static_cast<char>(*p);
        } else {
            out += '%';
            out += hex[*p >> 4];
            out += hex[*p & 15];
        }
    }
    return out;
}

// glTF's accessor types by component count (1 to 4).
const int kTypes[5] = {0, TINYGLTF_TYPE_SCALAR, TINYGLTF_TYPE_VEC2, TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4};

// "velocity" -> "_VELOCITY": glTF's application-specific attributes start with '_'.
std::string attribute_key(const char *name)
{
    std::string key = "_";
    for (const char *c = name; *c; c++) key += static_cast<char>(*c >= 'a' && *c <= 'z' ? *c - 'a' + 'A' : *c);
    return key;
}

// Attribute a's values as written: 3-vectors rotated into turned with z_up
// (then its data is returned), else the caller's array.
const float *attribute_values(const jmf_gltf_params *p, size_t a, size_t nv, std::vector<float> &turned)
{
    const jmf_attribute *at = &p->attributes[a];
    if (!p->z_up || at->components != 3) return at->values;
    turned.resize(3 * nv);
    for (size_t i = 0; i < nv; i++) {
        turned[3 * i] = at->values[3 * i];
        turned[3 * i + 1] = at->values[3 * i + 2];
        turned[3 * i + 2] = -at->values[3 * i + 1];
    }
    return turned.data();
}

} // namespace

std::string jmf_gltf_uri_encode(const char *s)
{
    return uri_encode(s);
}

// See gltf_model.hpp.
jmf_status jmf_gltf_fill_primitive(const jm_mesh *mesh, const jmf_gltf_params *p, tinygltf::Model &m,
                                   jmf_gltf_bin &buf, tinygltf::Primitive &prim, char *err, size_t errlen)
{
    const char *name = p->name ? p->name : "gltf";
    const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
    uint32_t max_index = 0;
    for (size_t i = 0; i < 3 * nt; i++) {
        const uint32_t v = mesh->indices[i];
        if (v >= nv) {
            std::snprintf(err, errlen, "%s: triangle %zu uses vertex %u of %zu", name, i / 3,
                          static_cast<unsigned>(v), nv);
            return JMF_E_FORMAT;
        }
        if (v > max_index) max_index = v;
    }
    // The attributes as written: z-up rotated when asked.
    std::vector<float> rpos, rnrm;
    const float *pos = mesh->positions, *nrm = mesh->normals;
    if (p->z_up) {
        rpos.resize(3 * nv);
        for (size_t i = 0; i < nv; i++) {
            rpos[3 * i] = pos[3 * i];
            rpos[3 * i + 1] = pos[3 * i + 2];
            rpos[3 * i + 2] = -pos[3 * i + 1];
        }
        pos = rpos.data();
        if (nrm) {
            rnrm.resize(3 * nv);
            for (size_t i = 0; i < nv; i++) {
                rnrm[3 * i] = nrm[3 * i];
                rnrm[3 * i + 1] = nrm[3 * i + 2];
                rnrm[3 * i + 2] = -nrm[3 * i + 1];
            }
            nrm = rnrm.data();
        }
    }
    std::vector<double> pmin(3, 0.0), pmax(3, 0.0);
    for (int k = 0; k < 3; k++) {
        float lo = std::numeric_limits<float>::infinity(), hi = -lo;
        for (size_t i = 0; i < nv; i++) {
            const float x = pos[3 * i + static_cast<size_t>(k)];
            if (!std::isfinite(x)) {
                std::snprintf(err, errlen, "%s: vertex %zu has a non-finite coordinate", name, i);
                return JMF_E_FORMAT;
            }
            lo = x < lo ? x : lo;
            hi = x > hi ? x : hi;
        }
        pmin[static_cast<size_t>(k)] = lo;
        pmax[static_cast<size_t>(k)] = hi;
    }

    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material = 0;
    if (!p->draco) {
        // the mesh's arrays are borrowed as they are (z-up: the rotated copies)
        const size_t op = rpos.empty() ? buf.borrow(pos, nv * 12) : buf.own(std::move(rpos));
        const int ap = add_accessor(m, add_view(m, op, nv * 12, TINYGLTF_TARGET_ARRAY_BUFFER),
                                    TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, nv);
        m.accessors[static_cast<size_t>(ap)].minValues = pmin;
        m.accessors[static_cast<size_t>(ap)].maxValues = pmax;
        prim.attributes["POSITION"] = ap;
        if (nrm) {
            const size_t o = rnrm.empty() ? buf.borrow(nrm, nv * 12) : buf.own(std::move(rnrm));
            prim.attributes["NORMAL"] =
                add_accessor(m, add_view(m, o, nv * 12, TINYGLTF_TARGET_ARRAY_BUFFER),
                             TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, nv);
        }
        if (mesh->uvs) {
            const size_t o = buf.borrow(mesh->uvs, nv * 8);
            prim.attributes["TEXCOORD_0"] =
                add_accessor(m, add_view(m, o, nv * 8, TINYGLTF_TARGET_ARRAY_BUFFER),
                             TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, nv);
        }
        // 65535 is the primitive-restart value: 16-bit only below it.
        const bool small = max_index < 65535;
        const size_t isz = small ? 2 : 4;
        size_t oi;
        if (small) {
            std::vector<unsigned char> b(3 * nt * 2);
            uint16_t *d = reinterpret_cast<uint16_t *>(b.data());
            for (size_t i = 0; i < 3 * nt; i++) d[i] = static_cast<uint16_t>(mesh->indices[i]);
            oi = buf.own(std::move(b));
        } else {
            oi = buf.borrow(mesh->indices, 3 * nt * 4);
        }
        prim.indices = add_accessor(
            m, add_view(m, oi, 3 * nt * isz, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
            small ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
            TINYGLTF_TYPE_SCALAR, 3 * nt);
    } else {
        jm_mesh rot = *mesh;
        rot.positions = pos;
        rot.normals = nrm;
        // the attributes as written (3-vectors z-up rotated), compressed with the mesh
        std::vector<std::vector<float>> turned(p->attribute_count);
        std::vector<jmf_attribute> attrs(p->attribute_count);
        for (size_t a = 0; a < p->attribute_count; a++) {
            attrs[a] = p->attributes[a];
            attrs[a].values = const_cast<float *>(attribute_values(p, a, nv, turned[a]));
        }
        jmf_draco_blob blob;
        jmf_status st = jmf_draco_encode_attributes(&rot, attrs.data(), attrs.size(), &p->draco_params, name, &blob,
                                                    err, errlen);
        if (st) return st;
        const unsigned char *bd = static_cast<const unsigned char *>(blob.data);
        const size_t o = buf.own(std::vector<unsigned char>(bd, bd + blob.size));
        const int view = add_view(m, o, blob.size, 0);
        const size_t np = blob.num_points, nf = blob.num_faces;
        tinygltf::Value::Object ids;
        // Accessors without a bufferView: the Draco decoder fills them.
        const int ap = add_accessor(m, -1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, np);
        m.accessors[static_cast<size_t>(ap)].minValues = pmin;
        m.accessors[static_cast<size_t>(ap)].maxValues = pmax;
        prim.attributes["POSITION"] = ap;
        ids["POSITION"] = tinygltf::Value(blob.position_id);
        if (nrm && blob.normal_id >= 0) {
            prim.attributes["NORMAL"] =
                add_accessor(m, -1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, np);
            ids["NORMAL"] = tinygltf::Value(blob.normal_id);
        }
        if (mesh->uvs && blob.uv_id >= 0) {
            prim.attributes["TEXCOORD_0"] =
                add_accessor(m, -1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, np);
            ids["TEXCOORD_0"] = tinygltf::Value(blob.uv_id);
        }
        for (size_t a = 0; a < blob.attribute_count; a++) {
            const std::string key = attribute_key(p->attributes[a].name);
            prim.attributes[key] = add_accessor(m, -1, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                kTypes[p->attributes[a].components], np);
            ids[key] = tinygltf::Value(blob.attribute_ids[a]);
        }
        prim.indices = add_accessor(m, -1,
                                    np <= 65535 ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                                : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                    TINYGLTF_TYPE_SCALAR, 3 * nf);
        jmf_draco_blob_free(&blob);
        tinygltf::Value::Object ext;
        ext["bufferView"] = tinygltf::Value(view);
        ext["attributes"] = tinygltf::Value(ids);
        prim.extensions[kDraco] = tinygltf::Value(ext);
        if (m.extensionsUsed.empty()) {
            m.extensionsUsed.push_back(kDraco);
            m.extensionsRequired.push_back(kDraco);
        }
        return JMF_OK;
    }
    // per-vertex attributes: "_NAME" (glTF's custom attributes start with '_')
    for (size_t a = 0; a < p->attribute_count; a++) {
        const size_t nc = static_cast<size_t>(p->attributes[a].components);
        std::vector<float> turned;
        const float *src = attribute_values(p, a, nv, turned);
        const size_t o = turned.empty() ? buf.borrow(src, nv * nc * 4) : buf.own(std::move(turned));
        prim.attributes[attribute_key(p->attributes[a].name)] =
            add_accessor(m, add_view(m, o, nv * nc * 4, TINYGLTF_TARGET_ARRAY_BUFFER), TINYGLTF_COMPONENT_TYPE_FLOAT,
                         kTypes[nc], nv);
    }
    return JMF_OK;
}

jmf_status jmf_gltf_fill_primitive(const jm_mesh *mesh, const jmf_gltf_params *p, tinygltf::Model &m,
                                   std::vector<unsigned char> &buf, tinygltf::Primitive &prim, char *err,
                                   size_t errlen)
{
    jmf_gltf_bin bin;
    bin.size = buf.size();
    const jmf_status st = jmf_gltf_fill_primitive(mesh, p, m, bin, prim, err, errlen);
    if (!st) bin.flatten(buf);
    return st;
}

void jmf_gltf_add_material(tinygltf::Model &m)
{
    tinygltf::Material mat;
    mat.name = "jetmesh";
    mat.emissiveFactor = {0.0, 0.0, 0.0}; // tinygltf writes [] when left empty
    mat.doubleSided = false;
    mat.pbrMetallicRoughness.baseColorFactor = {0.8, 0.8, 0.8, 1.0};
    mat.pbrMetallicRoughness.metallicFactor = 0.0;
    mat.pbrMetallicRoughness.roughnessFactor = 0.5;
    m.materials.push_back(mat);
}

namespace {

struct Built {
    MallocBuf main;
    jmf_gltf_bin bin;               // the .bin, or the GLB's BIN chunk
    size_t bin_pad = 0;             // GLB: zero bytes after bin
};

jmf_status build(const jm_mesh *mesh, const jmf_gltf_params *p, Built &built,
                 char *err, size_t errlen)
{
    const char *name = p->name ? p->name : "gltf";
    const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
    if (nt > 0 && (!mesh->positions || !mesh->indices)) {
        std::snprintf(err, errlen, "%s: mesh without positions or indices", name);
        return JMF_E_FORMAT;
    }
    if (nv > 0xffffffffu || nt > 0xffffffffu / 3) {
        std::snprintf(err, errlen, "%s: mesh too large for glTF", name);
        return JMF_E_LIMIT;
    }

    tinygltf::Model m;
    m.asset.version = "2.0";
    m.asset.generator = p->generator ? p->generator : "jetmesh " JM_VERSION_STRING;
    tinygltf::Scene scene;
    scene.name = "jetmesh";
    scene.nodes.push_back(0);
    m.scenes.push_back(scene);
    m.defaultScene = 0;
    tinygltf::Node node;
    node.name = "jetmesh";

    jmf_gltf_bin buf; // the one buffer
    if (nt > 0) {
        tinygltf::Primitive prim;
        jmf_status fst = jmf_gltf_fill_primitive(mesh, p, m, buf, prim, err, errlen);
        if (fst) return fst;

        jmf_gltf_add_material(m);
        tinygltf::Mesh gm;
        gm.name = "jetmesh";
        gm.primitives.push_back(prim);
        m.meshes.push_back(gm);
        node.mesh = 0;
    }
    m.nodes.push_back(node);

    tinygltf::TinyGLTF gltf;
    std::ostream os(&built.main);
    bool ok = true;
    if (p->container == JMF_GLTF_EMBEDDED) {
        // tinygltf's stream writer embeds the buffer as a base64 data: URI.
        built.main.reserve(buf.size / 3 * 4 + buf.size + 65536);
        if (buf.size) {
            m.buffers.resize(1);
            buf.flatten(m.buffers[0].data);
        }
        ok = gltf.WriteGltfSceneToStream(&m, os, true, false);
    } else {
        // The buffer is written by the caller, straight from built.bin (the
        // .bin, or the GLB's BIN chunk, without the copies tinygltf's GLB
        // writer would make): serialize the model without "buffers" and add
        // that entry to the JSON here.
        MallocBuf text;
        std::ostream ts(&text);
        const bool pretty = p->container == JMF_GLTF_SEPARATE;
        ok = gltf.WriteGltfSceneToStream(&m, ts, pretty, false);
        ts.flush();
        size_t n = 0;
        unsigned char *d = text.release(&n);
        std::string json(d ? reinterpret_cast<char *>(d) : "", n);
        std::free(d);
        const size_t close = json.rfind('}');
        if (!ok || !ts || close == std::string::npos) {
            std::snprintf(err, errlen, "%s: tinygltf could not serialize the model", name);
            return JMF_E_FORMAT;
        }
        if (buf.size) {
            size_t end = close;
            while (end > 0 && (json[end - 1] == '\n' || json[end - 1] == ' ')) end--;
            const std::string len = std::to_string(buf.size);
            const std::string entry =
                pretty ? ",\n  \"buffers\": [\n    {\n      \"byteLength\": " + len +
                             ",\n      \"uri\": \"" +
                             uri_encode(p->bin_uri ? p->bin_uri : "mesh.bin") + "\"\n    }\n  ]\n"
                       : ",\"buffers\":[{\"byteLength\":" + len + "}]";
            json = json.substr(0, end) + entry + json.substr(close);
        }
        if (p->container == JMF_GLTF_BINARY) {
            // GLB: 12-byte header, JSON chunk padded with spaces, BIN chunk
            // padded with zeros (the padding bytes are built.bin_pad).
            while (json.size() % 4) json += ' ';
            const uint64_t total = jmf_glb_total(json.size(), buf.size);
            if (total > 0xffffffffu) {
                std::snprintf(err, errlen, "%s: mesh too large for GLB (over 4 GiB); use .gltf", name);
                return JMF_E_LIMIT;
            }
            unsigned char head[20];
            jmf_glb_header(head, total, json.size());
            os.write(reinterpret_cast<const char *>(head), 20);
            os.write(json.data(), static_cast<std::streamsize>(json.size()));
            if (buf.size) {
                jmf_glb_bin_header(head, buf.size);
                os.write(reinterpret_cast<const char *>(head), 8);
                built.bin_pad = jmf_glb_pad4(buf.size) - buf.size;
            }
        } else {
            os.write(json.data(), static_cast<std::streamsize>(json.size()));
        }
        built.bin = std::move(buf);
    }
    os.flush();
    if (!ok || !os || built.main.failed()) {
        std::snprintf(err, errlen, "%s: %s", name,
                      built.main.failed() ? "out of memory" : "tinygltf could not serialize the model");
        return built.main.failed() ? JMF_E_NOMEM : JMF_E_FORMAT;
    }
    return JMF_OK;
}

} // namespace

extern "C" jmf_status jmf_gltf_build(const jm_mesh *mesh, const jmf_gltf_params *p,
                                     jmf_gltf_output *out, char *err, size_t errlen)
{
    if (!out) return JMF_E_NOMEM;
    std::memset(out, 0, sizeof *out);
    if (!mesh || !p) {
        std::snprintf(err, errlen, "glTF: no mesh or parameters");
        return JMF_E_FORMAT;
    }
    Built *b = nullptr;
    try {
        b = new Built;
        jmf_status st = build(mesh, p, *b, err, errlen);
        if (st) {
            delete b;
            return st;
        }
    } catch (const std::bad_alloc &) {
        delete b;
        std::snprintf(err, errlen, "%s: out of memory", p->name ? p->name : "glTF");
        return JMF_E_NOMEM;
    } catch (const std::exception &e) {
        delete b;
        std::snprintf(err, errlen, "%s: %s", p->name ? p->name : "glTF", e.what());
        return JMF_E_FORMAT;
    }
    out->main = b->main.release(&out->main_size);
    out->bin = b->bin.pieces.data();
    out->bin_pieces = b->bin.pieces.size();
    out->bin_size = b->bin.size;
    out->bin_pad = b->bin_pad;
    out->priv = b;
    return JMF_OK;
}

extern "C" void jmf_gltf_output_free(jmf_gltf_output *out)
{
    if (!out) return;
    std::free(out->main);
    delete static_cast<Built *>(out->priv);
    std::memset(out, 0, sizeof *out);
}
