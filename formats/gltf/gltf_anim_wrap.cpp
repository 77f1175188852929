// gltf_anim_wrap.cpp - one animated glTF/GLB for a whole sequence (tinygltf), the frames' bytes streamed to a temporary as they come.
#include "gltf_anim.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
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
    // The JSON, as compact text per top-level array: a few hundred bytes a
    // frame (no model of the whole sequence is kept)
    std::string accessors, views, meshes, nodes, samplers, channels, numbers;
    size_t naccessors = 0, nviews = 0, nmeshes = 0, nnodes = 0;
    bool draco = false, any_mesh = false;
    int no_sync = 0;
    size_t limit = JMF_ANIM_MAX_BYTES; // the largest file written
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

// ", " between the items of a JSON array kept as text
void item(std::string &list, const std::string &text)
{
    if (!list.empty()) list += ',';
    list += text;
}

std::string num(double v)
{
    char b[40];
    std::snprintf(b, sizeof b, "%.9g", v);
    return b;
}

std::string quoted(const std::string &s)
{
    std::string o = "\"";
    for (unsigned char c : s) {
        if (c == '"' || c == '\\') {
            o += '\\';
            o += static_cast<char>(c);
        } else if (c < 0x20) {
            char b[8];
            std::snprintf(b, sizeof b, "\\u%04x", c);
            o += b;
        } else {
            o += static_cast<char>(c);
        }
    }
    return o + "\"";
}

const char *type_name(int t)
{
    switch (t) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    default: return "VEC4";
    }
}

// One bufferView (offset into the buffer) and its index.
size_t add_view(jmf_anim *a, size_t off, size_t len, int target)
{
    std::string v = "{\"buffer\":0,\"byteLength\":" + std::to_string(len) + ",\"byteOffset\":" +
                    std::to_string(off);
    if (target) v += ",\"target\":" + std::to_string(target);
    item(a->views, v + "}");
    return a->nviews++;
}

// One accessor (view < 0: none, Draco fills it) and its index.
size_t add_accessor(jmf_anim *a, long view, int component, int type, size_t count, const std::vector<double> &mn,
                    const std::vector<double> &mx)
{
    std::string t = "{";
    if (view >= 0) t += "\"bufferView\":" + std::to_string(view) + ",";
    t += "\"componentType\":" + std::to_string(component) + ",\"count\":" + std::to_string(count);
    auto arr = [](const std::vector<double> &v) {
        std::string o = "[";
        for (size_t i = 0; i < v.size(); i++) o += (i ? "," : "") + num(v[i]);
        return o + "]";
    };
    if (!mx.empty()) t += ",\"max\":" + arr(mx);
    if (!mn.empty()) t += ",\"min\":" + arr(mn);
    t += ",\"type\":\"" + std::string(type_name(type)) + "\"}";
    item(a->accessors, t);
    return a->naccessors++;
}

// "2 GiB", or the bytes of a limit that is no whole number of GiB.
std::string limit_text(size_t limit)
{
    if (limit % (size_t(1) << 30) == 0) return std::to_string(limit >> 30) + " GiB";
    return std::to_string(limit) + " bytes";
}

// The refusal of a file that would pass the limit, naming what to write instead.
jmf_status over_limit(const jmf_anim *a, const char *when, uint64_t bytes, char *err, size_t errlen)
{
    std::snprintf(err, errlen,
                  "%s: the animated file would pass %s %s (%zu frames in, %llu bytes): glTF tools refuse files over "
                  "2 GiB (the Khronos glTF-Validator does) and GLB ends at 4 GiB. Write one file per frame "
                  "instead (-o 'DIR/frame_{}.glb') and stream them into Blender (jetmesh --blender-script), "
                  "or make the frames smaller (--draco)",
                  a->path.c_str(), limit_text(a->limit).c_str(), when, a->nnodes,
                  static_cast<unsigned long long>(bytes));
    return JMF_E_LIMIT;
}

} // namespace

extern "C" void jmf_anim_set_limit(jmf_anim *a, size_t bytes)
{
    a->limit = bytes ? bytes : JMF_ANIM_MAX_BYTES;
}

extern "C" size_t jmf_anim_bytes(const jmf_anim *a)
{
    // the JSON: its lists as kept, the scene's node list, and about 1 KiB of
    // fixed parts (asset, material, the two shared STEP outputs' entries)
    const size_t json = a->accessors.size() + a->views.size() + a->meshes.size() + a->nodes.size() +
                        a->samplers.size() + a->channels.size() + a->numbers.size() + a->generator.size() +
                        8 * a->nnodes + 1024;
    return 28 + json + a->size + 2 * 12 * 3 + 8;
}

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
    *out = a;
    return JMF_OK;
}

extern "C" jmf_status jmf_anim_add(jmf_anim *a, const char *node_name, long number, jmf_anim_piece *piece,
                                   char *err, size_t errlen)
{
    jmf_status st = JMF_OK;
    try {
        const std::string name = node_name ? node_name : "frame";
        std::string node = "{";
        // this frame's bytes, its JSON (a few hundred bytes) and alignment
        const size_t adds = (piece ? piece->data.size() : 0) + 1024;
        if (jmf_anim_bytes(a) + adds > a->limit) {
            char when[64];
            std::snprintf(when, sizeof when, "at frame %ld", number);
            st = over_limit(a, when, jmf_anim_bytes(a) + adds, err, errlen);
            delete piece;
            return st;
        }
        if (piece && !piece->m.meshes.empty()) {
            st = put(a, nullptr, 0, err, errlen); // align
            const size_t base = a->size;
            if (!st && !piece->data.empty()) st = put(a, piece->data.data(), piece->data.size(), err, errlen);
            if (st) {
                delete piece;
                return st;
            }
            // the piece's views and accessors, renumbered after those in the file
            const size_t vbase = a->nviews, abase = a->naccessors;
            for (const tinygltf::BufferView &v : piece->m.bufferViews)
                add_view(a, base + v.byteOffset, v.byteLength, v.target);
            for (const tinygltf::Accessor &ac : piece->m.accessors)
                add_accessor(a, ac.bufferView >= 0 ? static_cast<long>(vbase) + ac.bufferView : -1, ac.componentType,
                             ac.type, ac.count, ac.minValues, ac.maxValues);
            const tinygltf::Primitive &pr = piece->m.meshes[0].primitives[0];
            std::string at;
            for (const auto &kv : pr.attributes)
                item(at, quoted(kv.first) + ":" + std::to_string(abase + static_cast<size_t>(kv.second)));
            std::string prim = "{\"attributes\":{" + at + "}";
            auto e = pr.extensions.find(kDraco);
            if (e != pr.extensions.end()) {
                const tinygltf::Value &ext = e->second;
                std::string ids;
                const tinygltf::Value &attrs = ext.Get("attributes");
                for (const std::string &k : attrs.Keys())
                    item(ids, quoted(k) + ":" + std::to_string(attrs.Get(k).GetNumberAsInt()));
                prim += ",\"extensions\":{\"" + std::string(kDraco) + "\":{\"attributes\":{" + ids +
                        "},\"bufferView\":" + std::to_string(vbase + static_cast<size_t>(ext.Get("bufferView").GetNumberAsInt())) +
                        "}}";
                a->draco = true;
            }
            prim += ",\"indices\":" + std::to_string(abase + static_cast<size_t>(pr.indices)) +
                    ",\"material\":0,\"mode\":4}";
            item(a->meshes, "{\"name\":" + quoted(name) + ",\"primitives\":[" + prim + "]}");
            node += "\"mesh\":" + std::to_string(a->nmeshes++) + ",";
            a->any_mesh = true;
        }
        delete piece;
        piece = nullptr;
        item(a->nodes, node + "\"name\":" + quoted(name) + "}");
        // this node's key times: 0, k/fps, (k+1)/fps (frame 0: 0, 1/fps)
        const size_t k = a->nnodes++;
        float t[3];
        size_t nt = 0;
        if (k > 0) t[nt++] = 0.0f;
        t[nt++] = static_cast<float>(static_cast<double>(k) / a->fps);
        t[nt++] = static_cast<float>(static_cast<double>(k + 1) / a->fps);
        st = put(a, t, nt * 4, err, errlen);
        if (st) return st;
        const size_t view = add_view(a, a->size - nt * 4, nt * 4, 0);
        const size_t acc = add_accessor(a, static_cast<long>(view), TINYGLTF_COMPONENT_TYPE_FLOAT,
                                        TINYGLTF_TYPE_SCALAR, nt, {t[0]}, {t[nt - 1]});
        // the output: [1,0] for frame 0, [0,1,0] after it (accessors 0 and 1
        // of the outputs, made at the end: their indices are fixed up then)
        item(a->samplers, "{\"input\":" + std::to_string(acc) + ",\"interpolation\":\"STEP\",\"output\":@" +
                              (k == 0 ? "2" : "3") + "}");
        item(a->channels, "{\"sampler\":" + std::to_string(k) + ",\"target\":{\"node\":" + std::to_string(k) +
                              ",\"path\":\"scale\"}}");
        item(a->numbers, std::to_string(number));
    } catch (const std::bad_alloc &) {
        delete piece;
        std::snprintf(err, errlen, "%s: out of memory", a->path.c_str());
        return JMF_E_NOMEM;
    }
    return JMF_OK;
}

namespace {

// The whole JSON, once every frame is in: the two shared outputs of the
// STEP samplers, the animation, the scene, the material and the extras.
jmf_status to_json(jmf_anim *a, std::vector<std::string> &json, char *err, size_t errlen)
{
    static const float v2[6] = {1, 1, 1, 0, 0, 0};          // frame 0: shown, then hidden
    static const float v3[9] = {0, 0, 0, 1, 1, 1, 0, 0, 0}; // hidden, shown, hidden
    size_t out[2];
    const float *src[2] = {v2, v3};
    for (int i = 0; i < 2; i++) {
        const size_t count = i == 0 ? 2 : 3;
        jmf_status st = put(a, src[i], count * 12, err, errlen);
        if (st) return st;
        const size_t view = add_view(a, a->size - count * 12, count * 12, 0);
        out[i] = add_accessor(a, static_cast<long>(view), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                              count, {}, {});
    }
    std::string samplers;
    samplers.reserve(a->samplers.size() + a->samplers.size() / 8);
    for (size_t i = 0; i < a->samplers.size(); i++) {
        if (a->samplers[i] == '@') {
            samplers += std::to_string(out[a->samplers[i + 1] == '2' ? 0 : 1]);
            i++;
        } else {
            samplers += a->samplers[i];
        }
    }
    std::string().swap(a->samplers);
    std::string scene;
    for (size_t k = 0; k < a->nnodes; k++) item(scene, std::to_string(k));
    // in pieces, the large ones moved in (never one more copy of them)
    auto add = [&json](std::string &&t) { json.push_back(std::move(t)); };
    add("{\"accessors\":[");
    add(std::move(a->accessors));
    add("]");
    if (a->nnodes) {
        add(",\"animations\":[{\"channels\":[");
        add(std::move(a->channels));
        add("],\"name\":\"sequence\",\"samplers\":[");
        add(std::move(samplers));
        add("]}]");
    }
    add(",\"asset\":{\"extras\":{\"jetmesh_sequence\":{\"fps\":" + num(a->fps) + ",\"frame_numbers\":[");
    add(std::move(a->numbers));
    add("],\"frames\":" + std::to_string(a->nnodes) + "}},\"generator\":" + quoted(a->generator) +
        ",\"version\":\"2.0\"},\"bufferViews\":[");
    add(std::move(a->views));
    std::string b = "],\"buffers\":[{\"byteLength\":" + std::to_string(a->size);
    if (!a->glb) {
        const size_t slash = a->bin_path.rfind('/');
        b += ",\"uri\":" + quoted(jmf_gltf_uri_encode(slash == std::string::npos ? a->bin_path.c_str()
                                                                                   : a->bin_path.c_str() + slash + 1));
    }
    b += "}]";
    if (a->draco)
        b += ",\"extensionsRequired\":[\"" + std::string(kDraco) + "\"],\"extensionsUsed\":[\"" + std::string(kDraco) +
             "\"]";
    if (a->any_mesh)
        b += ",\"materials\":[{\"emissiveFactor\":[0,0,0],\"name\":\"jetmesh\",\"pbrMetallicRoughness\":"
             "{\"baseColorFactor\":[0.8,0.8,0.8,1],\"metallicFactor\":0,\"roughnessFactor\":0.5}}]";
    if (a->nmeshes) b += ",\"meshes\":[";
    add(std::move(b));
    if (a->nmeshes) {
        add(std::move(a->meshes));
        add("]");
    }
    add(",\"nodes\":[");
    add(std::move(a->nodes));
    add("],\"scene\":0,\"scenes\":[{\"name\":\"jetmesh\",\"nodes\":[");
    add(std::move(scene));
    add("]}]}");
    return JMF_OK;
}

} // namespace

extern "C" jmf_status jmf_anim_finish(jmf_anim *a, jmf_staged *out, size_t *out_bytes, char *err, size_t errlen)
{
    std::memset(out, 0, sizeof *out);
    if (out_bytes) *out_bytes = 0;
    jmf_status st = JMF_OK;
    std::vector<std::string> json; // the JSON in pieces
    size_t json_size = 0;
    try {
        st = to_json(a, json, err, errlen);
        for (const std::string &t : json) json_size += t.size();
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
    if (!a->glb && json_size + a->size > a->limit) {
        over_limit(a, "when finished", json_size + a->size, err, errlen);
        jmf_atomic_abort(&f);
        jmf_anim_abort(a);
        return JMF_E_LIMIT;
    }
    if (!a->glb) {
        // the .bin is complete: stage it, then the .gltf naming it
        for (size_t i = 0; !st && i < json.size(); i++) st = jmf_atomic_write(&f, json[i].data(), json[i].size(), err, errlen);
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
    const size_t json_padded = jmf_glb_pad4(json_size);
    json.push_back(std::string(json_padded - json_size, ' '));
    const uint64_t total = jmf_glb_total(json_padded, a->size);
    if (total > a->limit || total > 0xffffffffu) {
        over_limit(a, "when finished", total, err, errlen);
        jmf_atomic_abort(&f);
        jmf_anim_abort(a);
        return JMF_E_LIMIT;
    }
    unsigned char head[20];
    jmf_glb_header(head, total, json_padded);
    st = jmf_atomic_write(&f, head, 20, err, errlen);
    for (size_t i = 0; !st && i < json.size(); i++) st = jmf_atomic_write(&f, json[i].data(), json[i].size(), err, errlen);
    if (!st && a->size) {
        jmf_glb_bin_header(head, a->size);
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
        if (!st) st = jmf_atomic_write(&f, zeros, jmf_glb_pad4(a->size) - a->size, err, errlen);
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
