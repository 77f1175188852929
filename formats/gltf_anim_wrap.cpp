// gltf_anim_wrap.cpp - one animated glTF/GLB for a whole sequence (tinygltf), the frames' bytes streamed to a temporary as they come.
#include "gltf_anim.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "gltf_model.hpp"

struct jmf_anim_piece {
    tinygltf::Model m;              // its bufferViews (offsets into data), accessors, one mesh or none
    std::vector<unsigned char> data;
    bool draco = false;
};

struct jmf_anim {
    std::string path, bin_path;
    bool glb = false;
    double fps = 24.0;
    std::string generator;
    jmf_atomic_file scratch;        // the frames' bytes: the .bin of a .gltf, else a temporary
    bool scratch_open = false;
    size_t size = 0;                // bytes in scratch
    tinygltf::Model m;
    std::vector<long> numbers;
    std::vector<int> time_acc;      // per node: its times accessor
    bool draco = false, any_mesh = false;
    int no_sync = 0;
};

namespace {

const char *const kDraco = "KHR_draco_mesh_compression";

jmf_status put(jmf_anim *a, const void *d, size_t n, char *err, size_t errlen)
{
    static const unsigned char zeros[4] = {0, 0, 0, 0};
    jmf_status st = JMF_OK;
    if (a->size % 4) {
        const size_t pad = 4 - a->size % 4;
        st = jmf_atomic_write(&a->scratch, zeros, pad, err, errlen);
        if (st) return st;
        a->size += pad;
    }
    if (n) st = jmf_atomic_write(&a->scratch, d, n, err, errlen);
    if (!st) a->size += n;
    return st;
}

int add_view(tinygltf::Model &m, size_t off, size_t len)
{
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = off;
    v.byteLength = len;
    m.bufferViews.push_back(v);
    return static_cast<int>(m.bufferViews.size() - 1);
}

// The three shared STEP outputs: scale [1,0] for frame 0, [0,1,0] after
// it, [1] for a sequence of one frame; accessors made on first use.
struct Outputs {
    int one = -1, two = -1, three = -1;
};

} // namespace

extern "C" jmf_status jmf_anim_piece_build(const jm_mesh *mesh, const jmf_write_options *opt, int draco,
                                           const char *name, jmf_anim_piece **out, char *err, size_t errlen)
{
    *out = nullptr;
    jmf_anim_piece *p = nullptr;
    try {
        p = new jmf_anim_piece;
        if (mesh && mesh->triangle_count > 0) {
            jmf_gltf_params gp;
            jmf_write_gltf_params(opt, mesh, draco, name, &gp);
            tinygltf::Primitive prim;
            jmf_status st = jmf_gltf_fill_primitive(mesh, &gp, p->m, p->data, prim, err, errlen);
            if (st) {
                delete p;
                return st;
            }
            tinygltf::Mesh gm;
            gm.primitives.push_back(prim);
            p->m.meshes.push_back(gm);
            p->draco = draco != 0;
        }
    } catch (const std::bad_alloc &) {
        delete p;
        std::snprintf(err, errlen, "%s: out of memory", name ? name : "glTF");
        return JMF_E_NOMEM;
    } catch (const std::exception &e) {
        delete p;
        std::snprintf(err, errlen, "%s: %s", name ? name : "glTF", e.what());
        return JMF_E_FORMAT;
    }
    *out = p;
    return JMF_OK;
}

extern "C" size_t jmf_anim_piece_bytes(const jmf_anim_piece *p)
{
    return p ? p->data.size() : 0;
}

extern "C" void jmf_anim_piece_free(jmf_anim_piece *p)
{
    delete p;
}

extern "C" jmf_status jmf_anim_open(const char *path, int glb, const jmf_write_options *opt, double fps,
                                   jmf_anim **out, char *err, size_t errlen)
{
    *out = nullptr;
    jmf_anim *a = nullptr;
    try {
        a = new jmf_anim;
        a->path = path;
        a->glb = glb != 0;
        a->fps = fps > 0 ? fps : 24.0;
        a->generator = opt && opt->generator ? opt->generator : "jetmesh " JM_VERSION_STRING;
        a->no_sync = opt ? opt->no_sync : 0;
        if (!a->glb) {
            const size_t n = a->path.size();
            a->bin_path = (n > 5 && a->path.compare(n - 5, 5, ".gltf") == 0 ? a->path.substr(0, n - 5) : a->path) +
                          ".bin";
        }
    } catch (const std::bad_alloc &) {
        delete a;
        std::snprintf(err, errlen, "%s: out of memory", path);
        return JMF_E_NOMEM;
    }
    // the frames' bytes: a .gltf's .bin itself; for a .glb the temporary
    // of "NAME.glb.frames" (never published, removed at the end)
    const std::string scratch = a->glb ? a->path + ".frames" : a->bin_path;
    jmf_status st = jmf_atomic_open(&a->scratch, scratch.c_str(), err, errlen);
    if (st) {
        delete a;
        return st;
    }
    a->scratch.no_sync = a->no_sync;
    a->scratch_open = true;
    a->m.asset.version = "2.0";
    a->m.asset.generator = a->generator;
    *out = a;
    return JMF_OK;
}

extern "C" jmf_status jmf_anim_add(jmf_anim *a, const char *node_name, long number, jmf_anim_piece *piece,
                                   char *err, size_t errlen)
{
    jmf_status st = JMF_OK;
    try {
        tinygltf::Node node;
        node.name = node_name ? node_name : "frame";
        if (piece && !piece->m.meshes.empty()) {
            st = put(a, nullptr, 0, err, errlen); // align
            const size_t base = a->size;
            if (!st && !piece->data.empty()) st = put(a, piece->data.data(), piece->data.size(), err, errlen);
            if (st) {
                delete piece;
                return st;
            }
            const int vbase = static_cast<int>(a->m.bufferViews.size());
            const int abase = static_cast<int>(a->m.accessors.size());
            for (tinygltf::BufferView v : piece->m.bufferViews) {
                v.byteOffset += base;
                a->m.bufferViews.push_back(v);
            }
            for (tinygltf::Accessor ac : piece->m.accessors) {
                if (ac.bufferView >= 0) ac.bufferView += vbase;
                a->m.accessors.push_back(ac);
            }
            tinygltf::Mesh gm = piece->m.meshes[0];
            gm.name = node.name;
            for (tinygltf::Primitive &pr : gm.primitives) {
                for (auto &kv : pr.attributes) kv.second += abase;
                if (pr.indices >= 0) pr.indices += abase;
                auto e = pr.extensions.find(kDraco);
                if (e != pr.extensions.end()) {
                    tinygltf::Value::Object o = e->second.Get<tinygltf::Value::Object>();
                    o["bufferView"] = tinygltf::Value(o["bufferView"].GetNumberAsInt() + vbase);
                    e->second = tinygltf::Value(o);
                    a->draco = true;
                }
            }
            a->m.meshes.push_back(gm);
            node.mesh = static_cast<int>(a->m.meshes.size() - 1);
            a->any_mesh = true;
        }
        delete piece;
        piece = nullptr;
        // this node's key times: 0, k/fps, (k+1)/fps (frame 0: 0, 1/fps)
        const size_t k = a->numbers.size();
        float t[3];
        size_t nt = 0;
        if (k > 0) t[nt++] = 0.0f;
        t[nt++] = static_cast<float>(static_cast<double>(k) / a->fps);
        t[nt++] = static_cast<float>(static_cast<double>(k + 1) / a->fps);
        st = put(a, t, nt * 4, err, errlen);
        if (st) return st;
        tinygltf::Accessor ta;
        ta.bufferView = add_view(a->m, a->size - nt * 4, nt * 4);
        ta.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
        ta.type = TINYGLTF_TYPE_SCALAR;
        ta.count = nt;
        ta.minValues = {t[0]};
        ta.maxValues = {t[nt - 1]};
        a->m.accessors.push_back(ta);
        a->time_acc.push_back(static_cast<int>(a->m.accessors.size() - 1));
        a->m.nodes.push_back(node);
        a->numbers.push_back(number);
    } catch (const std::bad_alloc &) {
        delete piece;
        std::snprintf(err, errlen, "%s: out of memory", a->path.c_str());
        return JMF_E_NOMEM;
    }
    return JMF_OK;
}

namespace {

// The animation, the scene and the extras, once every frame is in.
jmf_status close_model(jmf_anim *a, char *err, size_t errlen)
{
    tinygltf::Model &m = a->m;
    const size_t n = m.nodes.size();
    // the shared outputs: [0,1,0], [1,0], [1] as VEC3 scales
    static const float v3[9] = {0, 0, 0, 1, 1, 1, 0, 0, 0};
    static const float v2[6] = {1, 1, 1, 0, 0, 0};
    int out3 = -1, out2 = -1, out1 = -1;
    auto scales = [&](const float *v, size_t count) -> int {
        if (put(a, v, count * 12, err, errlen)) return -1;
        tinygltf::Accessor ac;
        ac.bufferView = add_view(m, a->size - count * 12, count * 12);
        ac.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
        ac.type = TINYGLTF_TYPE_VEC3;
        ac.count = count;
        m.accessors.push_back(ac);
        return static_cast<int>(m.accessors.size() - 1);
    };
    if (n > 1) {
        out3 = scales(v3, 3);
        if (out3 < 0) return JMF_E_IO;
    }
    out2 = scales(v2, 2);
    if (out2 < 0) return JMF_E_IO;
    (void)out1;
    tinygltf::Animation anim;
    anim.name = "sequence";
    tinygltf::Scene scene;
    scene.name = "jetmesh";
    for (size_t k = 0; k < n; k++) {
        tinygltf::AnimationSampler s;
        s.input = a->time_acc[k];
        s.output = k == 0 ? out2 : out3;
        s.interpolation = "STEP";
        anim.samplers.push_back(s);
        tinygltf::AnimationChannel c;
        c.sampler = static_cast<int>(k);
        c.target_node = static_cast<int>(k);
        c.target_path = "scale";
        anim.channels.push_back(c);
        scene.nodes.push_back(static_cast<int>(k));
    }
    if (n) m.animations.push_back(anim);
    m.scenes.push_back(scene);
    m.defaultScene = 0;
    if (a->any_mesh) jmf_gltf_add_material(m);
    if (a->draco) {
        m.extensionsUsed.push_back(kDraco);
        m.extensionsRequired.push_back(kDraco);
    }
    tinygltf::Value::Object seq, ex;
    seq["fps"] = tinygltf::Value(a->fps);
    seq["frames"] = tinygltf::Value(static_cast<int>(n));
    tinygltf::Value::Array nums;
    for (long v : a->numbers) nums.push_back(tinygltf::Value(static_cast<int>(v)));
    seq["frame_numbers"] = tinygltf::Value(nums);
    ex["jetmesh_sequence"] = tinygltf::Value(seq);
    m.asset.extras = tinygltf::Value(ex);
    return JMF_OK;
}

// The model as JSON, with the one buffer of size bytes (uri: .gltf only).
bool to_json(jmf_anim *a, std::string &json)
{
    tinygltf::TinyGLTF gltf;
    std::ostringstream ts;
    const bool pretty = !a->glb;
    if (!gltf.WriteGltfSceneToStream(&a->m, ts, pretty, false)) return false;
    json = ts.str();
    const size_t close = json.rfind('}');
    if (close == std::string::npos) return false;
    if (a->size) {
        size_t end = close;
        while (end > 0 && (json[end - 1] == '\n' || json[end - 1] == ' ')) end--;
        const std::string len = std::to_string(a->size);
        std::string uri;
        if (!a->glb) {
            const size_t slash = a->bin_path.rfind('/');
            uri = jmf_gltf_uri_encode(slash == std::string::npos ? a->bin_path.c_str()
                                                                  : a->bin_path.c_str() + slash + 1);
        }
        const std::string entry = pretty ? ",\n  \"buffers\": [\n    {\n      \"byteLength\": " + len +
                                               ",\n      \"uri\": \"" + uri + "\"\n    }\n  ]\n"
                                         : ",\"buffers\":[{\"byteLength\":" + len + "}]";
        json = json.substr(0, end) + entry + json.substr(close);
    }
    return true;
}

} // namespace

extern "C" jmf_status jmf_anim_finish(jmf_anim *a, jmf_staged *out, size_t *out_bytes, char *err, size_t errlen)
{
    std::memset(out, 0, sizeof *out);
    if (out_bytes) *out_bytes = 0;
    jmf_status st = JMF_OK;
    std::string json;
    try {
        st = close_model(a, err, errlen);
        if (!st && !to_json(a, json)) {
            std::snprintf(err, errlen, "%s: tinygltf could not serialize the model", a->path.c_str());
            st = JMF_E_FORMAT;
        }
    } catch (const std::bad_alloc &) {
        std::snprintf(err, errlen, "%s: out of memory", a->path.c_str());
        st = JMF_E_NOMEM;
    }
    if (st) {
        jmf_anim_abort(a);
        return st;
    }
    jmf_atomic_file f;
    st = jmf_atomic_open(&f, a->path.c_str(), err, errlen);
    if (st) {
        jmf_anim_abort(a);
        return st;
    }
    f.no_sync = a->no_sync;
    if (!a->glb) {
        // the .bin is complete: stage it, then the .gltf naming it
        st = jmf_atomic_write(&f, json.data(), json.size(), err, errlen);
        if (st) {
            jmf_atomic_abort(&f);
            jmf_anim_abort(a);
            return st;
        }
        st = jmf_atomic_finish(&a->scratch, err, errlen); /* on failure it removes itself */
        a->scratch_open = false;
        if (st) {
            jmf_atomic_abort(&f);
            delete a;
            return st;
        }
        out->files[out->count++] = a->scratch;
        st = jmf_atomic_finish(&f, err, errlen);
        if (st) {
            jmf_staged_abort(out);
            delete a;
            return st;
        }
        out->files[out->count++] = f;
        if (out_bytes) *out_bytes = out->files[0].bytes + f.bytes;
        delete a;
        return JMF_OK;
    }
    // GLB: header, JSON chunk, BIN chunk copied from the temporary
    while (json.size() % 4) json += ' ';
    const size_t bin_padded = (a->size + 3) / 4 * 4;
    const uint64_t total = 12 + 8 + json.size() + (a->size ? 8 + bin_padded : 0);
    if (total > 0xffffffffu) {
        std::snprintf(err, errlen, "%s: the sequence is too large for one GLB (over 4 GiB); write .gltf",
                      a->path.c_str());
        jmf_atomic_abort(&f);
        jmf_anim_abort(a);
        return JMF_E_LIMIT;
    }
    unsigned char head[20];
    auto put32 = [](unsigned char *q, uint64_t v) {
        for (int k = 0; k < 4; k++) q[k] = static_cast<unsigned char>(v >> (8 * k));
    };
    std::memcpy(head, "glTF", 4);
    put32(head + 4, 2);
    put32(head + 8, total);
    put32(head + 12, json.size());
    std::memcpy(head + 16, "JSON", 4);
    st = jmf_atomic_write(&f, head, 20, err, errlen);
    if (!st) st = jmf_atomic_write(&f, json.data(), json.size(), err, errlen);
    if (!st && a->size) {
        put32(head, bin_padded);
        std::memcpy(head + 4, "BIN\0", 4);
        st = jmf_atomic_write(&f, head, 8, err, errlen);
        if (!st && std::fflush(a->scratch.fp) != 0) {
            std::snprintf(err, errlen, "%s: cannot flush its temporary: %s", a->path.c_str(), std::strerror(errno));
            st = JMF_E_IO;
        }
        FILE *in = st ? nullptr : std::fopen(a->scratch.temp_path, "rb");
        if (!st && !in) {
            std::snprintf(err, errlen, "%s: cannot read back its temporary: %s", a->path.c_str(),
                          std::strerror(errno));
            st = JMF_E_IO;
        }
        if (in) {
            std::vector<unsigned char> chunk(1 << 20);
            size_t left = a->size;
            while (!st && left) {
                const size_t want = left < chunk.size() ? left : chunk.size();
                const size_t got = std::fread(chunk.data(), 1, want, in);
                if (got != want) {
                    std::snprintf(err, errlen, "%s: short read of its temporary", a->path.c_str());
                    st = JMF_E_IO;
                    break;
                }
                st = jmf_atomic_write(&f, chunk.data(), got, err, errlen);
                left -= got;
            }
            std::fclose(in);
        }
        static const unsigned char zeros[4] = {0, 0, 0, 0};
        if (!st) st = jmf_atomic_write(&f, zeros, bin_padded - a->size, err, errlen);
    }
    if (!st) st = jmf_atomic_finish(&f, err, errlen);
    else jmf_atomic_abort(&f);
    jmf_anim_abort(a); // the temporary
    if (st) return st;
    out->files[out->count++] = f;
    if (out_bytes) *out_bytes = f.bytes;
    return JMF_OK;
}

extern "C" void jmf_anim_abort(jmf_anim *a)
{
    if (!a) return;
    if (a->scratch_open) jmf_atomic_abort(&a->scratch);
    delete a;
}
