# jetmesh_blender.py - imports a jetmesh sequence (one animated .glb/.gltf, or a folder of per-frame files) into Blender as one animated sequence.
#
# Three ways to use it (the path: `jetmesh --blender-script`):
#   blender --python jetmesh_blender.py -- out/jet.glb [--fps F] [--save scene.blend]
#   blender -b --python jetmesh_blender.py -- meshes/ --save scene.blend      (headless)
#   Edit > Preferences > Add-ons > Install...: this file; then
#   File > Import > jetmesh sequence (.glb/.gltf or a folder)
#
# What it does: imports every frame (Blender's glTF importer; PLY/OBJ files of
# a folder with Blender's own importers), shows frame k at scene frame k (the
# animated file's STEP scale keys, or visibility keys for a folder), sets the
# scene's frame range and fps (from the file's asset.extras.jetmesh_sequence,
# or --fps, default 24), turns the objects' motion blur off (Cycles aborts on
# a 0<->1 scale key inside the shutter), and adds each frame's interpolated
# per-vertex attributes as mesh attributes: "_VELOCITY" becomes a vector
# attribute "velocity" (in Blender's Z-up axes), "_DENSITY" a float
# "density", ... (Blender's glTF importer drops them, so they are read from
# the file here; PLY files: properties velocity_x/_y/_z and the like).
import json
import os
import re
import struct
import sys

bl_info = {
    "name": "jetmesh sequence",
    "author": "jetmesh",
    "version": (0, 3, 0),
    "blender": (3, 0, 0),
    "location": "File > Import > jetmesh sequence",
    "description": "Import a jetmesh animated glTF or a folder of frames as one animated sequence",
    "category": "Import-Export",
}

try:  # Debian's Blender 3.4 glTF importer with a newer numpy
    import numpy

    if not hasattr(numpy, "bool"):
        numpy.bool = bool
except ImportError:  # pragma: no cover
    numpy = None

import bpy  # noqa: E402

_COMP = {5126: ("f", 4), 5125: ("I", 4), 5123: ("H", 2), 5121: ("B", 1)}
_NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


# ---- reading glTF without Blender ----------------------------------------

def read_gltf(path):
    """(json, buffer bytes) of a .glb or a .gltf with its .bin."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":
        jlen = struct.unpack_from("<I", data, 12)[0]
        doc = json.loads(data[20:20 + jlen].decode("utf-8"))
        off = 20 + jlen
        binary = b""
        if off + 8 <= len(data):
            blen = struct.unpack_from("<I", data, off)[0]
            binary = data[off + 8:off + 8 + blen]
        return doc, binary
    doc = json.loads(data.decode("utf-8"))
    binary = b""
    bufs = doc.get("buffers", [])
    if bufs and "uri" in bufs[0]:
        from urllib.parse import unquote
        with open(os.path.join(os.path.dirname(path), unquote(bufs[0]["uri"])), "rb") as f:
            binary = f.read()
    return doc, binary


def accessor(doc, binary, index):
    """The values of an accessor with a bufferView, as a list of tuples."""
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    fmt, size = _COMP[acc["componentType"]]
    n = _NCOMP[acc["type"]]
    stride = view.get("byteStride", size * n)
    base = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    return [struct.unpack_from("<%d%s" % (n, fmt), binary, base + i * stride) for i in range(acc["count"])]


def sequence_info(doc):
    return (doc.get("asset", {}).get("extras", {}) or {}).get("jetmesh_sequence", {})


# ---- attributes -------------------------------------------------------------

def _to_blender(v):
    """glTF's +Y up to Blender's +Z up, as the importer converts positions."""
    return (v[0], -v[2], v[1])


def _vertex_order(mesh, positions):
    """Blender vertex index -> file vertex index (the importer may reorder)."""
    conv = [_to_blender(p) for p in positions]
    n = len(mesh.vertices)
    if n == len(conv) and all(
            abs(mesh.vertices[i].co[k] - conv[i][k]) < 1e-5 for i in range(0, n, max(1, n // 64)) for k in range(3)):
        return list(range(n))
    key = {}
    for i, p in enumerate(conv):
        key.setdefault(tuple(round(c, 5) for c in p), i)
    return [key.get(tuple(round(c, 5) for c in v.co), 0) for v in mesh.vertices]


def set_attribute(mesh, name, values, order):
    """values: per file vertex, 1 or 3 (or 2, 4) components."""
    n = len(values[0]) if values else 1
    if name in mesh.attributes:
        mesh.attributes.remove(mesh.attributes[name])
    kind = {1: "FLOAT", 2: "FLOAT2", 3: "FLOAT_VECTOR", 4: "FLOAT_COLOR"}[n]
    attr = mesh.attributes.new(name=name, type=kind, domain="POINT")
    flat = []
    for i in range(len(mesh.vertices)):
        flat.extend(values[order[i]])
    if n == 1:
        attr.data.foreach_set("value", flat)
    elif n == 4:
        attr.data.foreach_set("color", flat)
    else:
        attr.data.foreach_set("vector", flat)


def gltf_attributes(doc, binary, mesh_index):
    """{name: per-vertex tuples} of the custom "_NAME" attributes, and the positions."""
    prim = doc["meshes"][mesh_index]["primitives"][0]
    out = {}
    for key, idx in prim["attributes"].items():
        if key.startswith("_"):
            vals = accessor(doc, binary, idx)
            if len(vals[0]) == 3:
                vals = [_to_blender(v) for v in vals]
            out[key[1:].lower()] = vals
    pos = accessor(doc, binary, prim["attributes"]["POSITION"]) if out else []
    return out, pos


def _scene_fps(scene, fps):
    scene.render.fps = max(1, int(round(fps)))
    scene.render.fps_base = scene.render.fps / float(fps)


def _no_motion_blur(obj):
    if hasattr(obj, "cycles") and hasattr(obj.cycles, "use_motion_blur"):
        obj.cycles.use_motion_blur = False


# ---- the importers -----------------------------------------------------------

def import_animated(path, fps=None):
    """One animated .glb/.gltf written by `jetmesh convert --animate`."""
    doc, binary = read_gltf(path)
    info = sequence_info(doc)
    scene = bpy.context.scene
    # first: the importer puts keys at t * the scene's fps
    _scene_fps(scene, fps or info.get("fps", 24.0))
    before = set(bpy.data.objects)
    bpy.ops.import_scene.gltf(filepath=path)
    new = [o for o in bpy.data.objects if o not in before]
    by_name = {o.name: o for o in new}
    objects = []
    for k, node in enumerate(doc.get("nodes", [])):
        obj = by_name.get(node.get("name"))
        if obj is None:
            continue
        _no_motion_blur(obj)
        objects.append(obj)
        if "mesh" in node and obj.type == "MESH":
            attrs, pos = gltf_attributes(doc, binary, node["mesh"])
            if attrs:
                order = _vertex_order(obj.data, pos)
                for name, vals in attrs.items():
                    set_attribute(obj.data, name, vals, order)
    frames = info.get("frames", len(doc.get("nodes", [])))
    scene.frame_start = 0
    scene.frame_end = max(0, frames - 1)
    scene.frame_set(0)
    return objects


def _natural(s):
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", s)]


def _read_ply_attributes(path):
    """{name: per-vertex tuples} of a binary little-endian PLY's extra float properties, and positions."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header\n")
    if end < 0 or b"binary_little_endian" not in data[:end]:
        return {}, []
    props, nv, in_vertex = [], 0, False
    for line in data[:end].decode("ascii", "replace").splitlines():
        w = line.split()
        if w[:1] == ["element"]:
            in_vertex = w[1] == "vertex"
            if in_vertex:
                nv = int(w[2])
        elif w[:1] == ["property"] and in_vertex:
            if w[1] != "float":
                return {}, []
            props.append(w[2])
    rec = 4 * len(props)
    base = end + len(b"end_header\n")
    rows = [struct.unpack_from("<%df" % len(props), data, base + i * rec) for i in range(nv)]
    col = {p: i for i, p in enumerate(props)}
    skip = {"x", "y", "z", "nx", "ny", "nz", "s", "t"}
    out, used = {}, set()
    for p in props:
        if p in skip or p in used:
            continue
        m = re.match(r"(.+)_x$", p)
        if m and all(m.group(1) + s in col for s in ("_y", "_z")):
            b = m.group(1)
            ix = [col[b + s] for s in ("_x", "_y", "_z")]
            used.update(b + s for s in ("_x", "_y", "_z"))
            out[b] = [tuple(r[i] for i in ix) for r in rows]
        elif not re.match(r".+_[yzw]$", p):
            out[p] = [(r[col[p]],) for r in rows]
    pos = [(r[col["x"]], r[col["y"]], r[col["z"]]) for r in rows]
    return out, pos


def import_folder(folder, fps=None):
    """A folder of per-frame .glb/.gltf/.ply/.obj files, in natural order: frame k at scene frame k."""
    exts = (".glb", ".gltf", ".ply", ".obj")
    files = sorted((f for f in os.listdir(folder) if f.lower().endswith(exts) and not f.startswith(".")),
                   key=_natural)
    objects = []
    for k, name in enumerate(files):
        path = os.path.join(folder, name)
        before = set(bpy.data.objects)
        low = name.lower()
        if low.endswith((".glb", ".gltf")):
            bpy.ops.import_scene.gltf(filepath=path)
        elif low.endswith(".ply"):
            bpy.ops.import_mesh.ply(filepath=path)
        else:
            if hasattr(bpy.ops.wm, "obj_import"):
                bpy.ops.wm.obj_import(filepath=path)
            else:
                bpy.ops.import_scene.obj(filepath=path)
        new = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
        for obj in new:
            obj.name = "frame_%04d" % k
            _no_motion_blur(obj)
            if low.endswith((".glb", ".gltf")):
                doc, binary = read_gltf(path)
                attrs, pos = gltf_attributes(doc, binary, 0) if doc.get("meshes") else ({}, [])
            elif low.endswith(".ply"):
                attrs, pos = _read_ply_attributes(path)
                pos = [(p[0], p[2], -p[1]) for p in pos]  # _vertex_order expects glTF axes
                attrs = {n: v for n, v in attrs.items()}
            else:
                attrs, pos = {}, []
            if attrs:
                order = _vertex_order(obj.data, pos)
                for an, vals in attrs.items():
                    set_attribute(obj.data, an, vals, order)
            # visible at frame k only
            for f, hide in ((k - 1, True), (k, False), (k + 1, True)):
                if f < 0:
                    continue
                obj.hide_viewport = obj.hide_render = hide
                obj.keyframe_insert("hide_viewport", frame=f)
                obj.keyframe_insert("hide_render", frame=f)
            for fc in obj.animation_data.action.fcurves:
                for kp in fc.keyframe_points:
                    kp.interpolation = "CONSTANT"
            objects.append(obj)
    scene = bpy.context.scene
    _scene_fps(scene, fps or 24.0)
    scene.frame_start = 0
    scene.frame_end = max(0, len(files) - 1)
    scene.frame_set(0)
    return objects


def import_sequence(path, fps=None):
    """A folder of frames or one animated file."""
    if os.path.isdir(path):
        return import_folder(path, fps)
    return import_animated(path, fps)


# ---- add-on ------------------------------------------------------------------

class ImportJetmeshSequence(bpy.types.Operator):
    """Import a jetmesh animated glTF, or a folder of frames, as one animated sequence"""
    bl_idname = "import_scene.jetmesh_sequence"
    bl_label = "Import jetmesh sequence"
    bl_options = {"REGISTER", "UNDO"}

    filepath: bpy.props.StringProperty(subtype="FILE_PATH")
    directory: bpy.props.StringProperty(subtype="DIR_PATH")
    filter_glob: bpy.props.StringProperty(default="*.glb;*.gltf;*.ply;*.obj", options={"HIDDEN"})
    fps: bpy.props.FloatProperty(name="FPS (0: from the file)", default=0.0, min=0.0)
    whole_folder: bpy.props.BoolProperty(name="Whole folder of frames", default=False)

    def execute(self, context):
        path = self.directory if self.whole_folder or not self.filepath else self.filepath
        objs = import_sequence(path, self.fps or None)
        self.report({"INFO"}, "jetmesh: %d frames" % len(objs))
        return {"FINISHED"}

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}


def _menu(self, context):
    self.layout.operator(ImportJetmeshSequence.bl_idname, text="jetmesh sequence (.glb/.gltf, folder)")


def register():
    bpy.utils.register_class(ImportJetmeshSequence)
    bpy.types.TOPBAR_MT_file_import.append(_menu)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(_menu)
    bpy.utils.unregister_class(ImportJetmeshSequence)


# ---- command line: blender [-b] --python jetmesh_blender.py -- PATH [--fps F] [--save F.blend]

def _main(argv):
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    if not args:
        return
    path, fps, save = None, None, None
    i = 0
    while i < len(args):
        if args[i] == "--fps":
            fps = float(args[i + 1])
            i += 2
        elif args[i] == "--save":
            save = args[i + 1]
            i += 2
        else:
            path = args[i]
            i += 1
    if path is None:
        print("usage: blender [-b] --python jetmesh_blender.py -- FILE.glb|FOLDER [--fps F] [--save OUT.blend]")
        return
    objs = import_sequence(path, fps)
    scene = bpy.context.scene
    print("jetmesh: imported %d frames from %s; frames %d-%d at %g fps" %
          (len(objs), path, scene.frame_start, scene.frame_end, scene.render.fps / scene.render.fps_base))
    if save:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(save))


if __name__ == "__main__":
    _main(sys.argv)
