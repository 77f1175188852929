# check_sequence.py - run by t_blender.sh inside headless Blender: the streaming import of jetmesh_blender.py shows frame k's own mesh and velocity, blurs it along the velocity, survives a save, and reports bad input.
# Usage: blender -b --factory-startup --python-exit-code 1 --python check_sequence.py -- SCRIPT MODE ARGS...
#   stream PATH EXPECT FIRST LAST FPS BLEND   the command-line set-up (jetmesh_blender.main), three frames
#                                             checked against the files, a motion-blur render, saved to BLEND
#   reopen PATH EXPECT FIRST LAST             in a .blend opened with -y (its stored script): frames still load
#   render PATH EXPECT                        before `-a`: each rendered frame's mesh is its file's
#   blur DIR                                  a moving slab: the blur's direction and length (units: per second)
#   cases DIR                                 no frames, a broken frame, a frame without velocity, Draco;
#                                             gaps held or empty, an offset; the import operator; the panel
# EXPECT: the per-frame files as a printf template (DIR/f_%d.glb), or "animated" (PATH is one --animate file).
# The expectations are read from the files here, independently of the importer.
import importlib.util
import json
import math
import os
import struct
import sys
import types

import numpy as np

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
script, mode, args = args[0], args[1], args[2:]


def fail(msg):
    print("check_sequence: FAIL: " + msg, flush=True)
    sys.exit(1)


def load_module():
    """The importer as a module, registered (as --python or the add-on would)."""
    spec = importlib.util.spec_from_file_location("jetmesh_blender", script)
    jb = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(jb)
    jb.register()
    return jb


# ---- what the files hold (a reader of its own, not the importer's) ----------

def glb(path):
    with open(path, "rb") as f:
        d = f.read()
    jlen = struct.unpack_from("<I", d, 12)[0]
    return json.loads(d[20:20 + jlen]), d[20 + jlen + 8:]


def values(doc, binary, index, n):
    a = doc["accessors"][index]
    v = doc["bufferViews"][a["bufferView"]]
    off = v.get("byteOffset", 0) + a.get("byteOffset", 0)
    return np.frombuffer(binary, "<f4", a["count"] * n, off).reshape(-1, n)


def expected(path, expect, number):
    """(positions, velocities) of simulation frame number, in Blender's axes (+Z up)."""
    if expect == "animated":
        doc, binary = glb(path)
        k = doc["asset"]["extras"]["jetmesh_sequence"]["frame_numbers"].index(number)
        prim = doc["meshes"][doc["nodes"][k]["mesh"]]["primitives"][0]
    else:
        doc, binary = glb(expect % number)
        prim = doc["meshes"][0]["primitives"][0]
    turn = lambda a: np.stack([a[:, 0], -a[:, 2], a[:, 1]], axis=1)  # noqa: E731
    pos = turn(values(doc, binary, prim["attributes"]["POSITION"], 3))
    vel = prim["attributes"].get("_VELOCITY")
    return pos, (turn(values(doc, binary, vel, 3)) if vel is not None else None)


def check_frame(obj, path, expect, number, what):
    """obj shows simulation frame number: its vertex count, and velocities equal to the file's by position."""
    pos, vel = expected(path, expect, number)
    me = obj.data
    if len(me.vertices) != len(pos):
        fail("%s: the mesh has %d vertices, frame %d's file %d" % (what, len(me.vertices), number, len(pos)))
    if vel is None:
        fail("%s: frame %d's file has no _VELOCITY" % (what, number))
    a = me.attributes.get("velocity")
    if a is None or a.data_type != "FLOAT_VECTOR" or a.domain != "POINT":
        fail("%s: no FLOAT_VECTOR POINT attribute 'velocity' (%s)" % (what, [x.name for x in me.attributes]))
    co = np.empty(3 * len(pos), np.float32)
    me.vertices.foreach_get("co", co)
    got = np.empty(3 * len(pos), np.float32)
    a.data.foreach_get("vector", got)
    where = {tuple(np.round(p, 5)): i for i, p in enumerate(pos)}
    for i, p in enumerate(co.reshape(-1, 3)):
        j = where.get(tuple(np.round(p, 5)))
        if j is None:
            fail("%s: vertex %d at %s is not in frame %d's file" % (what, i, tuple(p), number))
        if np.abs(got[3 * i:3 * i + 3] - vel[j]).max() > 1e-6:
            fail("%s: vertex %d velocity %s, the file has %s" % (what, i, got[3 * i:3 * i + 3], vel[j]))
    print("check_sequence: %s: frame %d, %d vertices and velocities as in the file" % (what, number, len(pos)),
          flush=True)


def sequence_object():
    objs = [o for o in bpy.context.scene.objects if o.type == "MESH" and o.get("jetmesh") is not None]
    if len(objs) != 1:
        fail("%d sequence objects in the scene, expected 1 (%s)" % (len(objs), [o.name for o in bpy.context.scene.objects]))
    return objs[0]


# ---- renders ---------------------------------------------------------------------

def render_setup(size=(64, 48), samples=16):
    s = bpy.context.scene
    s.render.engine = "CYCLES"
    s.cycles.device = "CPU"
    s.cycles.samples = samples
    s.cycles.use_denoising = False
    s.render.resolution_x, s.render.resolution_y = size
    s.render.resolution_percentage = 100
    s.render.motion_blur_shutter = 0.5
    world = bpy.data.worlds.new("black")
    world.color = (0, 0, 0)
    s.world = world
    mat = bpy.data.materials.new("emit")  # an emitter on black: edges, hardly any noise
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    e = nt.nodes.new("ShaderNodeEmission")
    nt.links.new(e.outputs[0], nt.nodes.new("ShaderNodeOutputMaterial").inputs[0])
    return mat


def render(name, blur):
    s = bpy.context.scene
    s.render.use_motion_blur = blur
    s.render.image_settings.file_format = "OPEN_EXR"  # linear values: the blur's profile as rendered
    s.render.filepath = os.path.join(os.environ.get("CHECK_TMP", "/tmp"), name + ".exr")
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(s.render.filepath, check_existing=False)
    px = np.array(img.pixels[:], np.float32).reshape(s.render.resolution_y, s.render.resolution_x, 4)[:, :, 0]
    bpy.data.images.remove(img)
    return px


# ---- the modes -----------------------------------------------------------------------

def mode_stream(path, expect, first, last, fps, blend):
    jb = load_module()
    if "Cube" in bpy.data.objects:
        pass  # the factory scene's cube: the set-up below must remove it
    else:
        fail("the factory scene has no default cube to begin with")
    rc = jb.main(["blender", "--", path, "--fps", fps, "--save", blend])
    if rc != 0:
        fail("jetmesh_blender.main returned %d" % rc)
    if "Cube" in bpy.data.objects:
        fail("the default cube is still in the scene")
    scene = bpy.context.scene
    obj = sequence_object()
    if (scene.frame_start, scene.frame_end) != (int(first), int(last)):
        fail("frame range %d-%d, expected %s-%s" % (scene.frame_start, scene.frame_end, first, last))
    if abs(scene.render.fps / scene.render.fps_base - float(fps)) > 1e-6:
        fail("scene fps %g, expected %s" % (scene.render.fps / scene.render.fps_base, fps))
    first, last = int(first), int(last)
    for k in (last, first + 7, (first + last) // 2, first):  # not in order: the cache and the file reads
        scene.frame_set(k)
        check_frame(obj, path, expect, k, "scene frame %d" % k)
        if obj.data.has_custom_normals:
            fail("scene frame %d: the viewport mesh has the file's normals (by default, renders only)" % k)
    if scene.render.engine != "CYCLES":
        fail("the command-line set-up left the render engine at %s, not Cycles" % scene.render.engine)
    # motion blur from the velocity attribute: the render differs, and the
    # difference is the velocity's (the same render with zero velocities does not)
    k = first + 3 * (last - first) // 4
    scene.frame_set(k)
    obj.jetmesh.normals = "ALWAYS"  # no reload at the renders' start: the velocities zeroed below stay zero
    obj.data.materials.clear()
    obj.data.materials.append(render_setup())
    still = render("still", False)
    blurred = render("blurred", True)
    v = obj.data.attributes["velocity"]
    v.data.foreach_set("vector", np.zeros(3 * len(obj.data.vertices), np.float32))
    obj.data.update()
    zero = render("zero_velocity", True)
    moved, noise = np.abs(blurred - still).mean(), np.abs(zero - still).mean()
    print("check_sequence: frame %d: motion blur changes %.5f a pixel, with zero velocities %.5f" % (k, moved, noise),
          flush=True)
    if not (moved > 4 * noise and moved > 1e-4):
        fail("motion blur: the render with velocities differs by %.5f a pixel, with zero velocities by %.5f" %
             (moved, noise))
    print("check_sequence: ok", flush=True)


def mode_reopen(path, expect, first, last):
    scene = bpy.context.scene
    obj = sequence_object()
    if "jetmesh_frame_change" not in [h.__name__ for h in bpy.app.handlers.frame_change_pre]:
        fail("the .blend's stored script did not register the frame handler (opened without -y?)")
    first, last = int(first), int(last)
    for k in (first + 3, last, first + 11):
        scene.frame_set(k)
        check_frame(obj, path, expect, k, "reopened, scene frame %d" % k)
    print("check_sequence: ok", flush=True)


def mode_render(path, expect):
    """Checks at each render_post (the render itself runs after this script: blender ... -a)."""
    obj = sequence_object()

    def post(scene, *_):
        k = scene.frame_current
        pos, _ = expected(path, expect, k)
        n = len(obj.data.vertices)
        verdict = ("FAIL: the file has %d" % len(pos) if n != len(pos) else
                   "FAIL: not the file's normals" if not obj.data.has_custom_normals else "ok")
        print("check_sequence: rendered frame %d: %d vertices, %s" % (k, n, verdict), flush=True)
    bpy.app.handlers.render_post.append(post)
    render_setup((32, 24), 1)
    print("check_sequence: ok", flush=True)


def write_slab_ply(path, x0, vx):
    """A slab 0.1 wide (x) and 2 high (z) at x0, every vertex moving at (vx, 0, 0) per second (+Z up)."""
    c = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (x0 - 0.05, x0 + 0.05)], np.float32)
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = [(q[0], q[1], q[2]) for q in quads] + [(q[0], q[2], q[3]) for q in quads]
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
            "property float z\nproperty float velocity_x\nproperty float velocity_y\nproperty float velocity_z\n"
            "element face 12\nproperty list uchar int vertex_indices\nend_header\n").encode()
    verts = np.concatenate([c, np.tile(np.array([[vx, 0, 0]], np.float32), (8, 1))], axis=1).astype("<f4")
    faces = b"".join(struct.pack("<B3i", 3, *t) for t in tris)
    with open(path, "wb") as f:
        f.write(head + verts.tobytes() + faces)


def mode_blur(folder):
    """One slab per frame moving along +x at 1 unit/s: at fps 2 and shutter 1 frame it sweeps 0.5."""
    jb = load_module()
    os.makedirs(folder, exist_ok=True)
    for k in range(3):
        write_slab_ply(os.path.join(folder, "slab_%d.ply" % k), 0.5 * k, 1.0)
    scene = bpy.context.scene
    for o in list(scene.objects):
        if o.type == "MESH":
            bpy.data.objects.remove(o)
    obj = jb.open_sequence(folder, fps=2.0, ply_up="Z", normals="NEVER")
    mat = render_setup((64, 64), 64)
    obj.data.materials.clear()
    obj.data.materials.append(mat)
    cam = bpy.data.cameras.new("ortho")
    cam.type, cam.ortho_scale = "ORTHO", 4.0  # 16 pixels a unit
    co = bpy.data.objects.new("ortho", cam)
    co.location = (0.5, 0.0, 10.0)  # looking down -Z: image x is world x, image y world y
    scene.collection.objects.link(co)
    scene.camera = co
    scene.frame_set(1)  # the slab at x = 0.5: the image's centre
    scene.render.motion_blur_shutter = 1.0
    still, blurred = render("slab_still", False), render("slab_blurred", True)
    if still.max() < 0.5:
        fail("the slab is not in the image")
    # along x, the blurred profile is the slab's swept over d: its variance
    # grows by d^2 / 12 and its centre stays (the shutter is centred on the frame);
    # along y (across the velocity) nothing moves
    def sweep(axis):
        out = []
        for px in (still, blurred):
            img = np.where(px > 0.02, px, 0.0).astype(np.float64)  # not the background's faint noise
            prof = img.sum(axis=1 - axis)
            at = np.arange(len(prof), dtype=np.float64)
            mean = (prof * at).sum() / prof.sum()
            out.append((mean, (prof * (at - mean) ** 2).sum() / prof.sum()))
        return math.sqrt(max(0.0, 12.0 * (out[1][1] - out[0][1]))), out[1][0] - out[0][0]
    dx, cx = sweep(1)
    dy, cy = sweep(0)
    print("check_sequence: slab: the blur sweeps %.2f pixels along x (centre moved %.2f), %.2f across (%.2f)"
          % (dx, cx, dy, cy), flush=True)
    # 1 unit/s, a shutter of 1 frame at 2 fps: 0.5 units = 8 pixels
    if abs(dx - 8.0) > 1.0 or abs(cx) > 0.5:
        fail("the blur sweeps %.2f pixels along x, its centre moved by %.2f: expected 8 (0.5 units: velocity per "
             "second, shutter 1 frame at 2 fps), centred" % (dx, cx))
    if dy > 1.5 or abs(cy) > 0.5:
        fail("the blur reaches across the velocity: %.2f pixels along y, centre moved %.2f" % (dy, cy))
    print("check_sequence: ok", flush=True)


class Layout:
    """Records what a panel draws (the panel's draw() without a window)."""

    def __init__(self, log):
        self.log = log

    def column(self):
        return self

    def row(self):
        return self

    def prop(self, data, name, **kw):
        getattr(data, name)  # the property exists
        self.log.append("prop " + name)

    def label(self, text="", **kw):
        self.log.append("label " + text)

    def operator(self, idname, **kw):
        self.log.append("operator " + idname)


def mode_cases(folder):
    """Bad input (no frames, a broken frame, a frame without velocity, Draco), and the frame mapping
    (gaps held or empty, an offset), the import operator and the panel."""
    jb = load_module()
    scene = bpy.context.scene
    os.makedirs(os.path.join(folder, "empty"), exist_ok=True)
    # 1. a folder with no frames: the operator's report (an error raises in bpy.ops) and the console
    try:
        bpy.ops.import_scene.jetmesh_sequence(directory=os.path.join(folder, "empty") + "/", whole_folder=True)
        fail("importing an empty folder did not fail")
    except RuntimeError as e:
        if "no frames in" not in str(e):
            fail("empty folder: the report says %r" % str(e))
        print("check_sequence: empty folder reported: %s" % str(e).strip(), flush=True)
    # 2. frames 0-4 where frame 2 is cut short and frame 3 has no velocity: the others play
    seq = os.path.join(folder, "seq")
    obj = jb.open_sequence(seq)
    counts = {}
    for k in range(5):
        scene.frame_set(k)
        counts[k] = len(obj.data.vertices)
    msgs = [m for _, m in jb._state().get("messages", [])]
    print("check_sequence: vertices per frame %s" % counts, flush=True)
    if counts[2] != 0 or any(counts[k] == 0 for k in (0, 1, 3, 4)):
        fail("the broken frame 2 should show empty and the others play: %s" % counts)
    if not any("frame 2" in m and "truncated" in m and "f_2.glb" in m for m in msgs):
        fail("no message names frame 2's file and its truncation: %s" % msgs)
    if not any("frame 3" in m and "no velocity attribute" in m for m in msgs):
        fail("no message about frame 3's missing velocity: %s" % msgs)
    scene.frame_set(3)
    if "velocity" in obj.data.attributes:
        fail("frame 3 shows a velocity it does not have")
    scene.frame_set(4)
    if "velocity" not in obj.data.attributes:
        fail("frame 4 lost its velocity after frame 3")
    # the panel draws the object's settings and its error
    scene.frame_set(2)
    log = []
    panel = types.SimpleNamespace(layout=Layout(log))
    jb.VIEW3D_PT_jetmesh_sequence.draw(panel, types.SimpleNamespace(object=obj, scene=scene))
    for want in ("prop path", "prop fps", "prop offset", "prop cache_size", "operator jetmesh.reload"):
        if want not in log:
            fail("the panel does not draw %r: %s" % (want, log))
    if not any(x.startswith("label ") and "truncated" in x for x in log):
        fail("the panel does not show frame 2's error: %s" % log)
    bpy.data.objects.remove(obj)
    # 3. a Draco frame: read with Blender's Draco library, or a message that says there is none
    dobj = jb.open_sequence(os.path.join(folder, "draco"))
    scene.frame_set(0)
    doc, _ = glb(os.path.join(folder, "draco_reference.glb"))  # the same frame without Draco
    want = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]["count"]
    msgs = [m for _, m in jb._state().get("messages", [])]
    if jb.draco_library() is None:
        if len(dobj.data.vertices) or not any("Draco-compressed" in m and "no Draco decoder" in m for m in msgs):
            fail("a Draco frame without a decoder: %d vertices, messages %s" % (len(dobj.data.vertices), msgs[-3:]))
        print("check_sequence: Draco frame: this Blender has no decoder, reported", flush=True)
    elif len(dobj.data.vertices) != want:
        fail("the Draco frame shows %d vertices, the file has %d" % (len(dobj.data.vertices), want))
    bpy.data.objects.remove(dobj)
    # 4. frames 0, 2, 4 (--frames 0:4:2): gaps hold or show nothing; nothing after the last; an offset
    gap = jb.open_sequence(os.path.join(folder, "gaps", "f_{}.glb"), offset=10)
    if (scene.frame_start, scene.frame_end) != (10, 14):
        fail("frames 0-4 with offset 10: scene range %d-%d" % (scene.frame_start, scene.frame_end))
    n = {}
    for k in (10, 11, 12, 15, 9):
        scene.frame_set(k)
        n[k] = len(gap.data.vertices)
    if not (n[10] == n[11] > 0 and n[12] > 0 and n[12] != n[10] and n[15] == 0 and n[9] == 0):
        fail("gaps held, offset 10: vertices at scene frames %s" % n)
    gap.jetmesh.gaps = "EMPTY"
    scene.frame_set(11)
    if len(gap.data.vertices):
        fail("gaps empty: scene frame 11 (frame 1, missing) shows %d vertices" % len(gap.data.vertices))
    print("check_sequence: frames 0, 2, 4 at offset 10: %s; a gap empty with gaps=EMPTY" % n, flush=True)
    bpy.data.objects.remove(gap)
    # 5. the import operator on one frame's file: its siblings, one object
    before = set(bpy.data.objects)
    if bpy.ops.import_scene.jetmesh_sequence(filepath=os.path.join(folder, "gaps", "f_2.glb")) != {"FINISHED"}:
        fail("the import operator did not finish")
    new = [o for o in bpy.data.objects if o not in before]
    if len(new) != 1 or len(jb._runtime(new[0])["seq"]) != 3:
        fail("the operator made %d objects (%s), expected one of 3 frames" % (len(new), new))
    print("check_sequence: ok", flush=True)


{"stream": mode_stream, "reopen": mode_reopen, "render": mode_render, "blur": mode_blur,
 "cases": mode_cases}[mode](*args)
