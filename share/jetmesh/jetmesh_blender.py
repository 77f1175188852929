# jetmesh_blender.py - streams a jetmesh sequence (per-frame .glb/.gltf/.ply files, or one --animate file) into Blender as ONE object whose mesh is loaded when the frame changes.
#
# Use (the path: `jetmesh --blender-script`):
#   blender --python jetmesh_blender.py -- meshes/ [options]          (a folder of frames)
#   blender --python jetmesh_blender.py -- 'meshes/fluid_{}.glb'      (a pattern: {} %04d #### or *)
#   blender --python jetmesh_blender.py -- fluid.glb                  (one --animate file)
#   blender -b --python jetmesh_blender.py -- meshes/ --save scene.blend   (headless; the
#       command line sets Cycles up, without denoising where Blender has no denoiser)
#   options: --fps F  --offset N  --cache N  --gaps hold|empty  --ply-up y|z
#            --normals render|always|never  --motion-blur  --save FILE.blend
#   Add-on: Edit > Preferences > Add-ons > Install... this file, enable it; then
#   File > Import > jetmesh sequence, and the View3D sidebar's "jetmesh" tab.
#
# What it does: makes one object whose mesh is replaced by the frame's mesh on
# every frame change (a persistent frame_change_pre handler; a few frames in a
# small LRU cache), so a 500-frame run opens at once in constant memory. Scene
# frame k shows simulation frame k - offset (the number in the file name, or
# the --animate file's frame_numbers); frames missing inside the run hold the
# last one (gaps "hold") or show nothing ("empty"); before the first and after
# the last frame nothing shows. Meshes are parsed here with numpy (the file's
# normals as custom normals in renders, Blender's smooth normals in the
# viewport unless --normals always; TEXCOORD_0 as "UVMap"); the vertex attributes
# "_VELOCITY", "_DENSITY"... (PLY: velocity_x/_y/_z, density...) become the
# mesh attributes "velocity", "density"...: Cycles reads "velocity" (units
# per second, Blender axes) for motion blur, so set the scene's fps to the
# simulation's frames per second. glTF's +Y up becomes Blender's +Z up as
# Blender's glTF importer does; PLY files are taken as +Y up too unless
# --ply-up z.
#
# Saved .blend files: the settings live on the object (obj.jetmesh) and this
# script is stored in the .blend as the registered text "jetmesh_sequence.py".
# A new Blender process loads frames again when one of these runs it:
#   - the add-on enabled in the preferences (it registers the handler), or
#   - auto-run: `blender -b scene.blend -y -a` (-y, --enable-autoexec, runs the
#     stored text; in the UI: Preferences > Save & Load > Auto Run Python
#     Scripts, or "Allow Execution" when Blender asks), or
#   - `blender -b scene.blend --python "$(jetmesh --blender-script)" -a`.
# Without one of them every frame shows the mesh saved in the file.
import bisect
import collections
import ctypes
import glob
import json
import math
import os
import re
import struct
import sys
import types

bl_info = {
    "name": "jetmesh sequence",
    "author": "jetmesh",
    "version": (0, 4, 0),
    "blender": (3, 0, 0),
    "location": "File > Import > jetmesh sequence; 3D View > Sidebar > jetmesh",
    "description": "Stream a jetmesh sequence (per-frame GLB/glTF/PLY or one animated glTF) as one object",
    "category": "Import-Export",
}

import numpy as np  # noqa: E402

import bpy  # noqa: E402
from bpy.app.handlers import persistent  # noqa: E402

TEXT_NAME = "jetmesh_sequence.py"
EXTENSIONS = (".glb", ".gltf", ".ply")
DRACO = "KHR_draco_mesh_compression"


class FrameError(Exception):
    """A frame that cannot be read: the message names the file and what is wrong."""


class SequenceError(Exception):
    """A sequence that cannot be opened (no frames, no such path)."""


# ---- one frame's mesh -------------------------------------------------------

class Frame:
    """positions (N,3) and indices (M,3) in Blender's axes; normals (N,3),
    uvs (N,2) or None; attributes {name: (N,k) float32}."""
    __slots__ = ("positions", "indices", "normals", "uvs", "attributes")

    def __init__(self, positions, indices, normals=None, uvs=None, attributes=None):
        self.positions, self.indices, self.normals, self.uvs = positions, indices, normals, uvs
        self.attributes = attributes or {}


def y_up_to_z_up(a):
    """(x, y, z) -> (x, -z, y): glTF's +Y up to Blender's +Z up."""
    out = np.empty_like(a)
    out[:, 0], out[:, 1], out[:, 2] = a[:, 0], -a[:, 2], a[:, 1]
    return out


# ---- glTF / GLB ------------------------------------------------------------

_COMPONENT = {5120: "i1", 5121: "u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}
_NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


class Gltf:
    """A .glb/.gltf's JSON, and its buffers' bytes read on demand (a range at a time)."""

    def __init__(self, path):
        self.path = path
        self.size = os.path.getsize(path)
        self.buffers = []  # per buffer: (file, offset, length) or bytes
        with open(path, "rb") as f:
            head = f.read(20)
            if head[:4] == b"glTF":
                self._glb(f, head)
            else:
                self._gltf(head + f.read())

    def _glb(self, f, head):
        p = self.path
        if len(head) < 20:
            raise FrameError("%s: a GLB header is 20 bytes, the file has %d" % (p, len(head)))
        version, total, jlen = struct.unpack_from("<III", head, 4)
        if version != 2 or head[16:20] != b"JSON":
            raise FrameError("%s: not a glTF 2.0 GLB (version %d, first chunk %r)" % (p, version, head[16:20]))
        text = f.read(jlen)
        if len(text) < jlen:
            raise FrameError("%s: truncated: the JSON chunk ends at byte %d, the file at %d" % (p, 20 + jlen, self.size))
        try:
            self.doc = json.loads(text.decode("utf-8"))
        except ValueError as e:
            raise FrameError("%s: bad JSON chunk: %s" % (p, e))
        chunk = f.read(8)
        if len(chunk) == 8 and chunk[4:8] == b"BIN\0":
            blen = struct.unpack_from("<I", chunk)[0]
            self.buffers.append((p, 20 + jlen + 8, blen))
        for i, b in enumerate(self.doc.get("buffers", [])[len(self.buffers):], len(self.buffers)):
            self.buffers.append(self._uri_buffer(b, i))

    def _gltf(self, data):
        try:
            self.doc = json.loads(data.decode("utf-8"))
        except ValueError as e:
            raise FrameError("%s: neither a GLB nor glTF JSON: %s" % (self.path, e))
        self.buffers = [self._uri_buffer(b, i) for i, b in enumerate(self.doc.get("buffers", []))]

    def _uri_buffer(self, b, i):
        uri = b.get("uri")
        if uri is None:
            return b""
        if uri.startswith("data:"):
            import base64
            return base64.b64decode(uri.split(",", 1)[1])
        from urllib.parse import unquote
        path = os.path.join(os.path.dirname(self.path), unquote(uri))
        if not os.path.isfile(path):
            raise FrameError("%s: buffer %d's file %s is missing" % (self.path, i, path))
        return (path, 0, os.path.getsize(path))

    def read(self, buffer, offset, length, what):
        """length bytes at offset of buffer; what names them in messages."""
        src = self.buffers[buffer] if 0 <= buffer < len(self.buffers) else None
        if src is None:
            raise FrameError("%s: %s uses buffer %d, the file has %d" % (self.path, what, buffer, len(self.buffers)))
        if isinstance(src, bytes):
            if offset + length > len(src):
                raise FrameError("%s: %s needs bytes %d-%d of buffer %d, which has %d" %
                                 (self.path, what, offset, offset + length, buffer, len(src)))
            return src[offset:offset + length]
        path, base, blen = src
        if offset + length > blen:
            raise FrameError("%s: %s needs bytes %d-%d of buffer %d, which has %d" %
                             (self.path, what, offset, offset + length, buffer, blen))
        with open(path, "rb") as f:
            f.seek(base + offset)
            data = f.read(length)
        if len(data) < length:
            raise FrameError("%s: truncated: %s needs bytes %d-%d, the file ends at byte %d" %
                             (path, what, base + offset, base + offset + length, os.path.getsize(path)))
        return data

    def view(self, index, what):
        views = self.doc.get("bufferViews", [])
        if not 0 <= index < len(views):
            raise FrameError("%s: %s uses bufferView %d, the file has %d" % (self.path, what, index, len(views)))
        v = views[index]
        return v, self.read(v.get("buffer", 0), v.get("byteOffset", 0), v["byteLength"], what)

    def accessor(self, index, what):
        """The accessor's values as an array (count, components); floats for normalized integers."""
        accs = self.doc.get("accessors", [])
        if not 0 <= index < len(accs):
            raise FrameError("%s: %s uses accessor %d, the file has %d" % (self.path, what, index, len(accs)))
        a = accs[index]
        dt = np.dtype(_COMPONENT[a["componentType"]])
        n, count = _NCOMP[a["type"]], a["count"]
        if "sparse" in a:
            raise FrameError("%s: %s: sparse accessors are not read here" % (self.path, what))
        if "bufferView" not in a:
            return np.zeros((count, n), dt)
        v = self.doc["bufferViews"][a["bufferView"]]
        stride = v.get("byteStride") or dt.itemsize * n
        need = stride * (count - 1) + dt.itemsize * n if count else 0
        data = self.read(v.get("buffer", 0), v.get("byteOffset", 0) + a.get("byteOffset", 0), need,
                         "%s (accessor %d)" % (what, index))
        if stride == dt.itemsize * n:
            out = np.frombuffer(data, dt, count * n).reshape(count, n)
        else:
            out = np.lib.stride_tricks.as_strided(np.frombuffer(data, np.uint8), (count, n * dt.itemsize),
                                                  (stride, 1)).copy().view(dt).reshape(count, n)
        if a.get("normalized") and dt.kind in "iu":
            out = np.maximum(out / float(np.iinfo(dt).max), -1.0).astype(np.float32)
        return out


def sequence_info(doc):
    """The --animate file's asset.extras.jetmesh_sequence ({} elsewhere)."""
    return (doc.get("asset", {}).get("extras", {}) or {}).get("jetmesh_sequence", {}) or {}


def gltf_mesh(g, mesh_index, where):
    """Frame of the glTF mesh mesh_index: its triangle primitives, joined."""
    meshes = g.doc.get("meshes", [])
    if not 0 <= mesh_index < len(meshes):
        raise FrameError("%s: %s: no mesh %d (the file has %d)" % (g.path, where, mesh_index, len(meshes)))
    parts = []
    for pi, prim in enumerate(meshes[mesh_index].get("primitives", [])):
        if prim.get("mode", 4) != 4:
            continue
        what = "%s, mesh %d primitive %d" % (where, mesh_index, pi)
        if DRACO in prim.get("extensions", {}):
            arrays, indices = draco_primitive(g, prim, what)
        else:
            arrays = {k: g.accessor(i, "%s %s" % (what, k)) for k, i in prim["attributes"].items()}
            if "indices" in prim:
                indices = g.accessor(prim["indices"], what + " indices").ravel()
            else:
                indices = np.arange(len(arrays["POSITION"]), dtype=np.uint32)
        if "POSITION" not in arrays:
            raise FrameError("%s: %s has no POSITION" % (g.path, what))
        parts.append((arrays, indices))
    return join_parts(parts, g.path)


def join_parts(parts, path):
    """One Frame of several primitives (their indices offset), in Blender axes."""
    if not parts:
        return Frame(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.int32))
    names = set(parts[0][0])
    for a, _ in parts[1:]:
        names &= set(a)
    base, pos, idx = 0, [], []
    for a, ind in parts:
        if len(ind) % 3:
            raise FrameError("%s: %d indices, not a whole number of triangles" % (path, len(ind)))
        if len(ind) and int(ind.max()) >= len(a["POSITION"]):
            raise FrameError("%s: a triangle uses vertex %d of %d" % (path, int(ind.max()), len(a["POSITION"])))
        pos.append(a["POSITION"])
        idx.append(ind.astype(np.int64) + base)
        base += len(a["POSITION"])

    def cat(key):
        return np.ascontiguousarray(np.concatenate([a[key] for a, _ in parts]), dtype=np.float32)
    positions = y_up_to_z_up(cat("POSITION"))
    normals = y_up_to_z_up(cat("NORMAL")) if "NORMAL" in names else None
    uvs = cat("TEXCOORD_0") if "TEXCOORD_0" in names else None
    if uvs is not None:
        uvs[:, 1] = 1.0 - uvs[:, 1]  # glTF's v runs down, Blender's up
    attrs = {}
    for key in sorted(names):
        if key.startswith("_"):
            v = cat(key)
            attrs[key[1:].lower()] = y_up_to_z_up(v) if v.shape[1] == 3 else v
    indices = np.concatenate(idx).astype(np.int32).reshape(-1, 3)
    return Frame(positions, indices, normals, uvs, attrs)


# ---- Draco (Blender's own decoder library, when this Blender has one) -------

def draco_library():
    """Blender's glTF add-on's Draco decoder (libextern_draco), or None."""
    state = _state()
    if "draco" not in state:
        state["draco"] = None
        try:
            from io_scene_gltf2.io.com.gltf2_io_draco_compression_extension import dll_path
            path = dll_path()
            if path.is_file():
                dll = ctypes.cdll.LoadLibrary(str(path.resolve()))
                sig = {"decoderCreate": (ctypes.c_void_p, []),
                       "decoderRelease": (None, [ctypes.c_void_p]),
                       "decoderDecode": (ctypes.c_bool, [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t]),
                       "decoderReadAttribute": (ctypes.c_bool, [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_size_t,
                                                                ctypes.c_char_p]),
                       "decoderGetVertexCount": (ctypes.c_uint32, [ctypes.c_void_p]),
                       "decoderGetIndexCount": (ctypes.c_uint32, [ctypes.c_void_p]),
                       "decoderGetAttributeByteLength": (ctypes.c_size_t, [ctypes.c_void_p, ctypes.c_uint32]),
                       "decoderCopyAttribute": (None, [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_void_p]),
                       "decoderReadIndices": (ctypes.c_bool, [ctypes.c_void_p, ctypes.c_size_t]),
                       "decoderGetIndicesByteLength": (ctypes.c_size_t, [ctypes.c_void_p]),
                       "decoderCopyIndices": (None, [ctypes.c_void_p, ctypes.c_void_p])}
                for name, (res, args) in sig.items():
                    fn = getattr(dll, name)
                    fn.restype, fn.argtypes = res, args
                state["draco"] = dll
        except Exception as e:  # no add-on, no library, another API
            print("jetmesh: no Draco decoder: %s" % e)
    return state["draco"]


def draco_primitive(g, prim, what):
    """({semantic: array}, indices) of a KHR_draco_mesh_compression primitive."""
    dll = draco_library()
    if dll is None:
        raise FrameError("%s: %s is Draco-compressed (%s) and this Blender has no Draco decoder "
                         "(its glTF add-on's libextern_draco is missing; Debian's blender package leaves it out): "
                         "convert without --draco for Blender, or use a Blender from blender.org"
                         % (g.path, what, DRACO))
    ext = prim["extensions"][DRACO]
    _, data = g.view(ext["bufferView"], what + " Draco data")
    dec = dll.decoderCreate()
    try:
        if not dll.decoderDecode(dec, data, len(data)):
            raise FrameError("%s: %s: the Draco decoder refused its data" % (g.path, what))
        accs = g.doc["accessors"]
        out = {}
        for sem, did in ext["attributes"].items():
            a = accs[prim["attributes"][sem]]
            if not dll.decoderReadAttribute(dec, did, a["componentType"], a["type"].encode()):
                raise FrameError("%s: %s: Draco attribute %s (id %d) cannot be decoded" % (g.path, what, sem, did))
            buf = ctypes.create_string_buffer(dll.decoderGetAttributeByteLength(dec, did))
            dll.decoderCopyAttribute(dec, did, buf)
            out[sem] = np.frombuffer(buf.raw, _COMPONENT[a["componentType"]]).reshape(-1, _NCOMP[a["type"]])
        ia = accs[prim["indices"]]
        if not dll.decoderReadIndices(dec, ia["componentType"]):
            raise FrameError("%s: %s: the Draco indices cannot be decoded" % (g.path, what))
        buf = ctypes.create_string_buffer(dll.decoderGetIndicesByteLength(dec))
        dll.decoderCopyIndices(dec, buf)
        indices = np.frombuffer(buf.raw, _COMPONENT[ia["componentType"]])
    finally:
        dll.decoderRelease(dec)
    for sem, i in prim["attributes"].items():  # any left uncompressed
        if sem not in out:
            out[sem] = g.accessor(i, "%s %s" % (what, sem))
    return out, indices


# ---- PLY ---------------------------------------------------------------------

_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}
_PLY_KNOWN = {"x", "y", "z", "nx", "ny", "nz", "s", "t", "u", "v", "texture_u", "texture_v",
              "texture_s", "texture_t"}


def ply_header(path, data):
    """(format, [(element, count, [(name, type) or (name, (count type, item type))])], body offset)."""
    end = data.find(b"end_header", 0, 1 << 16)
    nl = data.find(b"\n", end) if end >= 0 else -1
    if not data.startswith(b"ply") or nl < 0:
        raise FrameError("%s: not a PLY file (no 'ply' ... 'end_header' in its first 64 KiB)" % path)
    fmt, elements = None, []
    for ln, line in enumerate(data[:end].decode("ascii", "replace").splitlines(), 1):
        w = line.split()
        if not w or w[0] in ("ply", "comment", "obj_info"):
            continue
        try:
            if w[0] == "format":
                fmt = w[1]
            elif w[0] == "element":
                elements.append((w[1], int(w[2]), []))
            elif w[0] == "property" and w[1] == "list":
                elements[-1][2].append((w[4], (_PLY_TYPES[w[2]], _PLY_TYPES[w[3]])))
            elif w[0] == "property":
                elements[-1][2].append((w[2], _PLY_TYPES[w[1]]))
            else:
                raise ValueError(line)
        except (IndexError, KeyError, ValueError):
            raise FrameError("%s: header line %d: cannot read %r" % (path, ln, line))
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise FrameError("%s: unknown PLY format %r" % (path, fmt))
    return fmt, elements, nl + 1


def _ply_binary(path, data, elements, at, order):
    """{element: structured array or list of face index lists} of a binary PLY."""
    out = {}
    for name, count, props in elements:
        lists = [p for p in props if isinstance(p[1], tuple)]
        if not lists:
            dt = np.dtype([(p, order + t) for p, t in props])
            if at + dt.itemsize * count > len(data):
                raise FrameError("%s: truncated: element '%s' needs bytes %d-%d, the file has %d" %
                                 (path, name, at, at + dt.itemsize * count, len(data)))
            out[name] = np.frombuffer(data, dt, count, at)
            at += dt.itemsize * count
            continue
        if len(props) == 1 and count:  # faces: try rows of one count and 3 indices
            ct, it = lists[0][1]
            dt = np.dtype([("n", order + ct), ("i", order + it, 3)])
            if at + dt.itemsize * count <= len(data):
                rows = np.frombuffer(data, dt, count, at)
                if np.all(rows["n"] == 3):
                    out[name] = rows["i"]
                    at += dt.itemsize * count
                    continue
        if name != elements[-1][0] and name != "face":
            raise FrameError("%s: element '%s' has list properties other than the faces'" % (path, name))
        faces, pos = [], at  # general polygons, one by one
        for _ in range(count):
            for p, t in props:
                if isinstance(t, tuple):
                    ct, it = np.dtype(order + t[0]), np.dtype(order + t[1])
                    if pos + ct.itemsize > len(data):
                        raise FrameError("%s: truncated in element '%s' at byte %d" % (path, name, pos))
                    k = int(np.frombuffer(data, ct, 1, pos)[0])
                    pos += ct.itemsize
                    if pos + k * it.itemsize > len(data):
                        raise FrameError("%s: truncated in element '%s' at byte %d" % (path, name, pos))
                    if p in ("vertex_indices", "vertex_index"):
                        faces.append(np.frombuffer(data, it, k, pos))
                    pos += k * it.itemsize
                else:
                    pos += np.dtype(t).itemsize
        out[name] = faces
        at = pos
    return out


def _ply_ascii(path, data, elements, at):
    tokens = data[at:].split()
    out, pos = {}, 0
    for name, count, props in elements:
        if all(not isinstance(t, tuple) for _, t in props):
            n = len(props) * count
            if pos + n > len(tokens):
                raise FrameError("%s: element '%s' needs %d values, the file has %d left" %
                                 (path, name, n, len(tokens) - pos))
            vals = np.array(tokens[pos:pos + n], dtype=np.float64).reshape(count, len(props))
            out[name] = {p: vals[:, i] for i, (p, _) in enumerate(props)}
            pos += n
            continue
        faces = []
        for _ in range(count):
            for p, t in props:
                if isinstance(t, tuple):
                    k = int(tokens[pos])
                    if p in ("vertex_indices", "vertex_index"):
                        faces.append(np.array(tokens[pos + 1:pos + 1 + k], dtype=np.int64))
                    pos += 1 + k
                else:
                    pos += 1
        out[name] = faces
    return out


def ply_frame(path, y_up):
    """Frame of a PLY file (binary or ASCII); y_up: rotate +Y up to Blender's +Z up."""
    with open(path, "rb") as f:
        data = f.read()
    fmt, elements, at = ply_header(path, data)
    if fmt == "ascii":
        els = _ply_ascii(path, data, elements, at)
    else:
        els = _ply_binary(path, data, elements, at, "<" if fmt == "binary_little_endian" else ">")
    vert = els.get("vertex")
    if vert is None:
        raise FrameError("%s: no 'vertex' element" % path)
    names = list(vert.dtype.names) if hasattr(vert, "dtype") else list(vert)
    if not all(c in names for c in "xyz"):
        raise FrameError("%s: the vertices have no x, y, z" % path)

    def col(*keys):
        return np.stack([np.asarray(vert[k], np.float32) for k in keys], axis=1)
    turn = y_up_to_z_up if y_up else (lambda a: a)
    positions = turn(col("x", "y", "z"))
    normals = turn(col("nx", "ny", "nz")) if all(k in names for k in ("nx", "ny", "nz")) else None
    uvs = None
    for u, v in (("s", "t"), ("u", "v"), ("texture_u", "texture_v"), ("texture_s", "texture_t")):
        if u in names and v in names:
            uvs = col(u, v)
            break
    attrs, used = {}, set()
    for p in names:
        if p in _PLY_KNOWN or p in used:
            continue
        m = re.match(r"(.+)_x$", p)
        if m and all(m.group(1) + s in names for s in ("_y", "_z")):
            b = m.group(1)
            used.update(b + s for s in ("_x", "_y", "_z"))
            attrs[b] = turn(col(b + "_x", b + "_y", b + "_z"))
        elif not re.match(r".+_[yz]$", p):
            attrs[p] = col(p)
    faces = els.get("face", [])
    if isinstance(faces, list):  # polygons: fans of triangles
        tris = [np.stack([f[0].repeat(len(f) - 2), f[1:-1], f[2:]], axis=1) for f in faces if len(f) >= 3]
        faces = np.concatenate(tris) if tris else np.zeros((0, 3), np.int64)
    indices = np.ascontiguousarray(faces, dtype=np.int64).reshape(-1, 3)
    if len(indices) and (indices.max() >= len(positions) or indices.min() < 0):
        raise FrameError("%s: a face uses vertex %d of %d" % (path, int(indices.max()), len(positions)))
    return Frame(positions, indices.astype(np.int32), normals, uvs, attrs)


# ---- sequences -----------------------------------------------------------------

def _natural(s):
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", s)]


def _split_ext(name):
    low = name.lower()
    for e in EXTENSIONS:
        if low.endswith(e):
            return name[:-len(e)], name[-len(e):]
    return None, None


def frame_key(name):
    """(name with its last number as '#', the number) of a frame file; (None, None) if not one."""
    stem, ext = _split_ext(name)
    if stem is None:
        return None, None
    m = None
    for m in re.finditer(r"\d+", stem):
        pass
    if m is None:
        return stem + ext, None
    return stem[:m.start()] + "#" + stem[m.end():] + ext, int(m.group())


class Sequence:
    """The frames of a sequence: numbers -> files (or the --animate file's meshes)."""

    def __init__(self, label, numbers, paths=None, gltf=None, meshes=None, fps=None, notes=()):
        self.label, self.numbers, self.paths = label, numbers, paths
        self.gltf, self.meshes, self.fps, self.notes = gltf, meshes, fps, list(notes)

    def __len__(self):
        return len(self.numbers)

    def number_for(self, k, hold):
        """The frame number shown at simulation frame k, or None."""
        nums = self.numbers
        if not nums or k < nums[0] or k > nums[-1]:
            return None
        i = bisect.bisect_right(nums, k) - 1
        return nums[i] if nums[i] == k or hold else None

    def where(self, number):
        return self.paths[number] if self.paths is not None else "%s (frame %d)" % (self.label, number)

    def load(self, number, ply_y_up):
        if self.gltf is not None:
            mesh = self.meshes[number]
            if mesh is None:  # a frame that failed at conversion: an empty node
                return Frame(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.int32))
            return gltf_mesh(self.gltf, mesh, "frame %d" % number)
        path = self.paths[number]
        if not os.path.isfile(path):
            raise FrameError("%s: the file is gone" % path)
        if path.lower().endswith(".ply"):
            return ply_frame(path, ply_y_up)
        g = Gltf(path)
        nodes = [n for n in g.doc.get("nodes", []) if "mesh" in n]
        if not nodes:
            return Frame(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.int32))
        return gltf_mesh(g, nodes[0]["mesh"], "frame %d" % number)


def _animated(path):
    """The Gltf of a jetmesh --animate file (or any glTF with several meshes and an animation), else None."""
    if not path.lower().endswith((".glb", ".gltf")):
        return None
    try:
        g = Gltf(path)
    except (FrameError, OSError) as e:
        raise SequenceError(str(e))
    with_mesh = [n for n in g.doc.get("nodes", []) if "mesh" in n]
    if sequence_info(g.doc) or (g.doc.get("animations") and len(with_mesh) > 1):
        return g
    return None


def _files_sequence(label, files):
    """A Sequence of frame files: the largest group of names that differ only in their last number."""
    groups = collections.OrderedDict()
    for f in sorted(files, key=_natural):
        key, num = frame_key(os.path.basename(f))
        if key is not None:
            groups.setdefault(key, []).append((num, f))
    if not groups:
        raise SequenceError("no frames in %s: no .glb, .gltf or .ply file (jetmesh writes them with "
                            "-o 'DIR/frame_{}.glb')" % label)
    key = max(groups, key=lambda k: len(groups[k]))
    notes = []
    if len(groups) > 1:
        others = [k for k in groups if k != key]
        notes.append("%s: took the %d files %s; left out %s" % (label, len(groups[key]), key,
                                                                ", ".join(others[:4]) + (" ..." if len(others) > 4 else "")))
    paths = {}
    for i, (num, f) in enumerate(groups[key]):
        num = i if num is None else num
        if num in paths:
            notes.append("%s: frame %d twice (%s and %s): took the first" % (label, num, paths[num], f))
            continue
        paths[num] = f
    return Sequence(label, sorted(paths), paths=paths, notes=notes)


def discover(path):
    """The Sequence at path: a folder, a pattern ({} %04d #### * ?), an --animate file, or one frame file
    (then its siblings that differ only in the number). Reads names and the animated file's JSON only."""
    path = os.path.abspath(bpy.path.abspath(path)) if path.startswith("//") else os.path.abspath(path)
    if os.path.isdir(path):
        files = [os.path.join(path, f) for f in os.listdir(path) if not f.startswith(".")]
        return _files_sequence(path, [f for f in files if os.path.isfile(f)])
    folder, base = os.path.split(path)
    m = re.search(r"\{\}|%0?\d*d|#+", base)
    if m:
        if not os.path.isdir(folder or "."):
            raise SequenceError("%s: no such folder %s" % (path, folder))
        rx = re.compile(re.escape(base[:m.start()]) + r"(\d+)" + re.escape(base[m.end():]) + "$")
        paths = {}
        for f in sorted(os.listdir(folder or "."), key=_natural):
            mm = rx.match(f)
            if mm and int(mm.group(1)) not in paths:
                paths[int(mm.group(1))] = os.path.join(folder, f)
        if not paths:
            raise SequenceError("no frames match %s" % path)
        return Sequence(path, sorted(paths), paths=paths)
    if any(c in base for c in "*?["):
        files = [f for f in glob.glob(path) if os.path.isfile(f)]
        if not files:
            raise SequenceError("no frames match %s" % path)
        return _files_sequence(path, files)
    if not os.path.isfile(path):
        raise SequenceError("%s: no such file or folder" % path)
    g = _animated(path)
    if g is not None:
        info = sequence_info(g.doc)
        nodes = g.doc.get("nodes", [])
        numbers = info.get("frame_numbers") or list(range(len(nodes)))
        meshes = {}
        for k, n in enumerate(nodes[:len(numbers)]):
            meshes.setdefault(int(numbers[k]), n.get("mesh"))
        return Sequence(path, sorted(meshes), gltf=g, meshes=meshes, fps=info.get("fps"))
    key, _ = frame_key(base)
    if key is None:
        raise SequenceError("%s: not a .glb, .gltf or .ply file" % path)
    siblings = [os.path.join(folder, f) for f in os.listdir(folder or ".") if frame_key(f)[0] == key]
    return _files_sequence(path, siblings)


# ---- state shared by every copy of this script in the process ---------------

def _state():
    """A dict that outlives file loads and a second copy of this module (the add-on and the .blend's text)."""
    mod = sys.modules.get("_jetmesh_sequence_state")
    if mod is None:
        mod = sys.modules["_jetmesh_sequence_state"] = types.ModuleType("_jetmesh_sequence_state")
        mod.d = {}
    return mod.d


def _runtime(obj):
    """Per object: its Sequence, LRU cache, the frame shown, errors reported."""
    rt = _state().setdefault("objects", {})
    key = obj.name_full
    if key not in rt:
        rt[key] = {"sig": None, "seq": None, "cache": collections.OrderedDict(), "shown": None,
                   "reported": set(), "status": "", "error": ""}
    return rt[key]


def report(level, msg):
    """A message in the console and, in the UI, in Blender's report (status bar, Info editor)."""
    print("jetmesh: %s: %s" % (level.lower(), msg), flush=True)
    log = _state().setdefault("messages", [])
    log.append((level, msg))
    del log[:-200]
    if not bpy.app.background:
        def later():
            try:
                bpy.ops.jetmesh.report(level=level, message=msg)
            except Exception:
                pass
            return None
        bpy.app.timers.register(later, first_interval=0.0)


# ---- building the mesh -----------------------------------------------------------

def apply_frame(me, fr, normals=True):
    """Replaces me's geometry by frame fr (None: empty), keeping its materials; normals: the file's as
    custom normals (the dearest step: about half the time), else Blender's smooth ones."""
    me.clear_geometry()
    if fr is None or len(fr.indices) == 0:
        me.update()
        return
    nv, nt = len(fr.positions), len(fr.indices)
    me.vertices.add(nv)
    me.vertices.foreach_set("co", fr.positions.ravel())
    me.loops.add(3 * nt)
    me.loops.foreach_set("vertex_index", fr.indices.ravel())
    me.polygons.add(nt)
    me.polygons.foreach_set("loop_start", np.arange(0, 3 * nt, 3, dtype=np.int32))
    me.polygons.foreach_set("loop_total", np.full(nt, 3, np.int32))
    me.polygons.foreach_set("use_smooth", np.ones(nt, bool))
    me.update(calc_edges=True)
    me.use_auto_smooth = bool(normals and fr.normals is not None)
    if me.use_auto_smooth:
        me.normals_split_custom_set_from_vertices(fr.normals)
    if fr.uvs is not None:
        me.uv_layers.new(name="UVMap").data.foreach_set("uv", fr.uvs[fr.indices.ravel()].ravel())
    for name, v in fr.attributes.items():
        kind, field = {1: ("FLOAT", "value"), 2: ("FLOAT2", "vector"), 3: ("FLOAT_VECTOR", "vector"),
                       4: ("FLOAT_COLOR", "color")}.get(v.shape[1], (None, None))
        if kind is None:
            continue
        try:
            me.attributes.new(name=name, type=kind, domain="POINT").data.foreach_set(field, v.ravel())
        except RuntimeError as e:
            print("jetmesh: attribute %s: %s" % (name, e))
    me.update()


def _signature(s):
    return (bpy.path.abspath(s.path), s.ply_up)


def get_sequence(obj):
    """obj's Sequence (discovered again when its path changed); SequenceError if none."""
    s, rt = obj.jetmesh, _runtime(obj)
    sig = _signature(s)
    if rt["sig"] != sig or rt["seq"] is None:
        rt.update(sig=sig, seq=None, shown=None, reported=set())
        rt["cache"].clear()
        rt["seq"] = discover(sig[0])
        for n in rt["seq"].notes:
            report("WARNING", n)
    return rt["seq"]


def load_frame(obj, seq, number):
    """The Frame of number from obj's cache or its file; FrameError when it cannot be read."""
    s, rt = obj.jetmesh, _runtime(obj)
    cache = rt["cache"]
    if number in cache:
        cache.move_to_end(number)
        return cache[number]
    fr = seq.load(number, s.ply_up == "Y")
    if s.cache_size > 0:
        cache[number] = fr
        while len(cache) > s.cache_size:
            cache.popitem(last=False)
    return fr


def scene_to_frame(obj, scene):
    """The simulation frame scene's current (sub)frame shows on obj."""
    f = scene.frame_current + scene.frame_subframe
    return int(math.floor(f + 0.5)) - obj.jetmesh.offset


def show(obj, scene, force=False):
    """Puts the mesh of scene's frame on obj (nothing when it is already there)."""
    s, rt = obj.jetmesh, _runtime(obj)
    try:
        seq = get_sequence(obj)
    except SequenceError as e:
        if rt["error"] != str(e):
            report("ERROR", "%s: %s" % (obj.name, e))
        rt["error"] = str(e)
        return
    k = scene_to_frame(obj, scene)
    number = seq.number_for(k, s.gaps == "HOLD")
    normals = s.normals == "ALWAYS" or (s.normals == "RENDER" and _state().get("rendering", False))
    key = (rt["sig"], number, normals)
    # the mesh's own mark too: an undo brings back another frame's geometry
    if rt["shown"] == key and obj.data.get("jetmesh_frame") == (-1 if number is None else number) and not force:
        return
    fr, err = None, ""
    if number is not None:
        try:
            fr = load_frame(obj, seq, number)
        except (FrameError, OSError, ValueError, KeyError, IndexError) as e:
            err = str(e) if isinstance(e, FrameError) else "%s: %s" % (seq.where(number), e)
            if number not in rt["reported"]:
                rt["reported"].add(number)
                report("ERROR", "frame %d: %s (shown empty; the other frames still play)" % (number, err))
        if fr is not None:
            missing = [a for a in s.attributes.split(",") if a and a not in fr.attributes]
            if missing and number not in rt["reported"]:
                rt["reported"].add(number)
                report("WARNING", "frame %d (%s) has no %s attribute (frame %d has): it renders without it%s"
                       % (number, seq.where(number), ", ".join(missing), seq.numbers[0],
                          " (no velocity motion blur)" if "velocity" in missing else ""))
    apply_frame(obj.data, fr, normals)
    obj.data["jetmesh_frame"] = -1 if number is None else number
    rt["shown"], rt["error"] = key, err
    rt["status"] = ("frame %d: %d vertices%s" % (number, len(fr.positions),
                                                  ", " + ", ".join(sorted(fr.attributes)) if fr.attributes else "")
                    if fr is not None else ("frame %s: failed" % number if err else "no frame %d: empty" % k))


def sequence_objects(scene):
    return [o for o in scene.objects if o.type == "MESH" and getattr(o, "jetmesh", None) and o.jetmesh.path]


@persistent
def jetmesh_frame_change(scene, depsgraph=None):
    for obj in sequence_objects(scene):
        show(obj, scene)


@persistent
def jetmesh_render_pre(scene, depsgraph=None):
    """Renders get the file's normals (settings' normals "RENDER"): the frame is shown again with them."""
    _state()["rendering"] = True
    for obj in sequence_objects(scene):
        show(obj, scene)


@persistent
def jetmesh_render_end(scene, depsgraph=None):
    _state()["rendering"] = False


@persistent
def jetmesh_load_post(_dummy=None):
    _state()["objects"] = {}
    _state()["rendering"] = False
    for scene in bpy.data.scenes:
        for obj in sequence_objects(scene):
            show(obj, scene, force=True)


def _changed(settings, context):
    obj = settings.id_data
    if _state().get("quiet") or not isinstance(obj, bpy.types.Object):
        return
    _runtime(obj)["shown"] = None
    scene = context.scene if context and context.scene else bpy.context.scene
    show(obj, scene, force=True)


def _fps_changed(settings, context):
    if not _state().get("quiet") and settings.fps > 0:
        set_fps(context.scene or bpy.context.scene, settings.fps)


def set_fps(scene, fps):
    scene.render.fps = max(1, int(round(fps)))
    scene.render.fps_base = scene.render.fps / float(fps)


class JetmeshSequenceSettings(bpy.types.PropertyGroup):
    path: bpy.props.StringProperty(name="Path", subtype="FILE_PATH", update=_changed,
                                   description="A folder of frames, a pattern (frame_{}.glb, %04d, ####, *) "
                                               "or a jetmesh --animate file")
    fps: bpy.props.FloatProperty(name="FPS", default=24.0, min=0.0, update=_fps_changed,
                                 description="The simulation's frames per second: the scene's fps (velocities "
                                             "are per second, so motion blur needs the right one)")
    offset: bpy.props.IntProperty(name="Frame offset", default=0, update=_changed,
                                  description="Scene frame k shows simulation frame k - offset")
    cache_size: bpy.props.IntProperty(name="Cache (frames)", default=8, min=0, max=10000, update=_changed,
                                      description="Frames kept in memory, least recently shown dropped first")
    gaps: bpy.props.EnumProperty(name="Missing frames", default="HOLD", update=_changed,
                                 items=[("HOLD", "Hold", "A frame missing inside the run shows the one before"),
                                        ("EMPTY", "Empty", "A frame missing inside the run shows nothing")])
    ply_up: bpy.props.EnumProperty(name="PLY up axis", default="Y", update=_changed,
                                   items=[("Y", "+Y", "PLY frames are +Y up (as glTF): turned to Blender's +Z"),
                                          ("Z", "+Z", "PLY frames are +Z up: taken as they are")])
    normals: bpy.props.EnumProperty(name="File normals", default="RENDER", update=_changed,
                                    items=[("RENDER", "Renders", "The file's normals in renders (F12, -a); Blender's "
                                                                 "smooth ones in the viewport: twice as fast"),
                                           ("ALWAYS", "Always", "The file's normals as custom normals everywhere"),
                                           ("NEVER", "Never", "Blender's smooth normals")])
    attributes: bpy.props.StringProperty(name="Attributes", default="",
                                         description="The first frame's vertex attributes; a frame without one "
                                                     "is reported")


# ---- opening a sequence -------------------------------------------------------------

def _material():
    mat = bpy.data.materials.get("jetmesh")
    if mat is None:
        mat = bpy.data.materials.new("jetmesh")
        mat.diffuse_color = (0.8, 0.8, 0.8, 1.0)
        mat.use_nodes = True
        bsdf = mat.node_tree.nodes.get("Principled BSDF")
        if bsdf:
            bsdf.inputs["Roughness"].default_value = 0.5
    return mat


def embed_script():
    """This script as the .blend's registered text, so a saved file can load frames on its own (auto-run)."""
    src = None
    here = globals().get("__file__")
    if here and os.path.isfile(here):
        with open(here, "r", encoding="utf-8") as f:
            src = f.read()
    if src is None:
        return
    txt = bpy.data.texts.get(TEXT_NAME) or bpy.data.texts.new(TEXT_NAME)
    if txt.as_string() != src:
        txt.clear()
        txt.write(src)
    txt.use_module = True


def open_sequence(path, fps=0.0, offset=0, cache_size=8, gaps="HOLD", ply_up="Y", normals="RENDER",
                  name=None, set_scene=True, scene=None):
    """Makes the streaming object of the sequence at path; SequenceError when there is none."""
    scene = scene or bpy.context.scene
    seq = discover(path)
    if not len(seq):
        raise SequenceError("%s: the file holds no frame" % seq.label)
    for n in seq.notes:
        report("WARNING", n)
    label = name or os.path.basename(seq.label.rstrip("/")) or "sequence"
    me = bpy.data.meshes.new(label)
    me.materials.append(_material())
    obj = bpy.data.objects.new(label, me)
    coll = bpy.context.collection if bpy.context.collection else scene.collection
    coll.objects.link(obj)
    fps = fps or seq.fps or (scene.render.fps / scene.render.fps_base if not set_scene else 24.0)
    st = _state()
    st["quiet"] = True
    try:
        s = obj.jetmesh
        s.path, s.fps, s.offset, s.cache_size = seq.label, fps, offset, cache_size
        s.gaps, s.ply_up, s.normals = gaps, ply_up, normals
    finally:
        st["quiet"] = False
    rt = _runtime(obj)
    rt.update(sig=_signature(obj.jetmesh), seq=seq)
    first = seq.numbers[0]
    try:  # the first frame tells which attributes every frame should have
        fr = load_frame(obj, seq, first)
        obj.jetmesh.attributes = ",".join(sorted(fr.attributes))
        if "velocity" not in fr.attributes:
            report("WARNING", "%s has no velocity attribute: Cycles cannot blur its motion "
                              "(convert with --attributes velocity)" % seq.where(first))
    except (FrameError, OSError) as e:
        report("ERROR", "frame %d: %s" % (first, e))
    if set_scene:
        set_fps(scene, fps)
        scene.frame_start, scene.frame_end = first + offset, seq.numbers[-1] + offset
        scene.render.use_lock_interface = True  # the handler edits a mesh while renders run
    scene.frame_set(scene.frame_start if set_scene else scene.frame_current)
    show(obj, scene)
    embed_script()
    return obj


# ---- UI: the import operator, the panel, reports -------------------------------------

class IMPORT_SCENE_OT_jetmesh_sequence(bpy.types.Operator):
    """Stream a jetmesh sequence (a folder of frames, one of its files, or an animated glTF) as one object"""
    bl_idname = "import_scene.jetmesh_sequence"
    bl_label = "Import jetmesh sequence"
    bl_options = {"REGISTER", "UNDO"}

    filepath: bpy.props.StringProperty(subtype="FILE_PATH")
    directory: bpy.props.StringProperty(subtype="DIR_PATH")
    filter_glob: bpy.props.StringProperty(default="*.glb;*.gltf;*.ply", options={"HIDDEN"})
    whole_folder: bpy.props.BoolProperty(name="Whole folder", default=False,
                                         description="Every frame in the folder, not only those named like the file")
    fps: bpy.props.FloatProperty(name="FPS (0: from the file, else 24)", default=0.0, min=0.0)
    offset: bpy.props.IntProperty(name="Frame offset", default=0)
    cache_size: bpy.props.IntProperty(name="Cache (frames)", default=8, min=0, max=10000)
    gaps: bpy.props.EnumProperty(name="Missing frames", items=[("HOLD", "Hold", ""), ("EMPTY", "Empty", "")])
    ply_up: bpy.props.EnumProperty(name="PLY up axis", items=[("Y", "+Y", ""), ("Z", "+Z", "")])

    def execute(self, context):
        path = self.directory if self.whole_folder or not self.filepath or os.path.isdir(self.filepath) \
            else self.filepath
        try:
            obj = open_sequence(path, self.fps, self.offset, self.cache_size, self.gaps, self.ply_up)
        except SequenceError as e:
            print("jetmesh: error: %s" % e, flush=True)
            self.report({"ERROR"}, "jetmesh: %s" % e)
            return {"CANCELLED"}
        seq = _runtime(obj)["seq"]
        self.report({"INFO"}, "jetmesh: %s: %d frames (%d-%d), streamed" %
                    (obj.name, len(seq), seq.numbers[0], seq.numbers[-1]))
        return {"FINISHED"}

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}


class JETMESH_OT_report(bpy.types.Operator):
    """Shows a jetmesh message in Blender's report"""
    bl_idname = "jetmesh.report"
    bl_label = "jetmesh report"
    bl_options = {"INTERNAL"}
    level: bpy.props.StringProperty(default="INFO")
    message: bpy.props.StringProperty()

    def execute(self, context):
        self.report({self.level if self.level in ("INFO", "WARNING", "ERROR") else "INFO"}, "jetmesh: " + self.message)
        return {"FINISHED"}


class JETMESH_OT_reload(bpy.types.Operator):
    """Reads the folder again (new frames) and reloads the frame shown"""
    bl_idname = "jetmesh.reload"
    bl_label = "Reload"

    def execute(self, context):
        obj = context.object
        rt = _runtime(obj)
        rt.update(sig=None, seq=None, shown=None)
        show(obj, context.scene, force=True)
        if rt["error"]:
            self.report({"ERROR"}, "jetmesh: " + rt["error"])
        return {"FINISHED"}


class JETMESH_OT_scene_range(bpy.types.Operator):
    """Sets the scene's frame range and fps to the sequence's"""
    bl_idname = "jetmesh.scene_range"
    bl_label = "Scene range and fps"

    def execute(self, context):
        obj = context.object
        try:
            seq = get_sequence(obj)
        except SequenceError as e:
            self.report({"ERROR"}, "jetmesh: %s" % e)
            return {"CANCELLED"}
        context.scene.frame_start = seq.numbers[0] + obj.jetmesh.offset
        context.scene.frame_end = seq.numbers[-1] + obj.jetmesh.offset
        set_fps(context.scene, obj.jetmesh.fps)
        return {"FINISHED"}


class VIEW3D_PT_jetmesh_sequence(bpy.types.Panel):
    bl_label = "jetmesh sequence"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "jetmesh"

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.type == "MESH"

    def draw(self, context):
        obj, col = context.object, self.layout.column()
        s = obj.jetmesh
        if not s.path:
            col.label(text="Not a jetmesh sequence")
            col.operator(IMPORT_SCENE_OT_jetmesh_sequence.bl_idname, text="Import a sequence...")
            return
        for p in ("path", "fps", "offset", "cache_size", "gaps", "ply_up", "normals"):
            col.prop(s, p)
        rt = _runtime(obj)
        seq = rt["seq"]
        if seq is not None and len(seq):
            col.label(text="%d frames, %d-%d" % (len(seq), seq.numbers[0], seq.numbers[-1]))
        if rt["status"]:
            col.label(text=rt["status"])
        if rt["error"]:
            col.label(text=rt["error"], icon="ERROR")
        row = col.row()
        row.operator(JETMESH_OT_reload.bl_idname)
        row.operator(JETMESH_OT_scene_range.bl_idname)


def _menu(self, context):
    self.layout.operator(IMPORT_SCENE_OT_jetmesh_sequence.bl_idname, text="jetmesh sequence (.glb/.gltf/.ply, folder)")


_CLASSES = (JetmeshSequenceSettings, IMPORT_SCENE_OT_jetmesh_sequence, JETMESH_OT_report, JETMESH_OT_reload,
            JETMESH_OT_scene_range, VIEW3D_PT_jetmesh_sequence)
_HANDLERS = ((lambda: bpy.app.handlers.frame_change_pre, jetmesh_frame_change),
             (lambda: bpy.app.handlers.render_init, jetmesh_render_pre),
             (lambda: bpy.app.handlers.render_pre, jetmesh_render_pre),
             (lambda: bpy.app.handlers.render_complete, jetmesh_render_end),
             (lambda: bpy.app.handlers.render_cancel, jetmesh_render_end),
             (lambda: bpy.app.handlers.load_post, jetmesh_load_post))


def register():
    """Registers the classes, the menu entry and the handlers; a copy registered before is unregistered first."""
    old = _state().get("unregister")
    if old is not None:
        try:
            old()
        except Exception as e:
            print("jetmesh: unregistering the earlier copy: %s" % e)
    for cls in _CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.jetmesh = bpy.props.PointerProperty(type=JetmeshSequenceSettings)
    bpy.types.TOPBAR_MT_file_import.append(_menu)
    for handlers, fn in _HANDLERS:
        lst = handlers()
        for h in [h for h in lst if getattr(h, "__name__", "") == fn.__name__]:
            lst.remove(h)
        lst.append(fn)
    _state()["unregister"] = unregister


def unregister():
    for handlers, fn in _HANDLERS:
        lst = handlers()
        for h in [h for h in lst if getattr(h, "__name__", "") == fn.__name__]:
            lst.remove(h)
    try:
        bpy.types.TOPBAR_MT_file_import.remove(_menu)
    except Exception:
        pass
    if hasattr(bpy.types.Object, "jetmesh"):
        del bpy.types.Object.jetmesh
    for cls in reversed(_CLASSES):
        try:
            bpy.utils.unregister_class(cls)
        except RuntimeError:
            pass
    if _state().get("unregister") is unregister:
        del _state()["unregister"]


# ---- command line ------------------------------------------------------------------------

USAGE = ("usage: blender [-b] --python jetmesh_blender.py -- PATH [--fps F] [--offset N] [--cache N] "
         "[--gaps hold|empty] [--ply-up y|z] [--normals render|always|never] [--motion-blur] [--save OUT.blend]")


def _remove_default_cube():
    cube = bpy.data.objects.get("Cube")
    if cube is not None and cube.type == "MESH" and cube.data.name == "Cube" and len(cube.data.vertices) == 8:
        me = cube.data
        bpy.data.objects.remove(cube)
        if me.users == 0:
            bpy.data.meshes.remove(me)


def _aim_camera(scene, obj):
    """Points the scene's camera, keeping its direction, at the first, middle and last frames' box."""
    cam = scene.camera
    seq = _runtime(obj)["seq"]
    boxes = []
    for number in sorted({seq.numbers[0], seq.numbers[len(seq) // 2], seq.numbers[-1]}):
        try:
            p = load_frame(obj, seq, number).positions
        except (FrameError, OSError):
            continue
        if len(p):
            boxes += [p.min(axis=0), p.max(axis=0)]
    if cam is None or not boxes:
        return
    from mathutils import Vector
    lo, hi = np.min(boxes, axis=0), np.max(boxes, axis=0)
    m = obj.matrix_world
    centre = m @ Vector((lo + hi) / 2.0)
    radius = max(float(np.linalg.norm(hi - lo)) / 2.0, 1e-6)
    forward = (cam.matrix_world.to_quaternion() @ Vector((0.0, 0.0, -1.0))).normalized()
    dist = radius / math.tan(min(cam.data.angle_x, cam.data.angle_y) / 2.0) * 1.1
    cam.location = centre - forward * dist
    cam.data.clip_start = min(cam.data.clip_start, dist / 100.0)
    cam.data.clip_end = max(cam.data.clip_end, 4.0 * dist)


def _render_settings(scene):
    """Cycles (it blurs motion by the velocity attribute); no denoising where this Blender has no denoiser
    (Debian's: a render with it on fails)."""
    scene.render.engine = "CYCLES"
    try:
        import _cycles
        if not _cycles.with_openimagedenoise:
            scene.cycles.use_denoising = False
    except (ImportError, AttributeError):
        pass


def main(argv):
    """blender [-b] --python jetmesh_blender.py -- PATH [options]: sets a scene up with the sequence."""
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    if not args:
        return 0
    opt = {"fps": 0.0, "offset": 0, "cache_size": 8, "gaps": "HOLD", "ply_up": "Y", "normals": "RENDER"}
    path, save, blur = None, None, False
    it = iter(args)
    try:
        for a in it:
            if a in ("--fps", "--offset", "--cache", "--gaps", "--ply-up", "--normals", "--save"):
                v = next(it)
                if a == "--fps":
                    opt["fps"] = float(v)
                elif a == "--offset":
                    opt["offset"] = int(v)
                elif a == "--cache":
                    opt["cache_size"] = int(v)
                elif a == "--gaps":
                    opt["gaps"] = {"hold": "HOLD", "empty": "EMPTY"}[v]
                elif a == "--ply-up":
                    opt["ply_up"] = v.upper()
                    assert opt["ply_up"] in ("Y", "Z")
                elif a == "--normals":
                    opt["normals"] = v.upper()
                    assert opt["normals"] in ("RENDER", "ALWAYS", "NEVER")
                else:
                    save = v
            elif a == "--motion-blur":
                blur = True
            elif a.startswith("--") or path is not None:
                raise ValueError(a)
            else:
                path = a
    except (StopIteration, ValueError, KeyError, AssertionError):
        print(USAGE)
        return 2
    if path is None:
        print(USAGE)
        return 2
    _remove_default_cube()
    try:
        obj = open_sequence(path, **opt)
    except SequenceError as e:
        print("jetmesh: error: %s" % e, flush=True)
        return 1
    scene = bpy.context.scene
    _aim_camera(scene, obj)
    _render_settings(scene)
    if blur:
        scene.render.use_motion_blur = True
    seq = _runtime(obj)["seq"]
    print("jetmesh: %s: %d frames (%d-%d) streamed as %s; scene frames %d-%d at %g fps" %
          (seq.label, len(seq), seq.numbers[0], seq.numbers[-1], obj.name, scene.frame_start, scene.frame_end,
           scene.render.fps / scene.render.fps_base), flush=True)
    if save:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(save))
    return 0


def _in_blend():
    """True when this runs as the .blend's registered text (its __file__ is inside the .blend)."""
    here = globals().get("__file__") or ""
    return os.path.isfile(os.path.dirname(here)) or (bpy.data.texts.get(os.path.basename(here)) is not None
                                                     and not os.path.isfile(here))


# Run by --python or as the .blend's text: register (the add-on path calls register() itself).
if __name__ == "__main__":
    register()
    if _in_blend():
        jetmesh_load_post()
    else:
        rc = main(sys.argv)
        if rc and bpy.app.background:
            sys.exit(rc)
